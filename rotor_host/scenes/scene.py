"""Scenes: one simulation case read from TOML and checked (running it: ``rotor_host.scenes.run``).

A scene names a rotor file, the internal (a name of ``bearing_fmu.internals.REGISTRY``), how
the bearings are reached (through the FMU, ``via = "fmu"``, or called in-process,
``via = "direct"``), the speed, unbalances, static loads, time span and step, and what to
record. Each internal's options sit in a sub-table named after it (``[reynolds] n_theta``,
``[taylor] surrogate``), checked against the registry; a scene may hold several, so the same
scene runs with another internal (``rotor-host compare``, ``--internal``).
``rotor_host.scenes.run.run_scene`` runs it.

Keys carry their units (``speed_hz``, ``radius_mm``, ``dt_s``); nodes are 1-based as in the
rotor file.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from pathlib import Path

from bearing_fmu.internals import registry
from bearing_fmu.io.schema import (Choice, FileName, Invalid, Key, List, Number, Table, Tables, Text,
                                   check_table, read_toml)

from ..integrate.forces import NEWTON_TANGENTS
from ..model.parts import NODE
from ..model.rotor import Rotor
from ..model.speed import SpeedProfile

VIA = ("fmu", "direct")
FMU_KINDS = ("python", "native")  # the pythonfmu FMU (any internal), or the compiled one (linear, map, taylor)
INITIAL_STATES = ("static_equilibrium", "centred")
DEFAULT_CHECKPOINT_S = 60.0  # [record] checkpoint_s: wall time between partial results [s]
G = 9.81


class SceneError(ValueError):
    """A scene file that cannot be used; the message names the file and key."""


# the keys of a scene file, per table, with the kind of value each takes (docs/file-formats.md
# shows these lists; load_scene checks a file against them once); besides them, one sub-table
# per registered internal holds its options ([reynolds], [taylor], ...)
TIME_KEYS = (
    Key("t_end_s", "simulated time [s]", allowed="> 0, a whole number of steps, at most 1e8 of them",
        kind=Number(0.0, exclusive_minimum=True)),
    Key("dt_s", "time step [s]", allowed="a finite number > 0, at most half a shaft revolution and half a period of "
        "the highest mode of interest (a warning above a tenth: rotor_host.scenes.sanity)",
        kind=Number(0.0, exclusive_minimum=True)),
    Key("hht_alpha", "HHT-alpha numerical damping (0: trapezoidal Newmark)", 0.0, "-1/3 .. 0",
        kind=Number(-1 / 3, 0.0, words="a finite number in [-1/3, 0]")),
    Key("newton_tangent", "Newton tangent of the bearing forces: the bearings' own K, C (bearing), those at the "
        "static equilibrium (frozen), finite differences (fd), or the rotor's alone (linear)", "bearing",
        ", ".join(NEWTON_TANGENTS), kind=Choice(NEWTON_TANGENTS)),
)
UNBALANCE_KEYS = (
    Key("node", "node, 1-based", allowed="1..number of nodes", kind=NODE),
    Key("mass_kg", "unbalance mass [kg]", kind=Number(0.0)),
    Key("radius_mm", "its radius [mm]", kind=Number(0.0)),
    Key("phase_deg", "angle at t = 0 from +y toward +z [deg]", 0.0, kind=Number()),
    Key("t_on_s", "acts from this time on [s] (a sudden unbalance)", 0.0, kind=Number(0.0)),
)
STATIC_LOAD_KEYS = (
    Key("node", "node, 1-based", allowed="1..number of nodes", kind=NODE),
    Key("Fy_N", "horizontal force [N]", 0.0, kind=Number()),
    Key("Fz_N", "vertical force [N] (up; the weight is added anyway)", 0.0, kind=Number()),
)
INITIAL_KEYS = (
    Key("state", "the rotor at its static equilibrium with the nonlinear bearing forces, or undeformed and "
        "centred", "static_equilibrium", ", ".join(INITIAL_STATES), kind=Choice(INITIAL_STATES)),
)
RECORD_KEYS = (
    Key("nodes", "nodes to record besides the bearing nodes, 1-based", [], "node numbers",
        kind=List(NODE)),
    Key("every", "record every n-th step", 1, kind=Number(1, integer=True)),
    Key("checkpoint_s", "write the partial result every this many seconds of wall time while running "
        "(a kill -9 keeps results up to the last one)", DEFAULT_CHECKPOINT_S, "> 0 s",
        kind=Number(0.0, exclusive_minimum=True)),
)
SPEED_PROFILE_KEYS = (
    Key("times_s", "times of the profile's points [s], increasing", kind=List(Number(0.0))),
    Key("speeds_hz", "shaft speed at those times [Hz]; linear in between, constant before the first and after "
        "the last (two points: a linear ramp)", kind=List(Number(0.0, exclusive_minimum=True))),
)

SCENE_KEYS = (
    Key("rotor", "rotor file, relative to the scene file", kind=FileName()),
    Key("internal", "which internal computes the bearing forces", allowed="a registered internal", kind=Text()),
    Key("speed_hz", "shaft speed [Hz] (with [speed_profile]: its speed at t = 0, which may be left out)", None,
        "a finite number > 0; required without [speed_profile]", kind=Number(0.0, exclusive_minimum=True)),
    Key("speed_profile", "run-up or coast-down: the speed over time ([speed_profile])", None,
        kind=Table(SPEED_PROFILE_KEYS)),
    Key("time", "time span and step ([time])", kind=Table(TIME_KEYS)),
    Key("name", "the scene's name in results and file names", None, "text (default: the file name)", kind=Text()),
    Key("description", "title of plots and tables", None, kind=Text()),
    Key("via", "bearings as FMUs through fmpy, or internals called in-process", "fmu", ", ".join(VIA),
        kind=Choice(VIA)),
    Key("fmu_kind", "via = fmu: the Python FMU (any internal) or the native one (the internal compiled to C, no "
        "Python at run time: reynolds, map, taylor, linear; built with zig from PyPI)", "python",
        ", ".join(FMU_KINDS), kind=Choice(FMU_KINDS)),
    Key("fmu", "a bearing FMU to use instead of building one, relative to the scene file", None,
        "file name of an .fmu", kind=FileName()),
    Key("initial", "initial state ([initial])", None, kind=Table(INITIAL_KEYS)),
    Key("unbalance", "unbalances ([[unbalance]])", None, kind=Tables(UNBALANCE_KEYS)),
    Key("static_loads", "static point loads ([[static_loads]]), e.g. to load the bearings", None,
        kind=Tables(STATIC_LOAD_KEYS)),
    Key("record", "what to record besides the bearing nodes ([record])", None, kind=Table(RECORD_KEYS)),
    Key("supply_temperature_C", "oil supply temperature [C]: every bearing (each needs an [oil] table) at the "
        "viscosity of its film's effective temperature, from the static equilibrium at the start, lagging the "
        "heat balance by the film's residence time with an internal that has the film's flows (reynolds, a map "
        "with flow tables, a Taylor surrogate with its film fit; docs/thermal.md); absent: the bearings' own "
        "viscosity", None, "inside every oil's range_C; via = 'fmu' (python or native) and a [speed_profile] need "
        "an internal with the film's flows (a map file with flow tables, version 3, or 4 for a grooved bore; a "
        "surrogate file with its film fit, version 2)", kind=Number()),
    Key("surrogate", "older form of [taylor] surrogate", None, kind=FileName()),
)


@dataclass
class Unbalance:
    node: int  # 0-based
    mass_kg: float
    radius_m: float
    phase_rad: float = 0.0
    t_on_s: float = 0.0  # the unbalance acts from this time on (a sudden unbalance)


@dataclass
class Scene:
    name: str
    rotor_path: Path
    speed_hz: float
    internal: str
    t_end_s: float
    dt_s: float
    via: str = "fmu"
    description: str = ""
    unbalances: list[Unbalance] = field(default_factory=list)
    static_loads: list[tuple[int, float, float]] = field(default_factory=list)  # (node0, Fy, Fz)
    # per internal name, the option values the scene sets (checked; file options as absolute paths)
    options: dict[str, dict] = field(default_factory=dict)
    alpha: float = 0.0
    initial: str = "static_equilibrium"
    record_nodes: list[int] = field(default_factory=list)  # 0-based; bearings are always recorded
    record_every: int = 1
    checkpoint_s: float = 60.0  # wall time between partial results written while running [s]
    fmu: Path | None = None
    source: Path | None = None
    newton_tangent: str = "bearing"  # bearing | frozen | fd | linear: see rotor_host.integrate.forces
    fmu_kind: str = "python"  # python | native: which bearing FMU via = fmu builds (bearing_fmu/native)
    speed_profile: SpeedProfile | None = None  # run-up / coast-down; None: speed_hz throughout
    supply_temperature_K: float | None = None  # oil supply [K]: bearings at mu_eff (docs/thermal.md); None: own mu

    @property
    def speed(self) -> SpeedProfile:
        """The speed over time (constant speed_hz without a profile)."""
        return self.speed_profile or SpeedProfile.constant(self.speed_hz)

    @property
    def omega(self) -> float:
        return 2.0 * math.pi * self.speed_hz

    @property
    def surrogate(self) -> Path | None:
        """The taylor internal's surrogate file, if the scene names one."""
        value = self.options.get("taylor", {}).get("surrogate")
        return Path(value) if value else None

    def internal_options(self, internal: str | None = None) -> dict:
        """The options the scene sets for ``internal`` (default: the scene's) and the internals it
        uses, as one flat dict (what the FMU parameters and ``InternalSpec.create`` take)."""
        spec = registry.get(internal or self.internal)
        out = {}
        for name in (*spec.uses, spec.name):
            out.update(self.options.get(name, {}))
        return out

    def with_internal(self, internal: str, *, options: dict | None = None, **kw) -> "Scene":
        """The same scene with another internal; ``options`` = {internal name: {option: value}}
        merged into the scene's (e.g. {"reynolds": {"n_theta": 64}}); ``kw`` other fields (via, dt_s, ...)."""
        try:
            registry.get(internal)
        except ValueError as exc:
            raise SceneError(str(exc)) from None
        merged = {k: dict(v) for k, v in self.options.items()}
        for name, values in (options or {}).items():
            spec = registry.get(name)
            merged.setdefault(name, {}).update(spec.check_options(
                {k: (str(v) if isinstance(v, Path) else v) for k, v in values.items()}, f"{name} options",
                complete=False))
        out = replace(self, internal=registry.get(internal).name, options=merged, **kw)
        if {"t_end_s", "dt_s"} & set(kw):  # overrides (--t-end, --dt) meet the checks the file's values met
            given = " and ".join(k for k in ("t_end_s", "dt_s") if k in kw)
            where = f"{self.source or self.name} (with {given} given)"
            for k in ("t_end_s", "dt_s"):
                try:
                    Number(0.0, exclusive_minimum=True).parse(getattr(out, k))
                except Invalid as exc:
                    raise SceneError(f"{where}: {k} = {getattr(out, k)!r}{exc.tail}") from None
            check_time(out.t_end_s, out.dt_s, where)
        return out


