"""What the Python FMU's thermal ports cost, side by side: one conformant iteration (restore the
state, set the inputs, doStep, get the outputs) of the Reynolds FMU with thermal = false and with
thermal = true (one film report more per evaluation: a second, warm-started Reynolds solve, plus
the heat balance's scalar root), and the same two in-process (Reynolds.force against
LaggedThermal.force), on the paper bearing with an ISO VG 46 oil at 44 Hz.

    .venv/bin/python benchmarks/bench_thermal_ports.py [--calls 400]
"""

from __future__ import annotations

import argparse
import math
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "examples"))

BEARING = ROOT / "rotor_host" / "bundled" / "bearing_paper_vg46.toml"
OMEGA = 2 * math.pi * 44.0
STATE = (12e-6, -45e-6, 1e-4, -2e-4)


def per_call_us(fn, n: int) -> float:
    fn()
    t0 = time.perf_counter()
    for _ in range(n):
        fn()
    return (time.perf_counter() - t0) / n * 1e6


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--calls", type=int, default=400)
    args = ap.parse_args(argv)
    from drive_fmu_with_fmpy import BearingInstance

    from bearing_fmu.fmu.build import build_fmu
    from bearing_fmu.internals.scaled import LaggedThermal
    from bearing_fmu.physics.params import BearingParams
    from bearing_fmu.physics.solver.reynolds import Reynolds

    params = BearingParams.from_toml(BEARING)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        fmu = build_fmu(Path(tmp) / "vg46.fmu", bearing=params, bearing_source=str(BEARING))
        for thermal in (False, True):
            inst = BearingInstance(fmu, {"thermal": thermal, "y": STATE[0], "z": STATE[1], "omega": OMEGA,
                                         "T_supply": 313.15})
            saved = inst.fmu.getFMUstate()

            def iteration(inst=inst, saved=saved):
                inst.fmu.setFMUstate(saved)
                inst.step(1e-4, *STATE, OMEGA)

            rows.append((f"FMU iteration, thermal = {str(thermal).lower()}", per_call_us(iteration, args.calls)))
            inst.fmu.freeFMUstate(saved)
            inst.close()
    rey = Reynolds(params)
    lag = LaggedThermal(Reynolds(params), params.oil, 313.15)
    lag.start(*STATE, OMEGA)
    lag.begin_step(1e-4)
    rows.append(("Reynolds.force in-process", per_call_us(lambda: rey.force(*STATE, OMEGA), args.calls)))
    rows.append(("LaggedThermal.force in-process", per_call_us(lambda: lag.force(*STATE, OMEGA), args.calls)))
    for name, us in rows:
        print(f"{name:40s} {us:9.1f} us")
    print(f"thermal / isoviscous: FMU {rows[1][1] / rows[0][1]:.2f}x, in-process {rows[3][1] / rows[2][1]:.2f}x")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
