"""``rotor-host level1``: API 617's Level I stability analysis.

**Anticipated cross-coupling** (API 617, 7th ed., 2.6.5.5; Wachel's formula). Each stage of the
rotor file's ``[[stages]]`` contributes::

    q_i = B T_i / (D_i H_i) (rho_d / rho_s)_i,     T_i = P_i / Omega

T_i the stage's torque [N m] at its rated power P_i [W] and the speed Omega [rad/s], D_i the
impeller diameter (blade pitch diameter) [m], H_i the restrictive dimension (the smaller of
diffuser and impeller discharge width; the effective blade height) [m], B = 3 for a
centrifugal stage, 1.5 for an axial one (whose formula has no density ratio); Q_A = sum q_i
[N/m] at the maximum continuous speed.
API 617 prints it in US units as q_A = sum HP B C / (D_c H_c N) (rho_d / rho_s) with C = 63
(HP in hp, D_c and H_c in inches, N in rpm, q_A in klbf/in): 63 = 63025 / 1000, the torque
T [lbf in] = 63025 HP / N in thousands; the two are the same formula (tests/test_response.py
checks one against the other).

**Log decrement against Q.** At the maximum continuous speed (the top of ``--operating-hz``)
the bearings' K, C at their static equilibrium (``linear.stability.Stability.at``) and a
destabilising cross-coupling Q [N/m] shared among the stages in proportion to their q_i,
each acting on its node as a support of Lund stiffness [[0, q], [-q, 0]] (force
(-q z, +q y): tangential, along a forward whirl, feeding it). The damped modes of the rotor
with it (``Rotor.modes``), and the log decrement of the first forward mode, for Q from 0 up;
Q_0 is where it crosses zero (Brent), delta_A its value at Q_A. "First forward mode" is taken
at Q = 0 as the least stable forward mode (``Rotor.whirl`` > 0) among those up to
``linear.modal``'s ranking band (2 x the speed), and followed as Q grows by its shape (the
mode of largest MAC with the previous Q's shape): on oil-film bearings the lowest forward mode
is often a rigid mode the film damps critically (log dec ~ 1.8 on the paper rotor at 30 Hz)
or one with a node at the stage that the cross-coupling does not move, while the first forward
bending mode, the one API 617 means, goes unstable; its frequency rises with Q (on the paper
rotor from 22 to 68 Hz at Q = 1 MN/m), hence the tracking by shape, not by frequency.

**Verdict** (API 617, 7th ed., 2.6.5.8): a Level II analysis is required if

* Q_0 / Q_A < 2, or
* delta_A < 0.1, or
* 2 <= Q_0 / Q_A <= 10 and the critical speed ratio CSR (maximum continuous speed over the
  first undamped critical on rigid supports) and the average gas density fall in region B of
  API 617's screening chart.

The third needs the average gas density (``--gas-density-kg-m3``) and the chart's region
boundary (``csr_boundary``, as digitised by ROSS's former report module); without the density,
when 2 <= Q_0 / Q_A <= 10, the command reports the CSR and says the chart is needed. Otherwise
the Level I screening is passed (no Level II analysis required).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..computed_for import wrapped
from ...model.rotor import Rotor
from ..linear.modal import band_hz

B_FACTOR = {"centrifugal": 3.0, "axial": 1.5}
RATIO_MIN, RATIO_SCREEN, LOG_DEC_MIN = 2.0, 10.0, 0.1  # API 617 Level I limits
DEFAULT_POINTS = 31
STAGE_KEYS_WORDS = "node, power_kw, density_ratio, diameter_mm, restrictive_mm"


def stage_cross_coupling(stage: dict, speed_hz: float) -> float:
    """q_i [N/m] of one [[stages]] entry at ``speed_hz`` (module docstring); the density ratio
    enters a centrifugal stage's only, as in API 617's two formulas."""
    kind = stage.get("kind") or "centrifugal"
    torque = stage["power_kw"] * 1e3 / (2.0 * math.pi * speed_hz)
    ratio = stage["density_ratio"] if kind == "centrifugal" else 1.0
    return B_FACTOR[kind] * torque / (stage["diameter_mm"] * 1e-3 * stage["restrictive_mm"] * 1e-3) * ratio


def anticipated_cross_coupling(stages, speed_hz: float) -> tuple[float, list[float]]:
    """(Q_A [N/m], q_i per stage)."""
    q = [stage_cross_coupling(s, speed_hz) for s in stages]
    return float(sum(q)), q


def with_supports(rotor: Rotor, nodes) -> Rotor:
    """The rotor with extra linear supports at ``nodes`` (0-based) after its bearings: its
    ``modes`` then take one 2x2 per bearing and per support (the stages' cross-coupling)."""
    return Rotor(elements=rotor.elements, material=rotor.material, disks=rotor.disks,
                 bearing_nodes=list(rotor.bearing_nodes) + list(nodes),
                 bearings=list(rotor.bearings) + [rotor.bearings[0]] * len(nodes), name=rotor.name)


def first_forward(freq_hz, log_dec, whirl, band_hz: float) -> int | None:
    """Index of the least stable forward mode with damped frequency <= ``band_hz`` (module
    docstring), None if none."""
    fwd = [i for i in range(len(freq_hz)) if whirl[i] > 0.0 and freq_hz[i] <= band_hz]
    return min(fwd, key=lambda i: log_dec[i]) if fwd else None


@dataclass
class Level1:
    """The check's numbers: Q grid [N/m] and the first forward mode's log dec and frequency there,
    Q_A and per-stage q_i, Q_0 (None: no crossing up to the grid's end), delta_A, the CSR."""

    speed_hz: float
    q_grid: np.ndarray
    log_dec: np.ndarray
    freq_hz: np.ndarray
    Q_A: float
    q_stages: list[float]
    Q_0: float | None
    delta_A: float
    delta_0: float
    first_rigid_critical_hz: float
    meta: dict = field(default_factory=dict)
    gas_density_kg_m3: float | None = None  # the average gas density (suction and discharge)

    @property
    def csr(self) -> float:
        return self.speed_hz / self.first_rigid_critical_hz

    def verdict(self) -> tuple[str, list[str]]:
        """("LEVEL II REQUIRED" | "LEVEL I PASSED" | "SCREENING CHART NEEDED", the reasons)."""
        why = []
        ratio = math.inf if self.Q_0 is None else self.Q_0 / self.Q_A
        if ratio < RATIO_MIN:
            why.append(f"Q_0 / Q_A = {ratio:.3g} < {RATIO_MIN:g}")
        if self.delta_A < LOG_DEC_MIN:
            why.append(f"delta_A = {self.delta_A:.3g} < {LOG_DEC_MIN:g}")
        if why:
            return "LEVEL II REQUIRED", why
        if ratio <= RATIO_SCREEN:
            if self.gas_density_kg_m3 is None:
                return "SCREENING CHART NEEDED", [
                    f"2 <= Q_0 / Q_A = {ratio:.3g} <= 10: API 617 requires a Level II analysis if CSR = {self.csr:.3g} "
                    "and the average gas density fall in region B of its screening chart (give --gas-density-kg-m3)"]
            edge = csr_boundary(self.gas_density_kg_m3)
            where = (f"2 <= Q_0 / Q_A = {ratio:.3g} <= 10, CSR = {self.csr:.3g} at {self.gas_density_kg_m3:g} kg/m^3 "
                     f"against the region boundary {edge:.3g}")
            if self.csr > edge:
                return "LEVEL II REQUIRED", [where + ": region B"]
            return "LEVEL I PASSED", [where + f": region A, delta_A = {self.delta_A:.3g} >= {LOG_DEC_MIN:g}"]
        return "LEVEL I PASSED", [f"Q_0 / Q_A = {'inf' if self.Q_0 is None else f'{ratio:.3g}'} > {RATIO_SCREEN:g} and "
                                  f"delta_A = {self.delta_A:.3g} >= {LOG_DEC_MIN:g}: no Level II analysis required"]


def csr_boundary(gas_density_kg_m3: float) -> float:
    """The critical speed ratio above which API 617's screening chart puts a machine in region B
    (Level II required), at the average gas density [kg/m^3]: 2.5 up to 16.53 kg/m^3, then falling
    along 2.69 - 0.0115 rho, and 0 from 60 kg/m^3 on (region B at any CSR). The chart as digitised
    by ROSS's report module (``Report.stability_level_1``, ROSS <= 1.x), not read off the standard."""
    rho = float(gas_density_kg_m3)
    if rho <= 16.53:
        return 2.5
    return 2.69 - 0.0115 * rho if rho < 60.0 else 0.0


class CrossCoupled:
    """The rotor at one speed with its bearings' K, C and Q shared among the stages."""

    def __init__(self, rotor: Rotor, speed_hz: float, K_b, C_b, stages, weights):
        self.base = rotor
        self.rotor = with_supports(rotor, [s["node"] for s in stages])
        self.omega = 2.0 * math.pi * speed_hz
        nb = len(rotor.bearing_nodes)  # one 2x2 for all bearings or one per bearing
        self.K_b, self.C_b = (np.broadcast_to(np.asarray(a, float), (nb, 2, 2)) for a in (K_b, C_b))
        self.w = np.asarray(weights, float) / float(np.sum(weights))

    def modes(self, Q: float):
        """(freq [Hz], log dec, shapes, whirl) with total cross-coupling Q [N/m]."""
        Kq = np.array([[[0.0, q], [-q, 0.0]] for q in Q * self.w]).reshape(-1, 2, 2)
        freq, ld, shapes = self.rotor.modes(self.omega, np.concatenate([self.K_b, Kq]),
                                            np.concatenate([self.C_b, np.zeros_like(Kq)]))
        busiest = np.argmax(np.abs(shapes[0::4]) ** 2 + np.abs(shapes[1::4]) ** 2, axis=0)
        whirl = np.array([self.base.whirl(shapes[:, i], int(busiest[i])) for i in range(freq.size)])
        return freq, ld, shapes, whirl

    def first_forward(self, Q: float, ref=None) -> tuple[float, float, np.ndarray]:
        """(log dec, damped frequency [Hz], shape) of the first forward mode at Q: without ``ref``
        the least stable forward one in the band, with it the forward mode most like ``ref`` (MAC)."""
        freq, ld, shapes, whirl = self.modes(Q)
        fwd = np.flatnonzero(whirl > 0.0)
        if ref is None:
            i = first_forward(freq, ld, whirl, band_hz(self.omega / (2.0 * math.pi)))
        elif fwd.size:
            mac = np.abs(ref.conj() @ shapes[:, fwd]) ** 2 / (np.sum(np.abs(shapes[:, fwd]) ** 2, axis=0)
                                                              * np.sum(np.abs(ref) ** 2))
            i = int(fwd[np.argmax(mac)])
        else:
            i = None
        if i is None:
            raise RuntimeError(f"no forward mode at {self.omega / (2 * math.pi):.4g} Hz with Q = {Q:.4g} N/m")
        return float(ld[i]), float(freq[i]), shapes[:, i]

    def along(self, grid) -> tuple[np.ndarray, list]:
        """(log dec, frequency) along an increasing Q grid from 0, the mode followed by its shape; and
        the shapes."""
        out, shapes, ref = [], [], None
        for q in grid:
            ld, f, ref = self.first_forward(float(q), ref)
            out.append((ld, f))
            shapes.append(ref)
        return np.array(out), shapes


def level1(rotor: Rotor, speed_hz: float, K_b, C_b, points: int = DEFAULT_POINTS) -> Level1:
    """The Level I numbers of ``rotor`` (with its ``stages``) at ``speed_hz`` on bearings K_b, C_b."""
    from scipy.optimize import brentq

    from .ucs import forward_criticals

    QA, qs = anticipated_cross_coupling(rotor.stages, speed_hz)
    cc = CrossCoupled(rotor, speed_hz, K_b, C_b, rotor.stages, qs)
    top = 2.0 * QA
    for _ in range(12):  # up to 2^12 x 2 Q_A: far enough for Q_0 / Q_A > 10 to be told
        grid = np.linspace(0.0, top, int(points))
        vals, shapes = cc.along(grid)
        if vals[0, 0] <= 0.0 or (vals[:, 0] < 0.0).any():
            break
        top *= 2.0
    Q0 = None
    if vals[0, 0] <= 0.0:
        Q0 = 0.0
    elif (vals[:, 0] < 0.0).any():
        k = int(np.argmax(vals[:, 0] < 0.0))
        Q0 = float(brentq(lambda q: cc.first_forward(q, shapes[k - 1])[0], grid[k - 1], grid[k], xtol=1e-9 * top))
        grid = np.linspace(0.0, max(1.25 * Q0, 1.25 * QA), int(points))
        vals, shapes = cc.along(grid)
    j = int(np.argmin(np.abs(grid - QA)))  # delta_A: followed from the nearest grid point
    delta_A = cc.first_forward(QA, shapes[j])[0]
    k_rigid = 1e3 * float(np.max(np.diag(rotor.K)))
    first = float(forward_criticals(rotor, k_rigid, 1)[0][0])
    return Level1(float(speed_hz), grid, vals[:, 0], vals[:, 1], QA, qs, Q0, delta_A, float(vals[0, 0]), first)


def plot_level1(r: Level1, path, inputs: str = "") -> Path:
    from ..plotting import pyplot, save_figure

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(9, 5.5))
    ax.plot(r.q_grid / 1e6, r.log_dec, "o-", ms=3, label="first forward mode")
    ax.axhline(0.0, color="k", lw=0.8)
    ax.axhline(LOG_DEC_MIN, color="tab:red", ls=":", lw=1, label=f"delta = {LOG_DEC_MIN:g} (API 617)")
    ax.axvline(r.Q_A / 1e6, color="tab:orange", ls="--", label=f"Q_A = {r.Q_A / 1e6:.3g} MN/m, delta_A {r.delta_A:.3g}")
    if r.Q_0 is not None:
        ax.axvline(r.Q_0 / 1e6, color="tab:red", ls="--", label=f"Q_0 = {r.Q_0 / 1e6:.3g} MN/m")
    ax.set_xlabel("cross-coupling Q at the stages [MN/m]")
    ax.set_ylabel("log decrement")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(f"API 617 Level I at {r.speed_hz:g} Hz: {r.verdict()[0]}\n{wrapped(inputs, 110)}", fontsize=9)
    return save_figure(fig, path)