# ---------------------------------------------------------------------------------- reading

# the most time steps a run takes: 1e8 (a 10 s run-up at 0.1 us; a step is 50 us .. 1 ms in the
# shipped scenes): beyond it the step count itself is the mistake (dt_s = 1e-300 asked for 5e299)
MAX_STEPS = 10 ** 8


def check_time(t_end: float, dt: float, where: str) -> None:
    """Refuse a span of more than MAX_STEPS steps, or not a whole number of steps (what the
    integrator would silently round); both values are already > 0."""
    if t_end / dt > MAX_STEPS:
        raise SceneError(f"{where}: dt_s = {dt:g} s makes t_end_s = {t_end:g} s {t_end / dt:.3g} steps, more than the "
                         f"{MAX_STEPS:.0e} a run may take: dt_s must be at least {t_end / MAX_STEPS:.3g} s (or shorten "
                         "t_end_s)")
    if abs(round(t_end / dt) * dt - t_end) > 1e-9 * t_end:
        raise SceneError(f"{where}: t_end_s = {t_end:g} is not a whole number of steps dt_s = {dt:g}")


def _node(value: int, n_nodes: int, what: str) -> int:
    """A 1-based node number (its type checked by the schema) against the rotor's nodes, 0-based."""
    if not 1 <= value <= n_nodes:
        raise SceneError(f"{what} = {value} is outside the rotor's nodes 1..{n_nodes}")
    return value - 1


