"""The Taylor surrogate as data: the fitted model with its metadata and its JSON file.

``Surrogate`` holds the coefficients of the monomial basis (:mod:`bearing_fmu.surrogates.basis`) and
what the fit recorded (expansion point, fitted ``Domain``, lambda, errors, provenance).

Wall factor (``wall_power`` p, default 0 = the plain polynomial): the force is the polynomial
divided by (1 - eps^2)^p, eps^2 = (y^2 + z^2) / CR^2 the absolute eccentricity ratio squared,

    F_i / F_ref = (1 - eps^2)^(-p) * sum_k c_ik * u^e_k,

so the polynomial only has to follow G = F (1 - eps^2)^p, which stays bounded as the journal
approaches the wall where F grows without bound. With p > 0 the force is undefined at
eps >= 1 (the Taylor internal raises BearingStateError there, as the domain guard does for any p).

Shape columns (``shape_order`` r, optional): F_i += sum_j (a_ij^y S_y + a_ij^z S_z) m_j(u),
S the closed-form short-bearing force (:mod:`bearing_fmu.physics.shortbearing`), m_j the monomials of
order <= r (docs/taylor.md).

Training states (``neighbours``, optional): a compact subset of the states the surrogate was
fitted to, in u, and a radius; the domain guard (:mod:`bearing_fmu.internals.guard`) measures the
distance of a state to its nearest stored point, so a state inside the bounds but far from
every training orbit is out of domain too (docs/taylor.md).

The file: ``save_surrogate`` / ``load_surrogate`` (format ``bearing-fmu-taylor-surrogate``,
version 1; older files without ``wall_power``, ``shape`` or ``neighbours`` load as the plain
polynomial, without shape columns, guarded by the bounds only). ``load_surrogate`` checks the
whole file (every key the evaluation needs, its type, shape, range and consistency) and names
the file and the key; ``check_params`` refuses a file fitted for another bearing. The evaluation is
:class:`bearing_fmu.internals.taylor.Taylor`; fitting lives in :mod:`bearing_fmu.fitting`.
"""

from __future__ import annotations

import datetime as _dt
import json
import math
from dataclasses import dataclass, field
from numbers import Integral
from pathlib import Path

import numpy as np

from ..io.schema import Key, check_keys
from ..physics.params import BearingParams
from .basis import N_VARS, design_matrix, exponents, n_terms, shape_force

FILE_FORMAT = "bearing-fmu-taylor-surrogate"
FILE_VERSION = 1
SHAPE_ROWS = ("Fy_Sy", "Fy_Sz", "Fz_Sy", "Fz_Sz")  # shape_coef rows: force component by short-bearing component


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
            ecc_max=_num(d, "ecc_max", where),
            pos_center=tuple(_vec(d, "pos_center", 2, where)),
            pos_radius=_num(d, "pos_radius", where),
            v_max=_num(d, "v_max", where),
            box_lo=tuple(_vec(d, "box_lo", 4, where)),
            box_hi=tuple(_vec(d, "box_hi", 4, where)),
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
    radius : in units of u; a state whose nearest stored point lies farther than ``radius``
             is outside the fitted domain (its excess (nn - radius) / the domain's size:
             guard.NearestTraining)
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
        return {"space": NEIGHBOURS_SPACE, "radius": self.radius, **_json_clean(self.info),
                "n_points": int(len(self.points)), "points": self.points.tolist()}

    @classmethod
    def from_dict(cls, d, where: str = "neighbours") -> "Neighbours":
        if not isinstance(d, dict):
            raise ValueError(f"{where}: expected a JSON object, got {d!r:.60}")
        pts = _get(d, "points", where)
        rows_ok = [isinstance(row, list) and len(row) == N_VARS and all(_is_number(x) for x in row)
                   for row in pts] if isinstance(pts, list) else []
        if not all(rows_ok) or not rows_ok:
            bad = f"; row {rows_ok.index(False)} is {pts[rows_ok.index(False)]!r:.60}" if not all(rows_ok) else ""
            raise ValueError(f"{where}: key 'points' must be a non-empty list of [u1, u2, u3, u4] rows of finite "
                             f"numbers{bad}")
        if "n_points" in d and d["n_points"] != len(pts):
            raise ValueError(f"{where}: key 'n_points' is {d['n_points']!r} but 'points' has {len(pts)} rows "
                             "(a truncated or edited file)")
        radius = _num(d, "radius", where)
        info = {k: v for k, v in d.items() if k not in ("space", "radius", "points", "n_points")}
        try:
            return cls(np.array(pts, float), radius, info)
        except ValueError as exc:
            raise ValueError(f"{where}: {str(exc).removeprefix('Neighbours: ')}") from None


