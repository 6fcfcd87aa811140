"""Limit-cycle study: the envelope of the bearing eccentricity over time.

The dt study (``rotor_host.analyses.dt_study``, ``rotor-host dt-study``) compares orbits point by
point in time. On a self-excited whirl that is the wrong yardstick for long runs: the whirl
phase drifts by O(dt^2) per cycle, so two runs on the *same* limit cycle drift apart point
by point while the size of the orbit agrees. This module measures what the limit cycle is:

- ``envelope``: the largest and smallest journal eccentricity (over the bearings) in each
  window of ``revs`` shaft revolutions; its max is the size of the orbit over time;
- ``settled_since``: the earliest time from which the windowed max stays inside a band of
  +-``tol_pct_cr`` % of CR to the end of the run (``None`` if it never does), so "the limit
  cycle holds" means: settled, and held for a while before the end;
- ``envelope_change``: the largest difference of two runs' envelopes (e.g. dt and dt/2),
  in % of CR, over the windows both runs completed.

``add_arguments``/``run`` form the command ``rotor-host limit-cycle`` (``SCENE`` or a saved
``.npz``) that writes the envelope as markdown + json (+ png) to an output folder.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from bearing_fmu.io.outputs import ensure_writable, write_json, write_text

from .plotting import pyplot, save_figure


@dataclass
class Envelope:
    """Per window of ``period_s``: its end time and the largest/smallest eccentricity ratio
    (over all bearings) of the samples in it. Only complete windows are kept."""

    t: np.ndarray
    e_max: np.ndarray
    e_min: np.ndarray
    period_s: float


def envelope(arrays: dict, period_s: float) -> Envelope:
    """Windowed max/min of the bearing eccentricity ratio (``arrays["eccentricity"]``,
    (n_out, n_bearings), as a scene run records it) over windows [k T, (k+1) T)."""
    t = np.asarray(arrays["t"], dtype=float)
    e = np.asarray(arrays["eccentricity"], dtype=float)
    e = e.reshape(len(t), -1).max(axis=1)
    if not period_s > 0:
        raise ValueError(f"period_s must be > 0, got {period_s}")
    k = np.floor((t - t[0]) / period_s + 1e-9).astype(int)
    n = int(np.floor((t[-1] - t[0]) / period_s + 1e-9)) if len(t) else 0  # complete windows
    if n < 1:
        return Envelope(np.empty(0), np.empty(0), np.empty(0), period_s)
    keep = k < n
    e_max = np.full(n, -np.inf)
    e_min = np.full(n, np.inf)
    np.maximum.at(e_max, k[keep], e[keep])
    np.minimum.at(e_min, k[keep], e[keep])
    return Envelope(t[0] + period_s * np.arange(1, n + 1), e_max, e_min, period_s)


def settled_since(env: Envelope, tol_pct_cr: float = 1.0) -> float | None:
    """Earliest window start t_s such that every windowed max from t_s to the end lies within
    +-tol_pct_cr % of CR of one value (max - min of them <= 2 tol); None for no windows.
    The last window alone always qualifies: judge the result by how long it is held."""
    if env.e_max.size == 0:
        return None
    hi = np.maximum.accumulate(env.e_max[::-1])[::-1]  # max of e_max[i:]
    lo = np.minimum.accumulate(env.e_max[::-1])[::-1]
    ok = (hi - lo) <= 2 * tol_pct_cr / 100 + 1e-12
    i = int(np.argmax(ok))  # ok is monotone (False..False True..True)
    return float(env.t[i] - env.period_s)


def envelope_change(coarse: Envelope, fine: Envelope) -> float:
    """Largest |e_max(fine) - e_max(coarse)| in % of CR over the windows both completed
    (windows must be the same length; the runs start at the same time)."""
    if not np.isclose(coarse.period_s, fine.period_s):
        raise ValueError("envelopes with different windows")
    n = min(coarse.e_max.size, fine.e_max.size)
    if n == 0:
        return float("nan")
    return 100 * float(np.max(np.abs(fine.e_max[:n] - coarse.e_max[:n])))


@dataclass
class LimitCycle:
    source: str
    speed_hz: float
    revs: int
    tol_pct_cr: float
    t_end_s: float
    settled_since_s: float | None
    held_s: float | None
    band: tuple[float, float] | None  # e_max range from settled_since to the end
    final_e_max: float | None
    drift_pct_cr: float | None  # least-squares trend of the windowed max over the held span, end minus start
    meta: dict | None = None
    # the whirl's size (windowed max - min eccentricity) over the last half of the run, and its
    # trend there relative to that size: a whirl dying away (or growing) slowly inside the
    # absolute band is no limit cycle
    amplitude: float | None = None
    amplitude_trend_pct: float | None = None
    rel_tol_pct: float = 10.0

    @property
    def holds(self) -> bool:
        """Settled, without a trend across the band (a slow monotone drift that merely has not
        left the band yet does not count), and the whirl's size steady relative to itself."""
        return (self.settled_since_s is not None and abs(self.drift_pct_cr) <= self.tol_pct_cr
                and (self.amplitude_trend_pct is None or abs(self.amplitude_trend_pct) <= self.rel_tol_pct))

    @property
    def kind(self) -> str:
        """'holds', 'dies out', 'grows' or 'not settled'."""
        if self.holds:
            return "holds"
        if self.amplitude_trend_pct is not None and abs(self.amplitude_trend_pct) > self.rel_tol_pct:
            return "dies out" if self.amplitude_trend_pct < 0 else "grows"
        return "not settled"

    def verdict(self) -> str:
        """One line: what the envelope does, with the numbers that say so."""
        if self.settled_since_s is None:
            return "verdict: no complete window (the run is shorter than one window)"
        size = (f"whirl size {self.amplitude:.4f} (max - min eccentricity per window), trend "
                f"{self.amplitude_trend_pct:+.1f} % of it over the last half" if self.amplitude is not None else "")
        band = (f"max eccentricity {self.band[0]:.4f}..{self.band[1]:.4f} from {self.settled_since_s:.2f} s "
                f"(held {self.held_s:.2f} s, trend {self.drift_pct_cr:+.2f} % CR)")
        head = {"holds": "the limit cycle holds", "dies out": "no limit cycle: the whirl dies out",
                "grows": "no limit cycle yet: the whirl grows",
                "not settled": f"not settled within +-{self.tol_pct_cr:g} % CR"}[self.kind]
        return f"verdict: {head}: {band}; {size}".rstrip("; ")