def _internal_keys() -> tuple[Key, ...]:
    """One key per registered internal: its options' sub-table (checked by the registry)."""
    return tuple(Key(n, f"options of the {n} internal ([{n}])", None, kind=Table()) for n in registry.names())


def load_scene(path) -> Scene:
    """Read and check a scene file; paths inside are relative to the scene file. Every fault
    is a SceneError of one line naming the file, the table and key, what was expected and what
    was given."""
    path = Path(path)
    where = str(path)
    data = check_table(read_toml(path, "scene file", SceneError), SCENE_KEYS + _internal_keys(), where, SceneError)
    base = path.parent
    rotor_path, rotor = _rotor(data["rotor"], base, where)
    n_nodes = rotor.n_nodes
    internal = data["internal"]
    if internal not in registry.names():
        raise SceneError(f"{where}: internal = {internal!r}; choose one of {', '.join(registry.names())}")

    tt = data["time"]
    check_time(tt["t_end_s"], tt["dt_s"], f"{where}: [time]")
    speed_hz, profile = _speed(data, where)
    unb = [Unbalance(node=_node(u["node"], n_nodes, f"{where}: [[unbalance]] {i + 1} node"),
                     mass_kg=u["mass_kg"], radius_m=u["radius_mm"] / 1e3, phase_rad=math.radians(u["phase_deg"]),
                     t_on_s=u["t_on_s"])
           for i, u in enumerate(data["unbalance"])]
    loads = [(_node(s["node"], n_nodes, f"{where}: [[static_loads]] {i + 1} node"), s["Fy_N"], s["Fz_N"])
             for i, s in enumerate(data["static_loads"])]
    rec = data["record"]
    rec_nodes = [_node(v, n_nodes, f"{where}: [record] nodes entry {i + 1}") for i, v in enumerate(rec["nodes"])]

    options = {name: _internal_options(name, data[name], where, base) for name in registry.names()
               if data.get(name) is not None}
    if data["surrogate"] is not None:  # the older form of [taylor] surrogate
        if "surrogate" in options.get("taylor", {}):
            raise SceneError(f"{where}: surrogate given twice, at the top and in [taylor]; keep [taylor] surrogate")
        options.setdefault("taylor", {}).update(_internal_options("taylor", {"surrogate": data["surrogate"]}, where, base))
    spec = registry.get(internal)
    for o in spec.options:
        if o.required and not options.get(internal, {}).get(o.name):
            raise SceneError(f"{where}: internal = {internal!r} needs the key {o.name!r} in [{internal}] ({o.help})")
    fmu = _fmu_file(data["fmu"], base, where) if data["fmu"] is not None else None
    supply = data["supply_temperature_C"]
    if supply is not None:
        check_supply(supply, data["internal"], data["via"], rotor, profile,
                     f"{where}: supply_temperature_C = {supply:g}")

    return Scene(name=data["name"] if data["name"] is not None else path.stem,
                 description=data["description"] or "",
                 rotor_path=rotor_path, speed_hz=speed_hz, speed_profile=profile, internal=internal, via=data["via"],
                 t_end_s=tt["t_end_s"], dt_s=tt["dt_s"], alpha=tt["hht_alpha"], unbalances=unb, static_loads=loads,
                 options=options, initial=data["initial"]["state"], record_nodes=rec_nodes,
                 record_every=rec["every"], checkpoint_s=rec["checkpoint_s"], fmu=fmu, source=path,
                 newton_tangent=tt["newton_tangent"], fmu_kind=data["fmu_kind"],
                 supply_temperature_K=None if supply is None else supply + 273.15)


