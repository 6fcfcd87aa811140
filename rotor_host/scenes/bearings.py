"""A scene's bearings: FMU instances through fmpy (the scene's FMU, or one built and cached for it,
Python or native) or the scene's internal in-process, with the feed lines placed at the scene's
speed and the warnings of in-process internals counted per run."""

from __future__ import annotations

import hashlib
import math
import warnings
from pathlib import Path

import numpy as np

from bearing_fmu.internals import registry
from bearing_fmu.internals.registry import Context
from bearing_fmu.io.cache import cache_dir, source_digest

from ..model.rotor import Rotor
from .sanity import check_native_bores
from .scene import Scene, SceneError, required_file, scene_files
from .thermal import thermal_internal


class InternalWarnings:
    """The warnings of a run's in-process internals (a surrogate leaving its fitted domain, once
    per excursion): the first is shown, the rest counted; the run's json has the count and the
    first (``internal_warnings``), so a long run does not bury its output in repeats."""

    def __init__(self):
        self.count, self.first = 0, None

    def __call__(self, message: str) -> None:
        self.count += 1
        if self.count == 1:
            self.first = message
            warnings.warn(f"{message} [further warnings of this run are counted in its json]", stacklevel=3)

    def report(self) -> dict:
        return {"count": self.count, "first": self.first}


def _context(scene: Scene, load, warn=None) -> Context:
    """What a bearing's internal may take from the run: its static load, the speed, a warning sink."""
    return Context(load=(float(load[0]), float(load[1])), omega=scene.omega, warn=warn)


def fmu_parameters(scene: Scene, params, load, thermal=None) -> dict:
    """FMU parameters of one bearing: the bearing (its bore and oil too), the internal and all its
    options (the static load and speed filled in where the internal takes them; files by their
    name in the FMU's resources); with ``thermal`` (the bearing's ``ThermalState``) the thermal
    model on and the inputs of Initialization Mode at its static equilibrium, where T_eff starts
    quasi-static. A native FMU takes the options it keeps (``native_parameters``: the linear
    model's coefficients are made here, per bearing)."""
    if scene.fmu_kind == "native":
        from bearing_fmu.fmu.native import native_parameters

        try:
            out = native_parameters(scene.internal, params, scene.internal_options(), _context(scene, load),
                                    where=f"{scene.source}: fmu_kind = 'native'")
        except ValueError as exc:
            raise SceneError(str(exc)) from None
        if thermal is not None:  # its oil law is the bearing's (compiled in), its Real parameters set here
            from bearing_fmu.fmu.native.portgen import OIL_REALS
            from bearing_fmu.fmu.ports import port_defaults

            oil = port_defaults(params)
            out.update({n: oil[n] for n in OIL_REALS if n in oil}, thermal=True, T_supply=thermal.T_supply_K,
                       y=thermal.y_m, z=thermal.z_m, omega=scene.omega)
        return out
    spec = registry.get(scene.internal)
    opts = spec.check_options(scene.internal_options(), str(scene.source), context=_context(scene, load))
    for o in spec.all_options():
        if o.file and opts[o.name]:
            opts[o.name] = Path(opts[o.name]).name
    from bearing_fmu.fmu.ports import port_defaults

    out = {"D": params.D, "L": params.L, "CR": params.CR, "mu": params.mu, "internal": spec.name, **opts,
           **port_defaults(params, pads=True)}
    if thermal is not None:
        out.update(thermal=True, T_supply=thermal.T_supply_K, y=thermal.y_m, z=thermal.z_m, omega=scene.omega)
    return out


def _direct_internal(scene: Scene, params, load, warn=None):
    """The scene's internal for one bearing, imported only when used."""
    return registry.create(scene.internal, params, scene.internal_options(), _context(scene, load, warn),
                           where=str(scene.source))


def linearisable(scene: Scene, rotor: Rotor, loads, bearings):
    """The internals in-process whose Lund coefficients stand for the bearings: the run's own
    (via = direct), the Python FMU's internal (its kernels already loaded in this process); None
    for a native FMU (no compiled Python to load for a check) or a foreign one."""
    if scene.via == "direct":
        return bearings.internals
    if scene.fmu is not None or scene.fmu_kind == "native":
        return None
    return [_direct_internal(scene, p, w, lambda *_: None) for p, w in zip(rotor.bearings, loads)]


def scene_fmu(scene: Scene, work_dir: Path | None, bearing=None) -> Path:
    """The bearing FMU for the scene: its ``fmu`` key, or one built into work_dir (None: the
    user's FMU cache, ``bearing_fmu.io.cache``, shared by every command and output folder) with
    the files of the scene's internal bundled (e.g. the surrogate of a Taylor scene), under a name
    that hashes what determines it, so a build is made once. A native FMU is built for ``bearing``
    (the rotor's first; the host sets each bearing's D, L, CR, mu)."""
    if scene.fmu is not None:
        if not scene.fmu.is_file():
            raise SceneError(f"{scene.source}: fmu = {scene.fmu}: file not found")
        return scene.fmu
    work_dir = Path(work_dir) if work_dir is not None else cache_dir()
    if scene.fmu_kind == "native":
        return _native_fmu(scene, work_dir, bearing)
    from bearing_fmu.fmu.build import build_fmu, package_name

    work_dir.mkdir(parents=True, exist_ok=True)
    files = scene_files(scene)
    # content-addressed: the code package (its name hashes every bundled source) and the
    # bundled files' bytes. Runs of the same scene reuse one build, parallel runs never write
    # into an FMU another run is reading (and build_fmu writes under a temporary name).
    h = hashlib.sha256(package_name().encode())
    for f in files:
        h.update(f.name.encode() + b"\0" + f.read_bytes())
    tag = "".join(f"_{f.stem}" for f in files)
    path = work_dir / f"bearing{tag}_{h.hexdigest()[:12]}.fmu"
    if path.is_file():
        return path
    return Path(build_fmu(path, surrogate=files or None))


