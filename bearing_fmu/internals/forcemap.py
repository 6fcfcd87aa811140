"""The force map: the Reynolds film force for every speed, load and velocity from one table.

In the line-of-centres frame the right-hand side of Reynolds' equation depends on the state
only through r sin(psi - beta) (derivation: docs/forcemap.md), the film thickness on eps and
psi only, and the cavitation problem is positively homogeneous in its right-hand side. So

    F = S r (G_r(eps, beta) u + G_t(eps, beta) w),    S = mu R L (R / CR)^2,

with u the unit vector toward the journal centre, w = u turned by +90 degrees (toward the
rotation), r and beta from the velocities (``_map_kernels``). For one L/D, Reynolds grid and
cavitation model, G is one smooth function of two variables: the map tabulates it from the
Reynolds internal on s = -ln(1 - eps) (clustered toward the wall) x beta (periodic), with the
wall growth (1 - eps)^-k factored out, and interpolates it with a tensor cubic spline (not-a-
knot in s, periodic in beta). D, CR and mu enter only through S.

Files (``save_map`` / ``load_map``, JSON): L/D, grid, cavitation, the table and provenance;
loading for a bearing checks its L/D.
"""

from __future__ import annotations

import copy
import json
import math
import signal
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..io.schema import find_non_finite
from ..physics.film import FilmReport, reduced_flows, reduced_report
from ..physics.params import L_OVER_D_RANGE, BearingParams
from .registry import BearingStateError, check_finite, overflow_error

FORMAT = "bearing-fmu-force-map"
VERSION = 1  # the force table alone (read still: such a map has no film flows)
FLOW_VERSION = 3  # with the flow table Q (2 and 4 are the grooved map's, groovemap.py)
NO_FLOWS_WHY = ("the map file {source} has no flow tables (format version 1, built before they were added): "
                "rebuild it with `bearing-fmu map --bearing FILE -o MAP` to get the film's inflow and side flow")
# defaults from the resolution study (docs/studies/2026-11-24-forcemap-resolution.md): 96 points in
# s and k = 0 take the interpolation error near the centre, where a growing 44 Hz whirl spends its
# first seconds, from 1.4e-3 (48 points, k = 2) to 5e-5; the held-out 44 Hz orbit from 0.059 to 0.002 % CR
DEFAULT_N_EPS = 96  # table points in s = -ln(1 - eps)
DEFAULT_N_BETA = 96  # table points in beta over one period
DEFAULT_EPS_MAX = 0.99  # last table point: beyond it the map refuses the state
DEFAULT_WALL_EXPONENT = 0.0  # k in H = G (1 - eps)^k (the s axis already follows the wall growth)
DEFAULT_N_PHASE = 4  # attitudes per table point, spread over one Reynolds cell (averaged)
EPS_MIN = 1e-6  # below: evaluated at EPS_MIN along the same direction (kernel docstring: 1/e in the
# attitude derivatives would amplify round-off; the shift moves the force by ~1e-6 of S omega)
LD_RTOL = 1e-9  # a map serves bearings whose L/D equals its own to this relative tolerance

# the map reduces the force to F = r G(eps, beta): true for the circular full bore only (a groove,
# an arc or a lobe fixes directions in the bore, docs/geometry.md)
REDUCTION_WHY = ("a version 1 map's reduction to eccentricity and one angle assumes the circular full bore; "
                 "`bearing-fmu map --bearing FILE` builds a 3-D map for grooves and partial arcs")

def scale(params: BearingParams) -> float:
    """S = mu R L (R / CR)^2 [N s]: the map's force per unit r [1/s]."""
    return params.mu * params.R * params.L * (params.R / params.CR) ** 2


def reduced(y: float, z: float, vy: float, vz: float, omega: float, CR: float):
    """(eps, phi, a, c): eccentricity ratio, attitude [rad], and the source coefficients
    a = eps (omega - 2 phidot), c = 2 epsdot [1/s] (docs/forcemap.md). e by libm's hypot, as the numba
    kernels and the native map (CPython's math.hypot rounds its own way, at times 1 ulp apart)."""
    e = float(np.hypot(y, z))
    cp, sp = (y / e, z / e) if e > 0.0 else (1.0, 0.0)
    vr, vt = vy * cp + vz * sp, -vy * sp + vz * cp
    eps = e / CR
    return eps, math.atan2(sp, cp), eps * omega - 2.0 * vt / CR, 2.0 * vr / CR