def check_supply(supply_c: float, internal: str, via: str, rotor: Rotor, profile, key: str,
                 name: str = "supply_temperature_C") -> None:
    """A scene's supply temperature [C]: every bearing has an [oil] whose law covers it; ``key``
    begins each error (the file and key, or the command-line option ``name`` that gave it). In-process with
    any internal at one speed (the static equilibrium's mu_eff); through an FMU (its thermal ports:
    the native FMU has every such internal's film report in C, its fmu/native/catalogue.py entry's
    film_report) or under a [speed_profile] only with an internal that has the film's flows, whose
    temperature then lags the heat balance (docs/thermal.md). A data file without them (a map
    without flow tables, a version 1 surrogate) is refused by the FMU at initialisation, naming the
    file."""
    spec = registry.get(internal)
    if (via != "direct" or profile is not None) and not spec.can.film_flow:
        why = "through an FMU's thermal ports" if via != "direct" else "with a [speed_profile]"
        raise SceneError(f"{key} {why} needs an internal with the film's friction and flows ("
                         f"{', '.join(registry.having(film_flow=True, **({'fmu': True} if via != 'direct' else {})))}); "
                         f"internal = {spec.name!r}: "
                         f"{spec.can.film_flow_why}")
    for k, p in enumerate(rotor.bearings):
        if p.oil is None:
            raise SceneError(f"{key}: bearing {k + 1} (node {rotor.bearing_nodes[k] + 1}) has no [oil] table in its "
                             f"bearing file (a viscosity law); it is isoviscous at {p.mu:g} Pa s")
        try:
            p.oil.check_temperature(supply_c + 273.15, name)
        except ValueError as exc:
            raise SceneError(f"{key}: bearing {k + 1}: {exc}") from None


