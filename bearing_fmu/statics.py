"""Static equilibrium and linearisation of any bearing internal.

Both work through the internal protocol only (``force``, and ``force_and_jacobian`` where the
internal has it), so they serve Reynolds, the Taylor surrogate and the linear model alike.
"""

from __future__ import annotations

import math

import numpy as np

from .internals import Internal, check_state
from .params import BearingParams
from .shortbearing import short_bearing_eccentricity


class EquilibriumError(RuntimeError):
    """No static equilibrium found: of one bearing for a load and speed (``equilibrium``), or of
    a whole rotor on its bearings (the host's ``equilibrium.static_equilibrium``), which also
    gives ``q`` the last iterate, ``residual`` its residual norm and ``iterations`` the Newton
    iterations done (None, nan, 0 where not known)."""

    def __init__(self, message: str, q: np.ndarray | None = None, residual: float = math.nan,
                 iterations: int = 0):
        super().__init__(message)
        self.q = q
        self.residual = residual
        self.iterations = iterations


def short_bearing_estimate(params: BearingParams, load, omega: float) -> tuple[float, float]:
    """Journal position (y, z) [m] for a static ``load`` (Wy, Wz) [N] from the closed-form
    short-bearing (Ocvirk) theory: a start for Newton, not an answer. The journal sits at the
    Ocvirk eccentricity, turned from the load line by the attitude angle in the direction of
    rotation (``shortbearing.short_bearing_eccentricity``)."""
    wy, wz = float(load[0]), float(load[1])
    w = math.hypot(wy, wz)
    if w == 0.0:
        return 0.0, 0.0
    eps, phi = short_bearing_eccentricity(params, w, omega)
    eps = min(eps, 0.999)
    c, s = math.cos(phi), math.sin(phi)
    ly, lz = wy / w, wz / w
    e = eps * params.CR
    return e * (c * ly - s * lz), e * (s * ly + c * lz)


def film_jacobian(internal: Internal, y: float, z: float, vy: float, vz: float, omega: float,
                  rel_step: float = 1e-5):
    """(F (2,), dF/dq (2, 2), dF/dv (2, 2)) from the internal's own ``force_and_jacobian`` or, for an
    internal without it, central differences with steps rel_step * CR and rel_step * CR * max(|omega|, 1)."""
    fj = getattr(internal, "force_and_jacobian", None)
    if fj is not None:
        f, dq, dv = fj(y, z, vy, vz, omega)
        return np.asarray(f, float), np.asarray(dq, float), np.asarray(dv, float)
    cr = internal.params.CR
    hq = rel_step * cr
    hv = rel_step * cr * max(abs(omega), 1.0)
    x0 = np.array([y, z, vy, vz], float)
    cols = []
    for j, h in enumerate((hq, hq, hv, hv)):
        xp, xm = x0.copy(), x0.copy()
        xp[j] += h
        xm[j] -= h
        fp = np.array(internal.force(*xp, omega))
        fm = np.array(internal.force(*xm, omega))
        cols.append((fp - fm) / (2 * h))
    jac = np.column_stack(cols)
    return np.array(internal.force(y, z, vy, vz, omega), float), jac[:, :2], jac[:, 2:]


def equilibrium(
    internal: Internal,
    load,
    omega: float,
    *,
    rtol: float = 1e-8,
    max_iter: int = 60,
    start: tuple[float, float] | None = None,
) -> tuple[float, float]:
    """Journal position (y0, z0) [m] where the film force balances the static external load
    ``load = (Wy, Wz)`` [N] on the journal (weight is ``(0, -W)``) at speed ``omega`` [rad/s]:
    F(y0, z0, 0, 0, omega) + load = 0 with |residual| <= rtol * |load|.

    Newton with the film Jacobian from the short-bearing start, each step backtracked so that
    the eccentricity ratio stays below 1 and the residual falls.
    """
    load = np.asarray(load, float).reshape(2)
    if not np.all(np.isfinite(load)):
        raise ValueError(f"equilibrium: load = {load.tolist()} must be finite")
    if not math.isfinite(omega):
        raise ValueError(f"equilibrium: omega = {omega!r} must be finite")
    w = float(np.hypot(*load))
    if w == 0.0:
        return 0.0, 0.0
    if omega == 0.0:
        raise EquilibriumError("equilibrium: omega = 0 carries no static load (no wedge film); give omega != 0")
    params = internal.params
    q = np.array(start if start is not None else short_bearing_estimate(params, load, omega), float)
    eps_max = 0.9995

    def residual(qq):
        return np.asarray(internal.force(qq[0], qq[1], 0.0, 0.0, omega), float) + load

    r = residual(q)
    for it in range(max_iter):
        rn = float(np.hypot(*r))
        if rn <= rtol * w:
            return float(q[0]), float(q[1])
        _, dq, _ = film_jacobian(internal, q[0], q[1], 0.0, 0.0, omega, 1e-5)
        try:
            step = -np.linalg.solve(dq, r)
        except np.linalg.LinAlgError:
            raise EquilibriumError(f"equilibrium: singular film Jacobian at y = {q[0]:.4g}, z = {q[1]:.4g}") from None
        alpha = 1.0
        for _ in range(40):
            trial = q + alpha * step
            if math.hypot(*trial) < eps_max * params.CR:
                r_trial = residual(trial)
                if float(np.hypot(*r_trial)) < (1.0 - 1e-4 * alpha) * rn or alpha < 1e-6:
                    break
            alpha *= 0.5
        else:
            trial = q + alpha * step
            r_trial = residual(trial)
        q, r = trial, r_trial
    eps = math.hypot(*q) / params.CR
    raise EquilibriumError(
        f"equilibrium: no convergence after {max_iter} Newton steps for load {load.tolist()} N at "
        f"omega = {omega:.4g} rad/s (eccentricity ratio {eps:.4f}, residual {np.hypot(*r):.3g} N); "
        "the load may exceed what the film carries below eccentricity 1"
    )


def linearize(internal: Internal, y0: float, z0: float, omega: float, *, rel_step: float = 1e-5):
    """Lund's 8 coefficients at the journal position (y0, z0) [m] and speed omega [rad/s].

    Returns (K, C) as 2x2 arrays in the usual sign, K_ij = -dF_i/dq_j [N/m] and
    C_ij = -dF_i/dqdot_j [N s/m] with q = (y, z), so direct terms are positive for a stable film.
    The paper's eq. 7 writes F = F0 + K dq + C dqdot with K_yz = dF_y/dz (eq. 8), i.e. the
    paper's coefficients are the negatives of these: K_paper = -K, C_paper = -C.
    Uses the internal's own derivatives when it has ``force_and_jacobian``, otherwise central
    differences with steps rel_step * CR and rel_step * CR * |omega|.
    """
    check_state(internal.params, y0, z0, 0.0, 0.0, omega)
    _, dq, dv = film_jacobian(internal, y0, z0, 0.0, 0.0, omega, rel_step)
    return -dq, -dv
