"""A scene with changes on top: what the command lines' ``--internal``, ``--via``, ``--t-end``,
``--surrogate FILE`` ... say, as one value that any caller (a CLI, a script, a sweep worker)
applies the same way."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping

from bearing_fmu.internals import registry

from .scene import Scene, load_scene


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
    """

    internal: str | None = None
    via: str | None = None
    native: bool = False
    t_end_s: float | None = None
    dt_s: float | None = None
    newton_tangent: str | None = None
    checkpoint_s: float | None = None
    files: Mapping[str, Path] = field(default_factory=dict)

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
        if not (changes or options or self.internal):
            return scene
        return scene.with_internal(self.internal or scene.internal, options=options, **changes)


def file_options() -> list[tuple[str, str]]:
    """(internal, option) of every file option in the registry: each is a command-line flag."""
    return [(spec.name, o.name) for spec in registry.REGISTRY.values() for o in spec.file_options()]


def load_with_overrides(path, overrides: SceneOverrides | None = None) -> Scene:
    """``load_scene(path)`` with ``overrides`` applied."""
    scene = load_scene(path)
    return overrides.apply(scene) if overrides is not None else scene


__all__ = ["SceneOverrides", "file_options", "load_with_overrides"]