def state_for(eps: float, beta: float, params: BearingParams, phi: float = -0.5 * math.pi, omega: float = 1.0,
              r: float = 1.0):
    """A journal state (y, z, vy, vz) with the given eps and beta, attitude phi and r [1/s] at
    ``omega``: the inverse of ``reduced`` (v_t = CR (eps omega - a) / 2, v_r = CR c / 2)."""
    a, c = r * math.cos(beta), r * math.sin(beta)
    CR = params.CR
    vt, vr = 0.5 * CR * (eps * omega - a), 0.5 * CR * c
    cp, sp = math.cos(phi), math.sin(phi)
    return eps * CR * cp, eps * CR * sp, vr * cp - vt * sp, vr * sp + vt * cp


# ------------------------------------------------------------------------------ the table

class TableAxes:
    """The s, eps and beta axes of a map table (``n_eps``, ``n_beta``, ``eps_max``)."""

    @property
    def s(self) -> np.ndarray:
        return np.linspace(0.0, -math.log1p(-self.eps_max), self.n_eps)

    @property
    def eps(self) -> np.ndarray:
        return -np.expm1(-self.s)

    @property
    def beta(self) -> np.ndarray:
        return -math.pi + 2.0 * math.pi * np.arange(self.n_beta) / self.n_beta


@dataclass
class MapTable(TableAxes):
    """G tabulated as H = G (1 - eps)^k on s_i = i s_max / (n_eps - 1), s = -ln(1 - eps), and
    beta_j = -pi + j 2 pi / n_beta; H has shape (n_eps, n_beta, 2) (radial, tangential)."""

    L_over_D: float
    n_theta: int
    n_x: int
    cavitation: str
    eps_max: float
    wall_exponent: float
    H: np.ndarray
    provenance: dict = field(default_factory=dict)
    coefficients: tuple | None = field(default=None, repr=False)  # (ts, tb, C) of ``spline``
    Q: np.ndarray | None = None  # (n_eps, n_beta, 2): (J_s, J_i) of film.reduced_flows, or None
    flow_coefficients: tuple | None = field(default=None, repr=False)  # (ts, tb, C) of ``flow_spline``

    def __post_init__(self):
        self.H = np.asarray(self.H, float)
        self.Q = None if self.Q is None else np.asarray(self.Q, float)
        problem = self.problem()
        if problem:
            raise ValueError(f"force map table: {problem}")

    def problem(self) -> str | None:
        """What makes the table unusable, naming its file key and what it must be, or None. A NaN
        L/D would pass every L/D comparison (NaN compares false) and a NaN wall exponent makes
        every force NaN: both are refused here, before any bearing meets the map."""
        problem = header_problem(self)
        if problem:
            return problem
        if self.H.ndim != 3 or self.H.shape[2] != 2 or self.H.shape[0] < 4 or self.H.shape[1] < 4:
            return f"key 'H' has shape {self.H.shape}, expected (n_eps >= 4, n_beta >= 4, 2)"
        if self.Q is not None and self.Q.shape != self.H.shape:
            return f"key 'Q' has shape {self.Q.shape}, expected that of 'H' {self.H.shape}"
        return finite_problem(self.H) or (None if self.Q is None else finite_problem(self.Q, "Q"))

    @property
    def n_eps(self) -> int:
        return self.H.shape[0]

    @property
    def n_beta(self) -> int:
        return self.H.shape[1]

    def spline(self):
        """(ts, tb, C): knots in s and beta and the tensor spline coefficients C (ns, nb, 2);
        stored in the file, so loading needs no scipy (0.6 s of import)."""
        if self.coefficients is None:
            self.coefficients = self._fit_spline(self.H)
        return self.coefficients

    def flow_spline(self):
        """(ts, tb, C) of the flow table Q, as ``spline`` of H (None without flow tables)."""
        if self.flow_coefficients is None and self.Q is not None:
            self.flow_coefficients = self._fit_spline(self.Q)
        return self.flow_coefficients

    def _fit_spline(self, H):
        from scipy.interpolate import make_interp_spline

        s, beta = self.s, self.beta
        along_s = make_interp_spline(s, H, k=3, axis=0)  # not-a-knot
        wrapped = np.concatenate([along_s.c, along_s.c[:, :1]], axis=1)  # periodic: first column again
        along_b = make_interp_spline(np.append(beta, math.pi), wrapped, k=3, axis=1, bc_type="periodic")
        # scipy keeps a BSpline's coefficients with the interpolation axis first: put beta back second
        return (np.ascontiguousarray(along_s.t), np.ascontiguousarray(along_b.t),
                np.ascontiguousarray(np.moveaxis(along_b.c, 0, 1)))

    def to_dict(self) -> dict:
        flows = {} if self.Q is None else {
            "flow_meaning": "Q[i][j] = (J_s, J_i): side flow r R L CR J_s, inflow |omega R L CR (1 + eps) / 2 - r R L CR J_i|",
            "Q": np.round(self.Q, 12).tolist(),
            "flow_spline": dict(zip(("knots_s", "knots_beta", "coefficients"),
                                    (a.tolist() for a in self.flow_spline())))}
        return {"format": FORMAT, "version": VERSION if self.Q is None else FLOW_VERSION, "L_over_D": self.L_over_D,
                "reynolds": {"n_theta": self.n_theta, "n_x": self.n_x, "cavitation": self.cavitation},
                "eps_max": self.eps_max, "wall_exponent": self.wall_exponent,
                "n_eps": self.n_eps, "n_beta": self.n_beta,
                "grid": "s = -ln(1 - eps) uniform on [0, -ln(1 - eps_max)]; beta = -pi + j 2 pi / n_beta",
                "meaning": "H[i][j] = (G_r, G_t) (1 - eps_i)^wall_exponent; F = mu R L (R/CR)^2 r (G_r u + G_t w)",
                "H": np.round(self.H, 12).tolist(),
                "spline": dict(zip(("knots_s", "knots_beta", "coefficients"), (a.tolist() for a in self.spline()))),
                "provenance": self.provenance, **flows}


