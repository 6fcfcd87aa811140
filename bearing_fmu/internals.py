"""The one protocol every bearing internal follows, and the state checks they share.

An internal computes the film force on the journal from its state. Reynolds (the truth),
Taylor (the fitted surrogate) and Linear (8 Lund coefficients) all satisfy it, so the
statics (equilibrium, linearize), the FMU slave and the host treat them alike.
"""

from __future__ import annotations

import math
from typing import Protocol, runtime_checkable

from .params import BearingParams


class BearingStateError(ValueError):
    """A journal state an internal cannot evaluate (non-finite input, journal at the wall)."""


@runtime_checkable
class Internal(Protocol):
    params: BearingParams

    def force(self, y: float, z: float, vy: float, vz: float, omega: float) -> tuple[float, float]:
        """Film force (Fy, Fz) [N] on the journal at displacement (y, z) [m],
        velocity (vy, vz) [m/s] and shaft speed omega [rad/s]."""
        ...


@runtime_checkable
class DifferentiableInternal(Internal, Protocol):
    def force_and_jacobian(self, y: float, z: float, vy: float, vz: float, omega: float):
        """Return (F, dF_dq, dF_dv): F = (Fy, Fz) [N] as an array of shape (2,), and the raw
        derivatives dF_dq[i, j] = dF_i/dq_j [N/m] with q = (y, z) and dF_dv[i, j] = dF_i/dv_j
        [N s/m] with v = (vy, vz), each of shape (2, 2). Lund's coefficients are their negatives."""
        ...


def check_state(params: BearingParams, y: float, z: float, vy: float, vz: float, omega: float) -> float:
    """Raise BearingStateError naming the variable for a non-finite input, or stating the
    eccentricity ratio when the journal is at or beyond the wall. Returns the eccentricity ratio."""
    for name, value in (("y", y), ("z", z), ("vy", vy), ("vz", vz), ("omega", omega)):
        if not math.isfinite(value):
            raise BearingStateError(f"bearing input {name} = {value!r} is not finite")
    eps = math.hypot(y, z) / params.CR
    if eps >= 1.0:
        raise BearingStateError(
            f"eccentricity ratio {eps:.4g} >= 1: the journal (y = {y:.4g} m, z = {z:.4g} m) "
            f"is at or beyond the bearing wall (CR = {params.CR:.4g} m)"
        )
    return eps
