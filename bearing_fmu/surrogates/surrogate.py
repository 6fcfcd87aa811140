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
S the closed-form short-bearing force (:mod:`bearing_fmu.physics.solver.shortbearing`), m_j the monomials of
order <= r (docs/taylor.md).

Training states (``neighbours``, optional): a compact subset of the states the surrogate was
fitted to, in u, and a radius; the domain guard (:mod:`bearing_fmu.internals.taylor.guard`) measures the
distance of a state to its nearest stored point, so a state inside the bounds but far from
every training orbit is out of domain too (docs/taylor.md).

Film fit (``film``, optional): the film's flows by the force map's reduction, two fitted functions
of eccentricity and one angle for the full bore, or (key 'kind' = 'grooved') the side flow and one
function per supply edge of (eps, phi, beta) for a grooved or partial-arc bore
(:mod:`bearing_fmu.surrogates.film`); a file with it
is format version 2 (FILM_VERSION), one without it version 1, which still loads: such a surrogate
has no film flows (``NO_FLOWS_WHY``).

The file: ``save_surrogate`` / ``load_surrogate`` (format ``bearing-fmu-taylor-surrogate``,
version 1 or 2; older files without ``wall_power``, ``shape`` or ``neighbours`` load as the plain
polynomial, without shape columns, guarded by the bounds only). ``load_surrogate`` checks the
whole file (every key the evaluation needs, its type, shape, range and consistency) and names
the file and the key; ``check_params`` refuses a file fitted for another bearing. ``Domain``,
``Neighbours`` and the value readers are in :mod:`bearing_fmu.surrogates.domain` (importable
from here too). The evaluation is :class:`bearing_fmu.internals.taylor.Taylor`; fitting lives
in :mod:`bearing_fmu.fitting`.
"""

from __future__ import annotations

import datetime as _dt
import json
import math
from dataclasses import dataclass, field
from numbers import Integral
from pathlib import Path

import numpy as np

from ..io.schema import Key, check_keys, find_non_finite
from ..physics.params import BearingParams
from .basis import N_VARS, design_matrix, exponents, n_terms, shape_force
from .domain import (Domain, Neighbours, SurrogateKeyError, close_to, get_key, json_clean, read_int, read_number,
                     read_object, read_vector)
from .film import FilmFit, GroovedFilmFit, film_from_dict

FILE_FORMAT = "bearing-fmu-taylor-surrogate"
FILE_VERSION = 1  # the force alone (read still: such a surrogate has no film flows)
FILM_VERSION = 2  # with the film fit (key 'film')
NO_FLOWS_WHY = ("the surrogate file {source} has no film fit (format version 1, fitted before it was added): fit it "
                "again (`bearing-fmu fit` or `rotor-host fit`), or add the film fit to it, its force unchanged, with "
                "benchmarks/add_film.py, to get the film's inflow, side flow and friction")
SHAPE_ROWS = ("Fy_Sy", "Fy_Sz", "Fz_Sy", "Fz_Sz")  # shape_coef rows: force component by short-bearing component


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
    film: FilmFit | GroovedFilmFit | None = None

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
        if self.film is not None and (self.film.kind == "full") != self.params.geometry.is_full_bore:
            raise ValueError(f"Surrogate.film: a film fit of kind {self.film.kind!r} does not fit the bore "
                             f"'{self.params.geometry.describe()}' (the full bore's reduction holds for it alone)")
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
            "version": FILE_VERSION if self.film is None else FILM_VERSION,
            "params": self.params.as_dict(),
            **({} if self.params.geometry.is_full_bore else {"geometry": self.params.geometry.as_table()}),
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
                         "force [N] at (y, z, vy, vz, omega) (bearing_fmu.physics.solver.shortbearing), m_j(u) = prod_v u_v^e_jv",
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
            "errors": json_clean(self.errors),
            "pruning": json_clean(self.pruning),
            "provenance": json_clean(prov),
            **({} if self.neighbours is None else {"neighbours": self.neighbours.to_dict()}),
            **({} if self.film is None else {"film": self.film.to_dict()}),
        }

    @classmethod
    def from_dict(cls, d: dict, where: str = "surrogate") -> "Surrogate":
        """The surrogate of a file's content, every key checked (type, shape, range, consistency);
        errors name ``where`` and the key."""
        if not isinstance(d, dict):
            raise ValueError(f"{where}: expected a JSON object at the top level")
        check_keys(d, FILE_KEYS, where, SurrogateKeyError, toml=False)  # JSON: no [table] wording
        fmt = d.get("format")
        if fmt != FILE_FORMAT:
            raise ValueError(f"{where}: key 'format' is {fmt!r}, expected {FILE_FORMAT!r}")
        version = d.get("version")
        if version not in (FILE_VERSION, FILM_VERSION) or isinstance(version, bool):
            raise ValueError(f"{where}: key 'version' is {version!r}, this reader knows {FILE_VERSION} and {FILM_VERSION}")
        if (version == FILM_VERSION) != ("film" in d):
            raise ValueError(f"{where}: key 'version' is {version}: " + ("missing key 'film' (the film fit)" if
                             version == FILM_VERSION else f"key 'film' belongs to version {FILM_VERSION} only"))
        params = _params(d, where)
        omega = read_number(d, "omega", where)
        if omega == 0.0:
            raise ValueError(f"{where}: key 'omega' must be nonzero (velocities are scaled by omega * CR)")
        if "speed_hz" in d and not close_to(read_number(d, "speed_hz", where), omega / (2 * math.pi)):
            raise ValueError(f"{where}: key 'speed_hz' = {d['speed_hz']!r} disagrees with omega = {omega!r} rad/s "
                             f"({omega / (2 * math.pi)!r} Hz)")
        ep = get_key(d, "expansion_point", where)
        y0, z0 = read_number(ep, "y0", f"{where}: expansion_point"), read_number(ep, "z0", f"{where}: expansion_point")
        if math.hypot(y0, z0) >= params.CR:
            raise ValueError(f"{where}: expansion_point (y0, z0) = ({y0!r}, {z0!r}) m is at or beyond the wall "
                             f"(CR = {params.CR!r} m)")
        for k in ("vy0", "vz0"):  # written for readers; the model expands about a journal at rest
            if k in ep and read_number(ep, k, f"{where}: expansion_point") != 0.0:
                raise ValueError(f"{where}: expansion_point: key {k!r} = {ep[k]!r} must be 0 (the expansion is "
                                 "about a journal at rest; velocities enter as vy, vz themselves)")
        force_scale = _scaling(d, params, omega, where)
        order = read_int(d, "order", where)
        exps = _exponents(d, "exponents", order, where)
        n = len(exps)
        if "n_terms" in d and read_int(d, "n_terms", where) != n:
            raise ValueError(f"{where}: key 'n_terms' is {d['n_terms']!r} but 'exponents' has {n} rows")
        _check_basis(exps, order, where)
        c = get_key(d, "coef", where)
        coef = np.array([read_vector(c, k, n, f"{where}: coef") for k in COMPONENTS])
        kept = None
        if "kept" in d:
            kd = get_key(d, "kept", where)
            kept = np.array([read_vector(kd, k, n, f"{where}: kept") for k in COMPONENTS])
            if not np.all((kept == 0) | (kept == 1)):
                raise ValueError(f"{where}: kept: every entry must be 0 or 1")
            kept = kept.astype(bool)
            pruned = np.argwhere(~kept & (coef != 0.0))
            if len(pruned):  # the internal evaluates kept terms only: such a coefficient would be dropped
                i, k = (int(x) for x in pruned[0])
                raise ValueError(f"{where}: coef: key {COMPONENTS[i]!r} entry {k} = {float(coef[i, k])!r} belongs to a term "
                                 f"that 'kept' marks pruned (0); expected 0 there (pruned terms have coefficient 0)")
        lam = (0.0, 0.0)
        if "lambda" in d:
            ld = get_key(d, "lambda", where)
            lam = tuple(read_number(ld, k, f"{where}: lambda", minimum=0.0) for k in COMPONENTS)
        load = d.get("load")
        if load is not None:
            load = tuple(read_vector(d, "load", 2, where))
        wall_power = read_number(d, "wall_power", where, minimum=0.0) if "wall_power" in d else 0.0  # older files: none
        shape_order = shape_coef = None
        if "shape" in d:  # older files: none
            sd = get_key(d, "shape", where)
            shape_order = read_int(sd, "order", f"{where}: shape")
            nr = n_terms(shape_order)
            shc = get_key(sd, "coef", f"{where}: shape")
            # the coefficients' length first: it bounds the order before its basis is built
            shape_coef = np.array([read_vector(shc, k, nr, f"{where}: shape: coef") for k in SHAPE_ROWS])
            if "exponents" in sd and sd["exponents"] != exponents(shape_order).tolist():
                raise ValueError(f"{where}: shape: key 'exponents' is not the full basis of order {shape_order}")
        domain = Domain.from_dict(get_key(d, "domain", where), f"{where}: domain")
        neighbours = Neighbours.from_dict(d["neighbours"], f"{where}: neighbours") if "neighbours" in d else None
        film = film_from_dict(d["film"], f"{where}: film", params.geometry) if "film" in d else None
        meta = {k: read_object(d, k, where) for k in ("errors", "pruning", "provenance")}
        bad = find_non_finite(d)  # the metadata too (the writer stores None, never NaN): shown by reports
        if bad is not None:
            raise ValueError(f"{where}: key {bad!r} is not a finite number (NaN, Infinity or beyond the float "
                             "range); expected finite numbers or null")
        try:
            return cls(params=params, omega=omega, y0=y0, z0=z0, order=order, exponents=exps, coef=coef,
                       force_scale=force_scale, domain=domain, kept=kept, lam=lam, load=load, **meta,
                       wall_power=wall_power, shape_order=shape_order, shape_coef=shape_coef, neighbours=neighbours,
                       film=film)
        except ValueError as exc:  # what only the whole model can check (e.g. an exponent beyond the order)
            raise ValueError(f"{where}: {exc}") from None


COMPONENTS = ("Fy", "Fz")

# The top-level keys of a surrogate file (docs/taylor.md, File); the loader checks each value.
FILE_KEYS = (
    Key("format", "file format name", allowed=repr(FILE_FORMAT)),
    Key("version", "file format version", allowed=f"{FILE_VERSION} (force only) or {FILM_VERSION} (with film)"),
    Key("params", "the bearing: D, L, CR [m], mu [Pa s]", allowed="numbers > 0, CR < D/2"),
    Key("geometry", "the bore, as a bearing file's [geometry] table (absent: the full 360 deg bore)", None,
        "the keys of [geometry] (docs/geometry.md)"),
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
    Key("film", "the film fit: J_s, J_i of (eps, beta); kind 'grooved': J_s, P_e of (eps, phi, beta) (version 2)",
        None, "degree, harmonics, coef, lambda, errors; grooved: kind, phi_degree, phi_center, edges_deg"),
)


def _params(d: dict, where: str) -> BearingParams:
    p = get_key(d, "params", where)
    values = {k: read_number(p, k, f"{where}: params") for k in ("D", "L", "CR", "mu")}
    from ..physics.params import read_geometry

    try:
        return BearingParams(**values, geometry=read_geometry(d.get("geometry"), f"{where}: key 'geometry'"))
    except ValueError as exc:
        raise ValueError(f"{where}: params: {exc}") from None


def _scaling(d: dict, params: BearingParams, omega: float, where: str) -> float:
    """The force scale, after checking the stored position and velocity scales are CR and |omega| CR."""
    sc = get_key(d, "scaling", where)
    fs = read_number(sc, "force_scale", f"{where}: scaling")
    if fs <= 0.0:
        raise ValueError(f"{where}: scaling: key 'force_scale' = {fs!r} must be > 0")
    for key, want, what in (("pos_scale", params.CR, "CR"), ("vel_scale", abs(omega) * params.CR, "|omega| CR")):
        if key in sc and not close_to(read_number(sc, key, f"{where}: scaling"), want):
            raise ValueError(f"{where}: scaling: key {key!r} = {sc[key]!r} disagrees with {what} = {want!r}")
    return fs


def _exponents(d: dict, key: str, order: int, where: str) -> np.ndarray:
    v = get_key(d, key, where)
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


def _check_basis(exps: np.ndarray, order: int, where: str) -> None:
    """The monomials must be distinct and reach the order: the kernels build powers up to
    ``order`` on every call, so an order above the highest degree is damage (or a cut table)."""
    if not len(exps):
        return
    top = int(exps.sum(axis=1).max())
    if top != order:
        raise ValueError(f"{where}: key 'order' = {order} but the highest degree in 'exponents' is {top}; "
                         "expected equal (a surrogate's order is its highest degree)")
    seen = set()
    for row in exps.tolist():
        if tuple(row) in seen:
            raise ValueError(f"{where}: key 'exponents' has the row {row} twice; expected each monomial once")
        seen.add(tuple(row))


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
    """Refuse a surrogate fitted for a different bearing, naming the field and both values, or
    for another bore (the file's ``geometry``, absent for the full bore)."""
    if not surrogate.params.geometry.close_to(params.geometry):
        raise ValueError(f"{where}: fitted for the bore '{surrogate.params.geometry.describe()}', but used with "
                         f"'{params.geometry.describe()}' (a surrogate is only valid for the bearing it was fitted to)")
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


# Domain, Neighbours and SurrogateKeyError live in .domain; re-exported: callers import them from here
__all__ = ["FILE_FORMAT", "FILE_VERSION", "FILM_VERSION", "NO_FLOWS_WHY", "FilmFit", "FILE_KEYS", "SHAPE_ROWS", "Domain", "Neighbours", "Surrogate",
           "SurrogateKeyError", "save_surrogate", "load_surrogate", "surrogate_json", "check_params"]
