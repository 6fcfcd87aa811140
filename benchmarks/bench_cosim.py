"""Host with bearing FMUs vs the same internal called directly, measured side by side.

Runs the paper's 22 Hz scene (rotor_host/bundled/scenes/paper_22hz.toml) for a short span with each
internal, once through the FMUs (fmpy, conformant state-restore iterations) and once
in-process, and prints the run-time ratio FMU / direct and the FMI overhead per bearing
evaluation. Integration time only (setup: FMU build, load, numba cache, equilibrium apart).
Each run's step is also split into the bearings' evaluations (FMI calls and the internal),
the per-step bearing bookkeeping (begin/accept: the FMU state saved and freed) and the rest,
the integrator's own work (timers around those methods during the integration only).

    .venv/bin/python benchmarks/bench_cosim.py [--t-end 0.2]
"""

from __future__ import annotations

import argparse
import platform
import subprocess
import tempfile
import time
from pathlib import Path

from rotor_host.analyses.report import markdown_table
from rotor_host.scenes.run import run_scene
from rotor_host.scenes.scene import load_scene

ROOT = Path(__file__).resolve().parents[1]


def cpu() -> str:
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
        return next(line.split(":", 1)[1].strip() for line in out.splitlines() if line.startswith("Model name"))
    except Exception:  # noqa: BLE001
        return platform.processor() or "unknown CPU"


class StepSplit:
    """Seconds spent in the bearing set's methods while Newmark.run integrates (the methods
    patched on their classes for the duration; nested calls, e.g. super(), count once)."""

    GROUPS = {"evaluate": "evaluate", "begin_step": "step", "accept_step": "step", "reject_step": "step"}

    def __enter__(self):
        from rotor_host.coupling.bearings import BearingSet, DirectBearings
        from rotor_host.coupling.cosim import FMUBearings
        from rotor_host.integrate.newmark import Newmark

        self.acc = {"evaluate": 0.0, "step": 0.0}
        self._depth = 0
        self._active = False
        self._saved = []
        for cls in (BearingSet, DirectBearings, FMUBearings):
            for name, group in self.GROUPS.items():
                if name in cls.__dict__:
                    self._patch(cls, name, self._timed(cls.__dict__[name], group))
        self._patch(Newmark, "run", self._integrating(Newmark.__dict__["run"]))
        return self

    def _patch(self, cls, name, new):
        self._saved.append((cls, name, cls.__dict__[name]))
        setattr(cls, name, new)

    def _timed(self, fn, group):
        clock = time.perf_counter

        def timed(*a, **k):
            if not self._active or self._depth:
                return fn(*a, **k)
            self._depth += 1
            t0 = clock()
            try:
                return fn(*a, **k)
            finally:
                self.acc[group] += clock() - t0
                self._depth -= 1
        return timed

    def _integrating(self, fn):
        def run(*a, **k):
            self._active = True
            try:
                return fn(*a, **k)
            finally:
                self._active = False
        return run

    def __exit__(self, *exc):
        for cls, name, fn in reversed(self._saved):
            setattr(cls, name, fn)
        return False


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--t-end", type=float, default=0.2)
    ap.add_argument("--repeat", type=int, default=2, help="runs per case, the fastest counts")
    args = ap.parse_args()
    base = load_scene(ROOT / "rotor_host" / "bundled" / "scenes" / "paper_22hz.toml")
    base.t_end_s = args.t_end
    internals = ["reynolds", "linear"]
    if base.surrogate and base.surrogate.is_file():
        internals.append("taylor")
    rows, splits = [], []
    with tempfile.TemporaryDirectory() as tmp:
        for internal in internals:
            times = {}
            for via in ("direct", "fmu"):
                s = base.with_internal(internal, via=via)
                best = None
                for _ in range(args.repeat):
                    with StepSplit() as split:
                        run = run_scene(s, work_dir=Path(tmp))
                    m = dict(run.meta, split=dict(split.acc))
                    if best is None or m["integration_time_s"] < best["integration_time_s"]:
                        best = m
                times[via] = best
                steps = best["steps"]
                ev, st = best["split"]["evaluate"], best["split"]["step"]
                splits.append({"internal": internal, "via": via, "us_step": 1e6 * best["integration_time_s"] / steps,
                               "eval": 1e6 * ev / steps, "step": 1e6 * st / steps,
                               "host": 1e6 * (best["integration_time_s"] - ev - st) / steps,
                               "per_eval": 1e6 * ev / (best["force_evaluations"] * 2)})
            d, f = times["direct"], times["fmu"]
            evals = f["force_evaluations"] * 2  # two bearings
            rows.append({
                "internal": internal, "steps": f["steps"], "evals": f["newton_mean_evaluations_per_step"],
                "direct": d["integration_time_s"], "fmu": f["integration_time_s"],
                "ratio": f["integration_time_s"] / d["integration_time_s"],
                "overhead_us": 1e6 * (f["integration_time_s"] - d["integration_time_s"]) / evals,
                "us_step": 1e6 * f["integration_time_s"] / f["steps"],
            })
    print(f"bench_cosim: paper_22hz, {args.t_end} s simulated at dt = {base.dt_s} s; {cpu()}, "
          f"{platform.machine()}, Python {platform.python_version()}")
    print(markdown_table(rows, [
        ("internal", "internal", ""), ("steps", "steps", "d"), ("evals", "evaluations/step", ".2f"),
        ("direct", "direct [s]", ".3f"), ("fmu", "FMU [s]", ".3f"), ("ratio", "FMU / direct", ".2f"),
        ("overhead_us", "FMI overhead per bearing evaluation [us]", ".1f"), ("us_step", "FMU us/step", ".0f"),
    ]))
    print("\nWhere a step goes [us per step; per bearing evaluation in the last column]:")
    print(markdown_table(splits, [
        ("internal", "internal", ""), ("via", "via", ""), ("us_step", "step", ".1f"),
        ("eval", "bearing evaluations", ".1f"), ("step", "bearing begin/accept", ".1f"),
        ("host", "integrator (the rest)", ".1f"), ("per_eval", "one bearing evaluation", ".1f"),
    ]))


if __name__ == "__main__":
    main()
