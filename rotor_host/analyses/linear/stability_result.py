"""What a stability sweep found (``stability.Stability.sweep``): one ``SpeedPoint`` per speed (the
damped modes, their log decrements and whirl), the ``Threshold`` of instability refined between two
speeds, and the ``StabilityResult`` with the verdict the command prints."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .modal import RANK_UP_TO, band_rule, beyond_band_line, least_beyond, least_in_band, no_critical_line

FORWARD = 0.0  # whirl() above this: forward, below: backward


def direction(w: float) -> str:
    """'forward' or 'backward' for a whirl measure (``Rotor.whirl``: +1 forward, -1 backward)."""
    return "forward" if w > FORWARD else "backward"


DEFAULT_MODES = 8  # modes shown in the Campbell diagram and the table


# ----------------------------------------------------------------------------- results

@dataclass
class SpeedPoint:
    """The rotor at one speed: equilibrium, bearing coefficients, modes.

    ``freq_hz``, ``log_dec``, ``whirl`` hold every oscillatory mode (sorted by damped
    frequency; ``Rotor.modes``), ``shapes`` their complex shapes (n_dof x n_modes);
    ``journal`` [m] and ``eccentricity`` per bearing; ``K`` [N/m], ``C`` [N s/m] per bearing
    (n_bearings, 2, 2), Lund's sign. ``status`` "ok" or "no equilibrium" (then ``message``
    says why and the arrays are empty). ``band_hz``: the least stable mode is ranked among the
    modes up to this damped frequency (``modal.RANK_UP_TO`` x the sweep's top speed)."""

    speed_hz: float
    status: str = "ok"
    message: str = ""
    journal: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    eccentricity: np.ndarray = field(default_factory=lambda: np.zeros(0))
    K: np.ndarray = field(default_factory=lambda: np.zeros((0, 2, 2)))
    C: np.ndarray = field(default_factory=lambda: np.zeros((0, 2, 2)))
    freq_hz: np.ndarray = field(default_factory=lambda: np.zeros(0))
    log_dec: np.ndarray = field(default_factory=lambda: np.zeros(0))
    whirl: np.ndarray = field(default_factory=lambda: np.zeros(0))
    band_hz: float = math.inf
    shapes: np.ndarray = field(default_factory=lambda: np.zeros((0, 0), complex), repr=False)
    T_eff_K: np.ndarray = field(default_factory=lambda: np.zeros(0))  # per bearing, with a supply temperature
    mu_eff_Pa_s: np.ndarray = field(default_factory=lambda: np.zeros(0))

    @property
    def ok(self) -> bool:
        return self.status == "ok"

    def forward(self, i: int) -> bool:
        """Mode i whirls forward (from +y toward +z, with the shaft)."""
        return bool(self.whirl[i] > FORWARD)

    @property
    def least(self) -> int | None:
        """Index of the least stable mode (smallest log decrement) up to ``band_hz``; None: none there."""
        return least_in_band(self.freq_hz, self.log_dec, self.band_hz)

    @property
    def least_log_dec(self) -> float:
        return math.inf if self.least is None else float(self.log_dec[self.least])


@dataclass
class Threshold:
    """Where the least stable mode's log decrement crosses zero: ``speed_hz`` and the mode's
    damped frequency ``whirl_hz`` there, its whirl direction, and the SpeedPoint at it;
    ``bracket`` the two range speeds around it; ``how`` "brent" (refined) or "interpolated"
    (linear between the bracket, when an equilibrium inside it failed)."""

    speed_hz: float
    whirl_hz: float
    whirl: float
    point: SpeedPoint
    bracket: tuple[float, float]
    how: str = "brent"

    @property
    def ratio(self) -> float:
        """Whirl frequency ratio: whirl frequency / shaft speed."""
        return self.whirl_hz / self.speed_hz


@dataclass
class StabilityResult:
    """A sweep: its points (one per speed asked), the threshold (None when the least stable
    log decrement does not cross zero in the range), the critical speeds (1x crossings) and
    the timings [s]: ``setup`` (internals built, numba loaded), ``equilibrium``,
    ``eigen`` (linearisation and modes), ``refine`` (the threshold's Brent evaluations)."""

    rotor: str
    internal: str
    options: dict
    bearing_nodes: list[int]  # 1-based
    loads_N: list[list[float]]
    points: list[SpeedPoint] = field(default_factory=list)
    threshold: Threshold | None = None
    unstable_from_start: bool = False
    criticals: list[dict] = field(default_factory=list)
    damped_crossings: list[dict] = field(default_factory=list)  # 1x crossings of modes with AF < 2.5
    rank_up_to: float = RANK_UP_TO
    band_hz: float = math.inf
    timings: dict = field(default_factory=lambda: {"setup": 0.0, "equilibrium": 0.0, "eigen": 0.0, "refine": 0.0})
    n_modes: int = DEFAULT_MODES
    unsupported: list = field(default_factory=list)  # speeds [Hz] where the bearings did not hold the rotor
    status: str = "ok"
    T_supply_K: float | None = None  # the oil's supply temperature (None: isoviscous bearings)
    inputs: str = ""  # what it was computed for, in one line (analyses.computed_for.title_line)

    @property
    def ok_points(self) -> list[SpeedPoint]:
        return [p for p in self.points if p.ok]

    def notes(self) -> list[str]:
        """The ranking rule with the modes beyond it, and the critical speeds' absence when none."""
        out = [] if self.criticals or not self.points else [
            no_critical_line(self.points[0].speed_hz, self.points[-1].speed_hz, self.damped_crossings)]
        return out + [band_rule(self.rank_up_to, self.band_hz),
                      beyond_band_line(least_beyond(self.ok_points, self.band_hz), self.band_hz)]

    def verdict(self) -> str:
        """The one line the command prints: ``threshold X Hz, whirl Y Hz`` or why there is none."""
        pts = self.ok_points
        if not pts:
            return "no threshold: no speed of the range has a static equilibrium"
        speeds = f"{self.points[0].speed_hz:g}-{self.points[-1].speed_hz:g} Hz"
        if self.threshold is not None:
            t = self.threshold
            return (f"threshold {t.speed_hz:.2f} Hz, whirl {t.whirl_hz:.2f} Hz (whirl ratio {t.ratio:.3f}, "
                    f"{'forward' if t.whirl > FORWARD else 'backward'})")
        if self.unstable_from_start:
            p = pts[0]
            return (f"no threshold in {speeds}: already unstable at {p.speed_hz:g} Hz (log dec {p.least_log_dec:.3g} "
                    f"at {p.freq_hz[p.least]:.2f} Hz); the threshold lies below the range")
        p = min(pts, key=lambda q: q.least_log_dec)
        if p.least is None:
            return f"no threshold in {speeds}: no mode up to {self.band_hz:.4g} Hz at any speed (see the json)"
        if p.least_log_dec <= 0.0:  # the crossing lies across speeds without an equilibrium
            first = next(q for q in pts if q.least_log_dec <= 0.0)
            return (f"no threshold refined in {speeds}: unstable at {first.speed_hz:g} Hz (log dec "
                    f"{first.least_log_dec:.3g}), but the speed before it has no static equilibrium; see the table")
        return (f"no threshold in {speeds}: every mode stays stable up to {self.band_hz:.4g} Hz (least log dec "
                f"{p.least_log_dec:.3g} at {p.speed_hz:g} Hz)" + ("" if self.status == "ok" else f" [{self.status}]"))