def run(rotor_file, operating_hz, *, internal="reynolds", options=None, static_loads=(), T_supply_K=None,
        points: int = DEFAULT_POINTS, gas_density_kg_m3=None) -> Level1:
    """Read the rotor file (its [[stages]] required), the bearings at the maximum continuous speed
    (the top of ``operating_hz``), and the check."""
    from ..linear.stability import Stability
    from ..linear.inputs import read_rotor
    from ..computed_for import title_line
    from .unbalance import check_operating

    rotor, loads = read_rotor(rotor_file, static_loads)
    if not rotor.stages:
        raise ValueError(f"{rotor_file}: no [[stages]] table: API 617's Level I check needs each stage's "
                         f"{STAGE_KEYS_WORDS} (docs/file-formats.md, Rotor file: [[stages]])")
    lo, mcs = check_operating(operating_hz)
    analysis = Stability(rotor, internal, options, loads, where=str(rotor_file), T_supply_K=T_supply_K)
    point, _ = analysis.at(mcs)
    r = level1(rotor, mcs, point.K, point.C, points)
    r.gas_density_kg_m3 = gas_density_kg_m3
    r.meta = {"rotor": rotor.name or Path(rotor_file).stem, "rotor_file": str(rotor_file), "internal": analysis.internal,
              "options": analysis.options, "operating_hz": [lo, mcs],
              "inputs": title_line(rotor, rotor_file, analysis.internal, analysis.options, T_supply_K)}
    return r


