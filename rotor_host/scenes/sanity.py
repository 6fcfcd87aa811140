"""Physical sanity of a scene, checked before anything is solved: a value no rotor can have is
refused by its key (``SceneError``, exit code 2) instead of being found out by its consequence
(a journal at eccentricity 1e291, a line search that fails at its first step).

* the time step against the shaft period (and, once the static equilibrium is known, against
  the period of the highest mode of interest: ``check_step_against_modes``): above a tenth of a revolution per step a warning (the
  orbit is coarsely drawn and the step's accuracy goes with (Omega dt)^2), above half a
  revolution a refusal (``MAX_REV_PER_STEP``: fewer than two steps per revolution cannot
  resolve a synchronous orbit, the sampling theorem's limit);
* the speed against the material: a surface speed of the rotor (shaft or disk rim) above the
  speed of sound in its material, sqrt(E / rho), would stress it by rho v^2 > E, beyond any
  material (steel bursts near a tenth of that);
* an unbalance mass above the rotor's own mass (an unbalance is a small eccentric mass on it);
* a native bearing FMU for a bore it does not model (``check_native_bores``, before any build).
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from .scene import SceneError

WARN_REV_PER_STEP = 0.1  # revolutions per time step above which a run warns
MAX_REV_PER_STEP = 0.5  # ... and above which it is refused (fewer than two steps per revolution)

__all__ = ["WARN_REV_PER_STEP", "MAX_REV_PER_STEP", "CoarseStepWarning", "check_scene_physics",
           "surface_speed_refusal", "check_native_bores", "check_step_against_modes"]


class CoarseStepWarning(UserWarning):
    """The time step is more than a tenth of a shaft revolution."""


def _max_speed(scene) -> tuple[float, str]:
    """The scene's highest shaft speed [Hz] and the key that sets it."""
    if scene.speed_profile is not None:
        return max(scene.speed_profile.speeds_hz), "[speed_profile] speeds_hz"
    return scene.speed_hz, "speed_hz"


def surface_speed_refusal(rotor, f_hz: float) -> str | None:
    """Why no rotor turns at ``f_hz`` [Hz]: its surface (the largest radius of the shaft and its
    disks) would move faster than the speed of sound in its material; None when it can. The text
    starts after the key, e.g. ``speed_hz = 1e+12: ...``."""
    radii = [e.od / 2 for e in rotor.elements] + [d.od / 2 for d in rotor.disks]
    r = max(radii)
    v = 2.0 * math.pi * f_hz * r
    c = math.sqrt(rotor.material.E / rotor.material.density)
    if v <= c:
        return None
    f_max = c / (2.0 * math.pi * r)
    return (f"{f_hz:g}: the rotor's surface at radius {r * 1e3:g} mm would move at {v:.3g} m/s, beyond the speed of "
            f"sound in its material (sqrt(E / density) = {c:.4g} m/s, where the centrifugal stress density v^2 "
            f"reaches E); no rotor turns so fast: the speed must be below {f_max:.4g} Hz (in Hz, not rpm or rad/s?)")


def check_scene_physics(scene, rotor) -> None:
    """Refuse (SceneError naming the key, the value and the allowed range) or warn
    (``CoarseStepWarning``) as the module says; ``rotor`` is the scene's ``Rotor``."""
    where = str(scene.source or scene.name)
    f_hz, speed_key = _max_speed(scene)
    why = surface_speed_refusal(rotor, f_hz)
    if why is not None:
        raise SceneError(f"{where}: {speed_key} = {why}")
    mass = rotor.mass
    for i, u in enumerate(scene.unbalances):
        if u.mass_kg > mass:
            raise SceneError(f"{where}: [[unbalance]] {i + 1} mass_kg = {u.mass_kg:g}: more than the whole rotor's "
                             f"mass ({mass:.4g} kg); an unbalance is a small mass on it (at most {mass:.4g} kg; in kg, "
                             "not g?)")
    rev = scene.dt_s * f_hz  # revolutions per step at the highest speed
    per_rev = 1.0 / f_hz
    if rev > MAX_REV_PER_STEP:
        raise SceneError(f"{where}: [time] dt_s = {scene.dt_s:g}: {rev:.3g} shaft revolutions per step at "
                         f"{f_hz:g} Hz ({speed_key}); the orbit cannot be resolved with fewer than two steps per "
                         f"revolution: dt_s must be at most {MAX_REV_PER_STEP * per_rev:.3g} s (half a revolution), "
                         f"and {WARN_REV_PER_STEP * per_rev:.3g} s (a tenth) or less to draw it")
    if rev > WARN_REV_PER_STEP:
        warnings.warn(f"{where}: [time] dt_s = {scene.dt_s:g} is {rev:.3g} of a shaft revolution at {f_hz:g} Hz "
                      f"({speed_key}): the orbit is coarsely resolved; {WARN_REV_PER_STEP * per_rev:.3g} s (a tenth "
                      "of a revolution) or less draws it", CoarseStepWarning, stacklevel=3)


