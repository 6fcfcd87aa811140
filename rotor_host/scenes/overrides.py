"""A scene with changes on top: what the command lines' ``--internal``, ``--via``, ``--t-end``,
``--surrogate FILE``, ``--supply-c``, ``--bearing FILE`` ... say, as one value that any caller (a
CLI, a script, a sweep worker) applies the same way.

A bearing swap (``--bearing``) writes a copy of the scene's rotor file whose [[bearings]] entries
name the new bearing file (``swapped_rotor``): every reader of ``Scene.rotor_path`` (the run, the
FMU build, a sweep's workers) then sees the same rotor, and the run's record names the file it
ran. The copy goes into the command's output folder, under a name hashing its content."""

from __future__ import annotations

import hashlib
import json
import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping

from bearing_fmu.internals import registry

from .scene import Scene, SceneError, check_supply, load_scene

ALL_BEARINGS = "*"  # the key of ``SceneOverrides.bearings`` that swaps every bearing's file


@dataclass(frozen=True)
class SceneOverrides:
    """Changes to a scene; None (or empty) leaves the scene's own value.

    internal       : the bearing internal (a registered name)
    via            : "fmu" (bearing FMUs through fmpy) or "direct" (internals in-process)
    native         : through native (C) FMUs: the scene key ``fmu_kind = "native"``
    t_end_s, dt_s  : end time and time step [s]
    newton_tangent : the Newton tangent word (``rotor_host.integrate.forces.NEWTON_TANGENTS``)
    checkpoint_s   : wall time between partial result writes [s]
    files          : file option name -> path, e.g. {"surrogate": Path(...)} (over the scene's
                     sub-table of the internal that owns the option)
    supply_c       : the oil's supply temperature [C] (the scene key supply_temperature_C), checked
                     against every bearing's oil as the file's value would be
    bearings       : which bearing file -> new bearing file: ``ALL_BEARINGS`` ("*") every bearing, else a
                     [[bearings]] entry's name or its 1-based node (as text) in the rotor file
    folder         : where a swapped rotor file is written (default: ``.rotor-host`` in the current
                     folder; the command lines give their output folder)
    """

    internal: str | None = None
    via: str | None = None
    native: bool = False
    t_end_s: float | None = None
    dt_s: float | None = None
    newton_tangent: str | None = None
    checkpoint_s: float | None = None
    files: Mapping[str, Path] = field(default_factory=dict)
    supply_c: float | None = None
    bearings: Mapping[str, Path] = field(default_factory=dict)
    folder: Path | None = None

    def apply(self, scene: Scene) -> Scene:
        """The scene with these changes, each checked as the scene file's own value would be."""
        changes = {k: getattr(self, k) for k in ("via", "t_end_s", "dt_s", "newton_tangent", "checkpoint_s")
                   if getattr(self, k) is not None}  # 0 is a value (refused by its check), not "unset"
        if self.native:
            via = self.via or scene.via
            if via != "fmu":
                raise ValueError(f"--native builds native bearing FMUs, which only via = \"fmu\" runs; "
                                 f"{scene.source or scene.name} runs via = \"{via}\" (the internals in-process, no "
                                 "FMU): add --via fmu, or leave --native out")
            changes["fmu_kind"] = "native"
        owners = dict((option, internal) for internal, option in file_options())
        options: dict = {}
        for option, path in self.files.items():
            if option not in owners:
                raise ValueError(f"no internal reads a file option {option!r}; known: {', '.join(owners)}")
            options.setdefault(owners[option], {})[option] = Path(path).resolve()
        if self.bearings:
            changes["rotor_path"] = swapped_rotor(scene.rotor_path, self.bearings,
                                                  Path(self.folder) if self.folder else Path(".rotor-host"))
        if not (changes or options or self.internal or self.supply_c is not None):
            return scene
        out = scene.with_internal(self.internal or scene.internal, options=options, **changes)
        if self.supply_c is not None:
            out = with_supply(out, self.supply_c)
        elif "rotor_path" in changes and out.supply_temperature_K is not None:  # the new bearings meet the file's
            out = with_supply(out, out.supply_temperature_K - 273.15, f"{scene.source}: supply_temperature_C")
        return out


