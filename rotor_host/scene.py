"""Scenes: one simulation case read from TOML, built with only what it names, run, saved.

A scene names a rotor file, the internal (a name of ``bearing_fmu.internals.REGISTRY``), how
the bearings are reached (through the FMU, ``via = "fmu"``, or called in-process,
``via = "direct"``), the speed, unbalances, static loads, time span and step, and what to
record. Each internal's options sit in a sub-table named after it (``[reynolds] n_theta``,
``[taylor] surrogate``), checked against the registry; a scene may hold several, so the same
scene runs with another internal (``rotor-host compare``, ``--internal``). ``run_scene``
builds the rotor, the bearings for that internal only (a Taylor scene never imports the
Reynolds solver), the static equilibrium as the initial state, integrates, and writes
``<out>/<name>.npz`` plus ``<out>/<name>.json`` (metadata) even when the run fails part-way.

Keys carry their units (``speed_hz``, ``radius_mm``, ``dt_s``); nodes are 1-based as in the
rotor file.
"""

from __future__ import annotations

import hashlib
import math
import os
import platform
import time
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path

import numpy as np

from bearing_fmu import internals as registry
from bearing_fmu.exits import as_interrupted, handled, note_kept
from bearing_fmu.internals import Context
from bearing_fmu.outputs import claim, ensure_writable, savez, write_json
from bearing_fmu.schema import (Choice, FileName, Invalid, Key, List, Number, Table, Tables, Text, check_table,
                               read_toml)

from .equilibrium import static_equilibrium
from .forces import NEWTON_TANGENTS
from .newmark import IntegrationError, Newmark, NewmarkConfig
from .rotor import NODE, Rotor
from .speed import SpeedProfile

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
    Key("t_end_s", "simulated time [s]", allowed="> 0, a whole number of steps",
        kind=Number(0.0, exclusive_minimum=True)),
    Key("dt_s", "time step [s]", kind=Number(0.0, exclusive_minimum=True)),
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
        "Python at run time: linear, map, taylor; needs a C compiler at build time)", "python",
        ", ".join(FMU_KINDS), kind=Choice(FMU_KINDS)),
    Key("fmu", "a bearing FMU to use instead of building one, relative to the scene file", None,
        "file name of an .fmu", kind=FileName()),
    Key("initial", "initial state ([initial])", None, kind=Table(INITIAL_KEYS)),
    Key("unbalance", "unbalances ([[unbalance]])", None, kind=Tables(UNBALANCE_KEYS)),
    Key("static_loads", "static point loads ([[static_loads]]), e.g. to load the bearings", None,
        kind=Tables(STATIC_LOAD_KEYS)),
    Key("record", "what to record besides the bearing nodes ([record])", None, kind=Table(RECORD_KEYS)),
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
    newton_tangent: str = "bearing"  # bearing | frozen | fd | linear: see rotor_host.forces
    fmu_kind: str = "python"  # python | native: which bearing FMU via = fmu builds (bearing_fmu/native)
    speed_profile: SpeedProfile | None = None  # run-up / coast-down; None: speed_hz throughout

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

def check_time(t_end: float, dt: float, where: str) -> None:
    """Refuse a span that is not a whole number of steps (what the integrator would silently
    round); both values are already > 0."""
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

    return Scene(name=data["name"] if data["name"] is not None else path.stem,
                 description=data["description"] or "",
                 rotor_path=rotor_path, speed_hz=speed_hz, speed_profile=profile, internal=internal, via=data["via"],
                 t_end_s=tt["t_end_s"], dt_s=tt["dt_s"], alpha=tt["hht_alpha"], unbalances=unb, static_loads=loads,
                 options=options, initial=data["initial"]["state"], record_nodes=rec_nodes,
                 record_every=rec["every"], checkpoint_s=rec["checkpoint_s"], fmu=fmu, source=path,
                 newton_tangent=tt["newton_tangent"], fmu_kind=data["fmu_kind"])


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

# ---------------------------------------------------------------------------------- statics

