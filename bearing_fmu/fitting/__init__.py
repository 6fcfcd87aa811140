"""Fitting the Taylor surrogate (never bundled into the FMU, which only evaluates it).

    recipe    FitRecipe: every fit setting once (meaning, unit, range), its command-line
              options and its record in the surrogate file
    ridge     ridge regression through one SVD, cross validation, lambda search, pruning, errors
    sampling  training data: designed samples, tubes about orbits, time series, their domain
    truth     the truth of a fit: Reynolds for the statics, Reynolds or a force map (truth_map)
              for the samples; its record in the file and its line in the report
    neighbours  the training states stored for the domain guard's nearest-neighbour distance
    fit       fit_surrogate (the fit, step by step), fit_condition (a designed domain at one
              load and speed), save_fit, refit_order
    report    the report table and the lambda plots
    output    what a fit leaves behind (file, report, plots, interrupted samples); fit_designed:
              ``bearing-fmu fit`` without its command line (scene-trained fitting is the host's
              ``rotor-host fit``)

The names below are re-exported for convenience (``from bearing_fmu import fitting as F``).
"""

from .fit import (COMPONENTS, FitResult, expansion_point, fit_condition, fit_surrogate,
                  refit_order, save_fit, truth_jacobian)
from .neighbours import neighbours_for_fit
from .output import fit_designed, write_fit
from .recipe import FitRecipe, RecipeError, command_line_options, recipe_from_values, recipe_of
from .report import format_report, plot_lambda
from .ridge import (CrossValidation, RidgeSVD, fold_indices, nrmse, prune_terms, rel_rms,
                    ridge_normal_equations, select_lambda)
from .sampling import designed_samples, domain_from_data, load_npz, sample_forces, tube_samples
from .truth import Truth, fit_truth, make_reynolds, truth_line

__all__ = [
    "FitRecipe", "RecipeError", "recipe_of", "command_line_options", "recipe_from_values",
    "RidgeSVD", "CrossValidation", "select_lambda", "prune_terms", "fold_indices", "nrmse", "rel_rms",
    "ridge_normal_equations", "designed_samples", "tube_samples", "sample_forces", "load_npz", "domain_from_data",
    "FitResult", "fit_surrogate", "save_fit", "fit_condition", "make_reynolds", "truth_jacobian", "expansion_point",
    "refit_order", "COMPONENTS", "neighbours_for_fit", "format_report", "plot_lambda",
    "fit_designed", "write_fit", "Truth", "fit_truth", "truth_line",
]