def header_problem(t) -> str | None:
    """What makes a map table's L/D, eps_max, wall exponent, Reynolds grid or cavitation model
    unusable (``t`` a MapTable or a grooved table), naming the file key, or None."""
    lo, hi = L_OVER_D_RANGE
    if not lo <= t.L_over_D <= hi:  # NaN fails too
        return f"key 'L_over_D' = {t.L_over_D!r} must be a finite number in {lo:g} .. {hi:g} (a bearing's L/D)"
    if not 0.0 < t.eps_max < 1.0:
        return f"key 'eps_max' = {t.eps_max!r} must lie in (0, 1) (the table's last eccentricity ratio)"
    if not (math.isfinite(t.wall_exponent) and t.wall_exponent >= 0.0):
        return f"key 'wall_exponent' = {t.wall_exponent!r} must be a finite number >= 0 (k in H = G (1 - eps)^k)"
    for name in ("n_theta", "n_x"):
        v = getattr(t, name)
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 1:
            return f"key 'reynolds.{name}' = {v!r} must be an integer >= 1 (the Reynolds grid it was built on)"
    if not isinstance(t.cavitation, str) or not t.cavitation:
        return f"key 'reynolds.cavitation' = {t.cavitation!r} must be the name of a cavitation model"
    return None


def finite_problem(H: np.ndarray, key: str = "H") -> str | None:
    """The first non-finite entry of a table H (file key ``key``), named, or None."""
    if not np.all(np.isfinite(H)):
        i = tuple(int(k) for k in np.argwhere(~np.isfinite(H))[0])
        return f"key '{key}' has a non-finite entry {key}{list(i)} = {float(H[i])!r}, expected finite numbers"
    return None


