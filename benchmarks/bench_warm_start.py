"""Reynolds in transients: the active set's cold start against the warm start, side by side.

Runs the paper scenes (rotor_host/bundled/scenes/paper_22hz.toml, paper_44hz.toml) with the Reynolds
internal called directly (``scene.with_internal("reynolds", via="direct", t_end_s=...)``),
once with every Reynolds instance on the cold start (``warm_start=False``: the start computed
from the inputs, as before the warm start) and once on the warm start (the default), and
prints per scene, over the integration's bearing calls (static equilibrium left out):

* active-set passes (banded Cholesky factorizations) per call, cold and warm;
* in the warm run: calls that took the cold start (a jump, or the first call) and warm starts
  abandoned for the cold start;
* wall time per call inside the solver (force_and_jacobian / force) and of the integration;
* whether the two runs are identical (every recorded array equal bit for bit).

``--window T0`` adds the same figures over the calls at t >= T0 only (e.g. the 44 Hz whirl,
which the journal reaches from about 3.5 s: ``--scenes paper_44hz --t-end 4.2 --window 4.0``).

    .venv/bin/python benchmarks/bench_warm_start.py [--t-end 0.5] [--repeat 1] [--window T0]
"""

from __future__ import annotations

import argparse
import platform
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from bearing_fmu.physics.solver import reynolds as rey  # noqa: E402
from rotor_host.analyses.report import markdown_table  # noqa: E402
from rotor_host.coupling import bearings as brg  # noqa: E402
from rotor_host.integrate import newmark  # noqa: E402
from rotor_host.scenes.run import run_scene  # noqa: E402
from rotor_host.scenes.scene import load_scene

ROOT = Path(__file__).resolve().parents[1]
SCENES = ("paper_22hz", "paper_44hz")


def cpu() -> str:
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
        return next(line.split(":", 1)[1].strip() for line in out.splitlines() if line.startswith("Model name"))
    except Exception:  # noqa: BLE001
        return platform.processor() or "unknown CPU"


class Recorder:
    """While the scene runs: every Reynolds instance the registry builds gets ``warm_start`` set,
    and each of its calls made during Newmark.run is recorded as (t of the step, passes, wall
    time of the call [s], started warm, warm start abandoned). Patches are undone on exit."""

    def __init__(self, warm: bool):
        self.warm = warm
        self.rows: list[tuple[float, int, float, bool, bool]] = []
        self._t = 0.0
        self._active = False
        self._saved = []

    def __enter__(self):
        rec = self
        make = rey.Reynolds.__dict__["from_options"].__func__

        def from_options(cls, params, options, context=None):
            r = make(cls, params, options, context)
            r.warm_start = rec.warm
            for name in ("force", "force_and_jacobian"):
                setattr(r, name, rec._timed(r, getattr(r, name)))
            return r

        begin = brg.BearingSet.begin_step

        def begin_step(self, t, dt):
            rec._t = float(t) + float(dt)
            return begin(self, t, dt)

        run = newmark.Newmark.run

        def integrating(*a, **k):
            rec._active = True
            try:
                return run(*a, **k)
            finally:
                rec._active = False

        self._patch(rey.Reynolds, "from_options", classmethod(from_options))
        self._patch(brg.BearingSet, "begin_step", begin_step)
        self._patch(newmark.Newmark, "run", integrating)
        return self

    def _patch(self, cls, name, new):
        self._saved.append((cls, name, cls.__dict__[name]))
        setattr(cls, name, new)

    def _timed(self, r, fn):
        clock, info, rows = time.perf_counter, r._info, self.rows

        def call(*a):
            t0 = clock()
            out = fn(*a)
            if self._active:
                rows.append((self._t, int(info[3]), clock() - t0, bool(info[4]), bool(info[5])))
            return out
        return call

    def __exit__(self, *exc):
        for cls, name, fn in reversed(self._saved):
            setattr(cls, name, fn)
        return False


def run_once(scene, warm: bool):
    with Recorder(warm) as rec:
        run = run_scene(scene, None)
    if not run.ok:
        raise SystemExit(f"{scene.name}: run failed: {run.meta.get('message')}")
    return run, np.array(rec.rows)