def bearing_loads(rotor: Rotor, f_static: np.ndarray) -> np.ndarray:
    """Static load (Wy, Wz) [N] on each bearing's journal, shape (n_bearings, 2).

    The reactions of the rotor pinned (y, z held) at its bearing nodes under ``f_static``:
    K q = f + r with r on the held DOFs only. On two bearings the shaft is statically
    determinate, so these are the film forces at equilibrium whatever the bearing stiffness;
    the load on the journal (``bearing_fmu.statics.equilibrium``'s convention) is -r.
    """
    q = _start_guess(rotor, f_static, np.zeros((len(rotor.bearing_nodes), 2)))
    r = rotor.K @ q - f_static
    fixed = [rotor.dof(nd, d) for nd in rotor.bearing_nodes for d in ("y", "z")]
    return -r[fixed].reshape(-1, 2)


def _start_guess(rotor: Rotor, f_static: np.ndarray, journal: np.ndarray) -> np.ndarray:
    """Rotor deflection with the bearing nodes held at the given journal positions."""
    n = rotor.n_dof
    fixed = np.array([rotor.dof(nd, d) for nd in rotor.bearing_nodes for d in ("y", "z")])
    free = np.setdiff1d(np.arange(n), fixed)
    q = np.zeros(n)
    q[fixed] = journal.reshape(-1)
    K = rotor.K
    q[free] = np.linalg.solve(K[np.ix_(free, free)], f_static[free] - K[np.ix_(free, fixed)] @ q[fixed])
    return q


# ---------------------------------------------------------------------------------- building

def _context(scene: Scene, load) -> Context:
    """What a bearing's internal may take from the run: its static load and the speed."""
    return Context(load=(float(load[0]), float(load[1])), omega=scene.omega)


def _fmu_parameters(scene: Scene, params, load) -> dict:
    """FMU parameters of one bearing: the bearing, the internal and all its options (the
    static load and speed filled in where the internal takes them; files by their name in
    the FMU's resources). A native FMU takes the options it keeps (``native_parameters``:
    the linear model's coefficients are made here, per bearing)."""
    if scene.fmu_kind == "native":
        from bearing_fmu.native import native_parameters

        try:
            return native_parameters(scene.internal, params, scene.internal_options(), _context(scene, load),
                                     where=f"{scene.source}: fmu_kind = 'native'")
        except ValueError as exc:
            raise SceneError(str(exc)) from None
    spec = registry.get(scene.internal)
    opts = spec.check_options(scene.internal_options(), str(scene.source), context=_context(scene, load))
    for o in spec.all_options():
        if o.file and opts[o.name]:
            opts[o.name] = Path(opts[o.name]).name
    return {"D": params.D, "L": params.L, "CR": params.CR, "mu": params.mu, "internal": spec.name, **opts}


def _direct_internal(scene: Scene, params, load):
    """The scene's internal for one bearing, imported only when used."""
    return registry.create(scene.internal, params, scene.internal_options(), _context(scene, load),
                           where=str(scene.source))


def _files(scene: Scene) -> list[Path]:
    """The files the scene's internal reads, each checked to exist: its own file options (the
    surrogate, the map) and those of the internals it uses that the scene sets (linear's map)."""
    spec = registry.get(scene.internal)
    opts = scene.internal_options()
    out = []
    for name in (spec.name, *spec.uses):
        for o in registry.get(name).options:
            if o.file and (name == spec.name or opts.get(o.name)):
                out.append(required_file(scene, name, o.name))
    return out


def scene_fmu(scene: Scene, work_dir: Path) -> Path:
    """The bearing FMU for the scene: its ``fmu`` key, or one built into work_dir (with the
    files of the scene's internal bundled, e.g. the surrogate of a Taylor scene)."""
    if scene.fmu is not None:
        if not scene.fmu.is_file():
            raise SceneError(f"{scene.source}: fmu = {scene.fmu}: file not found")
        return scene.fmu
    if scene.fmu_kind == "native":
        return _native_fmu(scene, work_dir)
    from bearing_fmu.build import build_fmu, package_name

    work_dir.mkdir(parents=True, exist_ok=True)
    files = _files(scene)
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