def to_json(r: Level1) -> dict:
    verdict, why = r.verdict()
    return {"speed_hz": r.speed_hz, "Q_A_N_m": r.Q_A, "q_stages_N_m": r.q_stages, "Q_0_N_m": r.Q_0,
            "ratio_Q0_QA": None if r.Q_0 is None else r.Q_0 / r.Q_A, "log_dec_at_Q_A": r.delta_A,
            "log_dec_at_0": r.delta_0, "first_rigid_critical_hz": r.first_rigid_critical_hz, "csr": r.csr,
            "gas_density_kg_m3": r.gas_density_kg_m3,
            "csr_boundary": None if r.gas_density_kg_m3 is None else csr_boundary(r.gas_density_kg_m3),
            "verdict": verdict, "reasons": why, "Q_N_m": r.q_grid.tolist(), "log_dec": r.log_dec.tolist(),
            "freq_hz": r.freq_hz.tolist(), **r.meta}


def markdown(r: Level1, inputs: list[str], figures=()) -> str:
    verdict, why = r.verdict()
    lines = [f"# API 617 Level I stability: {r.meta.get('rotor', '')}", "", f"**{verdict}**", ""]
    lines += [f"- {w}" for w in why] + ["", "## Inputs", ""] + [f"- {x}" for x in inputs]
    lines += ["", f"- maximum continuous speed {r.speed_hz:g} Hz; stages: Q_A = sum q_i = {r.Q_A:.4g} N/m "
                  f"({', '.join(f'{q:.4g}' for q in r.q_stages)})",
              f"- first forward mode: log dec {r.delta_0:.4g} at Q = 0, {r.delta_A:.4g} at Q_A; Q_0 = "
              + ("not reached" if r.Q_0 is None else f"{r.Q_0:.4g} N/m (Q_0 / Q_A = {r.Q_0 / r.Q_A:.3g})"),
              f"- CSR = {r.speed_hz:g} / {r.first_rigid_critical_hz:.4g} Hz (first undamped critical on rigid supports) "
              f"= {r.csr:.3g}", ""]
    if figures:
        lines += ["## Figures", ""] + [f"![{f.stem}]({f.name})" for f in figures] + [""]
    return "\n".join(lines)


