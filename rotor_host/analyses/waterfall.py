"""Run-up and coast-down: the response spectrum against speed (a waterfall, or cascade).

The whirl of a node, s(t) = y(t) + i z(t), is cut into windows (Hann, half overlapping); each
window's spectrum is taken at the window's mean speed. Positive frequencies are forward whirl
(from +y toward +z, the sense of rotation), negative backward whirl. An unbalance response is
the 1x line; a resonance shows as a peak along it where the speed crosses a critical speed; oil
whirl is a forward line just below 0.5x, and oil whip that line locking onto a natural frequency
(constant frequency while the speed rises).

``spectra`` computes it; ``plot_waterfall`` draws it with the 1x, 0.5x and -1x lines, the
critical speeds and the orbits at chosen speeds; ``summary`` finds the 1x peak (largest 1x
amplitude), which ``peak_line`` calls a critical speed only where one of the critical speeds
crossed (``crossings``: damped natural frequencies on the linearised bearings) lies near it, and
the speed where the subsynchronous whirl first exceeds the 1x response. ``rotor-host run`` draws
it for a scene with a [speed_profile]; ``rotor-host waterfall RUN.npz`` from a saved run. A run at
one constant speed, a window shorter than ``MIN_WINDOW_SAMPLES`` recorded samples or
``MIN_WINDOW_REVS`` revolutions at the run's top speed, and orbits asked outside the run's speeds
are refused.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .plotting import pyplot, save_figure

DEFAULT_WINDOW_S = 0.25  # 4 Hz resolution; a run-up of a few Hz per second stays within a bin
MIN_WINDOW_SAMPLES = 16  # fewer recorded samples in a window: no spectrum worth the name
MIN_WINDOW_REVS = 2.0  # shaft revolutions at the top speed: resolution 1/T below 0.5x, 1x and 0.5x apart


def speed_range(arrays: dict) -> tuple[float, float]:
    """(lowest, highest) shaft speed [Hz] of a run."""
    speed = np.asarray(arrays["speed_hz"], float)
    return float(np.min(speed)), float(np.max(speed))


def constant_speed(arrays: dict) -> float | None:
    """The run's speed [Hz] when it stays constant (to 1e-9 of it), else None."""
    lo, hi = speed_range(arrays)
    return hi if hi - lo <= 1e-9 * max(abs(hi), 1.0) else None


def window_problem(arrays: dict, window_s: float) -> str:
    """Why ``window_s`` is too short for the run's spectra ("" when it is not): fewer than
    MIN_WINDOW_SAMPLES recorded samples, or fewer than MIN_WINDOW_REVS revolutions at the top
    speed (a resolution 1/window that cannot tell 0.5x from 1x anywhere in the run)."""
    t = np.asarray(arrays["t"], float)
    dt = float(np.median(np.diff(t))) if t.size > 1 else math.inf
    top = speed_range(arrays)[1]
    need = max(MIN_WINDOW_SAMPLES * dt, MIN_WINDOW_REVS / top if top > 0 else 0.0)
    if window_s >= need * (1 - 1e-9):
        return ""
    return (f"shorter than {MIN_WINDOW_SAMPLES} recorded samples ({MIN_WINDOW_SAMPLES * dt:.3g} s at the record step "
            f"{dt:.3g} s) or {MIN_WINDOW_REVS:g} revolutions at the run's top speed {top:g} Hz "
            f"({MIN_WINDOW_REVS / top:.3g} s): give at least {need:.3g} s (default {DEFAULT_WINDOW_S:g} s)")


def outside_run(arrays: dict, speeds_hz) -> list[float]:
    """The speeds [Hz] of ``speeds_hz`` outside the run's lowest-highest speed."""
    lo, hi = speed_range(arrays)
    slack = 1e-9 * max(abs(hi), 1.0)
    return [float(f) for f in speeds_hz if not lo - slack <= f <= hi + slack]