def check_native_bores(scene, rotor, names) -> None:
    """SceneError unless the scene's native bearing FMU (``fmu_kind = "native"``) takes the bore
    of every bearing (``names`` theirs), before anything is built; nothing to check otherwise."""
    if scene.fmu_kind != "native":
        return
    from bearing_fmu.fmu.native.catalogue import NATIVE

    # the Python FMU takes any bore as parameters; a native FMU has one, the first bearing's, for
    # every bearing of that bore: compiled in, or its data file's (its catalogue entry's bore; the
    # build checks the file's bore against the bearing's)
    compiled = scene.fmu is None and scene.internal in NATIVE and NATIVE[scene.internal].bore != "full"
    for name, p in zip(names, rotor.bearings):
        if compiled and p.geometry != rotor.bearings[0].geometry:
            raise SceneError(f"{scene.source}: fmu_kind = 'native': the native FMU has the bore of {names[0]} "
                             f"compiled in ({rotor.bearings[0].geometry.describe()}), {name} has another "
                             f"({p.geometry.describe()}): give the bearings one bore, or use via = 'direct'")
        if compiled or p.geometry.is_full_bore:
            continue
        # this internal's native FMU has the full bore only; the native Reynolds FMU (its bore
        # compiled in) and the Python FMU take any bore
        from bearing_fmu.internals import registry

        # of those, the ones that take this kind of bore (tilting pads: the pads' internal alone)
        takes = {k for k in NATIVE if registry.get(k).can.pads == (p.geometry.pads is not None)}
        compiled_in = " or ".join(repr(k) for k, spec in NATIVE.items() if spec.bore == "compiled" and k in takes)
        from_data = " or ".join(repr(k) for k, spec in NATIVE.items() if spec.bore == "data" and k in takes)
        what = f"the native {scene.internal} FMU" if scene.fmu is None else f"the native FMU {scene.fmu}"
        raise SceneError(f"{scene.source}: fmu_kind = 'native': {what} models only the full 360 deg circular bore "
                         f"(its parameters are D, L, CR and mu), not {name}'s {p.geometry.describe()}: with --native "
                         f"use internal = {compiled_in} (the bore compiled in) or {from_data} (a map of this bore), "
                         "or leave --native out (the Python FMU takes any bore), or via = 'direct'")


def check_step_against_modes(scene, rotor, internals, q0) -> None:
    """The time step against the highest mode of interest, as against the shaft period: the
    rotor linearised at its static equilibrium ``q0`` (each bearing's Lund K, C from its
    ``internals``, at the scene's start speed), its modes that ring (log decrement below
    ``modal.LOG_DEC_HEAVY``, amplification factor >= 2.5) up to ``modal.RANK_UP_TO`` x the top
    speed (every whirl and every mode a 1x or 2x force drives, the band a stability analysis
    ranks in): above a tenth of that mode's period per step a ``CoarseStepWarning``, above half
    (fewer than two steps per period: its oscillation cannot be resolved) a SceneError naming
    [time] dt_s, the mode and both limits. ``internals`` None (a native or foreign FMU): not
    checked, the shaft period only."""
    if internals is None or q0 is None or not rotor.bearing_nodes:
        return
    from bearing_fmu.physics.statics import linearize

    from ..analyses.linear.modal import LOG_DEC_HEAVY, RANK_UP_TO, band_hz
    from ..model.band_modes import band_modes

    f_top, speed_key = _max_speed(scene)
    band = band_hz(f_top, RANK_UP_TO)
    K, C = [], []
    for internal, node in zip(internals, rotor.bearing_nodes):
        k, c = linearize(internal, float(q0[rotor.dof(node, "y")]), float(q0[rotor.dof(node, "z")]), scene.omega)
        K.append(k)
        C.append(c)
    freq, log_dec, _ = band_modes(rotor, scene.omega, np.array(K), np.array(C), band)
    ringing = freq[(freq <= band) & (log_dec < LOG_DEC_HEAVY) & np.isfinite(freq)]
    if ringing.size == 0:
        return
    f_m = float(np.max(ringing))
    per = scene.dt_s * f_m  # periods of that mode per step
    where = str(scene.source or scene.name)
    mode = (f"the highest mode of interest, {f_m:.4g} Hz (of the rotor on its bearings at the static equilibrium, "
            f"lightly damped, up to {RANK_UP_TO:g} x the top speed {f_top:g} Hz, {speed_key})")
    if per > MAX_REV_PER_STEP:
        raise SceneError(f"{where}: [time] dt_s = {scene.dt_s:g}: {per:.3g} periods per step of {mode}; its "
                         f"oscillation cannot be resolved with fewer than two steps per period: dt_s must be at most "
                         f"{MAX_REV_PER_STEP / f_m:.3g} s, and {WARN_REV_PER_STEP / f_m:.3g} s (a tenth) or less to "
                         "draw it")
    if per > WARN_REV_PER_STEP:
        warnings.warn(f"{where}: [time] dt_s = {scene.dt_s:g} is {per:.3g} of a period of {mode}: it is coarsely "
                      f"resolved; {WARN_REV_PER_STEP / f_m:.3g} s (a tenth of its period) or less draws it",
                      CoarseStepWarning, stacklevel=3)