def limit_cycle(arrays: dict, speed_hz: float, *, revs: int = 2, tol_pct_cr: float = 1.0,
                source: str = "", meta: dict | None = None, rel_tol_pct: float = 10.0) -> tuple[LimitCycle, Envelope]:
    env = envelope(arrays, revs / speed_hz)
    ts = settled_since(env, tol_pct_cr)
    t_end = float(np.asarray(arrays["t"])[-1])
    band = drift = None
    if ts is not None:
        m = env.t - env.period_s >= ts - 1e-12
        band = (float(env.e_max[m].min()), float(env.e_max[m].max()))
        drift = 0.0
        if m.sum() > 1:
            slope = np.polyfit(env.t[m], env.e_max[m], 1)[0]
            drift = 100 * float(slope * (env.t[m][-1] - env.t[m][0]))
    amp = trend = None
    half = env.t >= env.t[0] + 0.5 * (env.t[-1] - env.t[0]) if env.t.size else np.zeros(0, bool)
    if half.sum() >= 2:
        a = env.e_max[half] - env.e_min[half]
        amp = float(a.mean())
        if amp > 0.0:
            slope = np.polyfit(env.t[half], a, 1)[0]
            trend = 100 * float(slope * (env.t[half][-1] - env.t[half][0])) / amp
    lc = LimitCycle(source, speed_hz, revs, tol_pct_cr, t_end, ts,
                    None if ts is None else float(env.t[-1] - ts), band,
                    float(env.e_max[-1]) if env.e_max.size else None, drift, meta, amp, trend, rel_tol_pct)
    return lc, env


def plot_envelopes(envs: dict, path, *, title: str = "", tol_band: tuple[float, float] | None = None) -> Path:
    """Windowed max (solid) and min (thin) eccentricity against time for labelled envelopes."""

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(9, 4))
    for label, env in envs.items():
        (line,) = ax.plot(env.t, env.e_max, lw=1.2, label=f"{label}: max per window")
        ax.plot(env.t, env.e_min, lw=0.6, color=line.get_color(), alpha=0.6)
    if tol_band is not None:
        ax.axhspan(*tol_band, color="grey", alpha=0.15, label="+-1 % CR band")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("bearing eccentricity ratio")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    if title:
        ax.set_title(title, fontsize=10)
    return save_figure(fig, path)



