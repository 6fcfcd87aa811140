"""``rotor-host response``: the unbalance response of the linearised rotor over a speed range.

At every speed of the range the rotor's static equilibrium on its bearings, each film
linearised there, and the damped modes come from ``linear.stability.Stability.sweep`` (the
same sweep as ``rotor-host stability``, so the threshold and the critical speeds are the
Campbell diagram's); the steady 1x response to the unbalances is then one complex solve per
speed (``synchronous``). Every speed is computed and kept; one where the least stable mode's
log decrement is <= 0 is marked unstable (the steady response exists there but is not what
the machine does: the free whirl grows). The peaks at the probe nodes (by default the
bearings' and the disks' nodes) are refined between grid points and given their half-power
amplification factor and API margins (``peaks``).

Outputs in ``--out``: ``response.json`` (keys in ``to_json``), ``response.md``, and per probe
node ``bode_node<N>.png`` and ``polar_node<N>.png`` (``figures``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...model.rotor import Rotor
from . import peaks as pk
from .synchronous import FIELDS, node_response, solve


@dataclass
class ResponseResult:
    """The response over speed. ``X`` (n_speeds x n_dof, complex; NaN where a speed has no
    equilibrium); ``status`` per speed "ok", "unstable" or "no equilibrium: ..."; ``least_log_dec``
    per speed (None without equilibrium); ``K``, ``C`` the bearings' coefficients per speed
    (n_speeds x n_bearings x 2 x 2, NaN without equilibrium); ``probes`` 1-based nodes."""

    rotor: Rotor
    unbalances: list
    speeds_hz: list[float]
    X: np.ndarray
    status: list[str]
    least_log_dec: list
    K: np.ndarray
    C: np.ndarray
    probes: list[int]
    operating_hz: tuple[float, float] | None = None
    peaks: list[dict] = field(default_factory=list)
    threshold_hz: float | None = None
    unstable_from_start: bool = False
    criticals: list[dict] = field(default_factory=list)  # the Campbell diagram's (linear.modal)
    meta: dict = field(default_factory=dict)  # rotor name and file, internal, options, inputs line
    extra: dict = field(default_factory=dict)  # speed [Hz] -> X: solved between grid points near the peaks

    @property
    def unstable(self) -> list[bool]:
        return [s == "unstable" for s in self.status]

    def curve(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(speeds, X, unstable) of the grid and the ``extra`` speeds near the peaks, by speed: the
        figures' curves (a resonance narrower than the grid step drawn whole)."""
        s = np.array(list(self.speeds_hz) + list(self.extra))
        X = np.concatenate([self.X, np.array(list(self.extra.values())).reshape(-1, self.rotor.n_dof)])
        grid = np.asarray(self.speeds_hz)
        u = np.asarray(self.unstable)[np.abs(grid[None, :] - s[:, None]).argmin(axis=1)]
        order = np.argsort(s, kind="stable")
        return s[order], X[order], u[order]

    def node(self, node1: int, X=None) -> dict[str, np.ndarray]:
        """Per field of ``synchronous.FIELDS``: the values over speed at 1-based ``node1`` (NaN where
        none), of the grid's X (or of ``X``, e.g. ``curve()``'s)."""
        X = self.X if X is None else X
        out = {k: np.full(len(X), np.nan) for k in FIELDS}
        for i, x in enumerate(X):
            if np.all(np.isfinite(x)):
                for k, v in node_response(self.rotor, x, node1 - 1).items():
                    out[k][i] = v
        return out


def default_probes(rotor: Rotor) -> list[int]:
    """The bearings' and disks' nodes, 1-based, in order."""
    return sorted({n + 1 for n in rotor.bearing_nodes} | {d.node + 1 for d in rotor.disks})


class Evaluator:
    """The response at any speed: grid speeds from their coefficients, others through
    ``coefficients(speed_hz) -> (K_b, C_b)`` (which may raise for a speed without equilibrium);
    each speed solved once."""

    def __init__(self, rotor: Rotor, unbalances, coefficients):
        self.rotor, self.unbalances, self.coefficients = rotor, list(unbalances), coefficients
        self._cache: dict[float, np.ndarray] = {}

    def put(self, speed_hz: float, K, C) -> np.ndarray:
        X = solve(self.rotor, 2.0 * math.pi * speed_hz, K, C, self.unbalances)
        self._cache[float(speed_hz)] = X
        return X

    def X(self, speed_hz: float) -> np.ndarray:
        s = float(speed_hz)
        if s not in self._cache:
            self.put(s, *self.coefficients(s))
        return self._cache[s]

    def amplitude(self, node1: int, direction: str):
        dof = self.rotor.dof(node1 - 1, direction)
        return lambda s: float(abs(self.X(s)[dof]))


