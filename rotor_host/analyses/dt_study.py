"""Time-step study: halve dt until the bearing orbit stops changing.

A scene is run at dt, dt/2, dt/4, ... with one internal (called directly: the FMU gives the
same numbers to round-off, tests/test_cosim.py). After each halving the bearing journal
orbits of the two runs are compared at the coarser run's output times; the study stops when
the change is below ``tol_pct_cr`` (1 % of the radial clearance, RMS and max both reported;
the test uses the max) or after ``halvings``. Each row keeps the Newton statistics and the
run's status, so a case that does not converge is reported with its diagnosis.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from bearing_fmu.io.interrupts import as_interrupted, note_kept
from bearing_fmu.io.outputs import ensure_writable, write_json, write_text

from ..scenes.run import run_scene
from ..scenes.scene import load_scene
from .report import markdown_table


def orbit_change(coarse: dict, fine: dict) -> tuple[float, float]:
    """(RMS, max) over time and bearings of |journal(fine) - journal(coarse)| / CR in %, at
    the coarse run's times (fine values at those times taken from the fine grid; dt halved,
    so they coincide) up to where both runs got."""
    t_c, t_f = coarse["t"], fine["t"]
    n = int(np.searchsorted(t_c, t_f[-1] + 1e-12))  # coarse times the fine run reached
    idx = np.searchsorted(t_f, t_c[:n] - 1e-12)
    idx = np.minimum(idx, len(t_f) - 1)
    b = [list(coarse["nodes"]).index(k) for k in coarse["bearing_nodes"]]
    dy = fine["y"][idx][:, b] - coarse["y"][:n][:, b]
    dz = fine["z"][idx][:, b] - coarse["z"][:n][:, b]
    d = np.hypot(dy, dz) / np.asarray(coarse["CR"])
    return 100 * float(np.sqrt(np.mean(d**2))), 100 * float(d.max())


@dataclass
class DtStudy:
    scene: str
    internal: str
    t_end_s: float
    tol_pct_cr: float
    rows: list[dict] = field(default_factory=list)
    converged_dt: float | None = None

    def table(self) -> str:
        return markdown_table(self.rows, [
            ("dt_s", "dt [s]", ".3g"), ("steps", "steps", "d"), ("status", "status", ""),
            ("change_rms", "orbit change vs dt*2, RMS [% CR]", ".3f"),
            ("change_max", "max [% CR]", ".3f"), ("evals_mean", "evals/step", ".2f"),
            ("evals_max", "max evals/step", "d"), ("cuts", "step cuts", "d"),
            ("max_ecc", "max ecc.", ".3f"), ("wall_s", "run time [s]", ".1f"),
        ])


def dt_study(scene_path, internal: str = "reynolds", dt: float | None = None, t_end: float | None = None,
             halvings: int = 3, tol_pct_cr: float = 1.0, progress: bool = False, log=print,
             out_dir=None) -> DtStudy:
    """The study (see the module docstring); with ``out_dir`` each run is kept there
    (``dtstudy_<scene>_<internal>_<k>.npz/.json``). An interrupt is raised again with the rows
    done so far as its ``study`` attribute."""
    base = load_scene(scene_path)
    dt = base.dt_s if dt is None else dt  # None: the scene's (0 is a value, refused by the scene's checks)
    t_end = base.t_end_s if t_end is None else t_end
    study = DtStudy(Path(scene_path).name, internal, t_end, tol_pct_cr)
    prev = None
    for k in range(halvings + 1):
        h = dt / 2**k
        scene = base.with_internal(internal, via="direct", dt_s=h, t_end_s=t_end)
        log(f"{study.scene} [{internal}] dt = {h:.3g} s ...")
        try:
            run = run_scene(scene, out_dir, progress=progress,
                            stem=f"dtstudy_{Path(scene_path).stem}_{internal}_{k}")
        except KeyboardInterrupt as exc:
            exc.study = study
            raise
        m = run.meta
        row = {"dt_s": h, "steps": m["steps"], "status": m["status"] + (", crossed clearance" if m["crossed_clearance"] else ""),
               "message": m["message"], "evals_mean": m["newton_mean_evaluations_per_step"],
               "evals_max": m["newton_max_evaluations_per_step"], "cuts": m["step_cuts"],
               "max_ecc": max(m["max_eccentricity"]) if m["max_eccentricity"] else None,
               "wall_s": m["integration_time_s"], "t_reached_s": m["t_reached_s"],
               "change_rms": None, "change_max": None}
        if prev is not None and len(run.arrays["t"]) > 1:
            row["change_rms"], row["change_max"] = orbit_change(prev, run.arrays)
        study.rows.append(row)
        log(f"  {row['status']}: change {row['change_rms']} / {row['change_max']} % CR, "
            f"{row['evals_mean']:.2f} evals/step, {row['cuts']} cuts" + (f"; {m['message']}" if m["message"] else ""))
        # A run through the bearing wall (the linear model) is not a converged answer, however
        # little it changes with dt: it is reported, and the study goes on to its halvings.
        if (row["change_max"] is not None and row["change_max"] < tol_pct_cr and m["status"] == "ok"
                and not m["crossed_clearance"]):
            study.converged_dt = study.rows[-2]["dt_s"]
            break
        prev = run.arrays
    return study



def command(*, scene, internal: str = "reynolds", dt: float | None = None, t_end: float | None = None, halvings: int =
            3, tol: float = 1.0, out="out", quiet: bool = False) -> int:
    """``rotor-host dt-study``: halve dt from ``dt`` (the scene's) until the orbit changes by less than
    ``tol`` [% CR]; writes dtstudy_<scene>_<internal>.md/.json into ``out``; 0 when converged."""
    out = ensure_writable(out)
    stem = f"dtstudy_{Path(scene).stem}_{internal}"
    try:
        study = dt_study(scene, internal, dt, t_end, halvings, tol,
                         progress=not quiet, out_dir=out)
    except KeyboardInterrupt as exc:
        if getattr(exc, "study", None) is not None:
            _write(exc.study, out, stem, f"interrupted by {as_interrupted(exc).signal_name}: the rows above "
                                         "are the runs that finished")
            note_kept(exc, f"{out / f'{stem}.md'} ({len(exc.study.rows)} finished run(s))")
        raise
    verdict = (f"converged: dt = {study.converged_dt:g} s changes the orbit by less than {study.tol_pct_cr:g} % CR "
               "when halved" if study.converged_dt else
               "not converged: the orbit crosses the clearance circle (a model failure no dt fixes)"
               if study.rows and all("crossed clearance" in r["status"] for r in study.rows) else
               f"not converged to {study.tol_pct_cr:g} % CR within the halvings")
    print(_write(study, out, stem, verdict, _inputs(scene, internal)))
    return 0 if study.converged_dt else 1


def _inputs(scene, internal: str) -> str:
    """The inputs line of the scene file ``scene`` run with ``internal``."""
    from .computed_for import scene_line

    return scene_line(load_scene(scene).with_internal(internal))


def _write(study: DtStudy, out: Path, stem: str, verdict: str, inputs: str = "") -> str:
    text = (f"# dt study: {study.scene} [{study.internal}], {study.t_end_s:g} s\n\n"
            + (f"Computed for: {inputs}\n\n" if inputs else "") + f"{study.table()}\n\n{verdict}\n")
    write_text(out / f"{stem}.md", text)
    write_json(out / f"{stem}.json", {**asdict(study), "verdict": verdict})
    return text


__all__ = ["orbit_change", "dt_study", "DtStudy", "command"]