def command(*, rotor_file, operating_hz, internal: str = "reynolds", data_files=None, grid=None, static_load=(),
            supply_c=None, points: int = DEFAULT_POINTS, gas_density_kg_m3=None, out="out", no_plots: bool = False) -> int:
    """``rotor-host level1``: writes level1.json, level1.md and level1.png into ``out``."""
    from bearing_fmu.io.outputs import ensure_writable, write_json, write_text

    from ..linear.inputs import internal_options
    from ..computed_for import bearing_lines, internal_words

    out = ensure_writable(out)
    T = None if supply_c is None else supply_c + 273.15
    r = run(rotor_file, operating_hz, internal=internal, options=internal_options(internal, data_files, grid),
            static_loads=static_load, T_supply_K=T, points=points, gas_density_kg_m3=gas_density_kg_m3)
    rotor = Rotor.from_toml(rotor_file)
    files = [] if no_plots else [plot_level1(r, out / "level1.png", r.meta["inputs"])]
    inputs = [f"rotor: {rotor_file} ({r.meta['rotor']})", *bearing_lines(rotor, rotor_file),
              f"internal: {internal_words(r.meta['internal'], r.meta['options'])}"]
    files = [write_json(out / "level1.json", to_json(r)), write_text(out / "level1.md", markdown(r, inputs, files)),
             *files]
    verdict, why = r.verdict()
    print(f"computed for: {r.meta['inputs']}")
    print(f"{r.meta['rotor']} at {r.speed_hz:g} Hz: Q_A {r.Q_A:.4g} N/m, Q_0 "
          + ("not reached" if r.Q_0 is None else f"{r.Q_0:.4g} N/m") + f", log dec {r.delta_0:.3g} at Q = 0, "
          f"{r.delta_A:.3g} at Q_A, CSR {r.csr:.3g}")
    print(f"{verdict}: " + "; ".join(why))
    print("wrote " + ", ".join(str(f) for f in files))
    return 0


__all__ = ["B_FACTOR", "csr_boundary", "stage_cross_coupling", "anticipated_cross_coupling", "with_supports", "first_forward",
           "Level1", "CrossCoupled", "level1", "plot_level1", "run", "to_json", "markdown", "command"]
