"""The Taylor surrogate as data: the fitted model with its metadata and its JSON file.

``Surrogate`` holds the coefficients of the monomial basis (:mod:`bearing_fmu.basis`) and
what the fit recorded (expansion point, fitted ``Domain``, lambda, errors, provenance).

Wall factor (``wall_power`` p, default 0 = the plain polynomial): the force is the polynomial
divided by (1 - eps^2)^p, eps^2 = (y^2 + z^2) / CR^2 the absolute eccentricity ratio squared,

    F_i / F_ref = (1 - eps^2)^(-p) * sum_k c_ik * u^e_k,

so the polynomial only has to follow G = F (1 - eps^2)^p, which stays bounded as the journal
approaches the wall where F grows without bound. With p > 0 the force is undefined at
eps >= 1 (the Taylor internal raises BearingStateError there, as the domain guard does for any p).

Shape columns (``shape_order`` r, optional): F_i += sum_j (a_ij^y S_y + a_ij^z S_z) m_j(u),
S the closed-form short-bearing force (:mod:`bearing_fmu.shortbearing`), m_j the monomials of
order <= r (docs/taylor.md).

The file: ``save_surrogate`` / ``load_surrogate`` (format ``bearing-fmu-taylor-surrogate``,
version 1; older files without ``wall_power`` or ``shape`` load as the plain polynomial),
``check_params`` refuses a file fitted for another bearing. The evaluation is
:class:`bearing_fmu.taylor.Taylor`; fitting lives in :mod:`bearing_fmu.fitting`.
"""

from __future__ import annotations

import datetime as _dt
import json
import math
from dataclasses import dataclass, field
from numbers import Integral
from pathlib import Path

import numpy as np

