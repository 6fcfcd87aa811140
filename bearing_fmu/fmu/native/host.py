"""What a host sets on a native FMU: the parameters of one bearing, from the internal's options.

The native FMU keeps the options that make sense without Python (``codegen.NATIVE_OPTIONS``):
taylor's surrogate, domain_action, domain_limit; map's map; linear's omega_lin and lin_*;
reynolds's n_theta, n_x and cavitation.
The linear model is made here, per bearing (its static load differs), by the Python ``Linear``
internal, and handed to the FMU as its coefficients."""

from __future__ import annotations

from pathlib import Path

from ...internals import registry
from .codegen import INTERNALS, linear_starts


def fmu_internals(internal: str, options: dict) -> str:
    """The internals of the native FMU a host builds for ``internal`` with its registry ``options``:
    Taylor with domain_action = fallback holds the Reynolds internal too (it falls back to it)."""
    return f"{internal},reynolds" if internal == "taylor" and options.get("domain_action") == "fallback" else internal


def host_build_options(internal: str) -> dict | None:
    """Build options of a native FMU that a host sets up per bearing: the linear model's
    coefficients are set by the host (``native_parameters``), so its build linearises nothing."""
    return {"linear_from": "coefficients"} if internal == "linear" else None


def native_parameters(internal: str, params, options: dict, context=None, where: str = "") -> dict:
    """FMU parameters of one bearing for a native FMU of ``internal``: D, L, CR, mu, internal and
    the native options, from the registry ``options`` of the internal (and those it uses), with
    ``context`` (static load, speed) filling what the options leave open (Taylor with
    domain_action = fallback: the Reynolds options too, its FMU holds both: ``fmu_internals``).
    ValueError naming ``where`` for options the internal refuses."""
    spec = registry.get(internal)
    if spec.name not in INTERNALS:
        raise ValueError(f"{where + ': ' if where else ''}a native FMU computes one of {', '.join(INTERNALS)}, not "
                         f"{spec.name} (an internal registered from outside the package: use the Python FMU)")
    opts = spec.check_options(options, where or f"internal {spec.name!r}", context=context)
    out = {"D": params.D, "L": params.L, "CR": params.CR, "mu": params.mu, "internal": spec.name}
    if spec.name == "taylor":
        out.update(surrogate=Path(opts["surrogate"]).name, domain_action=opts["domain_action"],
                   domain_limit=opts["domain_limit"])
        if opts["domain_action"] == "fallback":  # the FMU holds the Reynolds internal too (fmu_internals)
            out.update(n_theta=opts["n_theta"], n_x=opts["n_x"], cavitation=opts["cavitation"])
    elif spec.name == "map":
        out["map"] = Path(opts["map"]).name
    elif spec.name == "reynolds":
        out.update(n_theta=opts["n_theta"], n_x=opts["n_x"], cavitation=opts["cavitation"])
    else:
        out.update(linear_starts(params, options, context))
    return out