def _native_fmu(scene: Scene, work_dir: Path) -> Path:
    """The scene's native FMU, built into work_dir under a name that hashes the C sources, the
    generator and the internal's data file, so runs of the same scene share one build. The
    linear FMU holds no data: the host sets each bearing's coefficients."""
    from bearing_fmu.native import INTERNALS
    from bearing_fmu.native.build import C_DIR, build_native_fmu

    if scene.internal not in INTERNALS:
        raise SceneError(f"{scene.source}: fmu_kind = 'native' computes one of {', '.join(INTERNALS)}, not internal = "
                         f"{scene.internal!r} (it needs its solver at run time): use fmu_kind = 'python'")
    work_dir.mkdir(parents=True, exist_ok=True)
    data = {"taylor": ("surrogate", "surrogate"), "map": ("map", "map")}.get(scene.internal)
    path = required_file(scene, scene.internal, data[0]) if data else None
    h = hashlib.sha256(scene.internal.encode())
    pkg = C_DIR.parent.parent  # bearing_fmu: the model description and docs generators too
    for f in (sorted(C_DIR.glob("*")) + sorted(C_DIR.parent.glob("*.py")) + [pkg / "fmu_meta.py", pkg / "fmu_docs.py"]
              + ([path] if path else [])):
        h.update(f.name.encode() + b"\0" + f.read_bytes())
    out = work_dir / f"bearing_native_{scene.internal}{'_' + path.stem if path else ''}_{h.hexdigest()[:12]}.fmu"
    if out.is_file():
        return out
    options = {"linear_from": "coefficients"} if scene.internal == "linear" else None
    return Path(build_native_fmu(out, scene.internal, options=options, **({data[1]: path} if data else {})))


def required_file(scene: Scene, internal: str, option: str) -> Path:
    """The file the scene names for ``option`` of ``internal`` (e.g. taylor's surrogate), or a
    SceneError that says what is missing and what it is."""
    value = scene.options.get(internal, {}).get(option)
    what = next(o.help for o in registry.get(internal).all_options() if o.name == option)
    if not value:
        raise SceneError(f"{scene.source}: the {internal} internal needs a {option} file, and the scene names "
                         f"none: set `{option} = \"...\"` in its [{internal}] table or pass --{option} ({what})")
    path = Path(value)
    if not path.is_file():
        raise SceneError(f"{scene.source}: {option} file {path} not found ({what})")
    return path


def build_bearings(scene: Scene, rotor: Rotor, loads: np.ndarray, work_dir: Path):
    """The BearingSet of the scene: FMU instances (via = fmu) or internals in-process."""
    pairs = [(rotor.dof(n, "y"), rotor.dof(n, "z")) for n in rotor.bearing_nodes]
    names = [f"bearing {k + 1} (node {n + 1})" for k, n in enumerate(rotor.bearing_nodes)]
    _files(scene)  # a missing file is named before anything is built
    if scene.via == "direct":
        from .bearings import DirectBearings

        internals = [_direct_internal(scene, p, w) for p, w in zip(rotor.bearings, loads)]
        return DirectBearings(internals, pairs, scene.omega, names, tangent=scene.newton_tangent)
    from .cosim import FMUBearings

    fmu = scene_fmu(scene, work_dir)
    params = [_fmu_parameters(scene, p, w) for p, w in zip(rotor.bearings, loads)]
    return FMUBearings(fmu, pairs, scene.omega, params, names, tangent=scene.newton_tangent)


def external_force(scene: Scene, rotor: Rotor, f_static: np.ndarray):
    """f_ext(t): static loads and weight plus the rotating unbalance forces. Under a speed
    profile the mass sits at the integrated shaft angle and, besides m r Omega^2 outward, pulls
    back with m r dOmega/dt against the turning (the reaction to its tangential acceleration)."""
    om = scene.omega
    parts = []
    for u in scene.unbalances:
        parts.append((rotor.dof(u.node, "y"), rotor.dof(u.node, "z"), u.mass_kg * u.radius_m, u.phase_rad, u.t_on_s))
    out = np.empty_like(f_static)
    profile = scene.speed_profile

    def f_ext(t: float) -> np.ndarray:
        out[:] = f_static
        for iy, iz, mr, ph, t_on in parts:
            if t >= t_on:
                a = om * t + ph
                amp = mr * om * om
                out[iy] += amp * math.cos(a)
                out[iz] += amp * math.sin(a)
        return out

    def f_ext_profile(t: float) -> np.ndarray:
        out[:] = f_static
        if parts:
            w, dw, th = profile.omega(t), profile.alpha(t), profile.angle(t)
            for iy, iz, mr, ph, t_on in parts:
                if t >= t_on:
                    c, s = math.cos(th + ph), math.sin(th + ph)
                    out[iy] += mr * (w * w * c + dw * s)
                    out[iz] += mr * (w * w * s - dw * c)
        return out

    return f_ext if profile is None else f_ext_profile


