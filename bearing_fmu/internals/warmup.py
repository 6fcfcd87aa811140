"""Compiled kernels loaded before a clock starts, not at the first step it times.

A numba kernel compiled with ``cache=True`` is loaded from its disk cache at its first call:
the first call in a process also initialises numba's compiler context (~0.2 s) and each kernel
costs a few ms more. A timed loop would count that as work. ``load_cached`` loads, without
calling them, every overload of a module's kernels that its disk cache holds for this machine,
so the calls that follow find them loaded. Which modules an internal's evaluation needs is its
registry entry's ``kernels`` (``warm_internal``); the host loads its integrator's the same way.

A kernel that has no cache entry yet (a fresh installation, a changed source) is compiled at its
first call, and cached for the next process. That first compilation takes a while (the Reynolds
kernel: ~8 s on an idle core, up to a minute on a busy machine), so ``announce_compiling`` says
so, once per process, on stderr or the FMU's log: numba's "numba:compile" event fires only when
a kernel is not found in its disk cache, so a warm installation never prints it.
"""

from __future__ import annotations

import importlib
import importlib.util
import sys
import threading
import time
from importlib.abc import MetaPathFinder
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


# what a first compilation costs (docs/studies/2026-12-06-first-command.md): the Reynolds kernel, the one
# the demo, stability and a Reynolds run compile, 7.5 s on an idle core, 15-50 s on 2 busy cores
NOTICE = ("compiling the bearing kernels, once per installation: about 8 s (up to a minute on a busy machine; "
          "later commands load them from numba's cache)")
KERNEL_PACKAGES = (__name__.split(".")[0], "rotor_host")  # this package (also its copy in a Python FMU) and the host
# set on the sys module once the notice is on stderr: shared by every copy of this module in the process
# (a Python FMU's bundled copy of the package), so a command's FMU does not say it again
SAID = "bearing_fmu_compile_notice_said"


class CompileNotice:
    """A numba "numba:compile" listener: the first kernel of ``packages`` that numba compiles
    (a cache miss) is announced once by ``write``; while a kernel compiles and ``ticking``, a
    line on stderr counts the seconds (a terminal's progress). Nested compilations (a kernel's
    callees) count as their caller's."""

    def __init__(self, write, packages=KERNEL_PACKAGES, ticking: bool = False):
        self.write, self.packages, self.ticking = write, tuple(packages), ticking
        self.said = False
        self._depth = 0
        self._stop: threading.Event | None = None

    def notify(self, event) -> None:
        (self.on_start if event.is_start else self.on_end)(event)

    def on_start(self, event) -> None:
        self._depth += 1
        if self._depth > 1:
            return
        func = getattr((event.data or {}).get("dispatcher"), "py_func", None)
        if func is None or not func.__module__.startswith(self.packages):
            return
        if not self.said:
            self.said = True
            if self.write is not _to_stderr or not getattr(sys, SAID, False):
                if self.write is _to_stderr:
                    setattr(sys, SAID, True)
                self.write(NOTICE)
        if self.ticking:
            self._stop = threading.Event()
            threading.Thread(target=self._tick, args=(func.__name__, self._stop), daemon=True).start()

    def on_end(self, event) -> None:
        self._depth = max(self._depth - 1, 0)
        if self._depth == 0 and self._stop is not None:
            self._stop.set()
            self._stop = None

    @staticmethod
    def _tick(name: str, stop: threading.Event) -> None:
        t0 = time.monotonic()
        while not stop.wait(1.0):
            print(f"\r  compiling {name}: {time.monotonic() - t0:.0f} s", end="", file=sys.stderr, flush=True)
        if time.monotonic() - t0 >= 1.0:
            print(f"\r  compiled {name} in {time.monotonic() - t0:.0f} s", file=sys.stderr, flush=True)


_ON_STDERR: list[CompileNotice] = []  # the process's notice on stderr (one, whoever asks)


def _to_stderr(line: str) -> None:
    print(line, file=sys.stderr, flush=True)


def _listen(notice: CompileNotice) -> None:
    """Register ``notice`` for numba's compile events (numba imported)."""
    from numba.core import event

    class Forward(event.Listener):
        def on_start(self, ev):
            notice.on_start(ev)

        def on_end(self, ev):
            notice.on_end(ev)

    event.register("numba:compile", Forward())


class _AfterImport(MetaPathFinder):
    """Run ``then()`` once ``name`` has been imported (first import only), without importing it:
    an FMU of an internal without kernels never loads numba."""

    def __init__(self, name: str, then):
        self.name, self.then = name, then

    def find_spec(self, fullname, path=None, target=None):
        if fullname != self.name or self not in sys.meta_path:
            return None
        sys.meta_path.remove(self)  # one shot; the other finders find the module
        spec = importlib.util.find_spec(fullname)
        if spec is None or spec.loader is None or not hasattr(spec.loader, "exec_module"):
            return spec
        load, then = spec.loader.exec_module, self.then

        def exec_module(module):
            load(module)
            then()

        spec.loader.exec_module = exec_module
        return spec


def announce_compiling(write=None, packages=KERNEL_PACKAGES) -> CompileNotice:
    """From now on, in this process, announce the first compilation of a kernel of ``packages``
    by ``write(line)``; default: one line on stderr, once per process, and the seconds counted
    while a kernel compiles when stderr is a terminal. Never on stdout. Does not import numba:
    listens from numba's import on if it is not loaded yet."""
    if write is None:
        if _ON_STDERR:
            return _ON_STDERR[0]
        notice = CompileNotice(_to_stderr, packages, ticking=sys.stderr is not None and sys.stderr.isatty())
        _ON_STDERR.append(notice)
    else:
        notice = CompileNotice(write, packages)
    if hasattr(sys.modules.get("numba"), "njit"):
        _listen(notice)
    else:
        sys.meta_path.insert(0, _AfterImport("numba", lambda: _listen(notice)))
    return notice


__all__ = ["load_cached", "load_loaded_under", "warm_internal", "announce_compiling", "CompileNotice", "NOTICE"]