def tabulate(params: BearingParams, *, n_eps: int = DEFAULT_N_EPS, n_beta: int = DEFAULT_N_BETA,
             eps_max: float = DEFAULT_EPS_MAX, wall_exponent: float = DEFAULT_WALL_EXPONENT,
             n_theta: int | None = None, n_x: int | None = None, cavitation: str = "reynolds",
             n_phase: int = DEFAULT_N_PHASE, workers: int = 1, progress=None, flows: bool = True) -> MapTable:
    """The map of ``params``' L/D from the Reynolds internal on the given grid: one solve per
    table point at r = 1, omega = 1 rad/s, the journal straight below the centre (phi = -90 deg).
    ``workers`` > 1 splits the eps rows over processes; ``progress(n_done)`` per row. ``flows``: the
    flow table Q too (one more solve per point), else the force alone (a version 1 map)."""
    from ..physics.reynolds import Reynolds

    params.require_full_bore("a force map", REDUCTION_WHY)
    rey = Reynolds(params, n_theta, n_x, cavitation)
    t0 = time.perf_counter()
    table = MapTable(params.L / params.D, rey.n_theta, rey.n_x, rey.cavitation, eps_max, wall_exponent,
                     np.zeros((n_eps, n_beta, 2)), Q=np.zeros((n_eps, n_beta, 2)) if flows else None)
    done = 0
    try:
        if workers > 1:
            import multiprocessing
            from functools import partial

            task = partial(_row, params, rey.n_theta, rey.n_x, rey.cavitation, betas=table.beta,
                           wall_exponent=wall_exponent, n_phase=n_phase, flows=flows)
            pool = multiprocessing.Pool(workers, initializer=worker_signals)
            try:
                for done, (h, q) in enumerate(pool.imap(task, table.eps), 1):
                    table.H[done - 1] = h
                    if flows:
                        table.Q[done - 1] = q
                    if progress is not None:
                        progress(done)
                pool.close()
            finally:
                pool.terminate()  # an interrupt must not wait for the rows being computed
                pool.join()
        else:
            for i, e in enumerate(table.eps):
                h, q = _row(params, rey.n_theta, rey.n_x, rey.cavitation, e, table.beta, wall_exponent, n_phase, rey,
                            flows)
                table.H[i] = h
                if flows:
                    table.Q[i] = q
                done = i + 1
                if progress is not None:
                    progress(done)
    except KeyboardInterrupt as exc:
        exc.map_rows_done = done  # the command says how far it got (a map is written only whole)
        raise
    _centre_row(table)
    if flows:  # the centre's side flow: the uniform film turns with the source
        table.Q[0, :, 0] = np.mean(table.Q[0, :, 0])
    table.provenance = {"built_s": round(time.perf_counter() - t0, 3), "solves": (1 + flows) * n_eps * n_beta * n_phase,
                        "n_phase": n_phase,
                        "truth": repr(rey), "date": time.strftime("%Y-%m-%dT%H:%M:%S%z")}
    return table


def worker_signals() -> None:
    """A pool worker: Ctrl-C (sent to the whole group) is the parent's to act on; the parent's
    terminate() (SIGTERM) ends the worker at once, without a traceback."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)


def _centre_row(table: MapTable) -> None:
    """At eps = 0 the film is uniform and the problem turns with the source: G(0, beta) =
    R(beta) g for one vector g (docs/forcemap.md). The continuous force is then independent of
    the attitude phi at the centre, which keeps the Jacobian finite there (its attitude terms
    carry 1/e); the solver's grid breaks this by ~1e-3, so the row is replaced by its
    projection on that form (least squares: g = mean over beta of R(-beta) G(0, beta))."""
    b = table.beta
    c, s = np.cos(b), np.sin(b)
    G = table.H[0]  # (1 - 0)^k = 1
    g = np.array([np.mean(c * G[:, 0] + s * G[:, 1]), np.mean(-s * G[:, 0] + c * G[:, 1])])
    table.H[0, :, 0] = c * g[0] - s * g[1]
    table.H[0, :, 1] = s * g[0] + c * g[1]


def _row(params, n_theta, n_x, cavitation, eps, betas, wall_exponent, n_phase, rey=None, flows=True):
    """(H, Q) at one eps for every beta (a process-pool task when ``rey`` is None). Q from the
    solver's film reports at omega = 1 and 2 rad/s (``film.reduced_flows``; at the centre at
    EPS_MIN, where the line of thickest film has the journal's direction)."""
    if rey is None:
        from ..physics.reynolds import Reynolds

        rey = Reynolds(params, n_theta, n_x, cavitation)
    S = scale(params)
    out, Q = np.zeros((len(betas), 2)), np.zeros((len(betas), 2))
    eps_flow = max(eps, EPS_MIN)
    # the solver's grid is fixed to the bearing: the same (eps, beta) at another attitude
    # differs by its discretisation (up to a few 1e-3 near the wall, docs/forcemap.md);
    # averaging over attitudes spread across one cell tabulates the grid-independent part
    phases = -0.5 * math.pi + (np.arange(n_phase) + 0.5) / n_phase * 2.0 * math.pi / rey.n_theta
    for phi in phases:
        u = np.array([math.cos(phi), math.sin(phi)])
        w = np.array([-math.sin(phi), math.cos(phi)])
        for j, b in enumerate(betas):
            y, z, vy, vz = state_for(eps, b, params, phi)
            F = np.array(rey.force(y, z, vy, vz, 1.0))
            out[j] += (F @ u / S, F @ w / S)
            if flows:
                Q[j] += reduced_flows(params, eps_flow, 1.0, {
                    om: rey.film_report(*state_for(eps_flow, b, params, phi, omega=om), om) for om in (1.0, 2.0)})
    return out / n_phase * (1.0 - eps) ** wall_exponent, Q / n_phase


