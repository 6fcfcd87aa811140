"""The Taylor surrogate's film fit: the film's inflow and side flow by the force map's reduction,
their two functions of (eps, beta) fitted beside the force (``bearing_fmu.fitting.flows``) and
stored in the surrogate file (key ``film``, format version 2).

The reduction (``physics.solver.film``, docs/forcemap.md "The flows"; exact for the full bore at any
speed): with eps the eccentricity ratio, a = eps (omega - 2 phidot), c = 2 epsdot, r = |(a, c)|,
beta = atan2(c, a) (``internals.map.tables.reduced``) and Q0 = R L CR,

    side flow  Q_s = r Q0 J_s(eps, beta)
    inflow     Q   = | omega Q0 (1 + eps) / 2 - r Q0 J_i(eps, beta) |

so the fit holds two smooth speed-free functions, each sum_k coef_k eps^i_k trig_k(beta) (trig:
1, cos m beta, sin m beta up to ``harmonics``). The friction needs no fit: the closed form of the
full bore from the surrogate's own force (``film.full_bore_friction``), as the map has it.

A grooved or partial-arc bore (``kind = "grooved"``, ``GroovedFilmFit``): the grooves fix directions,
so the functions depend on the attitude phi too, as the grooved force map's flow table (docs/forcemap.md,
"Grooved bores: the flows"): side flow r Q0 J_s(eps, phi, beta) and per supply edge e the signed flux
sign_e omega Q0 h_e / (2 CR) - r Q0 P_e(eps, phi, beta), the inflow the sum of their positive parts
(``film.grooved_report``). The surrogate holds one operating point, so eps and phi vary little: the
basis is the full bore's times a Fourier series in phi (1, cos phi, sin phi, .. up to phi_harmonics):
near the centre the attitude takes any value, and at eps -> 0 the field depends on phi + beta alone,
which a polynomial in phi about one attitude cannot follow.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .domain import get_key, json_clean, read_int, read_number, read_object, read_vector

TARGETS = ("J_s", "J_i")
MEANING = ("side flow r R L CR J_s, inflow |omega R L CR (1 + eps) / 2 - r R L CR J_i|; each J = sum_k coef_k "
           "eps^(k // (2 harmonics + 1)) t_(k % (2 harmonics + 1))(beta), t = 1, cos beta, sin beta, cos 2 beta, ...")
MAX_DEGREE, MAX_HARMONICS = 12, 24
GROOVED = "grooved"  # the key 'kind' of a grooved or partial-arc bore's film fit (absent: the full bore's)
GROOVED_MEANING = ("side flow r R L CR J_s; per supply edge e (edges_deg: theta_e [deg], sign_e) the flux into the "
                   "film sign_e omega R L h_e / 2 - r R L CR P_e, inflow the sum of its positive parts; each function "
                   "sum_k coef_k f_k, f = (the full bore's eps^i t_j(beta)) times t_l(phi) (1, cos phi, sin phi, ..), l outer")


def n_features(degree: int, harmonics: int) -> int:
    return (degree + 1) * (2 * harmonics + 1)


def features(eps, beta, degree: int, harmonics: int) -> np.ndarray:
    """(M, n_features): eps^i t_j(beta), i = 0 .. degree (outer), t_j = 1, cos beta, sin beta,
    cos 2 beta, ... (inner)."""
    eps, beta = np.atleast_1d(np.asarray(eps, float)), np.atleast_1d(np.asarray(beta, float))
    T = trig(beta, harmonics)
    P = eps[:, None] ** np.arange(degree + 1)
    return (P[:, :, None] * T[:, None, :]).reshape(len(eps), -1)


def trig(x, harmonics: int) -> np.ndarray:
    """(M, 2 harmonics + 1): 1, cos x, sin x, cos 2x, sin 2x, .."""
    x = np.atleast_1d(np.asarray(x, float))
    t = [np.ones_like(x)]
    for m in range(1, harmonics + 1):
        t += [np.cos(m * x), np.sin(m * x)]
    return np.stack(t, axis=1)


def grooved_features(eps, phi, beta, degree: int, harmonics: int, phi_harmonics: int) -> np.ndarray:
    """(M, (2 phi_harmonics + 1) n_features): ``features(eps, beta)`` times t_l(phi), l outer
    (t = 1, cos phi, sin phi, .. up to phi_harmonics)."""
    base = features(eps, beta, degree, harmonics)
    return (trig(phi, phi_harmonics)[:, :, None] * base[:, None, :]).reshape(len(base), -1)


@dataclass
class FilmFit:
    """The fitted flow functions: coef[0] of J_s, coef[1] of J_i over ``features(degree,
    harmonics)``; ``lam`` the ridge penalty of each; ``errors`` what the fit measured."""

    degree: int
    harmonics: int
    coef: np.ndarray
    lam: tuple = (0.0, 0.0)
    errors: dict = field(default_factory=dict)
    kind = "full"

    def __post_init__(self) -> None:
        self.degree, self.harmonics = int(self.degree), int(self.harmonics)
        if not (0 <= self.degree <= MAX_DEGREE and 0 <= self.harmonics <= MAX_HARMONICS):
            raise ValueError(f"FilmFit: degree {self.degree} (0 .. {MAX_DEGREE}), harmonics {self.harmonics} "
                             f"(0 .. {MAX_HARMONICS})")
        self.coef = np.ascontiguousarray(self.coef, dtype=float).reshape(2, -1)
        if self.coef.shape[1] != n_features(self.degree, self.harmonics):
            raise ValueError(f"FilmFit: {self.coef.shape[1]} coefficients per function, expected "
                             f"{n_features(self.degree, self.harmonics)}")
        if not np.all(np.isfinite(self.coef)):
            raise ValueError("FilmFit: coef has non-finite entries")
        self.lam = tuple(float(v) for v in self.lam)

    def values(self, eps, beta) -> np.ndarray:
        """(M, 2): J_s, J_i at (eps, beta)."""
        return features(eps, beta, self.degree, self.harmonics) @ self.coef.T

    def to_dict(self) -> dict:
        return {"meaning": MEANING, "degree": self.degree, "harmonics": self.harmonics,
                "coef": {t: self.coef[i].tolist() for i, t in enumerate(TARGETS)},
                "lambda": dict(zip(TARGETS, self.lam)), "errors": json_clean(self.errors)}

    @classmethod
    def from_dict(cls, d, where: str) -> "FilmFit":
        """The film fit of a file's key ``film``, each key checked and named."""
        if not isinstance(d, dict):
            raise ValueError(f"{where}: expected a table (degree, harmonics, coef)")
        degree, harmonics = read_int(d, "degree", where), read_int(d, "harmonics", where)
        if degree > MAX_DEGREE or harmonics > MAX_HARMONICS:
            raise ValueError(f"{where}: degree {degree} must be <= {MAX_DEGREE}, harmonics {harmonics} <= "
                             f"{MAX_HARMONICS}")
        c = get_key(d, "coef", where)
        coef = np.array([read_vector(c, t, n_features(degree, harmonics), f"{where}: coef") for t in TARGETS])
        lam = (0.0, 0.0)
        if "lambda" in d:
            ld = get_key(d, "lambda", where)
            lam = tuple(read_number(ld, t, f"{where}: lambda", minimum=0.0) for t in TARGETS)
        errors = read_object(d, "errors", where) if "errors" in d else {}
        return cls(degree, harmonics, coef, lam, errors)


