"""What a sweep runs: the values swept (speeds or unbalance masses), one ``Point`` per run with
the stem of its files, the scene of each run, and the checks made before any run (a fixed-speed
internal, a run-up scene, the settled part of each run)."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path

MAX_RUNS = 1000  # a range that expands to more is a typo (a step in the wrong unit)


# ------------------------------------------------------------------ the values swept

def swept_values(groups, option: str) -> list[float]:
    """The values of several command-line items (each a list: ``cliargs.float_range``), sorted,
    each once, at most MAX_RUNS of them."""
    values = sorted({v for g in groups for v in g})
    if len(values) > MAX_RUNS:
        raise ValueError(f"{option}: {len(values)} runs; a sweep takes at most {MAX_RUNS} (a step in the wrong unit?)")
    return values


@dataclass(frozen=True)
class Point:
    """One run of a sweep: the shaft speed [Hz], the first unbalance's mass [g] (None: the
    scene's own) and the stem of its result files."""

    speed_hz: float
    unbalance_g: float | None
    stem: str

    @property
    def label(self) -> str:
        return f"{self.speed_hz:g} Hz" if self.unbalance_g is None else f"{self.unbalance_g:g} g"


def run_base(scene) -> str:
    """``<scene file stem>_<internal>``: the start of every file name of a sweep of ``scene``."""
    return f"{Path(scene.source).stem if scene.source else scene.name}_{scene.internal}"


def points(scene, speeds_hz=None, unbalance_g=None) -> list[Point]:
    """The runs of a speed sweep (``speeds_hz``) or an unbalance sweep (``unbalance_g``: masses
    [g] on the scene's first [[unbalance]], at the scene's speed). Each run is at one constant
    speed: a scene with a [speed_profile] (a run-up) is refused."""
    base = run_base(scene)
    if getattr(scene, "speed_profile", None) is not None:
        option = "--unbalance-g" if unbalance_g is not None else "--speeds-hz"
        raise ValueError(f"{option}: the scene {scene.source} has a [speed_profile] (a run-up or coast-down); a sweep "
                         "runs each speed constant, from the static equilibrium: use a scene with speed_hz alone")
    if unbalance_g is not None:
        if not scene.unbalances:
            raise ValueError(f"--unbalance-g: the scene {scene.source} has no [[unbalance]] entry to vary; "
                             "add one (node, mass_kg, radius_mm) or sweep --speeds-hz")
        return [Point(scene.speed_hz, m, f"{base}_{m:.12g}g") for m in unbalance_g]
    return [Point(f, None, f"{base}_{f:.12g}hz") for f in speeds_hz]  # distinct: float_range rounds to 12 digits


def point_scene(scene, point: Point, disk_nodes: list[int]):
    """The scene of one run: its speed or first unbalance mass, and the disks recorded."""
    unb = list(scene.unbalances)
    if point.unbalance_g is not None:
        unb[0] = replace(unb[0], mass_kg=point.unbalance_g / 1e3)
    nodes = sorted(set(scene.record_nodes) | {n - 1 for n in disk_nodes})
    return replace(scene, speed_hz=point.speed_hz, unbalances=unb, record_nodes=nodes)


FIXED_SPEED_RTOL = 1e-9  # what the fixed-speed internals take as their speed (Taylor: OMEGA_RTOL)


def check_fixed_speed(scene, speeds_hz) -> None:
    """An internal that answers only at the speed its data was made for (capability
    ``fixed_speed``: a fitted surrogate) refuses any other: refuse a speed sweep with it before
    any run, naming what does sweep speeds."""
    from bearing_fmu.internals import registry
    from bearing_fmu.internals.registry import Context

    from ...model.rotor import Rotor

    spec = registry.get(scene.internal)
    if not spec.can.fixed_speed:
        return
    params = Rotor.from_toml(scene.rotor_path).bearings[0]
    f0 = registry.create(spec.name, params, scene.internal_options(), Context(omega=scene.omega),
                         where=str(scene.source)).omega / (2 * math.pi)
    other = [f for f in speeds_hz if abs(f - f0) > FIXED_SPEED_RTOL * f0]
    if other:
        sweepers = ", ".join(n for n in registry.having(any_state=True))
        raise ValueError(f"--speeds-hz: the {spec.name} internal answers only at the speed its data was made for "
                         f"({f0:g} Hz), not at {', '.join(f'{f:g}' for f in other[:4])}"
                         f"{' ...' if len(other) > 4 else ''} Hz; sweep speeds with an internal valid at any speed "
                         f"({sweepers}), or sweep --unbalance-g at {f0:g} Hz")


def settle_time(settle_s: float | None, scene) -> float:
    """The start of each run's settled part [s]: ``settle_s``, by default half the run."""
    settle = scene.t_end_s / 2 if settle_s is None else settle_s
    if settle >= scene.t_end_s:
        raise ValueError(f"--settle-s {settle:g}: must be less than the run's end time t_end = {scene.t_end_s:g} s "
                         "(the summary needs a settled part to measure)")
    return settle


__all__ = ["MAX_RUNS", "FIXED_SPEED_RTOL", "Point", "swept_values", "run_base", "points", "point_scene",
           "check_fixed_speed", "settle_time"]
