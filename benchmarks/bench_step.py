"""Cost of one Newmark step, side by side: the compiled driver, the Python driver, the compiled
floor and (with --before) the integrator of another checkout, on the paper rotor.

    .venv/bin/python benchmarks/bench_step.py [--before DIR] [--steps 2000] [--quick]

Columns, per step [us] (the process's CPU time in ``Newmark.run`` over the timed steps, the best
of REPEATS runs, after a warm-up run that loads every compiled kernel; CPU time, not wall time:
on a shared machine the wall time counts the other processes' turns):

  before    the integrator of the checkout DIR (e.g. ``git archive <commit> | tar -x -C DIR``), run
            in a subprocess on the same problems with the same settings (the dense n x n inverse
            and Python per Newton iteration, before the banded and compiled paths)
  python    this checkout, ``NewmarkConfig(compiled=False)``: the banded step, Python per iteration
  new       this checkout as a scene runs it: compiled chunks of 50 steps (the scene's progress
            calls), every step recorded at the scene's nodes 3, 6, 9; Python driver where the
            internal has no compiled kernel
  floor     the compiled loop alone: one chunk for all steps, nothing recorded but the end

Problems: the paper's 22 Hz scene (weight, 8.5 g at 37 mm on the disk) from its static
equilibrium, dt = 1e-4 s, with the map, Taylor (22 Hz surrogate) and linear internals called
directly; the map case again on the rotor cut into 4, 16, 64 elements per element (44, 164, 644,
2564 DOF), and with 2, 4, 8 map bearings on the 40-element rotor. Then the 44 Hz, 6 s map scene
(rotor_host/bundled/scenes/paper_44hz.toml, --internal map --via direct): its integration time as
``rotor-host run`` reports it (wall) and the CPU time of ``Newmark.run``, the first run of a
process and a second one.

Then the same map case through the scene's native map FMU (fmpy, one instance per bearing):
the Python driver with the FMU state saved and restored around every iterate (what any FMU gets),
the Python driver without (the FMU declares itself memoryless), the compiled loop calling the
FMU's C functions (``rotor_host.coupling.fmu_kernel``; chunks of 50 steps, recorded as "new"),
against the compiled floor of the map called directly (``--only-fmu``: these rows alone).

Then the Reynolds internal (no compiled kernel: the Python driver) against the same solver calls
replayed alone.

Targets (issue 27): map new <= 2 x floor; native FMU compiled <= 2.5 x floor; 644 DOF <= 16 x the
44-DOF step; the 44 Hz scene under 1 s of integration; Reynolds at its floor.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parents[1]
OMEGA = 2 * math.pi * 22.0
G = 9.81


def _root_from_argv() -> Path:
    if "--root" in sys.argv:
        return Path(sys.argv[sys.argv.index("--root") + 1]).resolve()
    return HERE


ROOT = _root_from_argv()
sys.path.insert(0, str(ROOT))

# a size case: (label, elements per element k, number of bearings); an internal case: internal name
SIZES = [(1, 2), (4, 2), (16, 2), (64, 2)]
BEARINGS = [(4, 2), (4, 4), (4, 8)]
INTERNALS = ["map", "taylor", "linear"]
REPEATS = 5  # the best of: the machine is shared


def build_rotor(k: int, n_bearings: int):
    """The paper rotor with each element cut into k; bearings at its two nodes, or n_bearings
    spread over the shaft (the two ends' bearing nodes and evenly between). Built from the
    rotor's parts (works on checkouts without Rotor.refined)."""
    from rotor_host.model.parts import Disk, ShaftElement
    from rotor_host.model.rotor import Rotor

    r = Rotor.from_toml(ROOT / "rotor_host" / "bundled" / "rotor_paper.toml")
    els = [ShaftElement(e.length / k, e.od, e.id) for e in r.elements for _ in range(k)]
    nodes = [nd * k for nd in r.bearing_nodes]
    if n_bearings > 2:
        lo, hi = nodes[0], nodes[-1]
        disk = r.disks[0].node * k
        cand = [int(round(x)) for x in np.linspace(lo, hi, n_bearings + 1)]
        nodes = sorted({nd for nd in cand if nd != disk})[:n_bearings]
        while len(nodes) < n_bearings:  # the disk's node was among them: one more next to an end
            nodes = sorted(set(nodes) | {max(nodes) - 1})
    return Rotor(elements=els, material=r.material, disks=[Disk(d.node * k, d.od, d.id, d.width) for d in r.disks],
                 bearing_nodes=nodes, bearings=[r.bearings[0]] * len(nodes), name="bench")


def internals(name: str, rotor, loads):
    from bearing_fmu.internals import registry
    from bearing_fmu.internals.registry import Context

    opts = {"reynolds": {}, "map": {"map": str(ROOT / "rotor_host" / "bundled" / "maps" / "paper_bearing.json")},
            "taylor": {"surrogate": str(ROOT / "rotor_host" / "bundled" / "surrogates" / "paper_22hz_16.7N.json")},
            "linear": {"linear_from": "map", "map": str(ROOT / "rotor_host" / "bundled" / "maps" / "paper_bearing.json")}}[name]
    return [registry.create(name, p, opts, Context(load=tuple(w), omega=OMEGA, warn=lambda m: None))
            for p, w in zip(rotor.bearings, loads)]


def problem(internal: str, k: int, n_bearings: int):
    """(rotor, f_ext, bearings factory, q0) of a case."""
    from rotor_host.coupling.bearings import DirectBearings
    from rotor_host.scenes.run import static_start

    rotor = build_rotor(k, n_bearings)
    fs = rotor.weight_vector(G)
    disk = rotor.disks[0].node
    unb = [(rotor.dof(disk, "y"), rotor.dof(disk, "z"), 8.5e-3 * 37e-3, 0.0, 0.0)]
    try:
        from rotor_host.integrate.loads import RotatingLoads

        f_ext = RotatingLoads(fs, unb, OMEGA)
    except ImportError:  # an older checkout: the scene's closure
        out = np.empty_like(fs)

        def f_ext(t):
            out[:] = fs
            for iy, iz, mr, ph, t_on in unb:
                a = OMEGA * t + ph
                out[iy] += mr * OMEGA * OMEGA * math.cos(a)
                out[iz] += mr * OMEGA * OMEGA * math.sin(a)
            return out
    pairs = [(rotor.dof(n, "y"), rotor.dof(n, "z")) for n in rotor.bearing_nodes]
    # the bearings' loads: the scene's way (the rotor pinned at its bearings), for the linear internal
    fixed = [d for p in pairs for d in p]
    free = np.setdiff1d(np.arange(rotor.n_dof), fixed)
    qp = np.zeros(rotor.n_dof)
    qp[free] = np.linalg.solve(rotor.K[np.ix_(free, free)], fs[free])
    loads = -(rotor.K @ qp - fs)[fixed].reshape(-1, 2)
    ints = internals(internal, rotor, loads)

    def bearings():
        return DirectBearings(ints, pairs, OMEGA)

    try:  # the scene's static start (short-bearing guess, then the rotor's equilibrium)
        q0 = static_start(rotor, fs, loads, bearings(), OMEGA)
    except Exception:  # noqa: BLE001 - many bearings may not settle from that guess: start centred
        q0 = np.zeros(rotor.n_dof)
    return rotor, f_ext, bearings, q0


def time_run(rotor, f_ext, bearings, q0, n_steps, mode):
    """Wall time per step [us] of Newmark.run in ``mode`` (before/python/new/floor), the best
    of REPEATS runs, and the force evaluations per step."""
    from rotor_host.integrate.newmark import Newmark, NewmarkConfig

    kw = {} if mode == "before" else {"compiled": mode != "python"}
    rec = [rotor.dof(nd, d) for nd in (2, rotor.disks[0].node, rotor.n_nodes - 3) for d in ("y", "z")]
    if mode == "floor":
        run_kw = dict(record_every=n_steps, record_dofs=rec[:1], progress_every=n_steps)
    else:
        run_kw = dict(record_every=1, record_dofs=rec, progress=lambda t: None, progress_every=50)
    dt = 1e-4
    Newmark(rotor.M, rotor.K, rotor.C, rotor.G, OMEGA, f_ext, bearings(), NewmarkConfig(**kw)).run(
        q0, np.zeros(rotor.n_dof), 0.0, 10 * dt, dt, **run_kw)  # warm-up: every kernel loaded
    best = math.inf
    res = None
    for _ in range(REPEATS):
        integ = Newmark(rotor.M, rotor.K, rotor.C, rotor.G, OMEGA, f_ext, bearings(), NewmarkConfig(**kw))
        t = time.process_time()
        res = integ.run(q0, np.zeros(rotor.n_dof), 0.0, n_steps * dt, dt, **run_kw)
        best = min(best, time.process_time() - t)
    return 1e6 * best / n_steps, float(res.mean_iterations)


def cases(quick: bool):
    out = [("internal", name, 1, 2) for name in INTERNALS]
    out += [("size", "map", k, nb) for k, nb in SIZES if not (quick and k > 16)]
    out += [("bearings", "map", k, nb) for k, nb in BEARINGS]
    return out


def measure(modes, n_steps, quick):
    """{case key: {mode: (us per step, evaluations per step)}}."""
    table = {}
    for kind, name, k, nb in cases(quick):
        key = f"{kind}:{name}:{k}:{nb}"
        rotor, f_ext, bearings, q0 = problem(name, k, nb)
        steps = max(50, min(n_steps, int(n_steps * 44 / rotor.n_dof)) if k > 4 else n_steps)
        table[key] = {}
        for mode in modes:
            table[key][mode] = time_run(rotor, f_ext, bearings, q0, steps, mode)
    return table


def native_fmu_rows(n_steps: int) -> dict:
    """The map case (paper rotor, 2 bearings) through the scene's native map FMU (fmpy, one
    instance per bearing), per step [us] and evaluations per step: {mode: (us, evals)} for the
    Python driver with the FMU state saved and restored around every iterate (any FMU), the
    Python driver without (the FMU is memoryless), the compiled loop calling the FMU (as a scene
    runs it), and the compiled floor of the same problem called directly."""
    import dataclasses
    import tempfile

    from rotor_host.scenes import bearings as scene_bearings, run as scene_run
    from rotor_host.scenes.scene import load_scene

    rotor, f_ext, direct, q0 = problem("map", 1, 2)
    sc = dataclasses.replace(load_scene(ROOT / "rotor_host" / "bundled" / "scenes" / "paper_22hz.toml"), internal="map", via="fmu",
                             fmu_kind="native")
    sc = sc.with_internal("map", options={"map": {"map": str(ROOT / "rotor_host" / "bundled" / "maps" / "paper_bearing.json")}})
    loads = scene_run.bearing_loads(rotor, rotor.weight_vector(G))
    work = Path(tempfile.mkdtemp(prefix="bench_step_"))
    opened = []

    def fmus(memoryless):
        def make():
            b = scene_bearings.build_bearings(sc, rotor, loads, work)
            b.memoryless = memoryless and b.memoryless
            opened.append(b)
            return b
        return make

    try:
        out = {"python, save/restore": time_run(rotor, f_ext, fmus(False), q0, n_steps, "python"),
               "python, memoryless": time_run(rotor, f_ext, fmus(True), q0, n_steps, "python"),
               "compiled": time_run(rotor, f_ext, fmus(True), q0, n_steps, "new"),
               "floor (direct)": time_run(rotor, f_ext, direct, q0, n_steps, "floor")}
    finally:
        for b in opened:
            b.close()
    return out


class Recorded:
    """An internal whose force_and_jacobian calls are logged (their arguments, in order)."""

    def __init__(self, inner, log: list):
        self.inner, self.log = inner, log

    def force_and_jacobian(self, *args):
        self.log.append(args)
        return self.inner.force_and_jacobian(*args)

    def __getattr__(self, name):
        return getattr(self.inner, name)


def reynolds_row(n_steps: int) -> tuple[float, float, float]:
    """The Reynolds internal (default grid, paper rotor, 2 bearings, Python driver: it has no
    compiled kernel): (per step [us], evaluations per step, its floor [us]): the floor is the same
    solver calls (the run's own, logged, warm start and all) replayed on fresh internals in a plain
    loop, so step - floor is what the driver costs around them."""
    from rotor_host.coupling.bearings import DirectBearings
    from rotor_host.integrate.newmark import Newmark, NewmarkConfig

    rotor, f_ext, _, q0 = problem("reynolds", 1, 2)
    pairs = [(rotor.dof(n, "y"), rotor.dof(n, "z")) for n in rotor.bearing_nodes]
    loads = [(0.0, 0.0)] * 2
    dt, best, floor, evals = 1e-4, math.inf, math.inf, 0.0
    for _ in range(REPEATS):
        logs = [[], []]
        fresh = internals("reynolds", rotor, loads)
        integ = Newmark(rotor.M, rotor.K, rotor.C, rotor.G, OMEGA, f_ext,
                        DirectBearings([Recorded(i, lg) for i, lg in zip(fresh, logs)], pairs, OMEGA), NewmarkConfig())
        t = time.process_time()
        res = integ.run(q0, np.zeros(rotor.n_dof), 0.0, n_steps * dt, dt, record_every=1,
                        record_dofs=[rotor.dof(2, "y")], progress=lambda t: None, progress_every=50)
        best = min(best, time.process_time() - t)
        evals = float(res.mean_iterations)
        again = internals("reynolds", rotor, loads)
        t = time.process_time()
        for internal, log in zip(again, logs):
            for args in log:
                internal.force_and_jacobian(*args)
        floor = min(floor, time.process_time() - t)
    return 1e6 * best / n_steps, evals, 1e6 * floor / n_steps


def scene_44hz(root: Path) -> list[float]:
    """[integration time [s] (wall, as reported), CPU time [s] of Newmark.run, evaluations per
    step] of the 44 Hz 6 s map scene, run twice in one process."""
    code = ("import sys, dataclasses, json, time; sys.path.insert(0, sys.argv[1]);"
            "from rotor_host.scenes.scene import load_scene; from rotor_host.scenes.run import run_scene;"
            "from rotor_host.integrate.newmark import Newmark; cpu = [];"
            "run = Newmark.run\n"
            "def timed(self, *a, **k):\n"
            "    t = time.process_time(); r = run(self, *a, **k); cpu.append(time.process_time() - t); return r\n"
            "Newmark.run = timed\n"
            "sc = dataclasses.replace(load_scene(sys.argv[1] + '/rotor_host/bundled/scenes/paper_44hz.toml'), internal='map',"
            " via='direct'); out = [run_scene(sc, None).meta for _ in range(2)];"
            "print(json.dumps([[m['integration_time_s'], c, m['newton_mean_evaluations_per_step']]"
            " for m, c in zip(out, cpu)]))")
    env = dict(os.environ, PYTHONPATH=str(root))
    r = subprocess.run([sys.executable, "-c", code, str(root)], capture_output=True, text=True, env=env)
    if r.returncode:
        raise RuntimeError(r.stderr[-2000:])
    return json.loads(r.stdout.strip().splitlines()[-1])


def fmt(x):
    return f"{x:9.1f}" if x is not None else "        -"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--before", type=Path, help="another checkout to measure side by side (its integrator)")
    ap.add_argument("--steps", type=int, default=2000, help="timed steps of a 44-DOF case (fewer for big rotors)")
    ap.add_argument("--quick", action="store_true", help="leave out the 2564-DOF rotor")
    ap.add_argument("--no-fmu", action="store_true", help="leave out the native FMU routes")
    ap.add_argument("--only-fmu", action="store_true", help="the native FMU routes alone")
    ap.add_argument("--no-scene", action="store_true", help="leave out the 44 Hz scene")
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--root", type=Path, help=argparse.SUPPRESS)
    a = ap.parse_args(argv)
    if a.worker:
        print(json.dumps(measure(["before"], a.steps, a.quick)))
        return
    import platform

    print(f"# bench_step: {time.strftime('%Y-%m-%d %H:%M')}, {platform.processor() or platform.machine()}, "
          f"{os.cpu_count()} cores, load {os.getloadavg()[0]:.1f}")
    before = {}
    if a.before:
        env = dict(os.environ, PYTHONPATH=str(a.before.resolve()))
        r = subprocess.run([sys.executable, __file__, "--worker", "--root", str(a.before.resolve()), "--steps",
                            str(a.steps)] + (["--quick"] if a.quick else []), capture_output=True, text=True, env=env)
        if r.returncode:
            raise SystemExit(f"--before {a.before}: the worker failed:\n{r.stderr[-3000:]}")
        before = json.loads(r.stdout.strip().splitlines()[-1])
    from bearing_fmu.internals import registry

    if a.only_fmu:
        a.no_scene = True
    table = {} if a.only_fmu else measure(["python", "new", "floor"], a.steps, a.quick)
    if table:
        print("\n| case | DOF | bearings | evals/step | before [us] | python [us] | new [us] | floor [us] | "
              "new/floor | before/new |")
        print("|---|---|---|---|---|---|---|---|---|---|")
    base = {}
    for key, row in table.items():
        kind, name, k, nb = key.split(":")
        k, nb = int(k), int(nb)
        compiled = registry.get(name).can.compiled
        b = before.get(key, {}).get("before", (None, None))[0]
        py, ev = row["python"]
        new = row["new"][0]
        floor = row["floor"][0] if compiled else None
        dof = 4 * (10 * k + 1)
        if kind != "internal" and nb == 2:
            base[dof] = (b, new)
        print(f"| {kind} {name} | {dof} | {nb} | {ev:.2f} | {fmt(b)} | {fmt(py)} | {fmt(new)} | {fmt(floor)} | "
              f"{(new / floor if floor else math.nan):.2f} | {(b / new if b else math.nan):.1f} |")
    if 44 in base:
        print("\nscaling with the rotor's size (map, 2 bearings), per step relative to 44 DOF:")
        for dof, (b, new) in sorted(base.items()):
            rb = f"{b / base[44][0]:.1f}" if b and base[44][0] else "-"
            print(f"  {dof:5d} DOF: before {rb:>6} x, new {new / base[44][1]:6.1f} x")
    if not a.only_fmu:
        step, ev, floor = reynolds_row(max(50, a.steps // 10))
        print(f"\nreynolds (default grid, Python driver): {step:.1f} us per step, {ev:.2f} evals/step; the same "
              f"solver calls replayed alone {floor:.1f} us: {step / floor:.3f} x its floor")
    if not a.no_fmu:
        rows = native_fmu_rows(a.steps)
        floor = rows["floor (direct)"][0]
        print("\nnative map FMU (fmpy, 2 instances), paper 22 Hz scene, per step against the compiled floor of "
              "the map called directly:\n")
        print("| route | evals/step | per step [us] | / floor |")
        print("|---|---|---|---|")
        for mode, (us, ev) in rows.items():
            print(f"| {mode} | {ev:.2f} | {fmt(us)} | {us / floor:.2f} |")
    if not a.no_scene:
        print("\n44 Hz 6 s map scene (direct), integration time (wall) / CPU time of Newmark.run [s], the first "
              "run of a process, then a second:")
        if a.before:
            print("  before: " + ", ".join(f"{t:.2f} / {c:.2f} s ({ev:.3f} evals/step)" for t, c, ev in
                                           scene_44hz(a.before)))
        print("  new:    " + ", ".join(f"{t:.2f} / {c:.2f} s ({ev:.3f} evals/step)" for t, c, ev in scene_44hz(HERE)))


if __name__ == "__main__":
    main()
