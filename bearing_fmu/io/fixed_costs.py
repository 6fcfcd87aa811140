"""A command's fixed costs, timed apart from its work and printed in one line.

What a command pays once whatever its size (imports, loading or compiling the kernels, building
or extracting an FMU, starting worker processes or a cluster) is not the work the user asked
for; a short command can be mostly the former. ``FixedCosts`` collects the named parts in the
order they happen (``timed`` around a block, ``add`` for seconds measured elsewhere, e.g. in a
worker) and ``line`` prints them beside the work:

    fixed costs 1.42 s (imports 0.61 s, kernels 0.35 s, pool start (2 workers) 0.05 s); work 1.52 s

``as_dict`` gives the same figures [s] for a command's JSON. Parts measured at the same time
(a build in a thread while the workers start) are each their own wall time, so the total is
an upper bound of what they cost together; the line says so when told (``overlapping``).

A command line's own costs: ``watch_command()`` starts, once per process, the clock of a command
and one process-wide ``FixedCosts`` that the parts are added to wherever they happen: every
module import (``imports``: its outermost exec, in the main thread) and every numba kernel load
or compilation (``kernels``: the time numba holds its compiler lock, whichever kernel), timed
from then on; what the command's code adds by name (FMU builds and extraction: ``command_mark``,
``command_add_since``: the parts timed inside left out).
``command_line()`` is the one line a command prints at its end: the parts beside the work (the
command's wall time less the parts). A kernel loaded while a module is imported (a cfunc at
import) counts as kernels, not imports.
"""

from __future__ import annotations

import sys
import threading
import time
from contextlib import contextmanager
from importlib.abc import MetaPathFinder


class FixedCosts:
    """Named fixed costs of one command [s], in the order first recorded."""

    def __init__(self) -> None:
        self.parts: dict[str, float] = {}
        self.overlapping: set[str] = set()

    def add(self, name: str, seconds: float | None, *, overlapping: bool = False) -> None:
        """Add ``seconds`` to the part ``name`` (None: nothing); ``overlapping``: measured while
        another part ran (not added to the total)."""
        if seconds is None:
            return
        self.parts[name] = self.parts.get(name, 0.0) + max(float(seconds), 0.0)
        if overlapping:
            self.overlapping.add(name)

    @contextmanager
    def timed(self, name: str):
        """Time the block's wall time as the part ``name`` (also when it raises)."""
        t0 = time.perf_counter()
        try:
            yield
        finally:
            self.add(name, time.perf_counter() - t0)

    @property
    def total_s(self) -> float:
        """The parts' sum [s], those measured while another ran left out."""
        return sum(s for k, s in self.parts.items() if k not in self.overlapping)

    def as_dict(self) -> dict:
        return {**{k: round(v, 4) for k, v in self.parts.items()}, "total": round(self.total_s, 4)}

    def line(self, work_s: float | None = None, work: str = "", min_s: float = 0.005) -> str:
        """``fixed costs T s (part s, ...)[; work W s (what)]``; parts under ``min_s`` left out."""
        shown = [f"{k} {v:.2f} s" + (" (meanwhile)" if k in self.overlapping else "")
                 for k, v in self.parts.items() if v >= min_s]
        text = f"fixed costs {self.total_s:.2f} s" + (f" ({', '.join(shown)})" if shown else "")
        if work_s is not None:
            text += f"; work {work_s:.2f} s" + (f" ({work})" if work else "")
        return text


