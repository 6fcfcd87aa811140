"""The Python FMU's (pythonfmu) cost per step beside the native FMU's, in one run (issue 37 item 3).

1. Per step: the paper's 22 Hz scene (rotor_host/bundled/scenes/paper_22hz.toml) with the force
   map internal for --t-end s through the Python FMU and through the native FMU (both loaded by
   fmpy; rotor_host/coupling/cosim.py), the CPU time of the integration only (Newmark.run, process
   time: the clock says little on a shared machine), best of --repeat runs. A third row runs the
   Python FMU the way it ran before it declared itself memoryless: the Python driver saving and
   restoring its FMU state around every iterate (``FMUBearings.memoryless`` forced off).
2. Per FMI call: each call of the host's iteration through fmpy's raw ctypes function on one
   instance of each FMU (map internal, a state near the 22 Hz equilibrium), and the same calls on
   the pythonfmu slave object in-process (the slave's Python share; the rest of the Python FMU's
   call is pythonfmu's C++ layer and ctypes).

    .venv/bin/python benchmarks/python_fmu_step.py [--t-end 0.2] [--repeat 3] [--calls 20000]
"""

from __future__ import annotations

import argparse
import ctypes
import math
import os
import platform
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

SCENE = ROOT / "rotor_host" / "bundled" / "scenes" / "paper_22hz.toml"
MAP = ROOT / "rotor_host" / "bundled" / "maps" / "paper_bearing.json"
OMEGA = 2 * math.pi * 22.0
STATE = (1.2e-5, -4.1e-5, 1e-4, -2e-4, OMEGA)  # near the paper bearing's 22 Hz equilibrium under 16.7 N


def cpu_name() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


class IntegrationCPU:
    """CPU seconds (process time) spent in Newmark.run while the block runs."""

    def __enter__(self):
        from rotor_host.integrate.newmark import Newmark

        self.cpu = 0.0
        self._orig = Newmark.run

        def run(integ, *a, **k):
            c0 = time.process_time()
            try:
                return self._orig(integ, *a, **k)
            finally:
                self.cpu += time.process_time() - c0

        Newmark.run = run
        return self

    def __exit__(self, *exc):
        from rotor_host.integrate.newmark import Newmark

        Newmark.run = self._orig


def per_step(t_end: float, repeat: int, work: Path) -> list[dict]:
    from rotor_host.coupling.cosim import FMUBearings
    from rotor_host.scenes.run import run_scene
    from rotor_host.scenes.scene import load_scene

    base = load_scene(SCENE)
    rows = []
    cases = [("Python FMU", "python", None), ("native FMU", "native", None),
             ("Python FMU, saved and restored per iterate (as before it declared itself memoryless)", "python", False)]
    for label, kind, memoryless in cases:
        scene = base.with_internal("map", t_end_s=t_end, via="fmu", fmu_kind=kind)
        run_scene(scene, work_dir=work)  # builds the FMU once, warms numba's and the OS's caches
        orig = FMUBearings._declared_memoryless
        if memoryless is False:
            FMUBearings._declared_memoryless = lambda self, parameters: False
        try:
            best = None
            for _ in range(repeat):
                with IntegrationCPU() as c:
                    run = run_scene(scene, work_dir=work)
                steps = run.meta["steps"]
                us = 1e6 * c.cpu / steps
                if best is None or us < best["us"]:
                    best = {"route": label, "us": us, "steps": steps, "evals": run.meta["force_evaluations"],
                            "wall_us": 1e6 * run.meta["integration_time_s"] / steps}
        finally:
            FMUBearings._declared_memoryless = orig
        rows.append(best)
    return rows