def initial_state(scene: Scene, rotor: Rotor, f_static, loads, bearings) -> np.ndarray:
    """Static equilibrium of the whole rotor with the nonlinear bearing forces (or the rotor
    undeformed and centred, ``initial.state = "centred"``)."""
    if scene.initial == "centred":
        return np.zeros(rotor.n_dof)
    from bearing_fmu.statics import short_bearing_estimate

    journal = np.array([short_bearing_estimate(p, w, scene.omega) for p, w in zip(rotor.bearings, loads)])
    # keep the short-bearing start inside the clearance: a finite bearing carries more
    for k, p in enumerate(rotor.bearings):
        e = np.hypot(*journal[k]) / p.CR
        if e > 0.9:
            journal[k] *= 0.9 / e
    q0 = _start_guess(rotor, f_static, journal)
    return static_equilibrium(rotor.K, f_static, bearings, q0, t=0.0)


# ---------------------------------------------------------------------------------- running

@dataclass
class SceneRun:
    """What a run produced: arrays (as saved in the .npz) and metadata (as in the .json)."""

    arrays: dict
    meta: dict
    npz: Path | None = None
    json: Path | None = None

    @property
    def ok(self) -> bool:
        return self.meta["status"] == "ok"


def _domain_report(scene: Scene, rotor: Rotor, q: np.ndarray, v: np.ndarray) -> dict:
    """Per bearing: the fraction of recorded states outside the surrogate's fitted domain and
    the largest distance outside it (``Taylor.domain_distance``: relative excess over its bounds
    or, with stored training states, the distance beyond their radius over the domain's size;
    <= 0: always inside)."""
    from bearing_fmu.taylor import Taylor

    frac, dist = [], []
    for k, params in enumerate(rotor.bearings):
        tay = Taylor.from_file(scene.surrogate, params)
        d = np.array([tay.domain_distance(*q[i, k], *v[i, k]) for i in range(len(q))])
        frac.append(float(np.mean(d > 1e-12)))
        dist.append(float(d.max()))
    return {"out_of_domain_fraction": frac, "max_domain_excess": dist}


def _versions() -> dict:
    import importlib.metadata as md

    out = {"python": platform.python_version()}
    for pkg in ("bearing-fmu", "numpy", "scipy", "numba", "fmpy", "pythonfmu"):
        try:
            out[pkg] = md.version(pkg)
        except md.PackageNotFoundError:
            out[pkg] = None
    return out


def run_scene(scene: Scene, out_dir=None, *, progress: bool = False, stem: str | None = None,
              work_dir=None) -> SceneRun:
    """Run a scene; write ``<out_dir>/<stem>.npz`` and ``.json``. Returns the SceneRun.

    What was computed is always written: a failed integration or static equilibrium gives
    meta["status"] == "failed" (with the message), an interrupt (Ctrl-C, SIGTERM) status
    "interrupted" and the signal, after which the interrupt is raised again; while running, a
    checkpoint (status "running") is written every ``scene.checkpoint_s`` of wall time. Files
    are written under a temporary name and renamed into place; a name another running process
    holds gets a suffix (``bearing_fmu.outputs.claim``)."""
    native = "_native" if scene.via == "fmu" and scene.fmu_kind == "native" else ""
    stem = stem or f"{Path(scene.source).stem if scene.source else scene.name}_{scene.internal}{native}"
    out_dir = ensure_writable(out_dir) if out_dir is not None else None
    work = Path(work_dir) if work_dir is not None else (out_dir or Path("out")) / "fmu"
    with handled():
        holder = claim(out_dir, stem) if out_dir is not None else None
        try:
            return _run(scene, holder, work, progress)
        finally:
            if holder is not None:
                holder.release()


