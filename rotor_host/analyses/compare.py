"""Error against run time: one scene run with several internals, each measured against a
Reynolds reference in the same process, on the same time grid.

Each variant is the scene with another internal (Reynolds on some grid, the Taylor surrogate
of some order, the linear model). A variant that stops (a Reynolds journal at the wall) or
whose orbit leaves the clearance circle (the linear model, as the paper describes) is
reported as such, with its errors up to where it got, not as a crash.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from bearing_fmu.internals import registry
from bearing_fmu.io.interrupts import as_interrupted, note_kept
from bearing_fmu.io.outputs import ensure_writable, write_json, write_text

from ..scenes.run import run_scene
from ..scenes.scene import Scene
from ..scenes.thermal import compared_thermal
from .plotting import pyplot, save_figure
from .report import errors_against, markdown_table, plot_runs


@dataclass
class Variant:
    """The scene run with ``internal`` and ``options`` ({internal name: {option: value}}, over
    the scene's own, e.g. {"reynolds": {"n_theta": 64, "n_x": 8}}; a grid of 0 is the default),
    through the bearing FMU of ``fmu_kind`` (python | native; None: the scene's) when the scene
    runs via fmu."""

    label: str
    internal: str
    options: dict = field(default_factory=dict)
    order: int | None = None  # taylor, for the table
    fmu_kind: str | None = None

    def scene(self, base: Scene) -> Scene:
        kind = {"fmu_kind": self.fmu_kind} if self.fmu_kind else {}
        return base.with_internal(self.internal, options=self.options, **kind)


COLUMNS = [
    ("label", "variant", ""), ("status", "status", ""),
    ("force_nrmse_pct", "force NRMSE [%]", ".3f"), ("orbit_rms_pct_cr", "orbit RMS [% CR]", ".3f"),
    ("orbit_max_pct_cr", "orbit max [% CR]", ".3f"), ("max_eccentricity", "max ecc.", ".3f"),
    ("envelope_rms_pct_cr", "envelope RMS [% CR]", ".3f"), ("late_eccentricity", "max ecc. last 20 %", ".3f"),
    ("integration_s", "run time [s]", ".2f"), ("setup_s", "setup [s]", ".2f"),
    ("speedup_vs_ref", "speed-up vs ref", ".1f"), ("speedup_vs_default", "speed-up vs Reynolds default", ".1f"),
    ("evals_per_step", "evals/step", ".2f"),
]
# with a supply temperature (docs/thermal.md): how hot the films run and how much power they take
THERMAL_COLUMNS = [("T_eff_end_C", "T_eff end [C]", ".2f"), ("T_eff_error_K", "T_eff error max [K]", ".2g"),
                   ("P_loss_end_W", "P_loss end [W]", ".3g")]


def compare(base: Scene, reference: Variant, variants: list[Variant], out_dir, *, progress: bool = False,
            default_label: str | None = None, log=print) -> list[dict]:
    """Run the reference and every variant; write ``compare_<scene>.md/.json/.png`` and the
    orbit plot into out_dir; return the table rows. ``default_label`` names the variant that
    is "Reynolds at its default grid", for the second speed-up column."""
    out_dir = ensure_writable(out_dir)
    stem = Path(base.source).stem if base.source else base.name
    runs = {}
    rows = []
    every = [reference, *variants]
    args = (base, reference, variants, rows, runs, out_dir, stem, default_label)
    drawing = False
    try:
        for v in every:
            _run_variant(base, reference, v, out_dir, stem, runs, rows, progress, log)
        _write(*args)
        drawing = True
        _write_plots(*args)
    except KeyboardInterrupt as exc:  # in a run, in writing or drawing: the table of what finished, then stop
        if rows:
            sig = as_interrupted(exc).signal_name
            if drawing:
                note = f"interrupted by {sig} while drawing the plots: every variant had finished"
            elif len(rows) < len(every):
                note = (f"interrupted by {sig} during {every[len(rows)].label}: the variants below are those that "
                        "finished")
            else:
                note = f"interrupted by {sig}: every variant had finished"
            files = _write(*args, note=note)
            if not drawing:  # the plots of what finished (a second interrupt skips them: the table is kept)
                try:
                    files += _write_plots(*args)
                except KeyboardInterrupt:
                    pass
            note_kept(exc, f"{', '.join(str(f) for f in files)} ({len(rows)} of {len(every)} variant(s) finished, "
                           "each with its run's .npz/.json)")
        raise
    return rows


def _run_variant(base, reference, v, out_dir, stem, runs, rows, progress, log) -> None:
    """Run one variant; append its row (errors against the reference's run) to ``rows``."""
    scene = v.scene(base)
    log(f"running {stem}: {v.label} via {route(scene)} ...")
    run = run_scene(scene, out_dir, progress=progress, stem=f"{stem}_{_slug(v.label)}")
    runs[v.label] = run
    m = run.meta
    status = m["status"]
    if m["crossed_clearance"]:
        status = "crossed clearance" if status == "ok" else f"{status}, crossed clearance"
    row = {"label": v.label, "internal": v.internal, "route": route(scene), "options": run.meta["internal_options"],
           "order": v.order, "status": status, "message": m["message"],
           "integration_s": m["integration_time_s"], "setup_s": m["setup_time_s"] + m["equilibrium_time_s"],
           "wall_s": m["wall_time_s"], "evals_per_step": m["newton_mean_evaluations_per_step"],
           "max_eccentricity": max(m["max_eccentricity"]), "t_reached_s": m["t_reached_s"]}
    row["late_eccentricity"] = late_max_eccentricity(run.arrays)
    if "max_domain_excess" in m:  # a surrogate: how far it left its fitted domain
        row["out_of_domain_pct"] = 100.0 * max(m["out_of_domain_fraction"])
        row["domain_excess_pct"] = 100.0 * max(m["max_domain_excess"])
    if v is not reference:
        row.update(errors_against(runs[reference.label].arrays, run.arrays))
        row["envelope_rms_pct_cr"] = envelope_error(runs[reference.label].arrays, run.arrays, base.speed_hz)
    else:
        row.update(force_nrmse_pct=0.0, orbit_rms_pct_cr=0.0, orbit_max_pct_cr=0.0, envelope_rms_pct_cr=0.0)
    row.update(compared_thermal(runs[reference.label].arrays, run.arrays))
    rows.append(row)
    log(f"  {status}: {row['integration_s']:.2f} s, force NRMSE {row['force_nrmse_pct']:.3g} %, "
        f"orbit RMS {row['orbit_rms_pct_cr']:.3g} % CR")


def _write(base, reference, variants, rows, runs, out_dir, stem, default_label, note: str = "") -> list[Path]:
    """compare_<stem>.md/.json from the rows there are; the files written (the plots: ``_write_plots``)."""
    t_ref = rows[0]["integration_s"]
    t_def = next((r["integration_s"] for r in rows if r["label"] == default_label), None)
    for r in rows:
        full = r["t_reached_s"] >= base.t_end_s - 1e-12
        r["speedup_vs_ref"] = t_ref / r["integration_s"] if full and r["integration_s"] > 0 else None
        r["speedup_vs_default"] = (t_def / r["integration_s"] if full and t_def and r["integration_s"] > 0 else None)

    table = print_table(rows)
    routes = ", ".join(dict.fromkeys(r["route"] for r in rows))
    header = (f"# {base.description or base.name}\n\ncomputed for: {compare_inputs(base)}\n\nscene {base.source}, via {routes}, "
              f"dt = {base.dt_s:g} s, {base.t_end_s:g} s simulated; reference: {reference.label}. "
              "Force NRMSE = RMS error / RMS of the reference's dynamic force; orbit errors on the "
              "bearing journals in % of the radial clearance; run time = integration only "
              "(setup = FMU load, compile, static equilibrium). Envelope = largest bearing eccentricity per "
              "2 shaft revolutions; its RMS difference and 'max ecc. last 20 %' size a whirl, which "
              "keeps no phase with the reference.\n\n")
    if note:
        header += f"**{note}**\n\n"
    return [write_text(out_dir / f"compare_{stem}.md", header + table + "\n"),
            write_json(out_dir / f"compare_{stem}.json", {"scene": str(base.source), "inputs": compare_inputs(base),
                                                          "via": base.via,
                                                          "status": "interrupted" if note else "ok", "note": note,
                                                          "rows": rows})]


def compare_inputs(base: Scene) -> str:
    """What the comparison was computed for: the scene's rotor, bearings, oil; each row its internal."""
    from .computed_for import scene_line

    line = scene_line(base)
    return line[:line.rindex("; internal ")] + "; internal: each row's"


def _write_plots(base, reference, variants, rows, runs, out_dir, stem, *_) -> list[Path]:
    """The error-against-run-time plot and the orbits of the reference and up to three variants
    that are not the truth on another grid."""
    show = [reference.label] + [v.label for v in variants
                                if not registry.get(v.internal).can.truth and v.label in runs][:3]
    title = base.description or base.name
    return [plot_error_vs_time(rows, out_dir / f"compare_{stem}_error_vs_time.png", title=title),
            plot_runs({k: runs[k].arrays for k in show}, out_dir / f"compare_{stem}_orbits.png", title=title,
                      history=True)]


def late_max_eccentricity(arrays, fraction: float = 0.2) -> float | None:
    """Largest bearing eccentricity ratio over the last ``fraction`` of the run: the size of a
    whirl limit cycle, which a pointwise orbit error cannot judge (a self-excited whirl keeps
    no phase with the reference, so the same cycle shifted in time scores a large error)."""
    t, ecc = arrays["t"], arrays["eccentricity"]
    if len(t) < 2:
        return None
    late = t >= t[0] + (1.0 - fraction) * (t[-1] - t[0])
    return float(ecc[late].max())


def envelope_error(ref, run, speed_hz: float, revs: float = 2.0) -> float | None:
    """RMS difference [% CR] of the two runs' envelopes (largest bearing eccentricity per
    ``revs`` shaft revolutions, ``rotor_host.analyses.limit_cycle.envelope``) over the windows both completed:
    the orbit's size over time, blind to the whirl phase that pointwise errors punish."""
    from .limit_cycle import envelope

    period = revs / speed_hz
    a, b = envelope(ref, period), envelope(run, period)
    n = min(a.e_max.size, b.e_max.size)
    if n == 0:
        return None
    return 100.0 * float(np.sqrt(np.mean((b.e_max[:n] - a.e_max[:n]) ** 2)))


def route(scene: Scene) -> str:
    """How a scene's bearings are called: "direct", "the native FMU" or "the Python FMU"."""
    if scene.via != "fmu":
        return scene.via
    if scene.fmu is not None:
        return f"the FMU {scene.fmu.name}"
    return {"python": "the Python FMU", "native": "the native FMU"}.get(scene.fmu_kind, f"the {scene.fmu_kind} FMU")


def _slug(label: str) -> str:
    return "".join(c if c.isalnum() else "_" for c in label).strip("_").lower()


def plot_error_vs_time(rows, path, title=""):
    """Each variant's orbit and force error against its run time (log-log), the reference's run time
    dotted. Both axes label their ticks in plain numbers (1, 2 and 5 of each decade on a span of a
    few decades: never a single label); the variants are named in a legend beside the panels
    (labels beside the points ran into each other and off the figure)."""
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    plt = pyplot()
    fig, ax = plt.subplots(1, 2, figsize=(13, 4.4))
    shapes = "osD^vP*X"  # one marker per internal, in the order the rows bring them
    markers = {name: shapes[i % len(shapes)] for i, name in enumerate(dict.fromkeys(r["internal"] for r in rows))}
    plain = FuncFormatter(lambda v, _pos: f"{v:g}")
    for a, key, yl in zip(ax, ("orbit_rms_pct_cr", "force_nrmse_pct"), ("orbit RMS error [% CR]", "force NRMSE [%]")):
        pts = [(r["integration_s"], max(r[key], 1e-4), r) for r in rows[1:]
               if r.get(key) is not None and math.isfinite(r[key]) and r.get("integration_s")]
        t_ref = rows[0].get("integration_s") if rows else None
        a.set_xscale("log")
        a.set_yscale("log")
        ts = [t for t, _, _ in pts] + ([t_ref] if t_ref else [])
        lo_t, hi_t = (min(ts) / 1.5, max(max(ts) * 1.5, min(ts) * 10.0)) if ts else (0.1, 10.0)
        a.set_xlim(lo_t, hi_t)  # at least a decade, so the axis has ticks to label
        for i, r in enumerate(rows[1:]):  # the same colour for a variant in both panels
            hit = [(t, val) for t, val, rr in pts if rr is r]
            if hit:
                a.plot(*hit[0], markers.get(r["internal"], "x"), ms=7, color=f"C{i % 10}", label=r["label"])
        vals = [v for _, v, _ in pts]
        if vals:
            a.set_ylim(min(vals) / 2.0, max(max(vals) * 2.0, min(vals) * 10.0))
        if t_ref:
            a.axvline(t_ref, color="k", ls=":", lw=1)
            a.annotate(rows[0]["label"], (t_ref, 0.5), xycoords=("data", "axes fraction"),
                       rotation=90, fontsize=7, ha="right", va="center")
        for axis, (lo, hi) in ((a.xaxis, a.get_xlim()), (a.yaxis, a.get_ylim())):
            decades = math.log10(hi / lo)  # 1, 2, 5 of each decade on a short span; on a long one 1 alone
            axis.set_major_locator(LogLocator(base=10, subs=(1.0, 2.0, 5.0) if decades <= 3.5 else (1.0,)))
            axis.set_major_formatter(plain)
            axis.set_minor_formatter(NullFormatter())
        a.set_xlabel("run time [s] (dotted: reference)")
        a.set_ylabel(yl)
        a.grid(alpha=0.3, which="both")
    ax[1].legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0)
    if title:
        fig.suptitle(title, fontsize=10)
    return save_figure(fig, path)


def print_table(rows) -> str:
    """The table, then one line per variant that did not end well (its reason) or whose
    surrogate left its fitted domain (how often and how far)."""
    notes = []
    for r in rows:
        if r["status"] != "ok":
            notes.append(f"- {r['label']}: {r['status']}" + (f": {r['message']}" if r.get("message") else ""))
        if r.get("out_of_domain_pct"):
            notes.append(f"- {r['label']}: {r['out_of_domain_pct']:.3g} % of the recorded states outside the "
                         f"surrogate's fitted domain, up to {r['domain_excess_pct']:.3g} % of its size beyond it")
    columns = COLUMNS + (THERMAL_COLUMNS if any("T_eff_end_C" in r for r in rows) else [])
    return markdown_table(rows, columns) + ("\n\n" + "\n".join(notes) if notes else "")


# ----------------------------------------------------------------------------- the variants

def _grid_options(grid) -> dict:
    """Reynolds grid (n_theta, n_x) as variant options; None = the solver's default."""
    n_theta, n_x = grid if grid else (0, 0)
    return {"reynolds": {"n_theta": n_theta, "n_x": n_x}}


def _grid_label(grid) -> str:
    return f"Reynolds {grid[0]}x{grid[1]}" if grid else "Reynolds default grid"


def reference_and_variants(scene: Scene, out, *, ref_grid=(256, 32), grids=((64, 8),), orders=(1, 3, 5, 7),
                           maps=None, internals=None) -> tuple[Variant, list[Variant]]:
    """The reference (Reynolds on ``ref_grid``; None: its default grid) and the variants of
    ``rotor-host compare``: Reynolds on each of ``grids``, one force map per file of ``maps``
    (None: the scene's map), the Taylor surrogate of the scene for each of ``orders`` (other
    orders refitted into ``out``), the linear model; or, with ``internals``, one variant per
    named internal with the scene's options for it (any registered internal that can be a
    compare variant)."""
    ref = Variant(_grid_label(ref_grid), "reynolds", _grid_options(ref_grid))
    if internals:
        variants = []
        for name in internals:
            spec = registry.get(name)
            if not spec.can.compare:
                raise ValueError(f"--internals {name}: this internal cannot be a compare variant; those that can: "
                                 f"{', '.join(registry.having(compare=True))}")
            variants.append(Variant(spec.name, spec.name))
        return ref, variants
    variants = []
    if ref_grid:
        variants.append(Variant(_grid_label(None), "reynolds", _grid_options(None)))
    for grid in grids or []:
        variants.append(Variant(_grid_label(grid), "reynolds", _grid_options(grid)))
    variants += map_variants(maps if maps is not None else scene_maps(scene))
    from bearing_fmu.surrogates.surrogate import load_surrogate

    for order, path in surrogates_at_orders(scene, orders, Path(out)):
        variants.append(Variant(f"Taylor {load_surrogate(path).recipe}", "taylor", {"taylor": {"surrogate": path}},
                                order=order))
    variants.append(Variant("linear", "linear", _grid_options(None)))
    return ref, variants


def scene_maps(scene: Scene) -> list[Path]:
    """The scene's force map as the one map variant, if it names one."""
    value = scene.options.get("map", {}).get("map")
    return [Path(value)] if value else []


def map_variants(paths) -> list[Variant]:
    """One compare variant per force map file, labelled with its resolution and truth grid."""
    from bearing_fmu.internals.map.mapfile import load_any_map

    out = []
    for path in paths:
        t = load_any_map(path)
        out.append(Variant(f"map {'x'.join(str(n) for n in t.H.shape[:-1])} (Reynolds {t.n_theta}x{t.n_x})", "map",
                           {"map": {"map": Path(path).resolve()}}))
    return out


def surrogates_at_orders(scene: Scene, orders, out: Path) -> list[tuple[int, Path]]:
    """(order, file) per requested order: the scene's surrogate for its own order, others
    fitted on the same declared domain into the output folder."""
    from bearing_fmu.surrogates.surrogate import load_surrogate

    from ..scenes.scene import required_file

    if not orders:  # `--orders` with nothing: no Taylor variant, no surrogate needed
        return []
    # read once: its order here, its recipe for the refits
    base = load_surrogate(required_file(scene, "taylor", "surrogate"))
    result = []
    for order in orders:
        if order == base.order:
            result.append((order, scene.surrogate))
            continue
        path = out / "surrogates" / f"{scene.surrogate.stem}_order{order}.json"
        if not path.is_file():
            from .training import refit

            refit(scene.surrogate, order, path, cache_dir=out / "series", surrogate=base)
        result.append((order, path))
    return result


# ----------------------------------------------------------------------------- the main job

PAPER_SCENES = ("paper_22hz.toml", "paper_44hz.toml")


def paper_job(scenes_dir, out, *, t_end: float | None = None, progress: bool = True) -> str:
    """The main job: the paper's 22 Hz and 44 Hz scenes, Reynolds (default grid) against the
    force map, the bundled Taylor surrogate of each scene and the linear model, all through the
    bearing FMUs: each through its native FMU (the internal compiled to C, loaded through fmpy,
    iterated by the integrator's compiled loop), and the force map once more through the Python
    FMU (pythonfmu), so the table shows both routes and what each costs. Writes
    paper_summary.md (also the scenes that finished when interrupted) and returns its text."""
    scenes_dir, out = Path(scenes_dir), ensure_writable(out)
    summary: list[str] = []
    try:
        _paper_scenes(scenes_dir, out, summary, t_end, progress)
    except KeyboardInterrupt as exc:
        if summary:  # the scenes that finished; compare wrote the interrupted scene's rows
            write_text(out / "paper_summary.md", "\n".join(summary) + "\n**interrupted: the scenes above finished**\n")
            note_kept(exc, f"{out / 'paper_summary.md'} ({len(summary)} finished scene(s))")
        raise
    text = "\n".join(summary)
    write_text(out / "paper_summary.md", text)
    return text


PAPER_REFERENCE = "Reynolds default grid"
PYTHON_FMU = "Python FMU"  # the label's tail of a variant through the Python FMU


def paper_variants(scene: Scene, surrogate) -> tuple[Variant, list[Variant]]:
    """The main job's reference and variants of ``scene`` (its Taylor ``surrogate`` loaded): each
    through its native FMU, the force map also through the Python FMU."""
    variants = []
    for m in map_variants(scene_maps(scene)):  # each map through both FMUs
        m.fmu_kind = "native"
        variants += [m, Variant(f"{m.label}, {PYTHON_FMU}", m.internal, m.options, fmu_kind="python")]
    variants += [Variant(f"Taylor {surrogate.recipe}", "taylor", order=surrogate.order, fmu_kind="native"),
                 Variant("linear", "linear", fmu_kind="native")]
    return Variant(PAPER_REFERENCE, "reynolds", fmu_kind="native"), variants


def _paper_scenes(scenes_dir: Path, out: Path, summary: list, t_end, progress: bool) -> None:
    from bearing_fmu.surrogates.surrogate import load_surrogate

    from ..scenes.scene import load_scene, required_file

    for name in PAPER_SCENES:
        scene = load_scene(scenes_dir / name)
        if t_end is not None:  # checked like the file's own value (a whole number of steps)
            scene = scene.with_internal(scene.internal, t_end_s=t_end)
        # 22 Hz: order 5; 44 Hz: order 7 with wall factor and shape columns
        sur = load_surrogate(required_file(scene, "taylor", "surrogate"))
        rows = compare(scene, *paper_variants(scene, sur), out, progress=progress, default_label=PAPER_REFERENCE)
        summary.append(f"## {scene.description}\n\ncomputed for: {compare_inputs(scene)}\n\n{print_table(rows)}\n")