def find_peaks(res: ResponseResult, ev: Evaluator, refine_errors: tuple = (ValueError, RuntimeError)) -> list[dict]:
    """Every grid peak of the y and z amplitude at each probe node, refined (``peaks``), by speed."""
    s = np.asarray(res.speeds_hz)
    out = []
    for node in res.probes:
        curves = res.node(node)
        for d in ("y", "z"):
            a = curves[f"{d}_amplitude_m"]
            amp = ev.amplitude(node, d)
            for i in pk.grid_peaks(a):
                try:
                    sp, ap = pk.refine_peak(amp, s[i - 1], s[i + 1])
                    refined = True
                    if ap < a[i]:  # Brent's search missed the top: the grid point stands
                        sp, ap = float(s[i]), float(a[i])
                except refine_errors:
                    sp, ap, refined = float(s[i]), float(a[i]), False
                try:
                    n1, n2 = pk.half_power_speeds(amp, s, a, sp, ap)
                except refine_errors:
                    n1 = n2 = None
                nearest = int(np.argmin(np.abs(s - sp)))
                out.append(pk.peak_record(node, d, sp, ap, n1, n2, res.operating_hz, res.unstable[nearest], refined))
    return sorted(out, key=lambda p: (p["speed_hz"], p["node"], p["direction"]))


EXTRA_POINTS = 41  # solved across each resonance for the figures


def extra_points(res: ResponseResult, ev: Evaluator, errors: tuple = (ValueError, RuntimeError)) -> dict:
    """speed -> X across each peak's half-power band (three times its width; +/- 2 % of the speed
    without one), at speeds not on the grid: the figures draw a resonance narrower than the grid
    step whole."""
    out: dict[float, np.ndarray] = {}
    lo_all, hi_all = res.speeds_hz[0], res.speeds_hz[-1]
    done = []
    for p in res.peaks:
        n1, n2 = p["half_power_hz"]
        c = p["speed_hz"]
        half = 1.5 * (n2 - n1) if n1 is not None and n2 is not None else 0.02 * c
        if any(abs(c - d) < 0.25 * half for d in done):
            continue  # the same resonance seen at another probe or direction
        done.append(c)
        for s in np.linspace(max(lo_all, c - half), min(hi_all, c + half), EXTRA_POINTS):
            if float(s) in out or np.min(np.abs(np.asarray(res.speeds_hz) - s)) < 1e-9:
                continue
            try:
                out[float(s)] = ev.X(float(s))
            except errors:
                continue
    return out


def from_sweep(rotor: Rotor, unbalances, sweep_result, coefficients, probes=None,
               operating_hz=None) -> tuple[ResponseResult, Evaluator]:
    """The response on the speeds of a ``StabilityResult`` (its bearing coefficients and log
    decrements), the peaks refined through ``coefficients`` between them."""
    ev = Evaluator(rotor, unbalances, coefficients)
    n, nb = len(sweep_result.points), len(rotor.bearing_nodes)
    X = np.full((n, rotor.n_dof), np.nan, complex)
    K, C = np.full((n, nb, 2, 2), np.nan), np.full((n, nb, 2, 2), np.nan)
    status, ld = [], []
    for i, p in enumerate(sweep_result.points):
        if not p.ok:
            status.append(f"{p.status}: {p.message}")
            ld.append(None)
            continue
        X[i] = ev.put(p.speed_hz, p.K, p.C)
        K[i], C[i] = p.K, p.C
        ld.append(None if p.least is None else p.least_log_dec)
        status.append("unstable" if p.least is not None and p.least_log_dec <= 0.0 else "ok")
    th = sweep_result.threshold
    res = ResponseResult(rotor, list(unbalances), [p.speed_hz for p in sweep_result.points], X, status, ld, K, C,
                         list(probes or default_probes(rotor)), operating_hz,
                         threshold_hz=None if th is None else th.speed_hz,
                         unstable_from_start=sweep_result.unstable_from_start, criticals=list(sweep_result.criticals))
    res.peaks = find_peaks(res, ev)
    res.extra = extra_points(res, ev)
    return res, ev