def _speed(data: dict, where: str) -> tuple[float, SpeedProfile | None]:
    """(speed at t = 0 [Hz], the profile or None) from speed_hz and [speed_profile]."""
    sp, f0 = data["speed_profile"], data["speed_hz"]
    if sp is None:
        if f0 is None:
            raise SceneError(f"{where}: missing key 'speed_hz' (the shaft speed [Hz]; or a [speed_profile])")
        return f0, None
    if len(sp["times_s"]) != len(sp["speeds_hz"]) or not sp["times_s"]:
        raise SceneError(f"{where}: [speed_profile] times_s and speeds_hz must have the same length >= 1, got "
                         f"{len(sp['times_s'])} and {len(sp['speeds_hz'])}")
    try:
        profile = SpeedProfile(tuple(sp["times_s"]), tuple(sp["speeds_hz"]))
    except ValueError as exc:
        raise SceneError(f"{where}: [{exc}]".replace("[speed profile:", "[speed_profile]")) from None
    start = profile.hz(0.0)
    if f0 is not None and abs(f0 - start) > 1e-9 * start:
        raise SceneError(f"{where}: speed_hz = {f0:g} differs from the [speed_profile] speed at t = 0, {start:g} Hz; "
                         "leave speed_hz out or make them equal")
    return start, profile


def _rotor(name: str, base: Path, where: str) -> tuple[Path, Rotor]:
    """The scene's rotor file, read and checked whole (so a bad rotor file is named now, and
    node numbers are checked against the rotor's own nodes); it must hold a bearing."""
    rotor_path = (base / name).resolve()
    if not rotor_path.is_file():
        what = "is a directory, not a file" if rotor_path.is_dir() else "not found"
        raise SceneError(f"{where}: rotor = {name!r}: {rotor_path} {what}")
    try:
        rotor = Rotor.from_toml(rotor_path)
    except ValueError as exc:  # RotorFileError, a bearing file's error: they name their file and key
        raise SceneError(f"{where}: rotor = {name!r}: {exc}") from None
    if not rotor.bearing_nodes:
        raise SceneError(f"{where}: rotor = {name!r}: the rotor has no bearings; a scene needs at least one "
                         "[[bearings]] entry (node, bearing file) in the rotor file")
    return rotor_path, rotor


