"""The main job at its floor: each row's integration against the sum of its kernels' own time.

For each row of `rotor-host paper` (the 22 Hz and 44 Hz scenes: Reynolds at its default grid,
the force map, the Taylor surrogate, the linear model) this runs, side by side in one process:

  python FMU   the row through the Python FMU (pythonfmu) and the Python driver: the main job
               before issue 37
  native FMU   the row as the main job runs it now: its native FMU, iterated by the compiled loop
  direct       `rotor-host run <scene> --via direct`: the internal called in-process, by the
               compiled loop where the internal has a compiled kernel (Reynolds' full bore too)
  direct, Python driver   the same through the integrator's Python driver (NewmarkConfig
               compiled=False): one Python call per evaluation, as the Reynolds row's direct
               route was before its kernel ran in the compiled loop
  kernels      the same FMU calls alone: every evaluation of the native run (its inputs and step
               times, recorded through the Python driver, which makes the same calls) replayed
               through the same compiled kernels (setReal, doStep, getReal and the FMU state's
               save and restore where the FMU has one) in one compiled loop, nothing else
  direct kernels   the same for the direct route: its evaluations replayed through the
               internal's compiled kernel (Reynolds: the solver's kernel on the instance's own
               arrays, its warm start carried from call to call as in the run)

and prints the integration time of each (the min of ``--repeats``), per step, and the ratios
native / kernels and direct / direct kernels (what the integrator adds to its kernels), the
Python driver / the compiled one, and native / direct.

    PYTHONPATH=$PWD python benchmarks/main_job_floor.py [--t-end 0.5] [--repeats 3] [--skip-python] [--rows reynolds]

--t-end shortens both scenes (default 0.5 s; the main job's own lengths: --t-end 0).
"""

from __future__ import annotations

import argparse
import os
import platform
import time
from datetime import date
from pathlib import Path

import numpy as np
from numba import njit

from bearing_fmu.internals.compiled import OUT_SIZE, address, advance, kernel_at
from bearing_fmu.surrogates.surrogate import load_surrogate
from rotor_host.analyses.compare import PYTHON_FMU, paper_variants
from rotor_host.coupling.cosim import FMUBearings
from rotor_host.integrate.newmark import Newmark, NewmarkConfig
from rotor_host.model.rotor import Rotor
from rotor_host.scenes import bearings as scene_bearings, run as scene_run
from rotor_host.scenes.scene import G, load_scene, required_file

SCENES = Path(__file__).resolve().parents[1] / "rotor_host" / "bundled" / "scenes"
# what the times are: the CPU time of this thread (a shared machine's load barely moves it; the FMUs
# and kernels run in this thread) or the wall time
CLOCKS = {"cpu": time.thread_time, "wall": time.perf_counter}
CLOCK = [time.thread_time]


@njit(cache=True)
def _replay(kaddr, data, doff, states, clock, out):
    """Every recorded evaluation (k, t, h, y, z, vy, vz, omega) through bearing k's kernel."""
    base = address(data.ctypes.data)
    op = address(out.ctypes.data)
    bad = 0
    for i in range(states.shape[0]):
        b = int(states[i, 0])
        clock[0] = states[i, 1]
        clock[1] = states[i, 2]
        kernel = kernel_at(kaddr[b])
        bad += kernel(advance(base, doff[b]), states[i, 3], states[i, 4], states[i, 5], states[i, 6], states[i, 7], op)
    return bad


def _run_time(scene) -> tuple[float, int]:
    run = scene_run.run_scene(scene, None)
    return run.meta["integration_time_s"], run.meta["steps"]


def _integrate(scene, record: bool = False, compiled: bool = True):
    """The scene's integration through its bearings (native FMUs, or the internals in-process);
    the Python driver when ``record`` (every evaluation's inputs and step kept) or not
    ``compiled``; returns (states, integration time [s]: CPU of this thread (``--clock cpu``) or
    wall, steps, the NewmarkResult)."""
    rotor = Rotor.from_toml(scene.rotor_path)
    fs = rotor.weight_vector(G) + rotor.point_load_vector(scene.static_loads)
    loads = scene_run.bearing_loads(rotor, fs)
    states = []
    with scene_bearings.build_bearings(scene, rotor, loads, None) as b:
        q0 = scene_run.initial_state(scene, rotor, fs, loads, b)
        if record:
            inner = b._bearing

            def bearing(k, y, z, vy, vz):
                states.append((k, b.t, getattr(b, "_h", b.dt), y, z, vy, vz, b.omega))
                return inner(k, y, z, vy, vz)

            b._bearing = bearing
        integ = Newmark(rotor.M, rotor.K, rotor.C, rotor.G, scene.omega, scene_run.external_force(scene, rotor, fs), b,
                        NewmarkConfig(alpha=scene.alpha, tangent=scene.newton_tangent,
                                      compiled=compiled and not record))
        c0 = CLOCK[0]()
        res = integ.run(q0, np.zeros(rotor.n_dof), 0.0, scene.t_end_s, scene.dt_s)
        spent = CLOCK[0]() - c0
    return np.array(states), spent, res.iterations.size, res


