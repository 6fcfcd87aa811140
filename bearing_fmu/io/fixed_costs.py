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
"""

from __future__ import annotations

import time
from contextlib import contextmanager


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


__all__ = ["FixedCosts"]
