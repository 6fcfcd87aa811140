"""External forces the compiled Newmark loop can evaluate itself: static loads plus unbalances
turning at a constant speed.

``RotatingLoads`` is a plain callable f_ext(t) for the integrator (``rotor_host.integrate.newmark``)
and also hands its numbers to the compiled loop (``arrays``), which evaluates the same formula
per step with no Python call (``rotating_loads`` below, shared by both so they agree to the bit).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["RotatingLoads", "rotating_loads"]


@njit(cache=True)
def rotating_loads(f_static, idx, par, t, out):
    """out = f_static + each unbalance switched on at t: m r Omega^2 (cos, sin)(Omega t + phase)
    at its (y, z) DOFs; idx (p, 2) the DOFs, par (p, 4) = m r [kg m], phase [rad], t_on [s],
    Omega [rad/s]."""
    for i in range(out.size):
        out[i] = f_static[i]
    for k in range(idx.shape[0]):
        mr, ph, t_on, om = par[k, 0], par[k, 1], par[k, 2], par[k, 3]
        if t >= t_on:
            a = om * t + ph
            amp = mr * om * om
            out[idx[k, 0]] += amp * math.cos(a)
            out[idx[k, 1]] += amp * math.sin(a)


class RotatingLoads:
    """f_ext(t) = f_static + the unbalances, each (dof_y, dof_z, m r [kg m], phase [rad],
    t_on [s]) at the constant speed omega [rad/s]. Calls return one reused buffer (n,)."""

    def __init__(self, f_static, unbalances=(), omega: float = 0.0):
        self.f_static = np.ascontiguousarray(np.asarray(f_static, dtype=float).reshape(-1))
        self.idx = np.array([(int(iy), int(iz)) for iy, iz, *_ in unbalances], dtype=np.int64).reshape(-1, 2)
        self.par = np.array([(float(mr), float(ph), float(t_on), float(omega)) for _, _, mr, ph, t_on in unbalances],
                            dtype=np.float64).reshape(-1, 4)
        self._out = np.empty_like(self.f_static)

    def __call__(self, t: float) -> np.ndarray:
        rotating_loads(self.f_static, self.idx, self.par, float(t), self._out)
        return self._out

    def arrays(self):
        """(f_static, idx, par) as ``rotating_loads`` takes them."""
        return self.f_static, self.idx, self.par
