"""The native Taylor model (c/internal_taylor.c, c/taylor_film.c): a surrogate file compiled in.

``taylor_model`` (the catalogue's generator) writes model_data.h: the same arrays ``taylor.Taylor``
hands its numba kernels (meta, domain, only the kept terms), the polynomials as coefficient rows
over their monomials (``taylor_polynomials``: the C kernel sums them as vectorised dot products),
the stored training states, and a version 2 file's film fit (``film_data_lines``).

The film fit: a surrogate file of format version 2 holds the film's flow functions J_s, J_i of
(eps, beta) (``surrogates.film.FilmFit``: coefficient rows over the basis eps^i t_j(beta), i = 0 ..
degree outer, t = 1, cos beta, sin beta, cos 2 beta, ... inner). The header gives the degree, the
harmonics and the two rows (``TAY_FILM_COEF``: J_s's then J_i's, each n_features long), from which
the C file evaluates the basis as ``surrogates.film.features`` does and the film report as
``Taylor.film_report`` does. They sit inside ``#if BN_FLOWS_TAYLOR`` (model_config.h: the Taylor
film report is compiled) and are taylor_film.c's alone (``BN_TAYLOR_FILM_UNIT``), the force's
data internal_taylor.c's, as their use is (an unused static array is a warning).

A grooved or partial-arc bore's film fit (kind 'grooved': the side flow and the supply edges'
functions of (eps, phi, beta)) is not ported: c/taylor_film.c holds the full bore's report only, so
such a native FMU has no film flows and refuses thermal by name (``native_film_why``).
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np

from ....internals import registry
from ....physics.params import BearingParams
from ..catalogue import refused_choices
from ..codegen import NativeModel, c_array, c_double, c_string, model_config, native_variables, registry_option

__all__ = ["taylor_model", "taylor_polynomials", "film_data_lines", "native_film_why"]


def _rows(exps: np.ndarray, coef: np.ndarray, index: dict, n: int) -> tuple[np.ndarray, np.ndarray]:
    """The value rows (2, n) and gradient rows (8, n) of two polynomials (rows of coef over
    the exponents exps) on the monomials ``index`` (exponent tuple -> column): the gradient
    is a polynomial too, d/du_v sum_k c_k u^e_k = sum_k e_kv c_k u^(e_k - 1_v)."""
    val, grad = np.zeros((2, n)), np.zeros((8, n))
    for k, e in enumerate(np.asarray(exps, int)):
        c = coef[:, k]
        if not np.any(c):
            continue
        val[:, index[tuple(int(x) for x in e)]] += c
        for v in range(4):
            if e[v] > 0:
                low = tuple(int(x) - (1 if w == v else 0) for w, x in enumerate(e))
                grad[[v, 4 + v], index[low]] += e[v] * c
    return val, grad


def _monomials(*exponent_sets) -> list[tuple]:
    """Every monomial the polynomials and their gradients need, with the chain of parents to
    the constant, in graded order (constant first): each is its parent times one u_v."""
    needed = {(0, 0, 0, 0)}
    for exps in exponent_sets:
        for e in np.asarray(exps, int):
            e = tuple(int(x) for x in e)
            needed.add(e)
            for v in range(4):
                if e[v] > 0:
                    needed.add(tuple(x - (1 if w == v else 0) for w, x in enumerate(e)))
    for mono in list(needed):
        m = list(mono)
        while sum(m) > 0:
            v = next(i for i in range(4) if m[i] > 0)
            m[v] -= 1
            needed.add(tuple(m))
    return sorted(needed, key=lambda m: (sum(m), tuple(-x for x in m)))


def _used(rows: np.ndarray) -> int:
    """Columns up to the last non-zero one, rounded up to a multiple of 8 (the kernel's stride)."""
    nz = np.nonzero(np.any(rows != 0.0, axis=0))[0]
    n = int(nz[-1]) + 1 if nz.size else 0
    return -(-n // 8) * 8


def taylor_polynomials(exps, coef, shape_exps=None, shape_coef=None) -> str:
    """The polynomials of the Taylor internal as data for the C kernel (internal_taylor.c):
    the monomials (``monomials(u, M)``: m_j = m_parent * u_var, graded order, padded with
    zeros to TAY_NM, a multiple of 8) and the coefficient rows over them: TAY_VAL (Fy, Fz),
    TAY_GRAD (dFy/du_0..3, dFz/du_0..3) and, with shape columns, TAY_SVAL (the four M_l) and
    TAY_SGRAD (dM_l/du_v, l-major). Each group's rows are used up to its last non-zero column
    (TAY_N_VAL, ...). Summed as dot products, the force rounds differently from the Python
    kernels' term-by-term order: they agree to ~1e-15 relative (tests: 1e-12)."""
    sets = [exps] + ([shape_exps] if shape_exps is not None else [])
    monos = _monomials(*sets)
    nm = -(-len(monos) // 8) * 8
    index = {m: j for j, m in enumerate(monos)}
    val, grad = _rows(exps, np.asarray(coef, float), index, nm)
    parent, var = [0], [0]
    for m in monos[1:]:
        lst = list(m)
        v = next(i for i in range(4) if lst[i] > 0)
        lst[v] -= 1
        parent.append(index[tuple(lst)])
        var.append(v)
    lines = ["    M[0] = 1.0;"] + [f"    M[{j}] = M[{parent[j]}] * u[{var[j]}];" for j in range(1, len(monos))]
    lines += [f"    M[{j}] = 0.0;" for j in range(len(monos), nm)]
    out = [f"#define TAY_NMONO {len(monos)}", f"#define TAY_NM {nm}",
           f"#define TAY_N_VAL {_used(val)}", f"#define TAY_N_GRAD {_used(grad)}",
           "/* the monomials m_j = m_parent * u_v, graded order; zeros up to TAY_NM */",
           "static void monomials(const double u[4], double M[TAY_NM]) {\n" + "\n".join(lines) + "\n}",
           c_matrix("TAY_VAL", val), c_matrix("TAY_GRAD", grad)]
    if shape_exps is not None:
        sc = np.asarray(shape_coef, float)
        v01, g01 = _rows(shape_exps, sc[0:2], index, nm)
        v23, g23 = _rows(shape_exps, sc[2:4], index, nm)
        sval = np.vstack([v01, v23])  # M_0..M_3
        sgrad = np.vstack([g01[0:4], g01[4:8], g23[0:4], g23[4:8]])  # dM_l/du_v, l-major
        out += [f"#define TAY_N_SVAL {_used(sval)}", f"#define TAY_N_SGRAD {_used(sgrad)}",
                c_matrix("TAY_SVAL", sval), c_matrix("TAY_SGRAD", sgrad)]
    return "\n".join(out) + "\n"


def c_matrix(name: str, rows: np.ndarray) -> str:
    """A (R, n) matrix as a static, 32-byte aligned C array (the kernel loads 4 doubles at a time)."""
    rows = np.asarray(rows, float)
    body = ",\n    ".join("{" + ", ".join(c_double(x) for x in r) + "}" for r in rows)
    return (f"static const double {name}[{rows.shape[0]}][{rows.shape[1]}] BN_ALIGN32 = {{\n    {body}}};\n")


def taylor_model(params: BearingParams, surrogate, map_path, options: dict) -> NativeModel:
    """The native model of the Taylor surrogate file ``surrogate`` (the catalogue's generator)."""
    from ....surrogates.surrogate import load_surrogate
    from ....internals.taylor import Taylor

    if not surrogate:
        raise ValueError("a native taylor FMU needs a surrogate file (--surrogate FILE)")
    path = Path(surrogate)
    sur = load_surrogate(path, params) if params is not None else load_surrogate(path)
    tay = Taylor(sur, source=str(path))  # its film_flow_why names the file
    # the file's: '' with its film fit (a grooved bore's is not ported: native_film_why)
    flows_why = registry.film_flow_of(registry.get("taylor"), tay) or native_film_why(sur.film)
    # the surrogate's bearing, with the bearing file's oil law when given (the thermal model's)
    params = sur.params if params is None or params.oil is None else dataclasses.replace(sur.params, oil=params.oil)
    exps, coef = tay._exps, tay._coef  # the kept terms, exactly what the numba kernels evaluate
    shape = sur.shape_order is not None
    what = " and ".join(([f"wall factor (1 - eps^2)^-{sur.wall_power:g}"] if sur.wall_power else [])
                        + (["short-bearing shape columns"] if shape else []))
    wall_why = (f"; the surrogate's {what} {'are' if shape else 'is'} undefined there" if what else "")
    nb = sur.neighbours
    # the Python guard's radius max(r_cv, r_lin) and size (nearest.NearestTraining); the bounds
    # in tay._dom are widened by as much already: the native FMU flags what the Python one flags
    near = tay.neighbours
    radius, size = (near.radius, near.size) if near is not None else (1.0, 1.0)
    parts = [
        "/* Generated by bearing_fmu.fmu.native.codegen from the surrogate file "
        f"{path.name} ({sur.recipe}). Do not edit. */",
        "#ifndef MODEL_DATA_H", "#define MODEL_DATA_H",
        f"#define TAY_SOURCE {c_string(path.name)}",
        f"#define TAY_SHAPE {int(shape)}",
        f"#define TAY_NN {0 if nb is None else len(nb.points)}",
        f"#define TAY_NN_RADIUS {c_double(radius)}",
        f"#define TAY_NN_SIZE {c_double(size)}",
        f"#define TAY_CR2 {c_double(tay._cr2)}",
        f"#define TAY_WALL_WHY {c_string(wall_why)}",
        c_array("TAY_PARAMS", (params.D, params.L, params.CR, params.mu)),
        # the force's data, internal_taylor.c's alone (taylor_film.c, the film report, holds the film fit's)
        "#if !defined(BN_TAYLOR_FILM_UNIT)",
        c_array("TAY_META", tay._meta),
        c_array("TAY_DOM", tay._dom),
        # sorted by u_0: the C search sweeps outward from the query in that order (internal_taylor.c: nearest)
        c_array("TAY_NN_POINTS", nb.points[np.argsort(nb.points[:, 0], kind="stable")] if nb is not None
                else [0.0, 0.0, 0.0, 0.0]),
        taylor_polynomials(exps, coef, *((sur.shape_exponents, sur.shape_coef) if shape else ())),
        "#endif /* the force's data (a comment: several.py drops the file's bare closing #endif) */",
        *film_data_lines(sur.film, c_array),  # the film fit (format version 2): c/taylor_film.c
    ]
    parts.append("#endif\n")
    starts = {"surrogate": path.name, "domain_action": "warn", "domain_limit": registry.DEFAULT_DOMAIN_LIMIT}
    for name in ("domain_action", "domain_limit"):
        if name in options:
            starts[name] = registry_option(name).check(options[name], "native FMU option")
    if starts["domain_action"] == "fallback":
        raise ValueError(f"domain_action = 'fallback': {refused_choices(('taylor',))['domain_action'][1]}")
    inputs = (sur.y0, sur.z0, 0.0, 0.0, sur.omega)
    data_h = "\n".join(parts)
    config_h = model_config("taylor", params, starts, inputs, flows_why)
    info = {"source": path.name, "recipe": sur.recipe, "order": sur.order, "terms": int(exps.shape[0]),
            "wall_power": sur.wall_power, "shape_order": sur.shape_order, "omega": sur.omega,
            "training_states": 0 if nb is None else len(nb.points),
            "provenance": sur.provenance}
    return NativeModel("taylor", params, native_variables("taylor", params, starts, inputs, flows_why), config_h, data_h,
                       path, f"hydrodynamic journal bearing, Taylor surrogate {path.name} ({sur.recipe}) at "
                       f"{sur.omega / (2 * math.pi):.6g} Hz, compiled (no Python)", info, flows_why=flows_why)


def native_film_why(film) -> str:
    """Why the native Taylor FMU lacks the film fit ``film``'s flows ('' when c/taylor_film.c has them:
    the full bore's, or no fit, whose why the Python internal gives)."""
    if film is None or film.kind == "full":
        return ""
    return ("the surrogate's film fit is a grooved or partial-arc bore's (key film: kind 'grooved'), which the "
            "native Taylor FMU does not compute (c/taylor_film.c: the full bore's only): use the Python FMU for "
            "its film's flows and thermal ports")


def film_data_lines(film, c_array) -> list[str]:
    """The header's lines of the film fit ``film`` (a ``FilmFit``, or None: a version 1 file, no
    lines); ``c_array``: codegen's exact literals."""
    if film is None or native_film_why(film):
        return []
    return ["#if BN_FLOWS_TAYLOR && defined(BN_TAYLOR_FILM_UNIT) /* the film fit (taylor_film.c): J_s, J_i over the "
            "basis of surrogates.film.features */",
            f"#define TAY_FILM_DEGREE {film.degree}",
            f"#define TAY_FILM_HARMONICS {film.harmonics}",
            f"#define TAY_FILM_NF {film.coef.shape[1]}",
            c_array("TAY_FILM_COEF", film.coef),
            "#endif /* BN_FLOWS_TAYLOR (a comment: several.py drops the file's bare closing #endif) */"]
