"""The Taylor surrogate's film fit: the film's inflow and side flow by the force map's reduction,
their two functions of (eps, beta) fitted beside the force (``bearing_fmu.fitting.flows``) and
stored in the surrogate file (key ``film``, format version 2).

The reduction (``physics.film``, docs/forcemap.md "The flows"; exact for the full bore at any
speed): with eps the eccentricity ratio, a = eps (omega - 2 phidot), c = 2 epsdot, r = |(a, c)|,
beta = atan2(c, a) (``internals.forcemap.reduced``) and Q0 = R L CR,

    side flow  Q_s = r Q0 J_s(eps, beta)
    inflow     Q   = | omega Q0 (1 + eps) / 2 - r Q0 J_i(eps, beta) |

so the fit holds two smooth speed-free functions, each sum_k coef_k eps^i_k trig_k(beta) (trig:
1, cos m beta, sin m beta up to ``harmonics``). The friction needs no fit: the closed form of the
full bore from the surrogate's own force (``film.full_bore_friction``), as the map has it. A bore
other than the full circle breaks the reduction (grooves fix directions): no film fit there.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .domain import get_key, json_clean, read_int, read_number, read_object, read_vector

TARGETS = ("J_s", "J_i")
MEANING = ("side flow r R L CR J_s, inflow |omega R L CR (1 + eps) / 2 - r R L CR J_i|; each J = sum_k coef_k "
           "eps^(k // (2 harmonics + 1)) t_(k % (2 harmonics + 1))(beta), t = 1, cos beta, sin beta, cos 2 beta, ...")
MAX_DEGREE, MAX_HARMONICS = 12, 24


def n_features(degree: int, harmonics: int) -> int:
    return (degree + 1) * (2 * harmonics + 1)


def features(eps, beta, degree: int, harmonics: int) -> np.ndarray:
    """(M, n_features): eps^i t_j(beta), i = 0 .. degree (outer), t_j = 1, cos beta, sin beta,
    cos 2 beta, ... (inner)."""
    eps, beta = np.atleast_1d(np.asarray(eps, float)), np.atleast_1d(np.asarray(beta, float))
    t = [np.ones_like(beta)]
    for m in range(1, harmonics + 1):
        t += [np.cos(m * beta), np.sin(m * beta)]
    T = np.stack(t, axis=1)
    P = eps[:, None] ** np.arange(degree + 1)
    return (P[:, :, None] * T[:, None, :]).reshape(len(eps), -1)


@dataclass
class FilmFit:
    """The fitted flow functions: coef[0] of J_s, coef[1] of J_i over ``features(degree,
    harmonics)``; ``lam`` the ridge penalty of each; ``errors`` what the fit measured."""

    degree: int
    harmonics: int
    coef: np.ndarray
    lam: tuple = (0.0, 0.0)
    errors: dict = field(default_factory=dict)

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


__all__ = ["FilmFit", "TARGETS", "MEANING", "features", "n_features"]
