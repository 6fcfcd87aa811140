"""What a fit command leaves behind: the surrogate file, its report, the lambda plots, and the
truth's samples of an interrupted fit; and ``fit_designed``, ``bearing-fmu fit`` without its
command line (the options are parsed in ``bearing_fmu.cli``, generated from the FitRecipe
fields). Scene-trained fitting runs a rotor and is the host's command, ``rotor-host fit``.
"""

from __future__ import annotations

from pathlib import Path

from ..io.interrupts import note_kept
from ..io.outputs import ensure_output_file, ensure_writable, savez
from .fit import FitResult, fit_condition, save_fit
from .recipe import FitRecipe
from .report import format_report, plot_lambda


def fit_designed(recipe: FitRecipe, *, output, bearing=None, plots=None, note: str | None = None) -> int:
    """``bearing-fmu fit``: fit ``recipe`` (a designed domain, or a time series ``from_npz``) for
    the bearing file ``bearing`` (default: the paper bearing), write ``output``, the report and
    the lambda plots into ``plots``."""
    check_outputs(output, plots)
    from ..physics.params import PAPER_BEARING, BearingParams

    params = BearingParams.from_toml(bearing) if bearing else PAPER_BEARING
    try:
        res = fit_condition(recipe, params=params)
    except KeyboardInterrupt as exc:
        if getattr(exc, "samples", None) is not None and len(exc.samples[0]):
            path = keep_samples(exc.samples, Path(output))
            note_kept(exc, f"{path} ({len(exc.samples[0])} samples of the truth; fit them with --from-npz "
                                f"{path})")
        raise
    res.surrogate.provenance["bearing"] = str(bearing) if bearing else "paper bearing (Table 2)"
    return write_fit(res, output, plots=plots, note=note)


def check_outputs(output, plots=None) -> None:
    """The output file and plot folder can be written: checked before the fit's work."""
    ensure_output_file(output, "-o/--output")
    if plots:
        ensure_writable(plots, "--plots")


def keep_samples(samples, output: Path) -> Path:
    """The truth's samples of an interrupted fit, as an npz that ``--from-npz`` reads."""
    states, forces = samples
    path = output.with_name(f"{output.stem}_samples_interrupted.npz")
    savez(path, **{k: states[:, i] for i, k in enumerate(("y", "z", "vy", "vz"))},
          Fy=forces[:, 0], Fz=forces[:, 1])
    return path


def write_fit(res: FitResult, output, *, plots=None, note: str | None = None) -> int:
    """Write the surrogate file (with ``note`` in its provenance), print the report, write the
    lambda plots into the folder ``plots``."""
    if note:
        res.surrogate.provenance["note"] = note
    path = save_fit(res, output)
    print(format_report(res))
    print(f"wrote {path}")
    if plots:
        written = plot_lambda(res, plots, Path(output).stem)
        for p in written:
            print(f"wrote {p}")
        if not written:  # say why rather than write nothing without a word
            print(f"no lambda plots in {plots}: lambda was fixed (--lambda), so there was no search to plot; "
                  "leave --lambda out to choose it by cross-validation and plot the search")
    return 0


__all__ = ["check_outputs", "fit_designed", "keep_samples", "write_fit"]
