"""Where the time of one conformant FMU iteration goes, and what it bounds.

One Newton iteration of the host on one bearing FMU is four FMI calls (fmi2SetFMUstate,
fmi2SetReal, fmi2DoStep, fmi2GetReal; the first iteration of a step skips the restore) and
each step adds fmi2GetFMUstate + fmi2FreeFMUstate. This script times every call through
fmpy's raw ctypes function on one Taylor FMU instance, the same calls on the pythonfmu slave
object in-process (its Python share), and the internal called directly, all side by side in
one run, then prints the Reynolds-vs-Taylor speed-up the FMU route can reach at most:

    speed-up <= (e (t_R + o) + r) / (e (t_T + o) + r + s)

with e evaluations per step (both bearings), t_R / t_T the Reynolds / Taylor call, o the
FMI cost per iteration, s the per-step state save, r the host's own work per step.

    .venv/bin/python benchmarks/bench_fmi_calls.py [--calls 20000]
"""

from __future__ import annotations

import argparse
import math
import platform
import shutil
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from bench_cosim import cpu  # noqa: E402

SURROGATE = ROOT / "rotor_host" / "bundled" / "surrogates" / "paper_22hz_16.7N.json"


def per_call_us(fn, n: int) -> float:
    fn()
    t0 = time.perf_counter()
    for _ in range(n):
        fn()
    return 1e6 * (time.perf_counter() - t0) / n