class _Writer:
    """Turns the integrator's (partial) result into the run's arrays and metadata and writes
    them; one instance per run, used for checkpoints, failures, interrupts and the end."""

    def __init__(self, scene: Scene, rotor: Rotor, loads, holder, t_wall0: float):
        self.scene, self.rotor, self.holder, self.t_wall0 = scene, rotor, holder, t_wall0
        # the bearings and the disks always: the plots and reports show them
        self.rec_nodes = sorted(set(scene.record_nodes) | set(rotor.bearing_nodes) | {d.node for d in rotor.disks})
        self.rec_dofs = [rotor.dof(n, d) for n in self.rec_nodes for d in ("y", "z")]
        self.q0 = None
        self.times = {"setup_time_s": 0.0, "equilibrium_time_s": 0.0}
        self.meta = {
            "scene": scene.name, "description": scene.description, "source": str(scene.source),
            "internal": scene.internal, "via": scene.via, "fmu_kind": scene.fmu_kind, "speed_hz": scene.speed_hz,
            "speed_profile": None if scene.speed_profile is None else scene.speed_profile.describe(), "dt_s": scene.dt_s,
            "t_end_s": scene.t_end_s, "hht_alpha": scene.alpha, "newton_tangent": scene.newton_tangent,
            "internal_options": scene.internal_options(),
            "bearing_loads_N": np.asarray(loads).tolist(), "recorded_nodes": [n + 1 for n in self.rec_nodes],
            "bearing_nodes": [n + 1 for n in rotor.bearing_nodes],
            "versions": _versions(), "machine": platform.machine(), "pid": os.getpid(),
            "status": "ok", "message": "",
        }

    def run(self, res, status: str = "ok", message: str = "", **extra) -> SceneRun:
        """The SceneRun of ``res`` (a NewmarkResult, or None before the integration started),
        written to disk when the run has an output folder."""
        rotor, scene = self.rotor, self.scene
        nb, n_rec = len(rotor.bearing_nodes), len(self.rec_nodes)
        if res is None:
            t = np.zeros(0)
            q = v = np.zeros((0, 2 * n_rec))
            f = np.zeros((0, 2 * nb))
            its, n_cuts, n_eval, wall, mean_its = np.zeros(0, int), 0, 0, 0.0, 0.0
        else:
            t, q, v, f = res.t, res.q, res.v, res.f_nl
            its, n_cuts, n_eval, wall, mean_its = (res.iterations, res.n_cuts, res.n_evaluations, res.wall_time,
                                                   res.mean_iterations)
        col = {n: i for i, n in enumerate(self.rec_nodes)}
        yz = q.reshape(len(t), n_rec, 2)
        vyz = v.reshape(len(t), n_rec, 2)
        fb = f.reshape(len(t), nb, 2)
        bcols = [col[n] for n in rotor.bearing_nodes]
        CR = np.array([p.CR for p in rotor.bearings])
        ecc = np.hypot(yz[:, bcols, 0], yz[:, bcols, 1]) / CR
        q0 = self.q0[self.rec_dofs] if self.q0 is not None else np.full(len(self.rec_dofs), np.nan)
        arrays = {
            "t": t, "nodes": np.array(self.rec_nodes) + 1,
            "y": yz[:, :, 0], "z": yz[:, :, 1], "vy": vyz[:, :, 0], "vz": vyz[:, :, 1],
            "Fy": fb[:, :, 0], "Fz": fb[:, :, 1], "eccentricity": ecc,
            "bearing_nodes": np.array(rotor.bearing_nodes) + 1, "CR": CR, "q0": q0,
            "disk_nodes": np.array([d.node for d in rotor.disks], dtype=int) + 1,
            "speed_hz": np.array([scene.speed.hz(x) for x in t]) if scene.speed_profile is not None
            else np.full(len(t), scene.speed_hz),
        }
        max_ecc = ecc.max(axis=0) if ecc.size else np.zeros(nb)
        meta = dict(self.meta)
        meta.update(status=status, message=message, **extra)
        meta.update({
            "wall_time_s": time.perf_counter() - self.t_wall0, **self.times,
            "integration_time_s": wall, "steps": int(its.size),
            "t_reached_s": float(t[-1]) if t.size else 0.0,
            "newton_mean_evaluations_per_step": mean_its,
            "newton_max_evaluations_per_step": int(its.max()) if its.size else 0,
            "force_evaluations": int(n_eval), "step_cuts": int(n_cuts),
            "max_eccentricity": max_ecc.tolist(),
            "crossed_clearance": bool(np.any(max_ecc >= 1.0)),
            "equilibrium_eccentricity": (None if self.q0 is None else
                                         (np.hypot(self.q0[[rotor.dof(n, "y") for n in rotor.bearing_nodes]],
                                                   self.q0[[rotor.dof(n, "z") for n in rotor.bearing_nodes]])
                                          / CR).tolist()),
        })
        if scene.internal == "taylor" and ecc.size and status != "running":
            meta.update(_domain_report(scene, rotor, yz[:, bcols], vyz[:, bcols]))
            worst = max(meta["max_domain_excess"])
            if meta["status"] != "ok" and worst > 1e-12:
                # the failure itself may read like a solver problem: say where the surrogate was
                meta["message"] += (f" [the surrogate had left its fitted domain: up to {100 * worst:.3g} % of its "
                                    f"size beyond it, {100 * max(meta['out_of_domain_fraction']):.3g} % of the recorded "
                                    "states outside; its forces there are extrapolations]")
        run = SceneRun(arrays, meta)
        if self.holder is not None:
            run.npz = savez(self.holder.path(".npz"), **arrays)
            run.json = write_json(self.holder.path(".json"), meta)
        return run


