"""The critical speeds a run-up or coast-down crosses: the rotor's damped natural frequencies on
its bearings linearised at the static equilibrium, over the run's speed range, by the stability
analysis (``stability.Stability``: the same equilibria, Lund coefficients and damped modes as
``rotor-host stability``), and their 1x crossings that can ring (``modal.critical_speeds``, AF >=
2.5). ``waterfall.summary`` then calls a 1x peak a critical speed only where one of them lies
near it (``modal.critical_near``); elsewhere it is a "1x peak" (docs/runup.md).

The bearings are the scene's internal when it is valid at every speed and load (the Reynolds
solver, a force map); a Taylor surrogate or a linear bearing answers only near its own point,
so for those the Reynolds solver (default grid) stands in, and the result says so.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

MAX_SPEEDS = 81  # speeds of the sweep over the run's range (0.5 Hz apart or closer, at least 11)


@dataclass
class RunCriticals:
    """The critical speeds [{speed_hz, log_dec, whirl, ...}] in ``lo_hz``-``hi_hz`` (None: not
    computed, ``note`` says why), the 1x crossings of heavily damped modes, the internal used."""

    lo_hz: float
    hi_hz: float
    criticals: list[dict] | None
    damped: list[dict] = field(default_factory=list)
    internal: str = ""
    note: str = ""

    @property
    def speeds_hz(self) -> list[float]:
        return [c["speed_hz"] for c in self.criticals or []]


def sweep_speeds(lo_hz: float, hi_hz: float) -> list[float]:
    """The speeds at which the modes are computed: lo-hi, at most 0.5 Hz apart (11 to 81 of
    them); a range from standstill starts at 1 % of the top speed (at 0 Hz a plain bearing
    carries nothing)."""
    lo = max(float(lo_hz), 0.01 * float(hi_hz))
    n = int(min(MAX_SPEEDS, max(11, math.ceil((hi_hz - lo) / 0.5) + 1)))
    return [float(s) for s in np.linspace(lo, hi_hz, n)]


def scene_criticals(scene, lo_hz: float, hi_hz: float) -> RunCriticals:
    """The critical speeds of the scene's rotor on its bearings in ``lo_hz``-``hi_hz``."""
    from bearing_fmu.internals import registry

    from ...model.rotor import Rotor
    from .stability import Stability

    internal, options, note = scene.internal, scene.internal_options(), ""
    if not registry.get(internal).can.any_state:
        internal, options = "reynolds", {}
        note = (f"natural frequencies from the Reynolds solver: the run's {scene.internal} answers only near its own "
                "point")
    try:
        analysis = Stability(Rotor.from_toml(scene.rotor_path), internal, options, scene.static_loads,
                             where=str(scene.source))
        res = analysis.sweep(sweep_speeds(lo_hz, hi_hz), n_modes=0)
    except (ValueError, RuntimeError) as exc:  # a map of another L/D, a non-finite coefficient: say so
        return RunCriticals(lo_hz, hi_hz, None, internal=internal, note=f"critical speeds not computed: {exc}")
    if not res.ok_points:
        return RunCriticals(lo_hz, hi_hz, None, internal=internal,
                            note="critical speeds not computed: no static equilibrium at any speed of the run")
    return RunCriticals(lo_hz, hi_hz, res.criticals, res.damped_crossings, internal, note)


def run_criticals(npz_path, arrays: dict) -> RunCriticals:
    """The critical speeds crossed by the saved run ``npz_path`` (its arrays ``arrays``): its scene
    from the json beside it (``source``), its speed range from ``speed_hz``. A scene that cannot be
    read any more gives criticals None and the reason."""
    from ...scenes.scene import load_scene

    speed = np.asarray(arrays["speed_hz"], float)
    lo, hi = float(np.min(speed)), float(np.max(speed))
    meta_path = Path(npz_path).with_suffix(".json")
    try:
        source = json.loads(meta_path.read_text()).get("source")
        scene = load_scene(source)
    except (OSError, ValueError, TypeError) as exc:  # a SceneError is a ValueError
        return RunCriticals(lo, hi, None, note=f"critical speeds not computed: the run's scene could not be read "
                                               f"({meta_path.name}: {exc})")
    return scene_criticals(scene, lo, hi)


__all__ = ["RunCriticals", "sweep_speeds", "scene_criticals", "run_criticals"]