from .basis import N_VARS, design_matrix, exponents, n_terms, shape_force
from .params import BearingParams

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

    def to_dict(self) -> dict:
        return {
            "ecc_max": self.ecc_max, "pos_center": list(self.pos_center), "pos_radius": self.pos_radius,
            "v_max": self.v_max, "box_lo": list(self.box_lo), "box_hi": list(self.box_hi),
        }

    @classmethod
    def from_dict(cls, d: dict, where: str = "domain") -> "Domain":
        return cls(
            ecc_max=_num(d, "ecc_max", where),
            pos_center=tuple(_vec(d, "pos_center", 2, where)),
            pos_radius=_num(d, "pos_radius", where),
            v_max=_num(d, "v_max", where),
            box_lo=tuple(_vec(d, "box_lo", 4, where)),
            box_hi=tuple(_vec(d, "box_hi", 4, where)),
        )


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
            from ._taylor_kernels import short_bearing_at  # compiled; only surrogates with shape columns need it

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
        from . import __version__

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
                         "force [N] at (y, z, vy, vz, omega) (bearing_fmu.shortbearing), m_j(u) = prod_v u_v^e_jv",
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
        }

    @classmethod
    def from_dict(cls, d: dict, where: str = "surrogate") -> "Surrogate":
        if not isinstance(d, dict):
            raise ValueError(f"{where}: expected a JSON object at the top level")
        fmt = d.get("format")
        if fmt != FILE_FORMAT:
            raise ValueError(f"{where}: key 'format' is {fmt!r}, expected {FILE_FORMAT!r}")
        if d.get("version") != FILE_VERSION:
            raise ValueError(f"{where}: key 'version' is {d.get('version')!r}, this reader knows {FILE_VERSION}")
        p = _get(d, "params", where)
        try:
            params = BearingParams(**{k: _num(p, k, f"{where}: params") for k in ("D", "L", "CR", "mu")})
        except TypeError as exc:  # pragma: no cover - _num already names missing keys
            raise ValueError(f"{where}: params: {exc}") from None
        ep = _get(d, "expansion_point", where)
        sc = _get(d, "scaling", where)
        order = _get(d, "order", where)
        if isinstance(order, bool) or not isinstance(order, int) or order < 0:
            raise ValueError(f"{where}: key 'order' must be a non-negative integer, got {order!r}")
        exps = np.asarray(_get(d, "exponents", where))
        if exps.ndim != 2 or exps.shape[1] != N_VARS or not np.issubdtype(exps.dtype, np.integer):
            raise ValueError(f"{where}: key 'exponents' must be a list of [e_dy, e_dz, e_dvy, e_dvz] integer rows")
        c = _get(d, "coef", where)
        coef = np.array([_vec(c, "Fy", exps.shape[0], f"{where}: coef"), _vec(c, "Fz", exps.shape[0], f"{where}: coef")])
        kept = None
        if "kept" in d:
            kd = d["kept"]
            kept = np.array([_vec(kd, "Fy", exps.shape[0], f"{where}: kept"),
                             _vec(kd, "Fz", exps.shape[0], f"{where}: kept")]).astype(bool)
        lam = d.get("lambda", {"Fy": 0.0, "Fz": 0.0})
        load = d.get("load")
        wall_power = _num(d, "wall_power", where) if "wall_power" in d else 0.0  # older files: none
        shape_order = shape_coef = None
        if "shape" in d:  # older files: none
            sd = _get(d, "shape", where)
            shape_order = _get(sd, "order", f"{where}: shape")
            if isinstance(shape_order, bool) or not isinstance(shape_order, int) or shape_order < 0:
                raise ValueError(f"{where}: shape: key 'order' must be a non-negative integer, got {shape_order!r}")
            nr = n_terms(shape_order)
            if "exponents" in sd and sd["exponents"] != exponents(shape_order).tolist():
                raise ValueError(f"{where}: shape: key 'exponents' is not the full basis of order {shape_order}")
            shc = _get(sd, "coef", f"{where}: shape")
            shape_coef = np.array([_vec(shc, k, nr, f"{where}: shape: coef") for k in SHAPE_ROWS])
        return cls(
            params=params,
            omega=_num(d, "omega", where),
            y0=_num(ep, "y0", f"{where}: expansion_point"),
            z0=_num(ep, "z0", f"{where}: expansion_point"),
            order=order,
            exponents=exps,
            coef=coef,
            force_scale=_num(sc, "force_scale", f"{where}: scaling"),
            domain=Domain.from_dict(_get(d, "domain", where), f"{where}: domain"),
            kept=kept,
            lam=(float(lam.get("Fy", 0.0)), float(lam.get("Fz", 0.0))),
            load=None if load is None else (float(load[0]), float(load[1])),
            errors=d.get("errors", {}),
            pruning=d.get("pruning", {}),
            provenance=d.get("provenance", {}),
            wall_power=wall_power,
            shape_order=shape_order,
            shape_coef=shape_coef,
        )


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


def _get(d: dict, key: str, where: str):
    if not isinstance(d, dict) or key not in d:
        raise KeyError(f"{where}: missing key {key!r}")
    return d[key]


def _num(d: dict, key: str, where: str) -> float:
    v = _get(d, key, where)
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise ValueError(f"{where}: key {key!r} must be a number, got {v!r}")
    return float(v)


def _vec(d: dict, key: str, n: int, where: str) -> list[float]:
    v = _get(d, key, where)
    if not isinstance(v, list) or len(v) != n or not all(
        isinstance(x, (int, float)) and not isinstance(x, bool) for x in v
    ):
        raise ValueError(f"{where}: key {key!r} must be a list of {n} numbers")
    return [float(x) for x in v]


def save_surrogate(surrogate: Surrogate, path: str | Path) -> Path:
    """Write the surrogate JSON file (creating its directory)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    data = surrogate.to_dict()
    text = json.dumps(data, indent=1, allow_nan=False) + "\n"
    from .outputs import write_text  # not bundled in the FMU, which never writes a surrogate

    return write_text(path, text)


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
    try:
        text = path.read_text()
    except FileNotFoundError:
        raise FileNotFoundError(f"surrogate file {str(path)!r} not found") from None
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise ValueError(f"surrogate file {str(path)!r} is not valid JSON: {exc}") from None
    where = f"surrogate file {str(path)!r}"
    sur = Surrogate.from_dict(data, where)
    if params is not None:
        check_params(sur, params, where)
    return sur



__all__ = ["FILE_FORMAT", "FILE_VERSION", "SHAPE_ROWS", "Domain", "Surrogate", "save_surrogate", "load_surrogate",
           "check_params"]