@dataclass
class Spectra:
    """speed_hz (k,), t_s (k,) window centres; freq_hz (m,) signed (forward > 0);
    amp (k, m) whirl amplitude [m] (a circular whirl of radius A shows A at its frequency)."""

    node: int
    speed_hz: np.ndarray
    t_s: np.ndarray
    freq_hz: np.ndarray
    amp: np.ndarray

    def along(self, ratio: float, band_hz: float = 2.0) -> np.ndarray:
        """Largest amplitude within band_hz of ratio x speed, per window (1x: the unbalance
        response; 0.5x: whirl)."""
        out = np.zeros(len(self.speed_hz))
        for k, f in enumerate(self.speed_hz):
            sel = np.abs(self.freq_hz - ratio * f) <= band_hz
            out[k] = self.amp[k, sel].max() if sel.any() else 0.0
        return out

    def subsynchronous(self, lo: float = 0.3, hi: float = 0.7) -> tuple[np.ndarray, np.ndarray]:
        """(amplitude, frequency [Hz]) of the largest forward peak between lo and hi x speed, per window."""
        amp, freq = np.zeros(len(self.speed_hz)), np.zeros(len(self.speed_hz))
        for k, f in enumerate(self.speed_hz):
            sel = (self.freq_hz >= lo * f) & (self.freq_hz <= hi * f)
            if sel.any():
                j = np.argmax(np.where(sel, self.amp[k], -1.0))
                amp[k], freq[k] = self.amp[k, j], self.freq_hz[j]
        return amp, freq