def with_supply(scene: Scene, supply_c: float, key: str = "--supply-c") -> Scene:
    """The scene at the oil supply temperature ``supply_c`` [C], refused (SceneError naming ``key``,
    the bearing and the oil's range) where the scene file's supply_temperature_C would be."""
    from dataclasses import replace

    from ..model.rotor import Rotor

    if not math.isfinite(supply_c):
        raise SceneError(f"{key} {supply_c!r}: give a finite temperature in C")
    check_supply(supply_c, scene.internal, scene.via, Rotor.from_toml(scene.rotor_path), scene.speed_profile,
                 f"{key} {supply_c:g}", key)
    return replace(scene, supply_temperature_K=supply_c + 273.15)


def _toml(value) -> str:
    """A value of a rotor file as TOML (inline tables and arrays: what read_toml gives back)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(value) if math.isfinite(value) else ("nan" if value != value else ("inf" if value > 0 else "-inf"))
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{_key(k)} = {_toml(v)}" for k, v in value.items()) + "}"
    raise TypeError(f"no TOML form for {value!r}")


def _key(k: str) -> str:
    return k if re.fullmatch(r"[A-Za-z0-9_-]+", k) else json.dumps(k)


def swapped_rotor(rotor_path, bearings: Mapping[str, Path], folder: Path) -> Path:
    """A copy of the rotor file ``rotor_path`` in ``folder`` whose [[bearings]] entries chosen by
    ``bearings`` (see ``SceneOverrides.bearings``) name their new bearing file (all paths absolute);
    a key that chooses no entry is a SceneError listing the entries."""
    from bearing_fmu.io.outputs import write_text
    from bearing_fmu.io.schema import read_toml

    from ..model.rotor import Rotor

    rotor_path = Path(rotor_path).resolve()
    data = read_toml(rotor_path, "rotor file", SceneError)
    entries = data.get("bearings", [])
    known = [str(e.get("name") or e.get("node")) for e in entries]
    for which in bearings:
        if which != ALL_BEARINGS and not any(which in (str(e.get("name")), str(e.get("node"))) for e in entries):
            raise SceneError(f"--bearing {which}=...: {rotor_path.name} has no bearing named {which!r} or at node "
                             f"{which}; its [[bearings]]: {', '.join(known) or 'none'}")
    for e in entries:
        new = next((bearings[k] for k in (str(e.get("name")), str(e.get("node"))) if k in bearings),
                   bearings.get(ALL_BEARINGS))
        e["bearing"] = str(Path(new).resolve() if new is not None else (rotor_path.parent / e["bearing"]).resolve())
    text = (f"# {rotor_path} with the bearing files of the command line's --bearing\n"
            + "".join(f"{_key(k)} = {_toml(v)}\n" for k, v in data.items()))
    digest = hashlib.sha256(text.encode()).hexdigest()[:10]
    Path(folder).mkdir(parents=True, exist_ok=True)
    path = write_text(Path(folder) / f"{rotor_path.stem}_bearings_{digest}.toml", text)
    try:
        Rotor.from_toml(path)  # the new bearing file's own one-line error (a key, a value), naming it
    except ValueError as exc:
        raise SceneError(f"--bearing: {exc}") from None
    return path


def file_options() -> list[tuple[str, str]]:
    """(internal, option) of every file option in the registry: each is a command-line flag."""
    return [(spec.name, o.name) for spec in registry.REGISTRY.values() for o in spec.file_options()]


def load_with_overrides(path, overrides: SceneOverrides | None = None) -> Scene:
    """``load_scene(path)`` with ``overrides`` applied."""
    scene = load_scene(path)
    return overrides.apply(scene) if overrides is not None else scene


__all__ = ["ALL_BEARINGS", "SceneOverrides", "file_options", "load_with_overrides", "with_supply", "swapped_rotor"]