def summary(rows: np.ndarray, t0: float | None = None) -> dict:
    sel = rows if t0 is None else rows[rows[:, 0] >= t0]
    return {"calls": len(sel), "passes": float(sel[:, 1].mean()), "us": 1e6 * float(sel[:, 2].mean()),
            "max_passes": int(sel[:, 1].max()), "cold": int(len(sel) - sel[:, 3].sum()),
            "fallbacks": int(sel[:, 4].sum())}


def identical(a, b) -> bool:
    keys = sorted(a.arrays)
    return keys == sorted(b.arrays) and all(np.array_equal(a.arrays[k], b.arrays[k]) for k in keys)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--t-end", type=float, default=0.5, help="simulated time per run [s] (default 0.5)")
    ap.add_argument("--scenes", nargs="+", default=list(SCENES), choices=SCENES)
    ap.add_argument("--repeat", type=int, default=1, help="runs per start, interleaved; the fastest counts")
    ap.add_argument("--window", type=float, default=None, help="also report the calls at t >= this [s]")
    args = ap.parse_args()
    if args.t_end <= 0 or args.repeat < 1:
        raise SystemExit("--t-end must be > 0 and --repeat >= 1")
    if args.window is not None and not 0 <= args.window < args.t_end:
        raise SystemExit(f"--window must be in [0, --t-end = {args.t_end}), got {args.window}")
    rows = []
    for name in args.scenes:
        scene = load_scene(ROOT / "rotor_host" / "bundled" / "scenes" / f"{name}.toml").with_internal(
            "reynolds", via="direct", t_end_s=args.t_end)
        best = {}
        for _ in range(args.repeat):
            for warm in (False, True):
                run, calls = run_once(scene, warm)
                t = run.meta["integration_time_s"]
                if warm not in best or t < best[warm][0].meta["integration_time_s"]:
                    best[warm] = (run, calls)
        (rc, cc), (rw, cw) = best[False], best[True]
        same = identical(rc, rw)
        for label, t0 in [(f"0-{args.t_end:g} s", None)] + ([(f"{args.window:g}-{args.t_end:g} s", args.window)]
                                                            if args.window is not None else []):
            c, w = summary(cc, t0), summary(cw, t0)
            rows.append({
                "scene": name, "window": label, "calls": c["calls"],
                "p_cold": c["passes"], "p_warm": w["passes"], "max_warm": w["max_passes"],
                "cold_in_warm": w["cold"], "fallbacks": w["fallbacks"],
                "us_cold": c["us"], "us_warm": w["us"], "call_speedup": c["us"] / w["us"],
                "run_cold": rc.meta["integration_time_s"] if t0 is None else float("nan"),
                "run_warm": rw.meta["integration_time_s"] if t0 is None else float("nan"),
                "same": "yes" if same else "NO",
            })
    print(f"bench_warm_start ({time.strftime('%Y-%m-%d')}): Reynolds {rey.DEFAULT_N_THETA} x {rey.DEFAULT_N_X} "
          f"called directly, dt from the scenes, {args.t_end:g} s simulated, fastest of {args.repeat}; "
          f"{cpu()}, {platform.machine()}, Python {platform.python_version()}")
    print(markdown_table(rows, [
        ("scene", "scene", ""), ("window", "calls at t in", ""), ("calls", "bearing calls", "d"),
        ("p_cold", "passes/call cold", ".3f"), ("p_warm", "passes/call warm", ".3f"),
        ("max_warm", "max passes warm", "d"), ("cold_in_warm", "cold starts in warm run", "d"),
        ("fallbacks", "warm starts abandoned", "d"),
        ("us_cold", "us/call cold", ".1f"), ("us_warm", "us/call warm", ".1f"),
        ("call_speedup", "per-call speed-up", ".2f"),
        ("run_cold", "integration cold [s]", ".2f"), ("run_warm", "integration warm [s]", ".2f"),
        ("same", "runs identical", ""),
    ]))


if __name__ == "__main__":
    main()
