"""The film fit's part of a native Taylor FMU's model_data.h (c/taylor_film.c).

A surrogate file of format version 2 holds the film's flow functions J_s, J_i of (eps, beta)
(``surrogates.film.FilmFit``: coefficient rows over the basis eps^i t_j(beta), i = 0 .. degree
outer, t = 1, cos beta, sin beta, cos 2 beta, ... inner). The header gives the degree, the
harmonics and the two rows (``TAY_FILM_COEF``: J_s's then J_i's, each n_features long), from which
the C file evaluates the basis as ``surrogates.film.features`` does and the film report as
``Taylor.film_report`` does. They sit inside ``#if BN_FLOWS_TAYLOR`` (model_config.h: the
Taylor film report is compiled) and are taylor_film.c's alone (``BN_TAYLOR_FILM_UNIT``), as their
use is (an unused static array is a warning).

A grooved or partial-arc bore's film fit (kind 'grooved': the side flow and the supply edges'
functions of (eps, phi, beta)) is not ported: c/taylor_film.c holds the full bore's report only, so
such a native FMU has no film flows and refuses thermal by name (``native_film_why``).
"""

from __future__ import annotations

__all__ = ["film_data_lines", "native_film_why"]


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