# ----------------------------------------------------------------------------- surrogate

@dataclass
class Surrogate:
    """Everything a fitted Taylor surrogate is: the model and its metadata.

    coef[i, k] is the scaled coefficient of term ``exponents[k]`` for force component i
    (0: Fy, 1: Fz); F_i = force_scale * sum_k coef[i, k] * prod_v u_v^exponents[k, v].
    Pruned terms have coef = 0 and kept = False. With ``wall_power`` p > 0 that sum is divided
    by (1 - eps^2)^p, eps^2 = (y^2 + z^2) / CR^2 (see the module doc); p = 0 (files without the
    key) is the plain polynomial.
    """

    params: BearingParams
    omega: float
    y0: float
    z0: float
    order: int
    exponents: np.ndarray
    coef: np.ndarray
    force_scale: float
    domain: Domain
    kept: np.ndarray | None = None
    lam: tuple[float, float] = (0.0, 0.0)
    load: tuple[float, float] | None = None
    errors: dict = field(default_factory=dict)
    pruning: dict = field(default_factory=dict)
    provenance: dict = field(default_factory=dict)
    wall_power: float = 0.0
    shape_order: int | None = None
    shape_coef: np.ndarray | None = None
    neighbours: Neighbours | None = None

    def __post_init__(self) -> None:
        self.order = int(self.order)
        self.exponents = np.ascontiguousarray(self.exponents, dtype=np.int64).reshape(-1, N_VARS)
        self.coef = np.ascontiguousarray(self.coef, dtype=float).reshape(2, -1)
        n = self.exponents.shape[0]
        if self.coef.shape[1] != n:
            raise ValueError(f"Surrogate: {self.coef.shape[1]} coefficients per component for {n} terms")
        if n and int(self.exponents.sum(axis=1).max()) > self.order:
            raise ValueError(f"Surrogate: exponents exceed the order {self.order}")
        if self.kept is None:
            self.kept = self.coef != 0.0
        self.kept = np.asarray(self.kept, bool).reshape(2, n)
        for name in ("omega", "y0", "z0", "force_scale"):
            v = float(getattr(self, name))
            if not math.isfinite(v):
                raise ValueError(f"Surrogate.{name} = {v!r} is not finite")
            setattr(self, name, v)
        if self.omega == 0.0:
            raise ValueError("Surrogate.omega must be nonzero (velocities are scaled by omega * CR)")
        if not np.all(np.isfinite(self.coef)):
            raise ValueError("Surrogate.coef has non-finite entries")
        self.lam = (float(self.lam[0]), float(self.lam[1]))
        self.wall_power = float(self.wall_power)
        if not (math.isfinite(self.wall_power) and self.wall_power >= 0.0):
            raise ValueError(f"Surrogate.wall_power = {self.wall_power!r} must be finite and >= 0")
        if self.shape_order is None:
            if self.shape_coef is not None:
                raise ValueError("Surrogate.shape_coef given without shape_order")
        else:
            if isinstance(self.shape_order, bool) or not isinstance(self.shape_order, Integral) or self.shape_order < 0:
                raise ValueError(f"Surrogate.shape_order = {self.shape_order!r} must be an integer >= 0")
            self.shape_order = int(self.shape_order)
            nr = n_terms(self.shape_order)
            sc = np.ascontiguousarray(self.shape_coef, dtype=float)
            if sc.shape != (4, nr):
                raise ValueError(f"Surrogate.shape_coef must have shape (4, {nr}) for shape_order "
                                 f"{self.shape_order}, got {sc.shape}")
            if not np.all(np.isfinite(sc)):
                raise ValueError("Surrogate.shape_coef has non-finite entries")
            self.shape_coef = sc
        if self.neighbours is not None and not isinstance(self.neighbours, Neighbours):
            raise ValueError(f"Surrogate.neighbours must be a Neighbours or None, got {type(self.neighbours).__name__}")

    @property
    def shape_exponents(self) -> np.ndarray:
        """Exponents of the monomials m_j that multiply the shape columns ((0, 4) without them)."""
        if self.shape_order is None:
            return np.zeros((0, N_VARS), np.int64)
        return exponents(self.shape_order)

    @property
    def pos_scale(self) -> float:
        return self.params.CR

    @property
    def vel_scale(self) -> float:
        return abs(self.omega) * self.params.CR

    def scaled(self, states) -> np.ndarray:
        """Raw states (M, 4) = (y, z, vy, vz) [m, m/s] -> scaled u (M, 4)."""
        s = np.atleast_2d(np.asarray(states, float))
        return np.column_stack([
            (s[:, 0] - self.y0) / self.pos_scale, (s[:, 1] - self.z0) / self.pos_scale,
            s[:, 2] / self.vel_scale, s[:, 3] / self.vel_scale,
        ])

    def wall_factor(self, states) -> np.ndarray:
        """(1 - eps^2)^(-wall_power) at raw states (M, 4) -> (M,); ones for wall_power 0
        (NaN or inf at eps >= 1 for wall_power > 0)."""
        s = np.atleast_2d(np.asarray(states, float))
        if self.wall_power == 0.0:
            return np.ones(len(s))
        q = 1.0 - (s[:, 0] ** 2 + s[:, 1] ** 2) / self.pos_scale**2
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(q > 0, q, np.nan) ** (-self.wall_power)

    def predict(self, states) -> np.ndarray:
        """Vectorised numpy evaluation: raw states (M, 4) -> forces (M, 2) [N]. No checks
        (NaN at eps >= 1 with a wall factor)."""
        X = design_matrix(self.scaled(states), self.exponents)
        F = (X @ self.coef.T) * self.force_scale
        if self.wall_power != 0.0:
            F *= self.wall_factor(states)[:, None]
        if self.shape_order is not None:
            F += self.shape_part(states)
        return F

    def shape_part(self, states, S=None) -> np.ndarray:
        """The shape columns' share of the force at raw states (M, 4) -> (M, 2) [N]:
        sum_j (a_ij^y S_y + a_ij^z S_z) m_j(u). ``S`` (M, >= 2): the short-bearing force there,
        if the caller has it."""
        s = np.atleast_2d(np.asarray(states, float))
        if self.shape_order is None:
            return np.zeros((len(s), 2))
        if S is None:
            from .taylor_kernels import short_bearing_at  # compiled; only surrogates with shape columns need it

            S = short_bearing_at(self.params, s, self.omega)
        return shape_force(self.scaled(s), S, self.shape_exponents, self.shape_coef)

    @property
    def recipe(self) -> str:
        """Short description of the model's form, e.g. 'order 7, wall factor 1.25, shape columns 3'."""
        parts = [f"order {self.order}"]
        if self.wall_power:
            parts.append(f"wall factor {self.wall_power:g}")
        if self.shape_order is not None:
            parts.append(f"shape columns {self.shape_order}")
        return ", ".join(parts)

    def n_kept(self) -> tuple[int, int]:
        return int(self.kept[0].sum()), int(self.kept[1].sum())

    # ------------------------------------------------------------------ file I/O
    def to_dict(self) -> dict:
        from .. import __version__

        prov = dict(self.provenance)
        prov.setdefault("package_version", __version__)
        prov.setdefault("date", _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"))
        return {
            "format": FILE_FORMAT,
            "version": FILE_VERSION,
            "params": self.params.as_dict(),
            "omega": self.omega,
            "speed_hz": self.omega / (2 * math.pi),
            "load": None if self.load is None else [float(self.load[0]), float(self.load[1])],
            "expansion_point": {"y0": self.y0, "z0": self.z0, "vy0": 0.0, "vz0": 0.0},
            "scaling": {
                "pos_scale": self.pos_scale, "vel_scale": self.vel_scale, "force_scale": self.force_scale,
                "variables": "u = ((y-y0)/CR, (z-z0)/CR, vy/(omega CR), vz/(omega CR)); F = force_scale * sum coef * u^e"
                             + ("" if self.wall_power == 0.0 else " / (1 - (y^2 + z^2)/CR^2)^wall_power"),
            },
            "wall_power": self.wall_power,
            **({} if self.shape_order is None else {"shape": {
                "order": self.shape_order,
                "model": "F_i += sum_j (a_ij^y S_y + a_ij^z S_z) m_j(u): S = short-bearing (Ocvirk, pi-film) "
                         "force [N] at (y, z, vy, vz, omega) (bearing_fmu.physics.shortbearing), m_j(u) = prod_v u_v^e_jv",
                "exponents": self.shape_exponents.tolist(),
                "coef": {k: self.shape_coef[i].tolist() for i, k in enumerate(SHAPE_ROWS)},
            }}),
            "order": self.order,
            "n_terms": int(self.exponents.shape[0]),
            "exponents": self.exponents.tolist(),
            "coef": {"Fy": self.coef[0].tolist(), "Fz": self.coef[1].tolist()},
            "kept": {"Fy": self.kept[0].astype(int).tolist(), "Fz": self.kept[1].astype(int).tolist()},
            "lambda": {"Fy": self.lam[0], "Fz": self.lam[1]},
            "domain": self.domain.to_dict(),
            "errors": _json_clean(self.errors),
            "pruning": _json_clean(self.pruning),
            "provenance": _json_clean(prov),
            **({} if self.neighbours is None else {"neighbours": self.neighbours.to_dict()}),
        }

    @classmethod
    def from_dict(cls, d: dict, where: str = "surrogate") -> "Surrogate":
        """The surrogate of a file's content, every key checked (type, shape, range, consistency);
        errors name ``where`` and the key."""
        if not isinstance(d, dict):
            raise ValueError(f"{where}: expected a JSON object at the top level")
        check_keys(d, FILE_KEYS, where, SurrogateKeyError)
        fmt = d.get("format")
        if fmt != FILE_FORMAT:
            raise ValueError(f"{where}: key 'format' is {fmt!r}, expected {FILE_FORMAT!r}")
        if d.get("version") != FILE_VERSION:
            raise ValueError(f"{where}: key 'version' is {d.get('version')!r}, this reader knows {FILE_VERSION}")
        params = _params(d, where)
        omega = _num(d, "omega", where)
        if omega == 0.0:
            raise ValueError(f"{where}: key 'omega' must be nonzero (velocities are scaled by omega * CR)")
        if "speed_hz" in d and not _close(_num(d, "speed_hz", where), omega / (2 * math.pi)):
            raise ValueError(f"{where}: key 'speed_hz' = {d['speed_hz']!r} disagrees with omega = {omega!r} rad/s "
                             f"({omega / (2 * math.pi)!r} Hz)")
        ep = _get(d, "expansion_point", where)
        y0, z0 = _num(ep, "y0", f"{where}: expansion_point"), _num(ep, "z0", f"{where}: expansion_point")
        if math.hypot(y0, z0) >= params.CR:
            raise ValueError(f"{where}: expansion_point (y0, z0) = ({y0!r}, {z0!r}) m is at or beyond the wall "
                             f"(CR = {params.CR!r} m)")
        force_scale = _scaling(d, params, omega, where)
        order = _int(d, "order", where)
        exps = _exponents(d, "exponents", order, where)
        n = len(exps)
        if "n_terms" in d and _int(d, "n_terms", where) != n:
            raise ValueError(f"{where}: key 'n_terms' is {d['n_terms']!r} but 'exponents' has {n} rows")
        c = _get(d, "coef", where)
        coef = np.array([_vec(c, k, n, f"{where}: coef") for k in COMPONENTS])
        kept = None
        if "kept" in d:
            kd = _get(d, "kept", where)
            kept = np.array([_vec(kd, k, n, f"{where}: kept") for k in COMPONENTS])
            if not np.all((kept == 0) | (kept == 1)):
                raise ValueError(f"{where}: kept: every entry must be 0 or 1")
            kept = kept.astype(bool)
        lam = (0.0, 0.0)
        if "lambda" in d:
            ld = _get(d, "lambda", where)
            lam = tuple(_num(ld, k, f"{where}: lambda", minimum=0.0) for k in COMPONENTS)
        load = d.get("load")
        if load is not None:
            load = tuple(_vec(d, "load", 2, where))
        wall_power = _num(d, "wall_power", where, minimum=0.0) if "wall_power" in d else 0.0  # older files: none
        shape_order = shape_coef = None
        if "shape" in d:  # older files: none
            sd = _get(d, "shape", where)
            shape_order = _int(sd, "order", f"{where}: shape")
            nr = n_terms(shape_order)
            if "exponents" in sd and sd["exponents"] != exponents(shape_order).tolist():
                raise ValueError(f"{where}: shape: key 'exponents' is not the full basis of order {shape_order}")
            shc = _get(sd, "coef", f"{where}: shape")
            shape_coef = np.array([_vec(shc, k, nr, f"{where}: shape: coef") for k in SHAPE_ROWS])
        domain = Domain.from_dict(_get(d, "domain", where), f"{where}: domain")
        neighbours = Neighbours.from_dict(d["neighbours"], f"{where}: neighbours") if "neighbours" in d else None
        meta = {k: _table(d, k, where) for k in ("errors", "pruning", "provenance")}
        try:
            return cls(params=params, omega=omega, y0=y0, z0=z0, order=order, exponents=exps, coef=coef,
                       force_scale=force_scale, domain=domain, kept=kept, lam=lam, load=load, **meta,
                       wall_power=wall_power, shape_order=shape_order, shape_coef=shape_coef, neighbours=neighbours)
        except ValueError as exc:  # what only the whole model can check (e.g. an exponent beyond the order)
            raise ValueError(f"{where}: {exc}") from None


COMPONENTS = ("Fy", "Fz")

# The top-level keys of a surrogate file (docs/taylor.md, File); the loader checks each value.
FILE_KEYS = (
    Key("format", "file format name", allowed=repr(FILE_FORMAT)),
    Key("version", "file format version", allowed=str(FILE_VERSION)),
    Key("params", "the bearing: D, L, CR [m], mu [Pa s]", allowed="numbers > 0, CR < D/2"),
    Key("omega", "shaft speed the surrogate was fitted at [rad/s]", allowed="a finite nonzero number"),
    Key("speed_hz", "omega / 2 pi [Hz], for readers", None, "equal to omega / 2 pi"),
    Key("load", "static bearing load (Wy, Wz) [N]", None, "two numbers or null"),
    Key("expansion_point", "y0, z0 [m] (vy0, vz0 = 0)", allowed="inside the clearance"),
    Key("scaling", "pos_scale = CR, vel_scale = |omega| CR, force_scale [N]", allowed="force_scale > 0"),
    Key("wall_power", "wall factor exponent p", 0.0, ">= 0"),
    Key("shape", "short-bearing shape columns: order, exponents, coef", None, "a table"),
    Key("order", "total degree of the polynomial", allowed="an integer >= 0"),
    Key("n_terms", "number of monomials (rows of exponents)", None, "equal to the rows of exponents"),
    Key("exponents", "the monomials' powers of (u1, u2, u3, u4)", allowed="integer rows of 4, degree <= order"),
    Key("coef", "coefficients Fy, Fz per monomial", allowed="n_terms finite numbers each"),
    Key("kept", "terms kept by pruning, Fy, Fz", None, "n_terms 0/1 each"),
    Key("lambda", "ridge penalty Fy, Fz", None, "numbers >= 0"),
    Key("domain", "the fitted domain's bounds", allowed="see Domain"),
    Key("errors", "the fit's errors", None, "a table"),
    Key("pruning", "the pruning's record", None, "a table"),
    Key("provenance", "truth, training data, recipe, date, version", None, "a table"),
    Key("neighbours", "training states for the nearest-neighbour guard: radius, points in u", None, "a table"),
)


class SurrogateKeyError(KeyError):
    """A missing or unknown key of a surrogate file (a KeyError whose text reads as a sentence)."""

    def __str__(self) -> str:
        return str(self.args[0]) if self.args else ""


def _json_clean(obj):
    """Metadata for JSON: numpy scalars/arrays to Python, non-finite floats to None."""
    if isinstance(obj, dict):
        return {str(k): _json_clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_json_clean(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _json_clean(obj.tolist())
    if isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def _is_number(x) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def _close(a: float, b: float, rtol: float = 1e-9) -> bool:
    return abs(a - b) <= rtol * max(abs(a), abs(b))


def _get(d: dict, key: str, where: str):
    if not isinstance(d, dict):
        raise ValueError(f"{where}: expected a JSON object, got {d!r:.60}")
    if key not in d:
        raise SurrogateKeyError(f"{where}: missing key {key!r}")
    return d[key]


def _num(d: dict, key: str, where: str, minimum: float | None = None) -> float:
    v = _get(d, key, where)
    if not _is_number(v):
        raise ValueError(f"{where}: key {key!r} must be a finite number, got {v!r:.60}")
    if minimum is not None and v < minimum:
        raise ValueError(f"{where}: key {key!r} = {v!r} must be >= {minimum:g}")
    return float(v)


def _int(d: dict, key: str, where: str) -> int:
    v = _get(d, key, where)
    if isinstance(v, bool) or not isinstance(v, int) or v < 0:
        raise ValueError(f"{where}: key {key!r} must be a non-negative integer, got {v!r:.60}")
    return v


def _vec(d: dict, key: str, n: int, where: str) -> list[float]:
    v = _get(d, key, where)
    if not isinstance(v, list) or len(v) != n:
        got = f"{len(v)} entries" if isinstance(v, list) else repr(v)[:60]
        raise ValueError(f"{where}: key {key!r} must be a list of {n} numbers, each finite, got {got}")
    bad = next((i for i, x in enumerate(v) if not _is_number(x)), None)
    if bad is not None:
        raise ValueError(f"{where}: key {key!r} must be a list of {n} numbers, each finite; entry {bad} is "
                         f"{v[bad]!r:.60}")
    return [float(x) for x in v]


def _table(d: dict, key: str, where: str) -> dict:
    v = d.get(key, {})
    if not isinstance(v, dict):
        raise ValueError(f"{where}: key {key!r} must be a JSON object, got {v!r:.60}")
    return v


def _params(d: dict, where: str) -> BearingParams:
    p = _get(d, "params", where)
    values = {k: _num(p, k, f"{where}: params") for k in ("D", "L", "CR", "mu")}
    try:
        return BearingParams(**values)
    except ValueError as exc:
        raise ValueError(f"{where}: params: {exc}") from None


def _scaling(d: dict, params: BearingParams, omega: float, where: str) -> float:
    """The force scale, after checking the stored position and velocity scales are CR and |omega| CR."""
    sc = _get(d, "scaling", where)
    fs = _num(sc, "force_scale", f"{where}: scaling")
    if fs <= 0.0:
        raise ValueError(f"{where}: scaling: key 'force_scale' = {fs!r} must be > 0")
    for key, want, what in (("pos_scale", params.CR, "CR"), ("vel_scale", abs(omega) * params.CR, "|omega| CR")):
        if key in sc and not _close(_num(sc, key, f"{where}: scaling"), want):
            raise ValueError(f"{where}: scaling: key {key!r} = {sc[key]!r} disagrees with {what} = {want!r}")
    return fs


def _exponents(d: dict, key: str, order: int, where: str) -> np.ndarray:
    v = _get(d, key, where)
    rows_ok = [isinstance(row, list) and len(row) == N_VARS
               and all(isinstance(e, int) and not isinstance(e, bool) and e >= 0 for e in row)
               for row in v] if isinstance(v, list) else [False]
    if not all(rows_ok):
        bad = f"; row {rows_ok.index(False)} is {v[rows_ok.index(False)]!r:.60}" if isinstance(v, list) else ""
        raise ValueError(f"{where}: key {key!r} must be a list of [e_dy, e_dz, e_dvy, e_dvz] rows of "
                         f"non-negative integers{bad}")
    exps = np.array(v, np.int64).reshape(-1, N_VARS)
    if len(exps) and int(exps.sum(axis=1).max()) > order:
        raise ValueError(f"{where}: key {key!r} has a term of degree {int(exps.sum(axis=1).max())} above "
                         f"the order {order}")
    return exps


def surrogate_json(data: dict) -> str:
    """The text of a surrogate file: ``json.dumps(data, indent=1)`` (one value a line, as
    every file so far), except the neighbours' points, one [u1, u2, u3, u4] row a line."""
    nb = data.get("neighbours")
    if not isinstance(nb, dict) or "points" not in nb:
        return json.dumps(data, indent=1, allow_nan=False) + "\n"
    mark = "@@neighbour-points@@"
    rows = ",\n".join("   " + json.dumps(row, allow_nan=False) for row in nb["points"])
    text = json.dumps({**data, "neighbours": {**nb, "points": mark}}, indent=1, allow_nan=False)
    return text.replace(json.dumps(mark), "[\n" + rows + "\n  ]") + "\n"


def save_surrogate(surrogate: Surrogate, path: str | Path) -> Path:
    """Write the surrogate JSON file (creating its directory)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    from ..io.outputs import write_text  # not bundled in the FMU, which never writes a surrogate

    return write_text(path, surrogate_json(surrogate.to_dict()))


def check_params(surrogate: Surrogate, params: BearingParams, where: str = "surrogate", rtol: float = 1e-9) -> None:
    """Refuse a surrogate fitted for a different bearing, naming the field and both values."""
    for name in ("D", "L", "CR", "mu"):
        a, b = getattr(surrogate.params, name), getattr(params, name)
        if abs(a - b) > rtol * max(abs(a), abs(b)):
            raise ValueError(
                f"{where}: fitted for bearing {name} = {a!r}, but used with {name} = {b!r} "
                "(a surrogate is only valid for the bearing it was fitted to)"
            )


def load_surrogate(path: str | Path, params: BearingParams | None = None) -> Surrogate:
    """Read a surrogate file; with ``params`` also check it belongs to that bearing."""
    path = Path(path)
    where = f"surrogate file {str(path)!r}"
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise FileNotFoundError(f"{where} not found") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ValueError(f"{where} cannot be read as text: {getattr(exc, 'strerror', None) or exc}") from None
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise ValueError(f"{where} is not valid JSON (truncated or damaged?): line {exc.lineno}, column {exc.colno}: "
                         f"{exc.msg}") from None
    sur = Surrogate.from_dict(data, where)
    if params is not None:
        check_params(sur, params, where)
    return sur


__all__ = ["FILE_FORMAT", "FILE_VERSION", "FILE_KEYS", "SHAPE_ROWS", "Domain", "Neighbours", "Surrogate",
           "SurrogateKeyError", "save_surrogate", "load_surrogate", "surrogate_json", "check_params"]
