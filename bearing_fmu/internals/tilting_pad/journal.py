"""The journal's static equilibrium on tilting pads: where the film force of the pads (massless, in
moment equilibrium) balances a static load. Its own Newton and not ``physics.statics.equilibrium``'s,
whose steps keep the journal inside the bearing's clearance circle: between pads the journal may pass
C_bearing, and the wall is each pad's film (a step is halved until every pad's film stays open)."""

from __future__ import annotations

import math

import numpy as np

from ...physics.statics import EquilibriumError
from ..base import BearingStateError

NEWTON_MAX = 80


def journal_equilibrium(bearing, load, omega: float, rtol: float = 1e-9, start=None) -> tuple[float, float]:
    """(y0, z0) [m] where the film force of the pads of ``bearing`` (a ``TiltingPad``, its pads in moment
    equilibrium) balances ``load`` = (Wy, Wz) [N]: Newton with the quasi-static Jacobian from ``start``
    (y, z) [m] (None: 0.2 C_bearing along the load), each step halved until every pad's film stays open
    and the residual falls."""
    load = np.asarray(load, float)
    w = float(np.hypot(*load))
    if w == 0.0:
        return 0.0, 0.0
    # from 0.2 C_bearing along the load: a centred journal on unpreloaded pads has no film force and
    # no stiffness to start Newton from
    q = 0.2 * bearing.params.CR * load / w if start is None else np.array(start, float)

    def residual(x):
        return np.asarray(bearing.force(x[0], x[1], 0.0, 0.0, omega)) + load

    r = residual(q)
    for _ in range(NEWTON_MAX):
        rn = float(np.hypot(*r))
        if rn <= rtol * w:
            return float(q[0]), float(q[1])
        _, dq, _ = bearing.force_and_jacobian(q[0], q[1], 0.0, 0.0, omega)
        try:
            step = -np.linalg.solve(dq, r)
        except np.linalg.LinAlgError:
            break
        alpha = 1.0
        while alpha > 1e-8:
            trial = q + alpha * step
            try:
                r_trial = residual(trial)
            except BearingStateError:
                alpha *= 0.5
                continue
            if float(np.hypot(*r_trial)) < (1.0 - 1e-4 * alpha) * rn:
                break
            alpha *= 0.5
        else:
            break
        q, r = trial, r_trial
    raise EquilibriumError(f"equilibrium: the tilting pads ({bearing.pads.pads.describe()}) found no static "
                           f"equilibrium under the load {load.tolist()} N at omega = {omega:.4g} rad/s (residual "
                           f"{np.hypot(*r):.3g} N at y = {q[0]:.4g} m, z = {q[1]:.4g} m)",
                           bearing="tilting pads", load_N=w, capacity_N=math.nan, speed_hz=omega / (2 * math.pi))


__all__ = ["journal_equilibrium"]
