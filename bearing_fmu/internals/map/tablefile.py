"""The full bore's force map file (format ``bearing-fmu-force-map``, version 1; version 3 with its
flow tables): ``save_map`` writes a ``MapTable`` (``tables``) as JSON (L/D, grid, cavitation, the
table, its spline and provenance), ``load_map`` reads one back with every key checked (type,
finiteness, range, and the stored spline against the table). The grooved bore's file is
``groovemap``'s; either file: ``mapfile``.
"""

from __future__ import annotations

import copy
import json
from pathlib import Path

import numpy as np

from ...io.schema import find_non_finite
from .tables import FLOW_VERSION, FORMAT, VERSION, MapTable

def save_map(table: MapTable, path) -> Path:
    from ...io.outputs import write_text  # not bundled in the FMU, which never writes a map

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