def training_state(path) -> tuple[float, float, float, float]:
    """A state the surrogate was trained on (one of the training states its file stores, inside
    its bounds too), so the domain guard lets it through; (y, z, vy, vz) [m, m/s]."""
    from bearing_fmu.internals.taylor import Taylor

    tay = Taylor.from_file(path)
    s = tay.surrogate
    for u in s.neighbours.points:
        x = (s.y0 + u[0] * s.pos_scale, s.z0 + u[1] * s.pos_scale, u[2] * s.vel_scale, u[3] * s.vel_scale)
        if tay.domain_distance(*x) <= 0.0:
            return tuple(map(float, x))
    raise ValueError(f"{path}: no stored training state inside its bounds")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--calls", type=int, default=20000)
    ap.add_argument("--host-us-per-step", type=float, default=17.0,
                    help="the host's own work per step (integrator, 2 bearings) for the bound [us]; "
                         "bench_cosim's direct Taylor run minus its 4 force calls gives ~17 us")
    ap.add_argument("--evals-per-step", type=float, default=4.0, help="bearing evaluations per step (2 bearings)")
    args = ap.parse_args()
    n = args.calls

    from bearing_fmu.fmu.build import build_fmu
    from bearing_fmu.fmu.slave import BearingFMU
    from bearing_fmu.internals.taylor.guard import DomainGuard
    from bearing_fmu.internals.taylor import Taylor
    from bearing_fmu.physics.params import PAPER_BEARING
    from bearing_fmu.physics.solver.reynolds import Reynolds
    from rotor_host.coupling.cosim import FMUBearings

    omega = 2 * math.pi * 22.0
    state = training_state(SURROGATE)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        fmu_path = build_fmu(Path(tmp) / "bearing.fmu", surrogate=SURROGATE)
        fb = FMUBearings(fmu_path, [(0, 1)], omega, [{"internal": "taylor"}])
        try:
            fmu, c = fb.instances[0], fb.instances[0].component
            dll = fmu.dll
            fb.begin_step(0.0, 1e-4)
            saved = fb._states[0]
            b = fb._buf_in
            b[0], b[1], b[2], b[3], b[4] = *state, omega
            n_out = len(fb._vr_out)

            def get_free():
                fmu.freeFMUstate(fmu.getFMUstate())

            clock = [0.0]

            def do_step():  # from where the last step ended (the FMU refuses another time)
                dll.fmi2DoStep(c, clock[0], 1e-4, 0)
                clock[0] += 1e-4

            fb._fresh[0] = False  # every host iteration restores the step's state (the steps above moved on)
            fmi = {
                "fmi2GetFMUstate + fmi2FreeFMUstate": per_call_us(get_free, n),
                "fmi2SetFMUstate": per_call_us(lambda: dll.fmi2SetFMUstate(c, saved), n),
                "fmi2SetReal (5 inputs)": per_call_us(lambda: dll.fmi2SetReal(c, fb._vr_in, 5, b), n),
                "fmi2DoStep": per_call_us(do_step, n),
                f"fmi2GetReal ({n_out} outputs)": per_call_us(lambda: dll.fmi2GetReal(c, fb._vr_out, n_out,
                                                                                      fb._buf_out), n),
                "host iteration (FMUBearings._bearing, restore + 3 calls + unpacking)":
                    per_call_us(lambda: fb._bearing(0, *state), n),
            }
        finally:
            fb.close()

        # the same calls on the pythonfmu slave object, in-process: the Python share of each
        res = Path(tmp) / "resources"
        (res / "surrogates").mkdir(parents=True)
        shutil.copy(SURROGATE, res / "surrogates")
        s = BearingFMU(instance_name="b", resources=str(res))
        s.internal = "taylor"
        s.exit_initialization_mode()
        s.y, s.z, s.vy, s.vz, s.omega = *state, omega
        vr_in = [vr for vr, (name, _, _) in s._by_vr.items() if name in ("y", "z", "vy", "vz", "omega")]
        vr_out = [vr for vr, (_, typ, caus) in s._by_vr.items() if caus == "output" and typ == "Real"]
        st = s._get_fmu_state()
        slave_clock = [0.0]

        def slave_step():
            s.do_step(slave_clock[0], 1e-4)
            slave_clock[0] += 1e-4

        py = {
            "fmi2GetFMUstate + fmi2FreeFMUstate": per_call_us(s._get_fmu_state, n),
            "fmi2SetFMUstate": per_call_us(lambda: s._set_fmu_state(st), n),
            "fmi2SetReal (5 inputs)": per_call_us(lambda: s.set_real(vr_in, [*state, omega]), n),
            "fmi2DoStep": per_call_us(slave_step, n),
            f"fmi2GetReal ({n_out} outputs)": per_call_us(lambda: s.get_real(vr_out), n),
        }
    tay = Taylor.from_file(SURROGATE, PAPER_BEARING)
    guard = DomainGuard(tay)
    rey = Reynolds(PAPER_BEARING)
    direct = {
        "Taylor.force_and_jacobian": per_call_us(lambda: tay.force_and_jacobian(*state, omega), n),
        "DomainGuard(Taylor).force_and_jacobian": per_call_us(lambda: guard.force_and_jacobian(*state, omega), n),
        "Reynolds.force_and_jacobian (128 x 16)": per_call_us(lambda: rey.force_and_jacobian(*state, omega),
                                                              max(200, n // 50)),
    }
    for name, t in fmi.items():
        rows.append((name, t, py.get(name)))
    print(f"bench_fmi_calls: paper_22hz surrogate, {n} calls each; {cpu()}, {platform.machine()}, "
          f"Python {platform.python_version()}\n")
    print("| FMI call (fmpy raw ctypes, Taylor FMU) | us per call | of which the slave's Python [us] |")
    print("|---|---|---|")
    for name, t, p in rows:
        print(f"| {name} | {t:.2f} | {'' if p is None else f'{p:.2f}'} |")
    print("\n| direct call | us per call |\n|---|---|")
    for name, t in direct.items():
        print(f"| {name} | {t:.2f} |")

    it = fmi["host iteration (FMUBearings._bearing, restore + 3 calls + unpacking)"]
    o = it - direct["DomainGuard(Taylor).force_and_jacobian"]
    save = fmi["fmi2GetFMUstate + fmi2FreeFMUstate"]
    e, r = args.evals_per_step, args.host_us_per_step
    t_r, t_t = direct["Reynolds.force_and_jacobian (128 x 16)"], direct["DomainGuard(Taylor).force_and_jacobian"]
    fmu_bound = (e * (t_r + o) + r + 2 * save) / (e * (t_t + o) + r + 2 * save)
    direct_bound = (e * t_r + r) / (e * t_t + r)
    print(f"\nFMI cost per iteration o = {o:.1f} us (host iteration minus the guarded Taylor call), "
          f"state save s = {save:.1f} us per bearing and step.")
    print(f"Reynolds / Taylor speed-up at {e:g} evaluations and r = {r:g} us host work per step: "
          f"through FMUs at most {fmu_bound:.1f}x, called directly {direct_bound:.1f}x.")
    print(f"For 20x through FMUs the FMI cost per iteration would have to be below "
          f"{((e * t_r + r + 2 * save) - 20 * (e * t_t + r + 2 * save)) / (19 * e):.1f} us.")


if __name__ == "__main__":
    main()