def on_grid(rotor: Rotor, unbalances, speeds_hz, coefficients, probes=None,
            operating_hz=None) -> tuple[ResponseResult, Evaluator]:
    """The response at ``speeds_hz`` with ``coefficients(speed_hz) -> (K_b, C_b)`` (given bearing
    coefficients, no stability sweep: every speed "ok"), its peaks refined."""
    ev = Evaluator(rotor, unbalances, coefficients)
    n, nb = len(speeds_hz), len(rotor.bearing_nodes)
    K, C = np.empty((n, nb, 2, 2)), np.empty((n, nb, 2, 2))
    for i, s in enumerate(speeds_hz):
        K[i], C[i] = (np.broadcast_to(np.asarray(a, float), (nb, 2, 2)) for a in coefficients(s))
    X = np.array([ev.X(s) for s in speeds_hz])
    res = ResponseResult(rotor, list(unbalances), [float(s) for s in speeds_hz], X, ["ok"] * n, [None] * n, K, C,
                         list(probes or default_probes(rotor)), operating_hz)
    res.peaks = find_peaks(res, ev)
    return res, ev


def _num(v):
    """A json number, or None for NaN / inf (the json holds no NaN)."""
    if v is None:
        return None
    v = float(v)
    return v if math.isfinite(v) else None


def to_json(res: ResponseResult) -> dict:
    """``response.json``: the issue's keys (speeds_hz, nodes, peaks) and what a reader needs besides."""
    nodes = {}
    for node in range(1, res.rotor.n_nodes + 1):
        curves = res.node(node)
        nodes[str(node)] = {k: [_num(v) for v in curves[k]] for k in FIELDS}
    clean = [{k: (_num(v) if isinstance(v, float) else [_num(x) for x in v] if isinstance(v, list) else v)
              for k, v in p.items()} for p in res.peaks]
    return {"speeds_hz": list(res.speeds_hz), "status": res.status, "unstable": res.unstable,
            "least_log_dec": [_num(v) for v in res.least_log_dec],
            "threshold_hz": res.threshold_hz, "unstable_from_start": res.unstable_from_start,
            "operating_hz": None if res.operating_hz is None else list(res.operating_hz),
            "unbalances": [u.as_dict() for u in res.unbalances], "probes": res.probes,
            "amplitude": "0-peak [m]; phase: y = A cos(Omega t + phase), Omega t = 0 when an unbalance of phase 0 "
                         "points along +y (docs/response.md)",
            "nodes": nodes, "peaks": clean,
            "critical_speeds_campbell": res.criticals,
            "bearings": {"nodes": [n + 1 for n in res.rotor.bearing_nodes],
                         "K_N_m": [None if not np.isfinite(k).all() else k.tolist() for k in res.K],
                         "C_N_s_m": [None if not np.isfinite(c).all() else c.tolist() for c in res.C]},
            **res.meta}


def stability_coefficients(analysis):
    """``coefficients(speed_hz) -> (K_b, C_b)`` of a ``linear.stability.Stability``: the oil at its
    effective temperature (with a supply temperature), the static equilibrium from the scene's
    start, each film linearised there. Raises EquilibriumError where there is none."""
    def coefficients(speed_hz: float):
        omega = 2.0 * math.pi * float(speed_hz)
        analysis.thermal(omega)
        return analysis.linearise(analysis.equilibrium(omega, None), omega)

    return coefficients


def check_operating(operating_hz) -> tuple[float, float] | None:
    """(min, max) [Hz] with 0 < min <= max, or ValueError naming --operating-hz."""
    if operating_hz is None:
        return None
    lo, hi = (float(v) for v in operating_hz)
    if not (math.isfinite(lo) and math.isfinite(hi) and 0.0 < lo <= hi):
        raise ValueError(f"--operating-hz {lo:g}:{hi:g}: expected MIN:MAX with 0 < MIN <= MAX [Hz]")
    return lo, hi


def response(rotor_file, speeds_hz, unbalances, *, internal: str = "reynolds", options=None, static_loads=(),
             operating_hz=None, T_supply_K=None, probes=None, log=None) -> ResponseResult:
    """Read the rotor file, sweep its speeds (``Stability.sweep``), solve the response at each and
    find its peaks; ``unbalances`` (node, mass_g, radius_mm[, phase_deg]) with 1-based nodes."""
    from ..linear.stability import Stability
    from ..linear.inputs import check_speeds, read_rotor

    rotor, loads = read_rotor(rotor_file, static_loads)
    check_inputs(rotor, rotor_file, unbalances, operating_hz, probes)
    analysis = Stability(rotor, internal, options, loads, where=str(rotor_file), T_supply_K=T_supply_K)
    sweep = analysis.sweep(check_speeds(speeds_hz), rotor_name=rotor.name or Path(rotor_file).stem, log=log)
    return response_from(analysis, sweep, rotor_file, unbalances, operating_hz, probes)