# ------------------------------------------------------------------------------- files

def save_map(table: MapTable, path) -> Path:
    from ..io.outputs import write_text  # not bundled in the FMU, which never writes a map

    return write_text(path, json.dumps(table.to_dict(), indent=None, allow_nan=False) + "\n")


MAP_KEYS = ("format", "version", "L_over_D", "reynolds", "eps_max", "wall_exponent", "n_eps", "n_beta", "grid",
            "meaning", "H", "spline", "provenance")  # what save_map writes; the loader refuses others
FLOW_KEYS = ("flow_meaning", "Q", "flow_spline")  # and these in a version 3 file
SPLINE_RTOL = 1e-10  # the stored spline must give back the table at its points to this, relative to max |H|


_READ: dict[tuple, MapTable] = {}  # (file, mtime, size) -> its checked table, once per process


def load_map(path) -> MapTable:
    """Read a map file; every key checked (type, finiteness, range, and the stored spline
    against the table), one line naming the file, the key, what was expected and given.
    A file read before in this process and unchanged since (path, modification time, size) is
    not read again: each bearing of a run, and each run of a sweep's worker, gets a copy of the
    table checked the first time (reading and checking it cost ~40 ms per bearing and run)."""
    path = Path(path)
    try:
        st = path.stat()
        key = (str(path.resolve()), st.st_mtime_ns, st.st_size)
    except OSError:
        key = None  # not there: _read_map names it
    if key not in _READ:
        table = _read_map(path)
        if key is None:
            return table
        _READ[key] = table
    return copy.deepcopy(_READ[key])  # a caller may change its table; the kept one stays as read