def per_call(work: Path, n: int) -> tuple[list[tuple], dict]:
    """(rows of (call, Python FMU us, native FMU us), the slave's Python share per call)."""
    from rotor_host.coupling.cosim import FMUBearings
    from rotor_host.scenes.bearings import scene_fmu
    from rotor_host.scenes.scene import load_scene

    base = load_scene(SCENE)
    paths = {kind: scene_fmu(base.with_internal("map", via="fmu", fmu_kind=kind), work) for kind in ("python", "native")}
    params = {"python": {"internal": "map", "map": MAP.name}, "native": {}}
    out: dict[str, dict] = {}
    for kind, path in paths.items():
        fb = FMUBearings(path, [(0, 1)], OMEGA, [params[kind]])
        try:
            fmu = fb.instances[0]
            c, dll = fmu.component, fmu.dll
            b = fb._buf_in
            b[0], b[1], b[2], b[3], b[4] = STATE
            clock = [0.0]
            h = 1e-4

            def step():
                status = dll.fmi2DoStep(c, clock[0], h, 0)
                clock[0] += h
                if status > 1:
                    raise RuntimeError(f"{kind} FMU: doStep returned {status}: {fb.messages[0][-1:]}")

            saved = ctypes.c_void_p()
            dll.fmi2GetFMUstate(c, ctypes.byref(saved))

            def get_free():
                s = ctypes.c_void_p()
                dll.fmi2GetFMUstate(c, ctypes.byref(s))
                dll.fmi2FreeFMUstate(c, ctypes.byref(s))

            n_out = len(fb._vr_out)
            calls = {
                "fmi2SetReal (5 inputs)": lambda: dll.fmi2SetReal(c, fb._vr_in, 5, b),
                "fmi2DoStep": step,
                f"fmi2GetReal ({n_out} outputs)": lambda: dll.fmi2GetReal(c, fb._vr_out, n_out, fb._buf_out),
                "fmi2SetFMUstate": lambda: dll.fmi2SetFMUstate(c, saved),
                "fmi2GetFMUstate + fmi2FreeFMUstate": get_free,
            }
            out[kind] = {name: timed(fn, n) for name, fn in calls.items()}
            if kind == "python":
                out["slave"] = slave_share(fb, n)
            dll.fmi2FreeFMUstate(c, ctypes.byref(saved))
        finally:
            fb.close()
    rows = [(name, out["python"][name], out["native"][name], out["slave"].get(name)) for name in out["python"]]
    return rows, out["slave"]


def slave_share(fb, n: int) -> dict:
    """The same calls on the pythonfmu slave object of ``fb``'s instance (it runs in this
    interpreter): what the slave's Python costs of each call."""
    import gc

    slave = next(o for o in gc.get_objects() if type(o).__name__ == "BearingFMU" and o._mode == "Step Mode")
    names = ("y", "z", "vy", "vz", "omega")
    vr_in = [fb._vars[name].valueReference for name in names]
    vr_out = list(fb._vr_out)
    clock = [slave._t]
    h = 1e-4

    def step():
        slave.do_step(clock[0], h)
        clock[0] += h

    saved = slave._get_fmu_state()
    return {"fmi2SetReal (5 inputs)": timed(lambda: slave.set_real(vr_in, list(STATE)), n),
            "fmi2DoStep": timed(step, n),
            f"fmi2GetReal ({len(vr_out)} outputs)": timed(lambda: slave.get_real(vr_out), n),
            "fmi2SetFMUstate": timed(lambda: slave._set_fmu_state(saved), n),
            "fmi2GetFMUstate + fmi2FreeFMUstate": timed(slave._get_fmu_state, n)}


def timed(fn, n: int) -> float:
    """CPU microseconds per call of ``fn``, best of three runs of n // 3 calls."""
    fn()
    best = math.inf
    for _ in range(3):
        c0 = time.process_time()
        for _ in range(max(1, n // 3)):
            fn()
        best = min(best, (time.process_time() - c0) / max(1, n // 3))
    return 1e6 * best


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--t-end", type=float, default=0.2, help="simulated time of each rotor run [s]")
    ap.add_argument("--repeat", type=int, default=3, help="runs per route, the fastest counts")
    ap.add_argument("--calls", type=int, default=20000, help="calls per FMI call timed")
    args = ap.parse_args()
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"python_fmu_step: {cpu_name()}, {os.cpu_count()} cores, load {load:.1f}, Python "
          f"{platform.python_version()}; CPU time (process time)\n")
    with tempfile.TemporaryDirectory(prefix="python_fmu_step_") as tmp:
        work = Path(tmp)
        rows = per_step(args.t_end, args.repeat, work)
        calls, _ = per_call(work, args.calls)
    native = next(r["us"] for r in rows if r["route"] == "native FMU")
    print(f"Per step: {SCENE.name}, internal map, {args.t_end} s ({rows[0]['steps']} steps, 2 bearings, "
          f"{rows[0]['evals'] / rows[0]['steps']:.2f} evaluations per step), integration only, best of {args.repeat}:\n")
    print("| route | CPU us per step | x native FMU | wall us per step |")
    print("| --- | ---: | ---: | ---: |")
    for r in rows:
        print(f"| {r['route']} | {r['us']:.1f} | {r['us'] / native:.2f} | {r['wall_us']:.1f} |")
    print(f"\nPer FMI call (fmpy's raw ctypes function from Python, one instance, map internal) [CPU us], "
          f"best of 3 x {args.calls // 3}:\n")
    print("| call | Python FMU | native FMU | of the Python FMU's: the slave's Python |")
    print("| --- | ---: | ---: | ---: |")
    for name, py, nat, slave in calls:
        print(f"| {name} | {py:.2f} | {nat:.2f} | {slave:.2f} |")
    print("\nThe Python FMU's call minus the native's is about pythonfmu's C++ layer plus the slave's Python; "
          "from the host's compiled loop (memoryless FMUs) the ctypes share (~1 us a call) is not paid.")


if __name__ == "__main__":
    main()