def _fmu_file(name: str, base: Path, where: str) -> Path:
    """The scene's own bearing FMU: there, and an FMU (a zip archive holding modelDescription.xml)."""
    import zipfile

    p = (base / name).resolve()
    if not p.is_file():
        what = "is a directory, not a file" if p.is_dir() else "not found"
        raise SceneError(f"{where}: fmu = {name!r}: {p} {what}")
    try:
        with zipfile.ZipFile(p) as z:
            if "modelDescription.xml" not in z.namelist():
                raise SceneError(f"{where}: fmu = {name!r}: {p} is not an FMU (a zip archive without "
                                 "modelDescription.xml); build one with `bearing-fmu build -o FILE.fmu`")
    except (zipfile.BadZipFile, OSError):
        raise SceneError(f"{where}: fmu = {name!r}: {p} is not an FMU (not a zip archive); build one with "
                         "`bearing-fmu build -o FILE.fmu`") from None
    return p


def _internal_options(name: str, table: dict, where: str, base: Path) -> dict:
    """The sub-table [name] of a scene: options of that internal, checked by the registry; file
    options resolved relative to the scene file."""
    spec = registry.get(name)
    try:
        opts = spec.check_options(table, f"{where}: [{name}]", complete=False)
    except ValueError as exc:
        raise SceneError(str(exc)) from None
    for o in spec.options:
        if o.file and opts.get(o.name):
            opts[o.name] = str((base / opts[o.name]).resolve())
    return opts


def scene_files(scene: Scene) -> list[Path]:
    """The files the scene's internal reads, each checked to exist: its own required file options (the
    surrogate, the map) and any other file option the scene sets (linear's map, tilting pads' pad_map)."""
    spec = registry.get(scene.internal)
    opts = scene.internal_options()
    out = []
    for name in (spec.name, *spec.uses):
        for o in registry.get(name).options:
            if o.file and ((name == spec.name and o.required) or opts.get(o.name)):
                out.append(required_file(scene, name, o.name))
    return out


def required_file(scene: Scene, internal: str, option: str) -> Path:
    """The file the scene names for ``option`` of ``internal`` (e.g. taylor's surrogate), or a
    SceneError that says what is missing and what it is."""
    value = scene.options.get(internal, {}).get(option)
    spec = next(o for o in registry.get(internal).all_options() if o.name == option)
    what = spec.help
    why = ""
    if not value:
        value, why = _stored_file(scene, internal, option, spec.file_format)
    if not value:
        raise SceneError(f"{scene.source}: the {internal} internal needs a {option} file, and the scene names "
                         f"none: set `{option} = \"...\"` in its [{internal}] table or pass --{option} ({what})"
                         + (f"; {why}" if why else ""))
    path = Path(value)
    if not path.is_file():
        raise SceneError(f"{scene.source}: {option} file {path} not found ({what})")
    return path


def _stored_file(scene: Scene, internal: str, option: str, file_format: str) -> tuple[str | None, str]:
    """(the map store's file for a file option the scene leaves out, '') -- a force map of its
    bearings' L/D and bore, built by ``bearing-fmu map`` -- set into the scene's options and named on
    stderr; or (None, why the store has none; '' for a kind of file it does not keep)."""
    import sys

    from bearing_fmu.internals.map.store import STORED_FORMATS, stored_file

    if file_format not in STORED_FORMATS:  # the rotor file is read only for a kind of file the store keeps
        return None, ""
    path, line = stored_file(file_format, Rotor.from_toml(scene.rotor_path).bearings)
    if path is None:
        return None, line
    scene.options.setdefault(internal, {})[option] = str(path)
    print(f"{scene.source or scene.name}: [{internal}] {option} not given: {line}", file=sys.stderr)
    return str(path), ""
