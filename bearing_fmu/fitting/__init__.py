"""Fitting the Taylor surrogate (never bundled into the FMU, which only evaluates it).

    recipe    FitRecipe: every fit setting once (meaning, unit, range), its command-line
              options and its record in the surrogate file
    ridge     ridge regression through one SVD, cross validation, lambda search, pruning, errors
    sampling  training data: designed samples, tubes about orbits, time series, their domain
    truth     the truth of a fit: Reynolds for the statics, Reynolds or a force map (truth_map)
              for the samples; its record in the file and its line in the report
    flows     the film fit: the film's flows (and a non-circular bore's torques) beside the force
    neighbours  the training states stored for the domain guard's nearest-neighbour distance
    fit       fit_surrogate (the fit, step by step), fit_condition (a designed domain at one
              load and speed), save_fit, refit_order
    report    the report table and the lambda plots
    output    what a fit leaves behind (file, report, plots, interrupted samples); fit_designed:
              ``bearing-fmu fit`` without its command line (scene-trained fitting is the host's
              ``rotor-host fit``)

The names below are re-exported for convenience (``from bearing_fmu import fitting as F``),
each imported on first use: ``fitting.recipe`` (the command lines' fit options) must not pull
in scipy and the compiled kernels of ``fit`` (a ``--help`` stays well under a second).
"""

import importlib

_EXPORTS = {
    "fit": ("COMPONENTS", "FitResult", "expansion_point", "fit_condition", "fit_surrogate", "refit_order",
            "save_fit", "truth_jacobian"),
    "flows": ("attach_film", "fit_film"),
    "neighbours": ("neighbours_for_fit",),
    "output": ("fit_designed", "write_fit"),
    "recipe": ("FitRecipe", "RecipeError", "command_line_options", "recipe_from_values", "recipe_of"),
    "report": ("format_report", "plot_lambda"),
    "ridge": ("CrossValidation", "RidgeSVD", "fold_indices", "nrmse", "prune_terms", "rel_rms",
              "ridge_normal_equations", "select_lambda"),
    "sampling": ("designed_samples", "domain_from_data", "load_npz", "sample_forces", "tube_samples"),
    "truth": ("Truth", "fit_truth", "make_reynolds", "truth_line"),
}
_HOME = {name: module for module, names in _EXPORTS.items() for name in names}

__all__ = sorted(_HOME)


def __getattr__(name: str):
    """A re-exported name, from its module (imported now, cached here)."""
    if name not in _HOME:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{_HOME[name]}", __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted({*globals(), *__all__})
