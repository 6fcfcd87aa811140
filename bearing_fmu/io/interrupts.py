"""Interrupts (SIGINT, SIGTERM) as a Python exception, and the blocks that hold them.

``handled()`` turns SIGINT and SIGTERM into :class:`Interrupted` (a ``KeyboardInterrupt``, so
``except Exception`` never swallows it) raised in the main thread. Code that calls into a foreign
layer that must not see a Python exception -- a bearing FMU built with pythonfmu runs its Python
slave in this same interpreter, and an exception raised there comes back as an FMI error status,
not as the interrupt -- wraps the call in ``deferred()``: a signal arriving inside is held and
raised by ``check()`` (or at the end of the block) in the caller's code. So does a few lines'
bookkeeping that must not be cut in half (a result name's lock created and registered:
``outputs.claim``). Whoever catches ``Interrupted`` writes what was computed, says so
(``note_kept`` / ``note_lost``) and re-raises; ``exits.run_command`` maps it to an exit code.
"""

from __future__ import annotations

import contextlib
import signal
import threading

SIGNALS = (signal.SIGINT, signal.SIGTERM)


class Interrupted(KeyboardInterrupt):
    """The run was stopped by a signal; ``signum`` says which."""

    def __init__(self, signum: int = signal.SIGINT):
        self.signum = int(signum)
        super().__init__(self.signal_name)

    @property
    def signal_name(self) -> str:
        return signal.Signals(self.signum).name

    @property
    def exit_code(self) -> int:
        return 128 + self.signum


def note_kept(exc: BaseException, what: str) -> None:
    """Record on an interrupt what was written before it went on (``run_command`` prints it)."""
    kept = getattr(exc, "kept", None)
    if kept is None:
        kept = exc.kept = []
    kept.append(what)


def note_lost(exc: BaseException, what: str) -> None:
    """Record on an interrupt what had been computed but could not be kept (a map needs all its
    rows), so the last line does not say that nothing had been computed."""
    lost = getattr(exc, "lost", None)
    if lost is None:
        lost = exc.lost = []
    lost.append(what)


def as_interrupted(exc: BaseException) -> Interrupted:
    """A plain KeyboardInterrupt (Ctrl-C without ``handled()``) is a SIGINT."""
    return exc if isinstance(exc, Interrupted) else Interrupted(signal.SIGINT)


_defer_depth = 0
_pending: int | None = None
_installed = 0


def _handler(signum, frame):
    global _pending
    if _defer_depth > 0:
        _pending = signum  # raised by check() once the foreign call has returned
        return
    raise Interrupted(signum)


@contextlib.contextmanager
def handled():
    """SIGINT and SIGTERM raise Interrupted inside this block (nestable; a no-op outside the
    main thread, where Python cannot install signal handlers)."""
    global _installed
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    old = {s: signal.getsignal(s) for s in SIGNALS} if _installed == 0 else None
    if old is not None:
        for s in SIGNALS:
            signal.signal(s, _handler)
    _installed += 1
    try:
        yield
    finally:
        _installed -= 1
        if old is not None:
            for s, h in old.items():
                signal.signal(s, h)


def check() -> None:
    """Raise the Interrupted a signal left pending during a deferred block."""
    global _pending
    if _pending is not None and _defer_depth == 0:
        signum, _pending = _pending, None
        raise Interrupted(signum)


@contextlib.contextmanager
def deferred():
    """Hold signals while foreign code runs (see the module docstring); raise on leaving."""
    global _defer_depth
    _defer_depth += 1
    try:
        yield
    finally:
        _defer_depth -= 1
    check()


def enter_deferred() -> None:
    """``deferred()`` without the context manager, for hot paths (pair with ``leave_deferred``)."""
    global _defer_depth
    _defer_depth += 1


def leave_deferred() -> None:
    global _defer_depth
    _defer_depth -= 1
    if _pending is not None:
        check()


__all__ = ["SIGNALS", "Interrupted", "note_kept", "note_lost", "as_interrupted", "handled", "check", "deferred",
           "enter_deferred", "leave_deferred"]