def check_inputs(rotor: Rotor, rotor_file, unbalances, operating_hz, probes) -> None:
    """ValueError naming the unbalance, operating range or probe that does not fit the rotor."""
    from .synchronous import check_unbalances

    check_unbalances(rotor, unbalances, str(rotor_file))
    check_operating(operating_hz)
    for n in probes or ():
        if not 1 <= int(n) <= rotor.n_nodes:
            raise ValueError(f"--probe {n}: outside the rotor's nodes 1..{rotor.n_nodes} ({rotor_file})")


def response_from(analysis, sweep, rotor_file, unbalances, operating_hz=None, probes=None) -> ResponseResult:
    """The response on a stability sweep already made (``Stability.sweep``) of ``analysis``."""
    from bearing_fmu.physics.statics import EquilibriumError

    from ..computed_for import title_line
    from .synchronous import check_unbalances

    rotor = analysis.rotor
    unb = check_unbalances(rotor, unbalances, str(rotor_file))
    res, _ = from_sweep(rotor, unb, sweep, _refusing(stability_coefficients(analysis), EquilibriumError),
                        [int(n) for n in probes] if probes else None, check_operating(operating_hz))
    res.meta = {"rotor": sweep.rotor, "rotor_file": str(rotor_file), "internal": analysis.internal,
                "options": analysis.options, "T_supply_K": analysis.T_supply_K,
                "inputs": title_line(rotor, rotor_file, analysis.internal, analysis.options, analysis.T_supply_K)}
    return res


def _refusing(coefficients, error):
    """``coefficients`` with ``error`` turned into ValueError (what the peak search skips)."""
    def call(speed_hz):
        try:
            return coefficients(speed_hz)
        except error as exc:
            raise ValueError(str(exc)) from None

    return call


def command(*, rotor_file, speeds_hz, unbalance, internal: str = "reynolds", data_files=None, grid=None,
            static_load=(), operating_hz=None, supply_c=None, probe=None, out="out", no_plots: bool = False) -> int:
    """``rotor-host response``: see the module docstring; writes into ``out``."""
    from bearing_fmu.io.outputs import ensure_writable, write_json, write_text

    from ..linear.inputs import internal_options, read_rotor
    from ..computed_for import bearing_lines, internal_words
    from .peaks import peak_words
    from .report import markdown

    out = ensure_writable(out)
    options = internal_options(internal, data_files, grid)
    T = None if supply_c is None else supply_c + 273.15
    res = response(rotor_file, speeds_hz, unbalance, internal=internal, options=options, static_loads=static_load,
                   operating_hz=operating_hz, T_supply_K=T, probes=probe, log=lambda msg: print(f"  {msg}"))
    rotor, _ = read_rotor(rotor_file)
    files = []
    if not no_plots:
        from .figures import plot_bode, plot_polar

        for n in res.probes:
            files += [plot_bode(res, n, out / f"bode_node{n}.png", res.meta["inputs"]),
                      plot_polar(res, n, out / f"polar_node{n}.png", res.meta["inputs"])]
    inputs = [f"rotor: {rotor_file} ({res.meta['rotor']})", *bearing_lines(rotor, rotor_file),
              f"internal: {internal_words(res.meta['internal'], res.meta['options'])}",
              "oil: " + ("each bearing's own viscosity" if T is None else f"supply {supply_c:g} C, mu_eff per speed")]
    files = [write_json(out / "response.json", to_json(res)), write_text(out / "response.md", markdown(res, inputs, files)),
             *files]
    if all(s not in ("ok", "unstable") for s in res.status):
        raise RuntimeError(f"{rotor_file}: no speed of the range has a static equilibrium ({res.status[0]}); wrote "
                           f"{files[0]}")
    print(f"computed for: {res.meta['inputs']}")
    print(f"{res.meta['rotor']} [{res.meta['internal']}]: {len(res.speeds_hz)} speeds, unbalance "
          + "; ".join(u.label() for u in res.unbalances))
    if res.threshold_hz is not None:
        print(f"threshold {res.threshold_hz:.2f} Hz: the speeds above it are marked unstable")
    for p in res.peaks:
        print(peak_words(p))
    if not res.peaks:
        print("no peak at the probes inside the range")
    print("wrote " + ", ".join(str(f) for f in files))
    return 0


__all__ = ["ResponseResult", "Evaluator", "default_probes", "find_peaks", "extra_points", "from_sweep", "on_grid", "to_json", "response",
           "response_from", "check_inputs",
           "stability_coefficients", "check_operating", "command"]