@dataclass
class GroovedFilmFit:
    """The fitted flow functions of a grooved or partial-arc bore: coef[0] of J_s, coef[1 + e] of P_e
    for each supply edge ``edges`` ((theta [rad], sign), ``Geometry.supply_edges``' order) over
    ``grooved_features``; ``lam`` the ridge penalty of each; ``errors`` what the fit measured."""

    degree: int
    harmonics: int
    phi_harmonics: int
    edges: tuple
    coef: np.ndarray
    lam: tuple = ()
    errors: dict = field(default_factory=dict)
    kind = GROOVED

    def __post_init__(self) -> None:
        self.degree, self.harmonics, self.phi_harmonics = int(self.degree), int(self.harmonics), int(self.phi_harmonics)
        if not (0 <= self.degree <= MAX_DEGREE and 0 <= self.harmonics <= MAX_HARMONICS
                and 0 <= self.phi_harmonics <= MAX_HARMONICS):
            raise ValueError(f"GroovedFilmFit: degree {self.degree} (0 .. {MAX_DEGREE}), harmonics {self.harmonics} "
                             f"and phi_harmonics {self.phi_harmonics} (0 .. {MAX_HARMONICS})")
        self.edges = tuple((float(t), float(s)) for t, s in self.edges)
        if not self.edges or any(s not in (1.0, -1.0) for _t, s in self.edges):
            raise ValueError("GroovedFilmFit: edges must list (theta [rad], sign +-1) of at least one supply edge")
        self.coef = np.ascontiguousarray(self.coef, dtype=float).reshape(1 + len(self.edges), -1)
        if self.coef.shape[1] != self.n_features:
            raise ValueError(f"GroovedFilmFit: {self.coef.shape[1]} coefficients per function, expected "
                             f"{self.n_features}")
        if not np.all(np.isfinite(self.coef)):
            raise ValueError("GroovedFilmFit: coef has non-finite entries")
        self.lam = tuple(float(v) for v in self.lam) or (0.0,) * len(self.coef)

    @property
    def n_features(self) -> int:
        return (2 * self.phi_harmonics + 1) * n_features(self.degree, self.harmonics)

    @property
    def targets(self) -> tuple:
        return ("J_s",) + tuple(f"P_{k + 1}" for k in range(len(self.edges)))

    def values(self, eps, phi, beta) -> np.ndarray:
        """(M, 1 + E): J_s, P_1 .. P_E at (eps, phi, beta)."""
        return grooved_features(eps, phi, beta, self.degree, self.harmonics, self.phi_harmonics) @ self.coef.T

    def to_dict(self) -> dict:
        return {"kind": GROOVED, "meaning": GROOVED_MEANING, "degree": self.degree, "harmonics": self.harmonics,
                "phi_harmonics": self.phi_harmonics,
                "edges_deg": [[math.degrees(t), s] for t, s in self.edges],
                "coef": {t: self.coef[i].tolist() for i, t in enumerate(self.targets)},
                "lambda": dict(zip(self.targets, self.lam)), "errors": json_clean(self.errors)}

    @classmethod
    def from_dict(cls, d, where: str, edges) -> "GroovedFilmFit":
        """The fit of a file's key ``film`` with kind 'grooved', for the bearing's supply ``edges``."""
        degree, harmonics = read_int(d, "degree", where), read_int(d, "harmonics", where)
        phi_harmonics = read_int(d, "phi_harmonics", where)
        if degree > MAX_DEGREE or max(harmonics, phi_harmonics) > MAX_HARMONICS:
            raise ValueError(f"{where}: degree {degree} must be <= {MAX_DEGREE}, harmonics {harmonics} and "
                             f"phi_harmonics {phi_harmonics} <= {MAX_HARMONICS}")
        rec = get_key(d, "edges_deg", where)
        want = [[math.degrees(t), s] for t, s in edges]
        if not (isinstance(rec, list) and len(rec) == len(want) and all(
                isinstance(r, list) and len(r) == 2 and abs(r[0] - w[0]) <= 1e-9 * 360 and r[1] == w[1]
                for r, w in zip(rec, want))):
            raise ValueError(f"{where}: key 'edges_deg' = {rec!r:.80} must list the bearing's supply edges "
                             f"[theta_deg, sign]: {want}")
        nf = (2 * phi_harmonics + 1) * n_features(degree, harmonics)
        targets = ("J_s",) + tuple(f"P_{k + 1}" for k in range(len(edges)))
        c = get_key(d, "coef", where)
        coef = np.array([read_vector(c, t, nf, f"{where}: coef") for t in targets])
        lam = ()
        if "lambda" in d:
            ld = get_key(d, "lambda", where)
            lam = tuple(read_number(ld, t, f"{where}: lambda", minimum=0.0) for t in targets)
        errors = read_object(d, "errors", where) if "errors" in d else {}
        return cls(degree, harmonics, phi_harmonics, tuple(edges), coef, lam, errors)


def film_from_dict(d, where: str, geometry):
    """The film fit of a file's key ``film`` for a bearing of bore ``geometry``: the full bore's
    (``FilmFit``, no key 'kind') or a grooved or partial-arc bore's (kind 'grooved'), each only
    for its own bore."""
    kind = d.get("kind", "full") if isinstance(d, dict) else "full"
    if kind not in ("full", GROOVED):
        raise ValueError(f"{where}: key 'kind' = {kind!r} must be 'grooved' (absent: the full bore)")
    if (kind == GROOVED) == geometry.is_full_bore:
        raise ValueError(f"{where}: a film fit of kind {kind!r} is for " + (
            "a grooved or partial-arc bore" if kind == GROOVED else "the full 360 deg bore")
            + f", the bearing has '{geometry.describe()}'")
    if kind == GROOVED:
        return GroovedFilmFit.from_dict(d, where, geometry.supply_edges())
    return FilmFit.from_dict(d, where)


__all__ = ["FilmFit", "GROOVED", "GroovedFilmFit", "TARGETS", "MEANING", "features", "film_from_dict",
           "grooved_features", "n_features", "trig"]