class _Watch(MetaPathFinder):
    """Times imports (a meta-path finder that wraps the found loader's exec_module, as
    ``internals.warmup``'s does) and numba's compiler lock (an event listener), into ``costs``."""

    def __init__(self, costs: FixedCosts):
        self.costs = costs
        self.t0 = time.perf_counter()
        self.finding = False
        # the parts open now, innermost last: [name, start, seconds of the parts closed inside it]
        self.stack: list[list] = []
        self.recorded = 0.0  # seconds of all outermost parts closed so far (``since``)
        self.numba_listening = False

    # imports
    def find_spec(self, fullname, path=None, target=None):
        if self.finding or threading.current_thread() is not threading.main_thread():
            return None
        self.finding = True
        try:
            spec = None
            for finder in sys.meta_path:
                find = getattr(finder, "find_spec", None)
                if finder is self or find is None:
                    continue
                spec = find(fullname, path, target)
                if spec is not None:
                    break
        finally:
            self.finding = False
        loader = getattr(spec, "loader", None)
        if loader is None or not hasattr(loader, "exec_module"):
            return spec
        load = loader.exec_module

        def exec_module(module):
            with self._part("imports"):
                load(module)
            if fullname == "numba" and not self.numba_listening:
                self._listen()

        try:
            loader.exec_module = exec_module
        except (AttributeError, TypeError):  # a loader that takes no attribute: not timed
            pass
        return spec

    @contextmanager
    def _part(self, name: str):
        """Time the block as part ``name``, less the parts inside it (a kernel loaded while a
        module is imported counts as kernels, not imports: nothing is counted twice)."""
        self.stack.append([name, time.perf_counter(), 0.0])
        try:
            yield
        finally:
            self._close()

    def _close(self) -> None:
        name, t0, inner = self.stack.pop()
        spent = time.perf_counter() - t0
        self.costs.add(name, spent - inner)
        if self.stack:
            self.stack[-1][2] += spent
        else:
            self.recorded += spent

    # numba's kernels
    def _listen(self) -> None:
        from numba.core import event

        watch = self
        self.numba_listening = True

        class Lock(event.Listener):  # the lock is re-entrant: only the outermost hold is a part
            depth = 0

            def on_start(self, ev):
                if threading.current_thread() is threading.main_thread():
                    self.depth += 1
                    if self.depth == 1:
                        watch.stack.append(["kernels", time.perf_counter(), 0.0])

            def on_end(self, ev):
                if threading.current_thread() is threading.main_thread() and self.depth > 0:
                    self.depth -= 1
                    if self.depth == 0 and watch.stack and watch.stack[-1][0] == "kernels":
                        watch._close()

        event.register("numba:compiler_lock", Lock())


_WATCH: list[_Watch] = []


def watch_command() -> FixedCosts:
    """Start timing a command in this process: its clock and fresh costs, to which its imports
    and kernel loads from now on are added, and the parts code adds to ``command_costs()`` (the
    watcher is installed once per process; a later command starts afresh)."""
    if not _WATCH:
        watch = _Watch(FixedCosts())
        _WATCH.append(watch)
        sys.meta_path.insert(0, watch)
        if hasattr(sys.modules.get("numba"), "njit"):
            watch._listen()
    watch = _WATCH[0]
    watch.costs, watch.t0 = FixedCosts(), time.perf_counter()
    return watch.costs


def command_costs() -> FixedCosts | None:
    """The process's command costs (``watch_command``), or None when no command is timed (a
    library call, a test): code that pays a fixed cost adds its part here when there is one."""
    return _WATCH[0].costs if _WATCH else None


def command_mark():
    """A mark for ``command_add_since`` (None when no command is timed)."""
    return (time.perf_counter(), _WATCH[0].recorded, _WATCH[0].costs) if _WATCH else None


def command_add_since(name: str, mark) -> None:
    """Add the wall time since ``mark`` to the command's part ``name``, less the imports and
    kernel loads timed meanwhile (each counted once, under its own name)."""
    if mark is None or not _WATCH or _WATCH[0].costs is not mark[2]:
        return
    t0, recorded, costs = mark
    costs.add(name, time.perf_counter() - t0 - (_WATCH[0].recorded - recorded))


def command_line() -> str:
    """The command's fixed costs beside its work: ``fixed costs T s (imports .., kernels .., ...);
    work W s``, W the wall time since ``watch_command`` less T."""
    watch = _WATCH[0] if _WATCH else _Watch(FixedCosts())
    total = time.perf_counter() - watch.t0
    return watch.costs.line(max(total - watch.costs.total_s, 0.0))


__all__ = ["FixedCosts", "watch_command", "command_costs", "command_mark", "command_add_since", "command_line"]