def _read_map(path: Path) -> MapTable:
    try:
        data = json.loads(path.read_text())
    except FileNotFoundError:
        raise FileNotFoundError(f"force map file {path} not found") from None
    except json.JSONDecodeError as exc:
        raise ValueError(f"force map file {path}: not valid JSON ({exc.msg} at line {exc.lineno}, "
                         f"column {exc.colno}); truncated?") from None
    if not isinstance(data, dict) or data.get("format") != FORMAT:
        raise ValueError(f"force map file {path}: 'format' is not {FORMAT!r}: not a force map")
    version = data.get("version")
    if version not in (VERSION, FLOW_VERSION):
        raise ValueError(f"force map file {path}: version {version!r}, this code reads {VERSION} and {FLOW_VERSION}")
    unknown = sorted(set(data) - set(MAP_KEYS + (FLOW_KEYS if version == FLOW_VERSION else ())))
    if unknown:
        raise ValueError(f"force map file {path}: unknown key(s) {', '.join(unknown)}; allowed: {', '.join(MAP_KEYS)}")
    try:
        rey = data["reynolds"]
        if not isinstance(rey, dict):
            raise ValueError(f"key 'reynolds' = {rey!r:.60} must be an object {{n_theta, n_x, cavitation}}")
        for k in ("n_theta", "n_x", "cavitation"):
            if k not in rey:
                raise KeyError(f"reynolds.{k}")
        table = MapTable(number_key(data, "L_over_D"), rey["n_theta"], rey["n_x"], rey["cavitation"],
                         number_key(data, "eps_max"), number_key(data, "wall_exponent"), array_key(data, "H"),
                         data.get("provenance", {}), Q=array_key(data, "Q") if version == FLOW_VERSION else None)
    except KeyError as exc:
        raise ValueError(f"force map file {path}: missing key {exc.args[0]!r}") from None
    except ValueError as exc:
        raise ValueError(f"force map file {path}: {str(exc).removeprefix('force map table: ')}") from None
    if not isinstance(table.provenance, dict):
        raise ValueError(f"force map file {path}: key 'provenance' must be an object, got {table.provenance!r:.60}")
    # every other number (the arrays were checked by numpy; JSON has no NaN, but Python's reader
    # takes one): a damaged value named by its key before anything shows or uses it
    bad = find_non_finite({k: v for k, v in data.items() if k not in ("H", "spline", "Q", "flow_spline")})
    if bad is not None:
        raise ValueError(f"force map file {path}: key {bad!r} is not a finite number (NaN, Infinity or beyond "
                         "the float range); expected finite numbers only")
    if (table.n_eps, table.n_beta) != (data.get("n_eps"), data.get("n_beta")):
        raise ValueError(f"force map file {path}: table shape {table.H.shape[:2]} differs from n_eps, n_beta = "
                         f"{data.get('n_eps')}, {data.get('n_beta')}")
    for key, values in (("spline", table.H), ("flow_spline", table.Q)):
        sp = data.get(key)
        if sp is None or values is None:
            continue
        # written by save_map from this table: checked for shape, finiteness and values
        try:
            if not isinstance(sp, dict):
                raise ValueError(f"an object {{knots_s, knots_beta, coefficients}} is expected, got {sp!r:.60}")
            ts, tb, C = (np.ascontiguousarray(array_key(sp, k)) for k in ("knots_s", "knots_beta", "coefficients"))
        except (KeyError, ValueError) as exc:
            raise ValueError(f"force map file {path}: key {key!r} is incomplete or damaged ({exc})") from None
        problem = spline_problem(table, ts, tb, C, values, "Q" if key == "flow_spline" else "H")
        if problem:
            raise ValueError(f"force map file {path}: key {key!r} {problem}: rebuild the map "
                             "(`bearing-fmu map --bearing FILE -o MAP`)")
        if key == "spline":
            table.coefficients = (ts, tb, C)
        else:
            table.flow_coefficients = (ts, tb, C)
    return table


def number_key(data: dict, key: str) -> float:
    v = data[key]
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise ValueError(f"key {key!r} = {v!r:.60} must be a number")
    return float(v)


def array_key(data: dict, key: str) -> np.ndarray:
    """data[key] as a float array: a ragged or non-numeric list, or a non-finite entry, named."""
    v = data[key]
    try:
        if not isinstance(v, list):
            raise TypeError
        a = np.array(v, float)
    except (TypeError, ValueError):
        raise ValueError(f"key {key!r} must be a regular array of numbers, got {v!r:.40}") from None
    if not np.all(np.isfinite(a)):
        i = [int(k) for k in np.argwhere(~np.isfinite(a))[0]]
        raise ValueError(f"key {key!r} has a non-finite entry {key}{i} = {float(a[tuple(i)])!r}, expected finite "
                         "numbers")
    return a


def spline_problem(table: MapTable, ts, tb, C, values=None, key: str = "H") -> str | None:
    """Whether the spline (ts, tb, C) is the interpolant of ``table``: shapes, ordered knots and
    its values at the table points (a spline from another table, or a table edited after the
    spline was written, would otherwise be evaluated silently: the map serves the spline).
    ``values``: the table it interpolates (H, or the flow table Q, file key ``key``)."""
    values = table.H if values is None else values
    if (C.shape != (table.n_eps, table.n_beta + 3, 2) or ts.shape != (table.n_eps + 4,)
            or tb.shape != (table.n_beta + 7,)):
        return (f"has shapes knots_s {ts.shape}, knots_beta {tb.shape}, coefficients {C.shape}; the table "
                f"({table.n_eps} x {table.n_beta}) needs {(table.n_eps + 4,)}, {(table.n_beta + 7,)}, "
                f"{(table.n_eps, table.n_beta + 3, 2)}")
    if np.any(np.diff(ts) < 0.0) or np.any(np.diff(tb) < 0.0):
        return "has knots out of order (they must not decrease)"
    nb = C.shape[1]
    b = tb[3] + np.mod(table.beta - tb[3], tb[nb] - tb[3])  # periodic in beta, as the kernel folds it
    Bs, Bb = bspline_matrix(ts, table.s, C.shape[0]), bspline_matrix(tb, b, nb)
    at_points = Bs @ np.ascontiguousarray(np.moveaxis(C, 2, 0)) @ Bb.T  # (2, n_eps, n_beta)
    err = float(np.max(np.abs(at_points - np.moveaxis(values, 2, 0))))
    if not err <= SPLINE_RTOL * max(1.0, float(np.max(np.abs(values)))):
        return f"does not reproduce the table '{key}' at its points (largest difference {err:.3g})"
    return None