def _native_fmu(scene: Scene, work_dir: Path, bearing=None) -> Path:
    """The scene's native FMU for ``bearing`` (a map serves its own L/D: the scene's bearing, not
    the paper's), its omega starting at the scene's speed, built into work_dir under a name that
    hashes bearing_fmu's sources (the C model, its generators and what they import), the
    internal's data file, the bearing and the speed, so runs of the same scene share one build. The linear FMU holds no data: the host sets each
    bearing's coefficients."""
    from bearing_fmu.fmu.native.host import fmu_internals, host_build_options
    from bearing_fmu.fmu.native.build import build_native_fmu
    from bearing_fmu.fmu.native.compile import host_platform

    spec = registry.get(scene.internal)
    if not spec.can.native:
        native = registry.having(native=True)
        raise SceneError(f"{scene.source}: fmu_kind = 'native' computes one of {', '.join(native)}, not internal = "
                         f"{scene.internal!r} (registered from outside the package): use fmu_kind = 'python'")
    work_dir.mkdir(parents=True, exist_ok=True)
    given = scene.internal_options()
    files = {o.name: required_file(scene, spec.name, o.name) for o in spec.file_options()
             if o.required or given.get(o.name)}  # an optional file (the pads' map) only when the scene names it
    path = next(iter(files.values()), None)  # a native FMU compiles at most one data file in
    options = host_build_options(scene.internal)
    if "pad_map" in files:  # the native pads' generator reads its map from the options
        options = {**(options or {}), "pad_map": str(files.pop("pad_map"))}
    taylor = spec.name == "taylor"  # its bearing and speed are the surrogate's
    speed_hz = None if taylor or not scene.omega else scene.omega / (2.0 * math.pi)
    # taylor: the surrogate's bearing, with the bearing file's oil law when it has one (its thermal model's)
    bearing = None if taylor and (bearing is None or bearing.oil is None) else bearing
    internals = fmu_internals(scene.internal, scene.internal_options())  # taylor's fallback: with reynolds
    h = hashlib.sha256(f"{internals} {bearing!r} {speed_hz!r} {source_digest()}".encode())
    if path:
        h.update(path.name.encode() + b"\0" + path.read_bytes())
    out = work_dir / f"bearing_native_{scene.internal}{'_' + path.stem if path else ''}_{h.hexdigest()[:12]}.fmu"
    if out.is_file():
        return out
    # this machine's binary only: the run loads it here (bearing-fmu build --native makes every platform's)
    return Path(build_native_fmu(out, internals, options=options, platforms=[host_platform()], bearing=bearing,
                                 speed_hz=speed_hz, **files))


def place_feeds_at_speed(scene: Scene, rotor: Rotor, loads) -> None:
    """Feed lines at the thickest film placed at the scene's speed, where they stay for the run."""
    if not any(p.geometry.feed_unplaced for p in rotor.bearings):
        return  # (its module loads the Reynolds solver: a Taylor scene never does)
    from bearing_fmu.physics.bore.feed import place_feeds

    rotor.bearings = place_feeds(rotor.bearings, loads, scene.omega, f"{scene.source}: ")


def build_bearings(scene: Scene, rotor: Rotor, loads: np.ndarray, work_dir: Path, warn=None, thermal=None):
    """The BearingSet of the scene: FMU instances (via = fmu) or internals in-process (their
    warnings to ``warn``, default: warnings.warn); ``thermal`` (``scene_thermal``): each internal
    at its bearing's mu_eff (its force scaled by mu_eff / mu: exact, F ~ mu)."""
    pairs = [(rotor.dof(n, "y"), rotor.dof(n, "z")) for n in rotor.bearing_nodes]
    names = [f"bearing {k + 1} (node {n + 1})" for k, n in enumerate(rotor.bearing_nodes)]
    scene_files(scene)  # a missing file is named before anything is built
    place_feeds_at_speed(scene, rotor, loads)
    if scene.via == "direct":
        from ..coupling.bearings import DirectBearings

        internals = [_direct_internal(scene, p, w, warn) for p, w in zip(rotor.bearings, loads)]
        if thermal is not None:
            internals = [thermal_internal(scene, i, p, st) for i, p, st in zip(internals, rotor.bearings, thermal)]
        return DirectBearings(internals, pairs, scene.omega, names, tangent=scene.newton_tangent)
    from ..coupling.cosim import FMUBearings

    check_native_bores(scene, rotor, names)  # before any build
    fmu = scene_fmu(scene, work_dir, rotor.bearings[0])
    params = [fmu_parameters(scene, p, w, st) for p, w, st in zip(rotor.bearings, loads, thermal or [None] * len(loads))]
    return FMUBearings(fmu, pairs, scene.omega, params, names, tangent=scene.newton_tangent)
