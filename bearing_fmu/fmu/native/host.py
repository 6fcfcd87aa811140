"""What a host sets on a native FMU: the parameters of one bearing, from the internal's options.

The native FMU keeps the options that make sense without Python (each internal's catalogue entry,
``catalogue.NATIVE``: taylor's surrogate, domain_action, domain_limit; map's map; linear's
omega_lin and lin_*; reynolds's n_theta, n_x and cavitation). The linear model is made here, per
bearing (its static load differs), by the Python ``Linear`` internal, and handed to the FMU as
its coefficients (its entry's ``host_values``)."""

from __future__ import annotations

from ...internals import registry
from .catalogue import companions, native_spec


def fmu_internals(internal: str, options: dict) -> str:
    """The internals of the native FMU a host builds for ``internal`` with its registry ``options``:
    its own and its companions (Taylor with domain_action = fallback holds the Reynolds internal too:
    it falls back to it)."""
    return ",".join((internal, *companions(native_spec(internal), options)))


def host_build_options(internal: str) -> dict | None:
    """Build options of a native FMU that a host sets up per bearing (the linear model's
    coefficients are set by the host, ``native_parameters``, so its build linearises nothing)."""
    build = native_spec(internal).host_build
    return dict(build) if build is not None else None


def native_parameters(internal: str, params, options: dict, context=None, where: str = "") -> dict:
    """FMU parameters of one bearing for a native FMU of ``internal``: D, L, CR, mu, internal and
    the native options, from the registry ``options`` of the internal (and those it uses), with
    ``context`` (static load, speed) filling what the options leave open (Taylor with
    domain_action = fallback: the Reynolds options too, its FMU holds both: ``fmu_internals``).
    ValueError naming ``where`` for options the internal refuses, or an internal without a native
    C model (and why: ``catalogue.native_spec``)."""
    spec = registry.get(internal)
    native = native_spec(spec, where)
    opts = spec.check_options(options, where or f"internal {spec.name!r}", context=context)
    out = {"D": params.D, "L": params.L, "CR": params.CR, "mu": params.mu, "internal": spec.name}
    for held in (native, *(native_spec(n) for n in companions(native, opts))):
        out.update(held.parameters(params, opts, options, context))
    return out
