"""Compiled kernels loaded before a clock starts, not at the first step it times.

A numba kernel compiled with ``cache=True`` is loaded from its disk cache at its first call:
the first call in a process also initialises numba's compiler context (~0.2 s) and each kernel
costs a few ms more. A timed loop would count that as work. ``load_cached`` loads, without
calling them, every overload of a module's kernels that its disk cache holds for this machine,
so the calls that follow find them loaded. Which modules an internal's evaluation needs is its
registry entry's ``kernels`` (``warm_internal``); the host loads its integrator's the same way.

A kernel that has no cache entry yet (a fresh checkout, a changed source) is compiled at its
first call as before, and cached for the next process.
"""

from __future__ import annotations

import importlib
import sys
from types import ModuleType

_LOADED: set[str] = set()  # modules whose cache this process has loaded (a worker's later runs skip them)


def load_cached(module: ModuleType | str) -> int:
    """Load every overload of ``module``'s public numba kernels (cache=True) that the disk cache
    holds for this machine and this source; returns how many were loaded. Once per module and
    process. A private kernel (``_name``) is skipped: the kernels calling it carry its code."""
    module = importlib.import_module(module) if isinstance(module, str) else module
    if module.__name__ in _LOADED:
        return 0
    from numba.core.dispatcher import Dispatcher

    n = 0
    for name, obj in list(vars(module).items()):
        cache = getattr(obj, "_cache", None)
        if name.startswith("_") or not isinstance(obj, Dispatcher) or getattr(cache, "_cache_file", None) is None:
            continue  # a private helper (its callers' compiled code holds it), not a kernel, or no disk cache
        codegen = obj.targetctx.codegen()  # the first also initialises numba's compiler context
        try:  # numba's cache index (not public API): (signature, machine, source hashes) -> file
            keys = [k for k in cache._cache_file._load_index() if k == cache._index_key(k[0], codegen)]
        except (AttributeError, TypeError, ValueError):  # another numba: loaded at the first call, as before
            continue  # (tests/test_fixed_costs.py fails then: warm_internal loads nothing)
        for key in keys:
            if tuple(key[0]) not in obj.overloads:
                obj.compile(key[0])  # found in the cache: loaded, not compiled
                n += 1
    _LOADED.add(module.__name__)
    return n


def load_loaded_under(prefix: str) -> int:
    """``load_cached`` for every module already imported whose name starts with ``prefix``
    (e.g. the host's integrator, ``rotor_host.integrate``: its kernels, whatever their modules)."""
    return sum(load_cached(m) for name, m in list(sys.modules.items())
               if m is not None and (name == prefix or name.startswith(prefix + ".")))


def warm_internal(name: str) -> int:
    """Load the compiled kernels of internal ``name`` (its registry entry's ``kernels``)."""
    from .registry import get

    return sum(load_cached(importlib.import_module(f"..{ref}", __package__)) for ref in get(name).kernels)


__all__ = ["load_cached", "load_loaded_under", "warm_internal"]
