"""The native FMU's catalogue: one ``NativeSpec`` per internal it has a C model of, beside the
internal's ``InternalSpec`` (``internals.registry``), keyed by the same name.

A ``NativeSpec`` says everything the native back end needs of one internal, so the build, the
code generator and the host ask it and never branch on a name: the C files it compiles
(``c/internal_<name>.c`` and its units, those of its film report), its options (the registry's
that the native FMU keeps as parameters), its data and start values (``model``: a generator in
``generators/``, named "module:function" and imported when used), the bore it takes, whether its force
depends on the bearing and the speed, what it refuses, what a host sets on it. As the FMI Reference
FMUs keep one folder per model, each generator is a module of its own in ``generators/``.

``native_spec(name)`` is the one way in: an internal without a C model is refused with the right
reason (registered from outside the package, or a package internal the native FMU does not
compile, or no internal of that name at all).

How to add a native internal: its C model ``c/internal_<name>.c`` (bearing_native.h: bn_setup,
bn_eval, ...), its generator ``generators/<name>.py`` (``<name>_model(params, surrogate, map, options)
-> codegen.NativeModel``), a ``NativeSpec`` here, and ``native=True`` in its registry capabilities.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from ...internals import registry

__all__ = ["NativeSpec", "NATIVE", "native_spec", "names", "companions", "refused_choices"]

_MODELS = "bearing_fmu.fmu.native.generators"


@dataclass(frozen=True)
class NativeSpec:
    """The native C model of one internal.

    name          : the internal's registry name (``registry.get(name)``)
    model         : "module:function" of its generator: (params, surrogate, map, options) -> NativeModel
    options       : the registry options the native FMU keeps, as parameters (the rest stay Python's)
    sources       : the C files compiled for it (its internal_<name>.c first)
    headers       : the headers they include (staged beside them)
    flow_sources  : C files compiled when its data hold the film's flows (its film report, bn_film)
    force_depends : does its force depend on (the bearing: 0 no, 1 by the scale law, 2 and on L/D;
                    the speed: 0, 1) as set? (model_config.h BN_BEARING_IN_FORCE, BN_SPEED_IN_FORCE)
    bore          : "full" (the full bore only), "compiled" (any bore, compiled in) or "data" (its
                    data file's, checked against the bearing's at build)
    own_bearing   : its data file holds the bearing and the speed (the build's bearing defaults
                    to it; in an FMU of several it is every internal's)
    speed_start   : the option the start speed sets (``native_model(omega=...)``), "" when refused:
                    ``speed_why`` says why
    companions    : (option, choice, internal, why): with that choice the FMU holds that internal
                    too (Taylor's domain_action = fallback: the Reynolds internal); without it the
                    choice is refused, ``why`` saying so
    alone_why     : why an FMU of several internals cannot hold it ("" when it can)
    host_build    : the build options of the FMU a host builds once for every bearing
    host_values   : "module:function" (params, options, context) -> its FMU parameters per bearing,
                    when they are not its checked options as they are (linear: the coefficients)
    """

    name: str
    model: str
    options: tuple[str, ...]
    sources: tuple[str, ...]
    headers: tuple[str, ...] = ()
    flow_sources: tuple[str, ...] = ()
    force_depends: tuple[int, int] = (1, 1)
    bore: str = "full"
    own_bearing: bool = False
    speed_start: str = "_omega"
    speed_why: str = ""
    companions: tuple[tuple[str, str, str, str], ...] = ()
    alone_why: str = ""

    @property
    def memoryless(self) -> bool:
        """Its outputs follow the inputs and parameters alone (``Capabilities.memoryless``)."""
        return registry.get(self.name).can.memoryless
    host_build: dict | None = None
    host_values: str = ""

    @property
    def film_report(self) -> bool:
        """Has a film report in C (bn_film: the thermal model's friction and flows)."""
        return bool(self.flow_sources)

    def build(self, params, surrogate, map_path, options: dict):
        """Its ``NativeModel`` (the generator's, ``model``)."""
        return _resolve(self.model)(params, surrogate, map_path, options)

    def parameters(self, params, checked: dict, options: dict, context=None) -> dict:
        """What a host sets on its FMU for one bearing: its options as ``checked`` (a data file
        by its name: the FMU holds it), or ``host_values``'s."""
        if self.host_values:
            return _resolve(self.host_values)(params, options, context)
        files = {o.name for o in registry.get(self.name).file_options()}
        return {n: Path(checked[n]).name if n in files else checked[n] for n in self.options}


def _resolve(ref: str) -> Callable:
    module, _, function = ref.partition(":")
    return getattr(importlib.import_module(module), function)


_FALLBACK_WHY = ("the fallback evaluates the Reynolds solver, which this native FMU does not hold; build one with it "
                 "(bearing-fmu build --native --internal taylor,reynolds), use warn or discard, or the Python FMU")

NATIVE: dict[str, NativeSpec] = {s.name: s for s in (
    NativeSpec("linear", f"{_MODELS}.linear:linear_model",
               ("omega_lin", "lin_y0", "lin_z0", "lin_Fy0", "lin_Fz0", "lin_Kyy", "lin_Kyz", "lin_Kzy", "lin_Kzz",
                "lin_Cyy", "lin_Cyz", "lin_Czy", "lin_Czz"),
               ("internal_linear.c",), force_depends=(0, 0), speed_start="omega_lin",
               host_build={"linear_from": "coefficients"}, host_values=f"{_MODELS}.linear:linear_starts"),
    NativeSpec("map", f"{_MODELS}.map:map_model", ("map",), ("internal_map.c",),
               ("py_mod.h", "film_friction.h", "map_spline.h", "map_arc.h"), ("map_flows.c",), force_depends=(1, 1),
               bore="data"),
    NativeSpec("taylor", f"{_MODELS}.taylor:taylor_model", ("surrogate", "domain_action", "domain_limit"),
               ("internal_taylor.c",), ("film_friction.h", "taylor_internal.h"), ("taylor_film.c",),
               force_depends=(0, 0), own_bearing=True, speed_start="",
               speed_why="a native taylor FMU's omega starts at the surrogate's speed (it refuses any other): give "
                         "no speed",
               companions=(("domain_action", "fallback", "reynolds", _FALLBACK_WHY),)),
    NativeSpec("reynolds", f"{_MODELS}.reynolds:reynolds_model", ("n_theta", "n_x", "cavitation"),
               ("internal_reynolds.c", "reynolds_solver.c", "reynolds_kernels.c", "reynolds_peak.c"),
               ("py_mod.h", "reynolds_solver.h", "film_friction.h"), ("reynolds_film.c",), force_depends=(2, 1),
               bore="compiled"),
    NativeSpec("tilting_pad", f"{_MODELS}.tilting_pad:tilting_pad_model", ("n_theta", "n_x", "cavitation", "pad_map"),
               ("internal_tilting_pad.c", "reynolds_solver.c", "reynolds_kernels.c"),
               ("py_mod.h", "reynolds_solver.h", "film_friction.h", "map_spline.h", "map_arc.h", "pad_map.h"),
               # its film report (bn_film: each pad's reynolds_film.c report summed) where the Python
               # internal has one (TiltingPad.film_report, Capabilities.film_flow)
               ("reynolds_film.c",) if registry.get("tilting_pad").can.film_flow else (),
               force_depends=(2, 1), bore="compiled",
               alone_why="its pads' variables and continuous states are its own: build a native FMU of it alone"),
)}


def names() -> tuple[str, ...]:
    """The internals a native FMU can compute."""
    return tuple(NATIVE)


def native_spec(internal, where: str = "") -> NativeSpec:
    """The native model of ``internal`` (a name or an ``InternalSpec``); ValueError naming
    ``where`` and the reason a native FMU cannot compute it."""
    name = str(getattr(internal, "name", internal)).strip().lower()
    if name in NATIVE:
        return NATIVE[name]
    head = f"{where}: " if where else ""
    if name not in registry.names():
        raise ValueError(f"{head}no internal {name!r}: a native FMU computes one of {', '.join(NATIVE)}")
    spec = registry.get(name)
    if callable(spec.factory):  # registered by a caller: the package's C models know nothing of it
        raise ValueError(f"{head}internal {name!r} is registered from outside the package, and a native FMU "
                         f"compiles the package's C models only ({', '.join(NATIVE)}): use the Python FMU "
                         "(`bearing-fmu build`), which runs any registered internal")
    raise ValueError(f"{head}the {name} internal has no native C model (a native FMU computes one of "
                     f"{', '.join(NATIVE)}): use the Python FMU (`bearing-fmu build`)")


def companions(spec: NativeSpec, options: dict) -> tuple[str, ...]:
    """The internals an FMU of ``spec`` holds besides, for these registry ``options``."""
    return tuple(need for option, choice, need, _why in spec.companions if options.get(option) == choice)


def refused_choices(parts) -> dict[str, tuple[str, str]]:
    """{option: (choice, why)} of the choices the FMU holding ``parts`` refuses: a companion's
    choice without its companion internal."""
    return {option: (choice, why) for p in parts for option, choice, need, why in NATIVE[p].companions
            if need not in parts}