def bspline_matrix(t: np.ndarray, x: np.ndarray, n: int) -> np.ndarray:
    """B[m, p] = N_p(x_m), the n cubic B-splines on knots t (Cox-de Boor, as map_kernels._basis
    but in numpy: the loader needs neither scipy nor the compiled kernels)."""
    m = len(x)
    i = np.clip(np.searchsorted(t, x, side="right") - 1, 3, n - 1)  # the kernel's span, clamped alike
    N = np.zeros((m, 4))
    N[:, 0] = 1.0
    left, right = np.zeros((m, 4)), np.zeros((m, 4))
    for j in range(1, 4):
        left[:, j] = x - t[i + 1 - j]
        right[:, j] = t[i + j] - x
        saved = np.zeros(m)
        for r in range(j):
            with np.errstate(divide="ignore", invalid="ignore"):
                temp = N[:, r] / (right[:, r + 1] + left[:, j - r])
            N[:, r] = saved + right[:, r + 1] * temp
            saved = left[:, j - r] * temp
        N[:, j] = saved
    B = np.zeros((m, n))
    for r in range(4):
        B[np.arange(m), i - 3 + r] = N[:, r]
    return B


# ---------------------------------------------------------------------------- internal

class ForceMap:
    """The map internal: ``force`` and ``force_and_jacobian`` (analytic, from the spline's
    derivatives) for a bearing whose L/D equals the table's. States at or beyond the table's
    last eccentricity (eps_max) are refused like Reynolds refuses the wall."""

    # no flow tables unless __init__ finds them (the grooved map, a subclass, sets its own)
    film_flow_why, _flow = "the map has no flow tables (docs/forcemap.md)", None

    def __init__(self, params: BearingParams, table: MapTable, source: str = ""):
        params.require_full_bore(f"the force map{' ' + source if source else ''}", REDUCTION_WHY)
        ld = params.L / params.D
        if not abs(ld - table.L_over_D) <= LD_RTOL * table.L_over_D:  # NaN is refused, not let through
            raise ValueError(f"force map{' ' + source if source else ''} is for L/D = {table.L_over_D:.6g}, the "
                             f"bearing has L/D = {ld:.6g} (L = {params.L:g} m, D = {params.D:g} m): build a map for "
                             "it with `bearing-fmu map --bearing FILE -o MAP`")
        self.params, self.table, self.source = params, table, source
        self._ts, self._tb, self._C = table.spline()
        self._ns, self._nb = self._C.shape[0], self._C.shape[1]
        self._scale = scale(params)
        self._F = np.zeros(2)
        self._J = np.zeros((2, 4))
        from .map_kernels import map_force  # numba, compiled (or loaded from its cache) here

        self._kernel = map_force
        self._args = (self._ts, self._tb, self._C, self._ns, self._nb, float(table.wall_exponent), EPS_MIN,
                      self._scale, float(params.CR))
        self._eps_max = float(table.eps_max)
        # the film's flows (registry capability film_flow, per file): '' when the file has them
        self.film_flow_why = "" if table.Q is not None else NO_FLOWS_WHY.format(source=source or "(in memory)")
        self._flow, self._Jq = table.flow_spline(), np.zeros((2, 3))

    @classmethod
    def from_file(cls, path, params: BearingParams) -> "ForceMap":
        return cls(params, load_map(path), source=str(path))

    @classmethod
    def from_options(cls, params: BearingParams, options, context) -> "ForceMap":
        """From the registry's checked options (``internals.REGISTRY["map"]``)."""
        if not options["map"]:
            raise ValueError("internal 'map' needs the option map (a force map JSON file)")
        return cls.from_file(context.path(options["map"]), params)

    def __repr__(self) -> str:
        t = self.table
        return (f"ForceMap(L/D {t.L_over_D:.4g}, {t.n_eps} x {t.n_beta}, eps <= {t.eps_max:g}, Reynolds "
                f"{t.n_theta} x {t.n_x} {t.cavitation})")

    def _run(self, y, z, vy, vz, omega, want_jac):
        y, z, vy, vz, omega = float(y), float(z), float(vy), float(vz), float(omega)
        # the kernel returns eps (NaN when its result is not finite); a non-finite input, a state
        # beyond the table or an overflow is checked after it (one call on the good path) and
        # refused before anything is used
        eps = self._kernel(*self._args, y, z, vy, vz, omega, want_jac, self._F, self._J)
        if not eps < self._eps_max or not math.isfinite(vy + vz + omega):
            self._refuse(y, z, vy, vz, omega, want_jac)

    def _refuse(self, y, z, vy, vz, omega, want_jac):
        refuse_state(self.params, self._eps_max, y, z, vy, vz, omega, want_jac)

    def compiled_force(self):
        """Its force and Jacobian as a compiled kernel (``internals.compiled``)."""
        from .compiled import CompiledForce
        from .map_kernels import map_kernel, pack

        return CompiledForce(map_kernel(), pack(*self._args[:3], *self._args[5:], self._eps_max))

    def force(self, y: float, z: float, vy: float, vz: float, omega: float) -> tuple[float, float]:
        """Film force (Fy, Fz) [N]."""
        self._run(y, z, vy, vz, omega, False)
        return float(self._F[0]), float(self._F[1])

    def force_and_jacobian(self, y: float, z: float, vy: float, vz: float, omega: float):
        """(F (2,), dF/dq (2, 2), dF/dv (2, 2)) [N, N/m, N s/m]."""
        self._run(y, z, vy, vz, omega, True)
        return self._F.copy(), self._J[:, :2].copy(), self._J[:, 2:].copy()

    def film_report(self, y: float, z: float, vy: float, vz: float, omega: float) -> FilmReport:
        """Friction (closed form, from the force) and flows (the file's flow table) of the film, as
        ``Reynolds.film_report`` (docs/forcemap.md, "The flows"); ValueError without the table."""
        if self._flow is None:
            raise ValueError(f"film_report: {self.film_flow_why}")
        from .map_kernels import spline2

        F = self.force(y, z, vy, vz, omega)
        eps, _phi, a, c = reduced(float(y), float(z), float(vy), float(vz), float(omega), self.params.CR)
        e = max(eps, EPS_MIN)  # as the table's centre row (and the force) have it
        spline2(*self._flow, self._ns, self._nb, -math.log1p(-e), math.atan2(c, a), self._Jq)
        return reduced_report(self.params, float(y), float(z), float(vy), float(vz), float(omega), F, eps,
                              math.hypot(a, c), float(self._Jq[0, 0]), float(self._Jq[1, 0]))


def refuse_state(params: BearingParams, eps_max: float, y, z, vy, vz, omega, want_jac) -> None:
    """Raise the error of a state a map cannot answer (the map kernels returned eps >= eps_max,
    NaN, or took a non-finite velocity): a non-finite input, the wall, beyond the table, or a
    force that overflows, each by name."""
    check_finite(y, z, vy, vz, omega)
    eps = math.hypot(y, z) / params.CR  # as the kernel has it (which returns NaN on overflow)
    if eps < eps_max:  # finite inputs inside the table: the force overflowed
        # F = S r G is linear in r ~ |v| / CR: beyond the float range no finite value is the
        # model's answer, so the state is refused by name rather than returned as inf or NaN
        raise overflow_error(params, y, z, vy, vz, omega, "force and its Jacobian" if want_jac else "force")
    CR = params.CR
    why = "at or beyond the bearing wall" if eps >= 1.0 else "beyond the force map's last point"
    raise BearingStateError(
        f"eccentricity ratio {eps:.4g} >= {1.0 if eps >= 1.0 else eps_max:g}: the journal "
        f"(y = {y:.4g} m, z = {z:.4g} m) is {why} (CR = {CR:.4g} m; the map covers eps < {eps_max:g})")