def kernels_time(scene, states: np.ndarray, repeats: int) -> float:
    """The recorded evaluations replayed through fresh instances' compiled kernels: min of repeats [s]."""
    rotor = Rotor.from_toml(scene.rotor_path)
    fs = rotor.weight_vector(G) + rotor.point_load_vector(scene.static_loads)
    loads = scene_run.bearing_loads(rotor, fs)
    best = np.inf
    for _ in range(repeats):
        with scene_bearings.build_bearings(scene, rotor, loads, None) as b:
            scene_run.initial_state(scene, rotor, fs, loads, b)  # the instances as the run has them
            plan = b.compiled()
            if plan is None:
                return np.nan  # no compiled kernel (a bore whose kernel runs from Python)
            forces = plan[0]
            clock = plan[2] if len(plan) > 2 else np.zeros(2)
            if len(plan) > 3:
                plan[3][0]()  # enter: the FMU instances handed to the compiled side
            kaddr = np.array([cf.address for cf in forces], dtype=np.int64)
            data = np.ascontiguousarray(np.concatenate([cf.data for cf in forces]))
            doff = np.cumsum([0] + [cf.data.size for cf in forces])[:-1].astype(np.int64)
            out = np.zeros(OUT_SIZE)
            _replay(kaddr, data, doff, states[:0], clock, out)  # loaded before the clock
            t0 = CLOCK[0]()
            bad = _replay(kaddr, data, doff, states, clock, out)
            best = min(best, CLOCK[0]() - t0)
            if bad:
                raise RuntimeError(f"{scene.name}: {bad} replayed evaluations refused")
    return best


def _check_direct(names, t_end: float, rows=None) -> None:
    """Each row's direct run by the compiled loop against the Python driver: the largest
    difference of their states [m, m/s] and forces [N] (0: the same to the bit), and their
    force evaluations."""
    for name in names:
        scene = load_scene(SCENES / f"{name}.toml")
        for internal in rows or ("reynolds", "map", "taylor", "linear"):
            s = scene.with_internal(internal, via="direct", t_end_s=t_end)
            a, b = _integrate(s)[3], _integrate(s, compiled=False)[3]
            d = [float(np.max(np.abs(x - y))) for x, y in ((a.q, b.q), (a.v, b.v), (a.f_nl, b.f_nl))]
            print(f"{name} {internal} direct, compiled loop - Python driver: q {d[0]:.3g} m, v {d[1]:.3g} m/s, "
                  f"f {d[2]:.3g} N; evaluations {a.n_evaluations} and {b.n_evaluations}", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--t-end", type=float, default=0.5, help="simulated time of both scenes [s]; 0: the scenes' own")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--skip-python", action="store_true", help="no Python FMU column (the slowest)")
    ap.add_argument("--scenes", nargs="+", default=["paper_22hz", "paper_44hz"], help="of the bundled scenes")
    ap.add_argument("--rows", nargs="+", default=None, help="only the rows of these internals (reynolds map ...)")
    ap.add_argument("--clock", choices=tuple(CLOCKS), default="cpu",
                    help="the times: this thread's CPU time (default) or the wall time")
    ap.add_argument("--check", action="store_true",
                    help="also: each direct row's forces, compiled loop against the Python driver (to the bit)")
    ap.add_argument("--check-scenes", nargs="+", default=None, help="the scenes --check runs (default: --scenes)")
    args = ap.parse_args()
    CLOCK[0] = CLOCKS[args.clock]
    load = os.getloadavg()
    print(f"# main job floor, {date.today()}, {platform.machine()} {os.cpu_count()} CPUs, load at start "
          f"{load[0]:.2f} {load[1]:.2f} {load[2]:.2f}; min of {args.repeats}; times = integration only "
          f"({args.clock} time) [s]")
    print("| scene | row | steps | python FMU | native FMU | direct, Python driver | direct | kernels alone "
          "| direct kernels alone | native / kernels | direct / direct kernels | Python driver / direct "
          "| native / direct | python / native |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for name in args.scenes:
        scene = load_scene(SCENES / f"{name}.toml")
        if args.t_end:
            scene = scene.with_internal(scene.internal, t_end_s=args.t_end)
        ref, variants = paper_variants(scene, load_surrogate(required_file(scene, "taylor", "surrogate")))
        for v in [ref, *variants]:
            if v.label.endswith(PYTHON_FMU) or (args.rows and v.internal not in args.rows):
                continue
            native = v.scene(scene)
            direct = native.with_internal(v.internal, via="direct")
            routes = {"native": native, "direct": direct}
            if not args.skip_python:
                routes["python"] = native.with_internal(v.internal, fmu_kind="python")
            for s in routes.values():  # load and compile once, outside the clocks
                _run_time(s.with_internal(v.internal, t_end_s=10 * s.dt_s))
            routes["driver"] = direct
            times = {k: np.inf for k in routes}
            steps = 0
            for _ in range(args.repeats):  # side by side: every route once per round
                for k, s in routes.items():
                    _states, t, steps, _res = _integrate(s, compiled=k != "driver")
                    times[k] = min(times[k], t)
            tk = kernels_time(native, _integrate(native, record=True)[0], args.repeats)
            tkd = kernels_time(direct, _integrate(direct, record=True)[0], args.repeats)
            py = times.get("python", np.nan)
            print(f"| {scene.name} | {v.label} | {steps} | {py:.3f} | {times['native']:.3f} | {times['driver']:.3f} "
                  f"| {times['direct']:.3f} | {tk:.3f} | {tkd:.3f} | {times['native'] / tk:.2f} "
                  f"| {times['direct'] / tkd:.2f} | {times['driver'] / times['direct']:.2f} "
                  f"| {times['native'] / times['direct']:.2f} | {py / times['native']:.1f} |", flush=True)
    if args.check:
        _check_direct(args.check_scenes or args.scenes, args.t_end or 0.05, args.rows)
    load = os.getloadavg()
    print(f"\nload at end {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}")


if __name__ == "__main__":
    main()
