"""The readers of a surrogate file's values and the two parts of it the domain guard uses:
the fitted ``Domain`` (bounds) and the ``Neighbours`` (training states).

Apart from ``surrogate.py`` so that the file's model (coefficients, scaling, I/O) and its
fitted domain, which the guard and the fitting code use on their own, each stay one module
under the size limit. The readers (``get_key``, ``read_number``, ``read_int``, ``read_vector``,
``read_object``) check one value of a JSON object and raise ValueError (``SurrogateKeyError``
for a missing key) naming the file and the key, what was expected and what was given.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .basis import N_VARS

# ----------------------------------------------------------------------------- reading values

class SurrogateKeyError(KeyError):
    """A missing or unknown key of a surrogate file (a KeyError whose text reads as a sentence)."""

    def __str__(self) -> str:
        return str(self.args[0]) if self.args else ""


def json_clean(obj):
    """Metadata for JSON: numpy scalars/arrays to Python, non-finite floats to None."""
    if isinstance(obj, dict):
        return {str(k): json_clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [json_clean(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return json_clean(obj.tolist())
    if isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def is_number(x) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def close_to(a: float, b: float, rtol: float = 1e-9) -> bool:
    return abs(a - b) <= rtol * max(abs(a), abs(b))


def get_key(d: dict, key: str, where: str):
    if not isinstance(d, dict):
        raise ValueError(f"{where}: expected a JSON object, got {d!r:.60}")
    if key not in d:
        raise SurrogateKeyError(f"{where}: missing key {key!r}")
    return d[key]


def read_number(d: dict, key: str, where: str, minimum: float | None = None) -> float:
    v = get_key(d, key, where)
    if not is_number(v):
        raise ValueError(f"{where}: key {key!r} must be a finite number, got {v!r:.60}")
    if minimum is not None and v < minimum:
        raise ValueError(f"{where}: key {key!r} = {v!r} must be >= {minimum:g}")
    return float(v)


def read_int(d: dict, key: str, where: str) -> int:
    v = get_key(d, key, where)
    if isinstance(v, bool) or not isinstance(v, int) or v < 0:
        raise ValueError(f"{where}: key {key!r} must be a non-negative integer, got {v!r:.60}")
    return v


def read_vector(d: dict, key: str, n: int, where: str) -> list[float]:
    v = get_key(d, key, where)
    if not isinstance(v, list) or len(v) != n:
        got = f"{len(v)} entries" if isinstance(v, list) else repr(v)[:60]
        raise ValueError(f"{where}: key {key!r} must be a list of {n} numbers, each finite, got {got}")
    bad = next((i for i, x in enumerate(v) if not is_number(x)), None)
    if bad is not None:
        raise ValueError(f"{where}: key {key!r} must be a list of {n} numbers, each finite; entry {bad} is "
                         f"{v[bad]!r:.60}")
    return [float(x) for x in v]


def read_object(d: dict, key: str, where: str) -> dict:
    v = d.get(key, {})
    if not isinstance(v, dict):
        raise ValueError(f"{where}: key {key!r} must be a JSON object, got {v!r:.60}")
    return v


# ----------------------------------------------------------------------------- fitted domain

@dataclass(frozen=True)
class Domain:
    """Where the surrogate was fitted, for the guard (a caller decides what to do outside).

    All lengths in scaled units: positions in CR, velocities in omega * CR.
      ecc_max    : bound on the eccentricity ratio |(y, z)| / CR of the training states
      pos_center : centre of the position disc, relative to the expansion point (in CR)
      pos_radius : radius of the position disc (in CR)
      v_max      : radius of the velocity disc |(vy, vz)| / (omega CR)
      box_lo/hi  : bounding box of the training states in u = (dy, dz, dvy, dvz) scaled
    A state is inside when it satisfies all of them.
    """

    ecc_max: float
    pos_center: tuple[float, float]
    pos_radius: float
    v_max: float
    box_lo: tuple[float, float, float, float]
    box_hi: tuple[float, float, float, float]

    def __post_init__(self) -> None:
        problem = self.problem()
        if problem:
            raise ValueError(f"Domain: {problem}")

    def problem(self) -> str | None:
        """What makes these bounds inconsistent (non-finite, ecc_max outside (0, 1], a negative
        radius, box_lo > box_hi), or None."""
        values = [self.ecc_max, *self.pos_center, self.pos_radius, self.v_max, *self.box_lo, *self.box_hi]
        if not all(math.isfinite(float(v)) for v in values):
            return f"every bound must be finite, got {self.to_dict()}"
        if not 0.0 < self.ecc_max <= 1.0:
            return f"ecc_max = {self.ecc_max!r} must lie in (0, 1] (an eccentricity ratio)"
        for name in ("pos_radius", "v_max"):
            if getattr(self, name) < 0.0:
                return f"{name} = {getattr(self, name)!r} must be >= 0"
        for i, (lo, hi) in enumerate(zip(self.box_lo, self.box_hi)):
            if lo > hi:
                return f"box_lo[{i}] = {lo!r} > box_hi[{i}] = {hi!r}; the box needs box_lo <= box_hi"
        return None

    def to_dict(self) -> dict:
        return {
            "ecc_max": self.ecc_max, "pos_center": list(self.pos_center), "pos_radius": self.pos_radius,
            "v_max": self.v_max, "box_lo": list(self.box_lo), "box_hi": list(self.box_hi),
        }

    @classmethod
    def from_dict(cls, d: dict, where: str = "domain") -> "Domain":
        values = dict(
            ecc_max=read_number(d, "ecc_max", where),
            pos_center=tuple(read_vector(d, "pos_center", 2, where)),
            pos_radius=read_number(d, "pos_radius", where),
            v_max=read_number(d, "v_max", where),
            box_lo=tuple(read_vector(d, "box_lo", 4, where)),
            box_hi=tuple(read_vector(d, "box_hi", 4, where)),
        )
        try:
            return cls(**values)
        except ValueError as exc:
            raise ValueError(f"{where}: {str(exc).removeprefix('Domain: ')}") from None


# ----------------------------------------------------------------------------- training states

NEIGHBOURS_SPACE = "u (scaling.variables); Euclidean distance"


@dataclass(eq=False)
class Neighbours:
    """Training states for the nearest-neighbour part of the domain guard.

    points : (K, 4) scaled states u (see ``Surrogate.scaled``) chosen from the states the
             surrogate was fitted to (bearing_fmu.fitting.neighbours: farthest-point thinning,
             rounded)
    radius : in units of u, r_cv (their spacing); a state whose nearest stored point lies
             farther than the larger of it and r_lin is outside the fitted domain (its excess
             (nn - radius) / the domain's size: guard.NearestTraining)
    info   : how points and radius were chosen (rule, counts, covering radius, spacing), kept
             in the file as written
    """

    points: np.ndarray
    radius: float
    info: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        p = np.ascontiguousarray(self.points, dtype=float)
        if p.ndim != 2 or p.shape[1] != N_VARS or p.shape[0] == 0:
            raise ValueError(f"Neighbours: points must be a non-empty list of [u1, u2, u3, u4] rows, got shape "
                             f"{p.shape}")
        if not np.all(np.isfinite(p)):
            raise ValueError("Neighbours: points has non-finite entries")
        r = float(self.radius)
        if not (math.isfinite(r) and r > 0.0):
            raise ValueError(f"Neighbours: radius = {self.radius!r} must be finite and > 0 (units of u)")
        self.points, self.radius, self.info = p, r, dict(self.info)

    def to_dict(self) -> dict:
        return {"space": NEIGHBOURS_SPACE, "radius": self.radius, **json_clean(self.info),
                "n_points": int(len(self.points)), "points": self.points.tolist()}

    @classmethod
    def from_dict(cls, d, where: str = "neighbours") -> "Neighbours":
        if not isinstance(d, dict):
            raise ValueError(f"{where}: expected a JSON object, got {d!r:.60}")
        pts = get_key(d, "points", where)
        rows_ok = [isinstance(row, list) and len(row) == N_VARS and all(is_number(x) for x in row)
                   for row in pts] if isinstance(pts, list) else []
        if not all(rows_ok) or not rows_ok:
            bad = f"; row {rows_ok.index(False)} is {pts[rows_ok.index(False)]!r:.60}" if not all(rows_ok) else ""
            raise ValueError(f"{where}: key 'points' must be a non-empty list of [u1, u2, u3, u4] rows of finite "
                             f"numbers{bad}")
        if "n_points" in d and d["n_points"] != len(pts):
            raise ValueError(f"{where}: key 'n_points' is {d['n_points']!r} but 'points' has {len(pts)} rows "
                             "(a truncated or edited file)")
        radius = read_number(d, "radius", where)
        info = {k: v for k, v in d.items() if k not in ("space", "radius", "points", "n_points")}
        try:
            return cls(np.array(pts, float), radius, info)
        except ValueError as exc:
            raise ValueError(f"{where}: {str(exc).removeprefix('Neighbours: ')}") from None