def _saved_run(path: Path) -> dict:
    """The arrays of a saved run (``rotor-host run``'s .npz), or ValueError naming the file and
    what it lacks."""
    from bearing_fmu.io.npz import read_npz

    arrays = read_npz(path, "a saved run (.npz of rotor-host run)")
    missing = [k for k in ("t", "eccentricity") if k not in arrays]
    if missing:
        raise ValueError(f"{path}: a saved run needs the arrays t and eccentricity; missing: {', '.join(missing)}")
    if len(arrays["t"]) < 2:
        raise ValueError(f"{path}: the saved run holds {len(arrays['t'])} time step(s); an envelope needs more")
    return arrays


def command(*, source, internal: str = "reynolds", dt: float | None = None, t_end: float | None = None, speed_hz:
            float | None = None, revs: int = 2, tol: float = 1.0, hold: float = 1.0, rel_tol: float = 10.0,
            out="out", quiet: bool = False) -> int:
    """``rotor-host limit-cycle``: run the scene ``source`` (called directly) or read a saved run's .npz
    (``speed_hz`` then), measure the eccentricity envelope and whether it holds; 0 when held."""
    src = Path(source)
    out = ensure_writable(out)
    from .computed_for import run_inputs, scene_line, wrapped

    stem = f"limitcycle_{src.stem}"
    meta = None
    if src.suffix == ".npz":
        if speed_hz is None:
            raise ValueError(f"--speed-hz: a .npz source ({src}) needs the shaft speed it was run at [Hz]")
        arrays, speed = _saved_run(src), speed_hz
        inputs = run_inputs(src)
    else:
        from ..scenes.run import run_scene
        from ..scenes.scene import load_scene

        scene = load_scene(src)
        kw = {"via": "direct"}
        if dt is not None:
            kw["dt_s"] = dt
        if t_end is not None:
            kw["t_end_s"] = t_end
        scene = scene.with_internal(internal, **kw)
        inputs = scene_line(scene)
        # the run is kept (<stem>_run.npz/.json, checkpoints while running): an interrupted or
        # failed run can be analysed later with `limit-cycle <stem>_run.npz --speed-hz ...`
        r = run_scene(scene, out, progress=not quiet, stem=f"{stem}_run")
        arrays, speed = r.arrays, scene.speed_hz
        meta = {k: r.meta[k] for k in ("status", "message", "dt_s", "steps", "newton_mean_evaluations_per_step",
                                       "step_cuts", "integration_time_s", "max_eccentricity", "crossed_clearance")}
    lc, env = limit_cycle(arrays, speed, revs=revs, tol_pct_cr=tol, source=str(src), meta=meta,
                          rel_tol_pct=rel_tol)
    step = max(1, int(round(0.25 / env.period_s))) if env.t.size else 1  # about every 0.25 s
    rows = "\n".join(f"| {t:.3f} | {a:.4f} | {b:.4f} |" for t, a, b in
                     zip(env.t[::step], env.e_max[::step], env.e_min[::step]))
    text = (f"# Limit cycle: {src.name}, {speed:g} Hz, windows of {revs} revolutions\n\n"
            + (f"Computed for: {inputs}\n\n" if inputs else "")
            + f"| window end [s] | max ecc. | min ecc. |\n|---|---|---|\n{rows}\n\n{lc.verdict()}\n")
    write_text(out / f"{stem}.md", text)
    write_json(out / f"{stem}.json",
               {**asdict(lc), "t": env.t.tolist(), "e_max": env.e_max.tolist(), "e_min": env.e_min.tolist()}, indent=1)
    if env.t.size:
        plot_envelopes({src.stem: env}, out / f"{stem}.png",
                       title=wrapped(lc.verdict(), 110) + (f"\n{wrapped(inputs, 110)}" if inputs else ""))
    print(text)
    held = lc.holds and lc.held_s >= hold
    if lc.holds and not held:
        print(f"(held {lc.held_s:.2f} s < --hold {hold:g} s: not counted as held; exit status 1)")
    return 0 if held else 1


__all__ = ["Envelope", "envelope", "settled_since", "envelope_change", "LimitCycle", "limit_cycle",
           "plot_envelopes", "command"]