def spectra(arrays: dict, node: int, window_s: float = DEFAULT_WINDOW_S, t_from: float = 0.0) -> Spectra:
    """The waterfall of recorded ``node`` (1-based) from a run's arrays (``run_scene``'s npz)."""
    nodes = list(np.asarray(arrays["nodes"]).ravel())
    if node not in nodes:
        raise ValueError(f"node {node} was not recorded; recorded nodes: {', '.join(map(str, nodes))} "
                         "(add it to the scene's [record] nodes)")
    c = nodes.index(node)
    t = np.asarray(arrays["t"], float)
    if t.size < MIN_WINDOW_SAMPLES:
        raise ValueError(f"the run has {t.size} recorded times: too short for a spectrum")
    if "speed_hz" in arrays:
        check_run_up(arrays)
        problem = window_problem(arrays, window_s)
        if problem:
            raise ValueError(f"window {window_s:g} s: {problem}")
    dt = float(np.median(np.diff(t)))
    n = int(round(window_s / dt))
    if n > t.size:
        raise ValueError(f"window {window_s:g} s is longer than the run ({t[-1] - t[0]:g} s); pass a shorter window")
    s = np.asarray(arrays["y"], float)[:, c] + 1j * np.asarray(arrays["z"], float)[:, c]
    speed = np.asarray(arrays.get("speed_hz", np.full(t.size, np.nan)), float)
    w = np.hanning(n)
    freq = np.fft.fftshift(np.fft.fftfreq(n, dt))
    rows, sp, tc = [], [], []
    start = int(np.searchsorted(t, t_from))
    for i in range(start, t.size - n + 1, n // 2):
        seg = s[i:i + n] - s[i:i + n].mean()  # the static deflection is not a whirl
        rows.append(np.abs(np.fft.fftshift(np.fft.fft(seg * w))) / w.sum())
        sp.append(float(np.mean(speed[i:i + n])))
        tc.append(float(t[i + n // 2]))
    return Spectra(node, np.array(sp), np.array(tc), freq, np.array(rows))


def summary(sp: Spectra, criticals: list[dict] | None = None) -> dict:
    """The 1x peak (speed of the largest 1x amplitude) and the whirl onset: the speed from which
    the subsynchronous forward peak stays above the 1x amplitude to the end of the run (None if
    it does not at the end), with its frequency and ratio to the speed there.

    ``criticals``: the critical speeds the run crosses (``crossings.RunCriticals.criticals``;
    None: not known). ``critical_hz`` is the one near the 1x peak (``modal.critical_near``:
    within 10 % of it plus the speed change over one window), None when none is: then the peak
    is no resonance, just the largest 1x response (e.g. the top of a run that stays below its
    first critical, where an unbalance response grows with speed squared)."""
    from .linear.modal import critical_near

    one = sp.along(1.0)
    sub, fsub = sp.subsynchronous()
    k = int(np.argmax(one))
    # the speed change over one window: twice the step between windows (they overlap by half)
    step = 2.0 * float(np.median(np.abs(np.diff(sp.speed_hz)))) if sp.speed_hz.size > 1 else 0.0
    near = None if criticals is None else critical_near(float(sp.speed_hz[k]), criticals, step)
    out = {"node": sp.node, "peak_1x_hz": float(sp.speed_hz[k]), "peak_1x_amplitude_m": float(one[k]),
           "peak_at_end": k in (0, sp.speed_hz.size - 1), "critical_hz": None if near is None else near["speed_hz"],
           "criticals_hz": None if criticals is None else [c["speed_hz"] for c in criticals],
           "whirl_onset_hz": None, "whirl_hz": None, "whirl_ratio": None}
    # onset: from where on the whirl stays above the 1x response to the end (a free vibration
    # ringing after a critical speed also shows below 1x, but dies away)
    above = sub > np.maximum(one, 1e-12)
    if above.size >= 2 and above[-1] and above[-2]:
        below = np.nonzero(~above)[0]
        j = int(below[-1]) + 1 if below.size else 0
        out.update(whirl_onset_hz=float(sp.speed_hz[j]), whirl_hz=float(fsub[j]),
                   whirl_ratio=float(fsub[j] / sp.speed_hz[j]))
    return out


def peak_line(s: dict, lo_hz: float, hi_hz: float, note: str = "") -> str:
    """The summary's words for the 1x peak of ``summary`` ``s`` in a run over lo-hi Hz: a
    critical speed only where one lies near the peak (``note``: why the critical speeds are not
    known, when they are not)."""
    amp = f"{s['peak_1x_amplitude_m'] * 1e6:.1f} um 1x"
    where = f"{s['peak_1x_hz']:.1f} Hz" + (", the end of the run" if s["peak_at_end"] else "")
    if s["critical_hz"] is not None:
        return f"critical speed {s['critical_hz']:.1f} Hz crossed, 1x peak at {s['peak_1x_hz']:.1f} Hz ({amp})"
    if s["criticals_hz"] is None:
        return f"1x peak at {where} ({amp}; {note or 'critical speeds not computed'})"
    crossed = (f"critical speed(s) crossed: {', '.join(f'{c:.1f} Hz' for c in s['criticals_hz'])}"
               if s["criticals_hz"] else f"no critical speed crossed in {lo_hz:g}-{hi_hz:g} Hz")
    return f"1x peak at {where} ({amp}), not a critical speed ({crossed})"


def plot_waterfall(arrays: dict, path, *, nodes, window_s: float = DEFAULT_WINDOW_S, title: str = "",
                   orbit_speeds_hz=None, criticals_hz=()) -> Path:
    """One panel per node: whirl amplitude (log colour) against frequency and speed, with the
    1x, 0.5x and -1x lines and the critical speeds on the 1x line; a row of orbits (bearing
    journal and each node) at chosen speeds inside the run's (default: the start, the 1x peak and
    the end); with a supply temperature (the run's ``T_eff``) beside them each bearing's effective
    film temperature against the speed."""

    plt = pyplot()
    specs = [spectra(arrays, n, window_s) for n in nodes]
    t, speed = np.asarray(arrays["t"]), np.asarray(arrays["speed_hz"])
    if orbit_speeds_hz is None:
        res = summary(specs[0])["peak_1x_hz"]
        orbit_speeds_hz = sorted({round(float(speed[0]), 1), round(res, 1), round(float(speed[-1]), 1)})
    bad = outside_run(arrays, orbit_speeds_hz)
    if bad:
        lo, hi = speed_range(arrays)
        raise ValueError(f"orbit speed {bad[0]:g} Hz is outside the run's speeds {lo:g}-{hi:g} Hz")
    thermal = bool(np.size(arrays.get("T_eff", ())))
    below = len(orbit_speeds_hz) + thermal
    fig = plt.figure(figsize=(max(5.2 * len(specs), 3.8 * below), 8.6))
    grid = fig.add_gridspec(2, 1, height_ratios=(2.2, 1))
    top, bottom = grid[0].subgridspec(1, len(specs)), grid[1].subgridspec(1, below)  # each row full: no empty slot
    for i, sp in enumerate(specs):
        ax = fig.add_subplot(top[0, i])
        fmax = 1.3 * float(np.nanmax(sp.speed_hz))
        sel = np.abs(sp.freq_hz) <= fmax
        amp = np.maximum(sp.amp[:, sel], 1e-12) * 1e6
        lo = max(amp.max() * 1e-3, 1e-6)
        mesh = ax.pcolormesh(sp.freq_hz[sel], sp.speed_hz, np.log10(np.maximum(amp, lo)), shading="nearest",
                             cmap="viridis")
        fig.colorbar(mesh, ax=ax, label="log10 whirl amplitude [um]")
        for ratio, style in ((1.0, "w--"), (0.5, "w:"), (-1.0, "w-.")):
            ax.plot(ratio * sp.speed_hz, sp.speed_hz, style, lw=0.9, label=f"{ratio:g}x")
        if len(criticals_hz):
            ax.plot(criticals_hz, criticals_hz, "o", ms=9, mfc="none", mec="white", mew=1.4,
                    label="critical speed")
        ax.set_xlabel("whirl frequency [Hz] (forward > 0)")
        ax.set_ylabel("shaft speed [Hz]")
        ax.set_title(f"node {sp.node}")
        ax.legend(loc="lower right", fontsize=7)
    col = {n: i for i, n in enumerate(np.asarray(arrays["nodes"]).ravel())}
    for j, f in enumerate(orbit_speeds_hz):
        ax = fig.add_subplot(bottom[0, j])
        k = int(np.argmin(np.abs(speed - f)))
        dtr = float(np.median(np.diff(t)))
        span = max(1, int(round(3.0 / (0.4 * max(speed[k], 1e-9)) / dtr)))  # three periods of a 0.4x whirl
        a, b = max(0, k - span // 2), min(t.size, k + span // 2 + 1)
        for n in nodes:
            c = col[n]
            ax.plot(arrays["y"][a:b, c] * 1e6, arrays["z"][a:b, c] * 1e6, lw=0.8, label=f"node {n}")
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_title(f"{speed[k]:.1f} Hz (t = {t[k]:.2f} s)", fontsize=9)
        ax.set_xlabel("y [um]")
        ax.set_ylabel("z [um]")
        ax.legend(fontsize=7)
    if thermal:
        ax = fig.add_subplot(bottom[0, len(orbit_speeds_hz)])
        for k, n in enumerate(np.asarray(arrays["bearing_nodes"]).ravel()):
            ax.plot(speed, np.asarray(arrays["T_eff"])[:, k] - 273.15, lw=1.0, label=f"bearing at node {n}")
        ax.set_xlabel("shaft speed [Hz]")
        ax.set_ylabel("T_eff [C]")
        ax.set_title("effective film temperature", fontsize=9)
        ax.legend(fontsize=7)
    if title:
        fig.suptitle(title, fontsize=9)
    return save_figure(fig, path)



def default_nodes(arrays: dict) -> list[int]:
    """The first bearing node and the recorded node with the largest whirl amplitude."""
    nodes = [int(n) for n in np.asarray(arrays["nodes"]).ravel()]
    bearing = int(np.asarray(arrays["bearing_nodes"]).ravel()[0])
    ampl = [float(np.ptp(arrays["y"][:, i]) + np.ptp(arrays["z"][:, i])) for i in range(len(nodes))]
    big = nodes[int(np.argmax(ampl))]
    return [bearing] if big == bearing else [bearing, big]


def whirl_line(s: dict) -> str:
    """The summary's words for the whirl onset of ``summary`` ``s``."""
    return (f"whirl from {s['whirl_onset_hz']:.1f} Hz at {s['whirl_hz']:.1f} Hz ({s['whirl_ratio']:.2f}x)"
            if s["whirl_onset_hz"] else "no subsynchronous whirl above the 1x response")


def check_run_up(arrays: dict, path="the run") -> None:
    """ValueError unless the run's speed changes (a run-up or coast-down)."""
    if "speed_hz" not in arrays:
        raise ValueError(f"{path}: the run has no speed_hz array (made before run-ups were recorded); run it again")
    speed, t = np.asarray(arrays["speed_hz"], float), np.asarray(arrays.get("t", []), float)
    for name, a in (("speed_hz", speed), ("t", t)):
        bad = np.flatnonzero(~np.isfinite(a))
        if bad.size:
            raise ValueError(f"{path}: array {name} holds {bad.size} value(s) that are not finite numbers (first at "
                             f"index {bad[0]}: {float(a[bad[0]])!r}); a spectrum against speed needs every one")
    f = constant_speed(arrays)
    if f is not None:
        raise ValueError(f"{path}: the run is at one constant speed, {f:g} Hz; a waterfall shows the spectra against "
                         "a changing speed: run a scene with a [speed_profile] (docs/runup.md), or see this run with "
                         "`rotor-host limit-cycle`")


def command(*, run, nodes=None, window_s: float = DEFAULT_WINDOW_S, orbits_at_hz=None, output=None) -> int:
    """``rotor-host waterfall``: the response spectra of a run-up run's .npz against speed, drawn
    into ``output`` (default: beside the run); the 1x peak named a critical speed only where the
    run crosses one (``crossings.run_criticals``)."""
    from .linear.crossings import run_criticals
    from .computed_for import run_inputs, wrapped

    from bearing_fmu.io.npz import read_npz

    path = Path(run)
    arrays = read_npz(path, "a saved run (.npz of rotor-host run)")
    check_run_up(arrays, path)
    lo, hi = speed_range(arrays)
    problem = window_problem(arrays, window_s)
    if problem:
        raise ValueError(f"--window-s {window_s:g}: {problem}")
    bad = outside_run(arrays, orbits_at_hz or [])
    if bad:
        raise ValueError(f"--orbits-at-hz {bad[0]:g}: outside the run's speeds {lo:g}-{hi:g} Hz ({path})")
    nodes = nodes or default_nodes(arrays)
    crit = run_criticals(path, arrays)
    out = Path(output) if output else path.with_name(f"{path.stem}_waterfall.png")
    inputs = run_inputs(path)
    if inputs:
        print(f"computed for: {inputs}")
    plot_waterfall(arrays, out, nodes=nodes, window_s=window_s, orbit_speeds_hz=orbits_at_hz,
                   title=path.stem + (f"\n{wrapped(inputs)}" if inputs else ""), criticals_hz=crit.speeds_hz)
    if crit.note:
        print(crit.note)
    for n in nodes:
        s = summary(spectra(arrays, n, window_s), crit.criticals)
        print(f"node {n}: {peak_line(s, lo, hi, crit.note)}; {whirl_line(s)}")
    print(f"wrote {out}")
    return 0


__all__ = ["Spectra", "spectra", "summary", "peak_line", "whirl_line", "plot_waterfall", "default_nodes",
           "speed_range", "constant_speed", "window_problem", "outside_run", "check_run_up", "command"]
