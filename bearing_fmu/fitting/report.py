"""The report of a fit (a markdown table of the errors per force component) and the lambda
plots in the manner of the paper's Figs. 9-10."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..io.outputs import write_with
from .fit import COMPONENTS, FitResult
from .truth import truth_line


def format_report(res: FitResult) -> str:
    r, e = res.report, res.report["errors"]
    s = res.surrogate
    b = s.params
    lines = [
        f"Taylor surrogate, order {r['order']} ({r['n_terms']} terms), speed {s.omega / (2 * math.pi):g} Hz, "
        f"load {list(s.load) if s.load else None} N",
        f"bearing: {s.provenance.get('bearing', 'given by the caller')}: D {b.D * 1e3:g} mm, L {b.L * 1e3:g} mm, "
        f"CR {b.CR * 1e6:g} um, mu {b.mu:g} Pa s",
        f"expansion point y0 = {s.y0 * 1e6:.3f} um, z0 = {s.z0 * 1e6:.3f} um "
        f"(eccentricity {math.hypot(s.y0, s.z0) / s.params.CR:.4f}); force scale {s.force_scale:.4g} N",
        f"domain: ecc <= {s.domain.ecc_max:g}, position disc radius {s.domain.pos_radius:g} CR, "
        f"|v| <= {s.domain.v_max:g} omega CR; {r['n_train']} training samples, cond(X) = {r['cond_X']:.3g}",
        _truth(res),
        f"NRMSE = RMS error / std of the truth; {r['k_folds']}-fold CV chooses lambda (per-sample objective)"
        + (f"; wall factor: the polynomial fits F (1 - eps^2)^{s.wall_power:g} (CV errors of that)"
           if s.wall_power else "")
        + (f"; short-bearing shape columns of order {s.shape_order} ({r['n_shape_columns']} per component, "
           "never pruned)" if s.shape_order is not None else ""),
        "| component | lambda chosen | lambda search | train NRMSE | CV NRMSE (LS) | held-out NRMSE | "
        "held-out unpruned | held-out LS (lambda = 0) | terms kept |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for c in COMPONENTS:
        ls = r["lambda_search"][c] if r["lambda_search"] else float("nan")
        lines.append(
            f"| {c} | {r['lambda'][c]:.3g} | {ls:.3g} | {e['train_nrmse'][c]:.3e} | {e['cv_nrmse_ls'][c]:.3e} | "
            f"{e.get('test_nrmse', {}).get(c, float('nan')):.3e} | "
            f"{e.get('test_nrmse_unpruned', {}).get(c, float('nan')):.3e} | "
            f"{e.get('test_nrmse_ls_unpruned', {}).get(c, float('nan')):.3e} | {r['kept'][c]} / {r['n_terms']} |"
        )
    for name, o in e.get("other_scenes", {}).items():
        lines.append(f"held out, scene {name}: NRMSE Fy {o['nrmse']['Fy']:.3e}, Fz {o['nrmse']['Fz']:.3e}; "
                     f"{o['out_of_domain_fraction']:.1%} of its states outside the fitted domain")
    if s.neighbours is not None:
        nb = s.neighbours
        lines.append(f"domain guard: {len(nb.points)} training states stored, radius {nb.radius:.4g} in u "
                     f"(covering radius {nb.info.get('covering_radius', float('nan')):.3g}); a state farther "
                     "than the radius from all of them is outside the fitted domain")
    lines.append(_timing(r))
    return "\n".join(lines)


def _truth(res: FitResult) -> str:
    """The truth line: from the file's provenance, the map's path as the user gave it."""
    rec = res.recipe
    return truth_line(res.surrogate.provenance, map_shown=None if rec is None else rec.truth_map,
                      scene=rec is not None and rec.kind == "scene")


def _timing(r: dict) -> str:
    """'fit time' (the regression) and, where measured, the truth's samples and the whole fit."""
    text = f"fit time {r['fit_seconds']:.1f} s"
    if "sampling_seconds" in r:
        text += f"; the truth's samples {r['sampling_seconds']:.2f} s"
    if "total_seconds" in r:
        text += f"; whole fit {r['total_seconds']:.1f} s"
    return text


def plot_lambda(res: FitResult, outdir: str | Path, stem: str = "fit") -> list[Path]:
    """Figs. 9-10 in the manner of the paper: CV objective vs lambda (full range and zoom on
    the minimum, LS level dashed) and bias^2 / variance vs lambda, per component."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    c = res.curves
    if "cv_curve" not in c:
        return []
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    lam = 10.0 ** c["log10_grid"]
    paths = []
    fig, axes = plt.subplots(2, 2, figsize=(10, 7))
    for j, comp in enumerate(COMPONENTS):
        for k, zoom in enumerate((False, True)):
            ax = axes[j, k]
            y = c["cv_curve"][:, j]
            if zoom:
                zg, zy = c["zoom"][j]
                ax.semilogx(10.0**zg, zy, "o-", ms=3, label="k-fold CV objective")
            else:
                ax.loglog(lam, y, "o-", ms=3, label="k-fold CV objective")
            ax.axhline(c["cv_ls"][j], color="k", ls="--", lw=1, label="least squares (lambda = 0)")
            lamc = res.report["lambda_search"][comp]
            ax.axvline(lamc, color="r", lw=1, label=f"line search: {lamc:.2g}")
            if zoom:
                yy = np.concatenate([zy, [c["cv_ls"][j]]])
                pad = 0.05 * (yy.max() - yy.min()) + 1e-300
                ax.set_ylim(yy.min() - pad, yy.max() + pad)
                ax.set_title(f"({'abcd'[2 * j + k]}) zoom, {comp}")
            else:
                ax.set_title(f"({'abcd'[2 * j + k]}) objective, {comp} adjustment")
            ax.set_xlabel("lambda (per-sample ridge penalty)")
            ax.set_ylabel("CV mean squared error (scaled)")
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=7)
    fig.tight_layout()
    p = write_with(outdir / f"{stem}_objective.png", lambda f: fig.savefig(f, dpi=110, format="png"))
    plt.close(fig)
    paths.append(p)
    if "bias2" in c:
        fig, axes = plt.subplots(1, 2, figsize=(10, 4))
        lg = c["lam_grid"]
        for j, comp in enumerate(COMPONENTS):
            ax = axes[j]
            b, v = c["bias2"][:, j], c["variance"][:, j]
            ax.loglog(lg, np.maximum(b, 1e-300), label="bias^2")
            ax.loglog(lg, v, label="variance")
            ax.loglog(lg, b + v, "k--", label="bias^2 + variance")
            ax.set_title(f"({'ab'[j]}) bias-variance trade-off, {comp}")
            ax.set_xlabel("lambda")
            ax.set_ylabel("mean squared (scaled force)")
            lo = max(min(v.min(), (b + v).min()) * 0.1, 1e-30)
            ax.set_ylim(lo, (b + v).max() * 2)
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=7)
        fig.tight_layout()
        p = write_with(outdir / f"{stem}_bias_variance.png", lambda f: fig.savefig(f, dpi=110, format="png"))
        plt.close(fig)
        paths.append(p)
    return paths


__all__ = ["format_report", "plot_lambda"]