def _run(scene: Scene, holder, work: Path, progress: bool) -> SceneRun:
    from bearing_fmu.statics import EquilibriumError

    t_wall0 = time.perf_counter()
    rotor = Rotor.from_toml(scene.rotor_path)
    f_static = rotor.weight_vector(G) + rotor.point_load_vector(scene.static_loads)
    loads = bearing_loads(rotor, f_static)
    out = _Writer(scene, rotor, loads, holder, t_wall0)
    integ = None
    try:
        with build_bearings(scene, rotor, loads, work) as bearings:
            t_setup = time.perf_counter()
            out.times["setup_time_s"] = t_setup - t_wall0
            try:
                out.q0 = initial_state(scene, rotor, f_static, loads, bearings)
            except EquilibriumError as exc:
                return out.run(None, "failed", str(exc),
                               equilibrium={k: v for k, v in exc.diagnosis().items() if v is not None})
            out.times["equilibrium_time_s"] = time.perf_counter() - t_setup
            if scene.speed_profile is not None:  # a run-up: the bearings and D follow the speed
                bearings.speed = scene.speed_profile.omega
            integ = Newmark(rotor.M, rotor.K, rotor.C, rotor.G,
                            scene.omega if scene.speed_profile is None else scene.speed_profile.omega,
                            external_force(scene, rotor, f_static), bearings,
                            NewmarkConfig(alpha=scene.alpha, tangent=scene.newton_tangent))
            bar = None
            if progress:
                from tqdm import tqdm

                bar = tqdm(total=scene.t_end_s, unit="s", desc=f"{scene.name} [{scene.internal}]",
                           bar_format="{l_bar}{bar}| {n:.3f}/{total:.3f} s [{elapsed}<{remaining}]")
            last = [time.perf_counter()]

            def tick(t):
                if bar is not None:
                    bar.update(t - bar.n)
                now = time.perf_counter()
                if holder is not None and now - last[0] >= scene.checkpoint_s:
                    out.run(integ.partial_result(), "running",
                            "checkpoint written while running: the run had not finished when this was written")
                    last[0] = time.perf_counter()

            try:
                res = integ.run(out.q0, np.zeros(rotor.n_dof), 0.0, scene.t_end_s, scene.dt_s,
                                record_every=scene.record_every, record_dofs=out.rec_dofs, progress=tick,
                                progress_every=_progress_every(scene))
                status, message = "ok", ""
            except IntegrationError as exc:
                res, status, message = exc.result, "failed", str(exc)
            finally:
                if bar is not None:
                    bar.close()
    except KeyboardInterrupt as exc:
        sig = as_interrupted(exc).signal_name
        res = integ.partial_result() if integ is not None and integ.started else None
        t = float(res.t[-1]) if res is not None and res.t.size else 0.0
        run = out.run(res, "interrupted", f"interrupted by {sig} at t = {t:.6g} s", signal=sig)
        if run.json is not None:
            note_kept(exc, f"{run.npz}, {run.json} (status interrupted, t = {t:.6g} s)")
        raise
    return out.run(res, status, message)


def _progress_every(scene: Scene) -> int:
    """Steps between progress calls (which also write checkpoints): ~200 per run, at most 50
    steps apart so a long run's checkpoints come on time."""
    n_steps = max(1, int(round(scene.t_end_s / scene.dt_s)))
    return max(1, min(n_steps // 200, 50))
