"""Static equilibrium and linearisation of any bearing internal.

Both work through the internal protocol only (``force``, and ``force_and_jacobian`` where the
internal has it), so they serve Reynolds, the Taylor surrogate and the linear model alike.
"""

from __future__ import annotations

import math

import numpy as np

from ..internals.registry import Internal, check_state
from .params import BearingParams
from .solver.shortbearing import short_bearing_eccentricity

# Where "load capacity" is measured: near the wall, where the thinnest film is 5 % of the
# clearance (a few um) and a real bearing is at its practical limit. The film force still grows
# beyond (to infinity at the wall), but not a load the bearing could run at.
CAPACITY_ECCENTRICITY = 0.95


class EquilibriumError(RuntimeError):
    """No static equilibrium found: of one bearing for a load and speed (``equilibrium``), or of
    a whole rotor on its bearings (the host's ``equilibrium.static_equilibrium``), which also
    gives ``q`` the last iterate, ``residual`` its residual norm and ``iterations`` the Newton
    iterations done (None, nan, 0 where not known).

    The diagnosis, where one was made (None / nan otherwise): ``bearing`` the bearing's name,
    ``load_N`` its static load [N], ``capacity_N`` the film force it carries at eccentricity
    ratio ``CAPACITY_ECCENTRICITY`` at that speed [N] (0 at omega = 0), ``speed_hz`` the shaft
    speed [Hz]. ``str()`` is the whole one-line diagnosis."""

    def __init__(self, message: str, q: np.ndarray | None = None, residual: float = math.nan,
                 iterations: int = 0, *, bearing: str | None = None, load_N: float = math.nan,
                 capacity_N: float = math.nan, speed_hz: float = math.nan):
        super().__init__(message)
        self.q = q
        self.residual = residual
        self.iterations = iterations
        self.bearing = bearing
        self.load_N = load_N
        self.capacity_N = capacity_N
        self.speed_hz = speed_hz

    def diagnosis(self) -> dict:
        """The diagnosis fields for a json report (None where not known)."""
        def num(x):
            return float(x) if x is not None and math.isfinite(x) else None
        return {"bearing": self.bearing, "load_N": num(self.load_N), "capacity_N": num(self.capacity_N),
                "capacity_eccentricity": CAPACITY_ECCENTRICITY, "speed_hz": num(self.speed_hz)}


def format_newtons(x: float) -> str:
    """A force [N] for messages: '1.98 kN', '16.7 N', '396 mN', '1e+09 N'."""
    a = abs(x)
    for scale, unit in ((1e3, "kN"), (1.0, "N"), (1e-3, "mN")):
        if scale <= a < 1e3 * scale:
            return f"{x / scale:.3g} {unit}"
    return f"{x:.3g} N"


def capacity_message(bearing: str, load_N: float, capacity_N: float, speed_hz: float) -> str:
    """'<bearing> carries at most ~1.98 kN at 22 Hz at eccentricity 0.95; asked for 1e+09 N',
    or, at zero speed, that a hydrodynamic bearing carries nothing there."""
    if speed_hz == 0.0:
        return (f"{bearing} carries no load at omega = 0 (a hydrodynamic film builds its pressure from "
                f"the shaft's rotation); asked for {format_newtons(load_N)}")
    return (f"{bearing} carries at most ~{format_newtons(capacity_N)} at {speed_hz:.4g} Hz at eccentricity "
            f"{CAPACITY_ECCENTRICITY:g}; asked for {format_newtons(load_N)}")


def journal_at_eccentricity(load, omega: float, eps: float, CR: float) -> tuple[float, float]:
    """Journal position (y, z) [m] at eccentricity ratio ``eps`` where a plain bearing's film
    pushes back against ``load = (Wy, Wz)`` [N]: the load direction turned by the short-bearing
    attitude angle tan(phi) = pi sqrt(1 - eps^2) / (4 eps) in the direction of rotation
    (``shortbearing.short_bearing_eccentricity``). The origin for a zero load."""
    wy, wz = float(load[0]), float(load[1])
    w = math.hypot(wy, wz)
    if w == 0.0:
        return 0.0, 0.0
    phi = math.copysign(math.atan2(math.pi * math.sqrt(1.0 - eps * eps), 4.0 * eps), omega)
    c, s = math.cos(phi), math.sin(phi)
    ly, lz = wy / w, wz / w
    e = eps * CR
    return e * (c * ly - s * lz), e * (s * ly + c * lz)


def load_capacity(internal: Internal, load, omega: float) -> float:
    """The film force |F| [N] of the internal with the journal at eccentricity ratio
    ``CAPACITY_ECCENTRICITY``, placed where it carries ``load`` (``journal_at_eccentricity``):
    what the bearing carries near the wall at this speed, in one evaluation. 0 at omega = 0;
    nan if the internal refuses that state."""
    if omega == 0.0:
        return 0.0
    load = load if math.hypot(float(load[0]), float(load[1])) > 0.0 else (0.0, -1.0)
    y, z = journal_at_eccentricity(load, omega, CAPACITY_ECCENTRICITY, internal.params.CR)
    try:
        fy, fz = internal.force(y, z, 0.0, 0.0, omega)
    except (ValueError, ArithmeticError):  # BearingStateError is a ValueError
        return math.nan
    return float(math.hypot(fy, fz))


def short_bearing_estimate(params: BearingParams, load, omega: float) -> tuple[float, float]:
    """Journal position (y, z) [m] for a static ``load`` (Wy, Wz) [N] from the closed-form
    short-bearing (Ocvirk) theory: a start for Newton, not an answer. The journal sits at the
    Ocvirk eccentricity, turned from the load line by the attitude angle in the direction of
    rotation (``shortbearing.short_bearing_eccentricity``)."""
    w = math.hypot(float(load[0]), float(load[1]))
    if w == 0.0:
        return 0.0, 0.0
    eps, _ = short_bearing_eccentricity(params, w, omega)
    return journal_at_eccentricity(load, omega, min(eps, 0.999), params.CR)


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
    name: str = "the bearing",
) -> tuple[float, float]:
    """Journal position (y0, z0) [m] where the film force balances the static external load
    ``load = (Wy, Wz)`` [N] on the journal (weight is ``(0, -W)``) at speed ``omega`` [rad/s]:
    F(y0, z0, 0, 0, omega) + load = 0 with |residual| <= rtol * |load|.

    Newton with the film Jacobian from the short-bearing start, each step backtracked so that
    the eccentricity ratio (of a bore that is not the full circle: its film closure) stays
    below 1 and the residual falls. When none is found, the
    EquilibriumError names the bearing (``name``), its load and what it carries at
    eccentricity CAPACITY_ECCENTRICITY at this speed (``load_capacity``).
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
        raise EquilibriumError(f"equilibrium: {capacity_message(name, w, 0.0, 0.0)}; give omega != 0",
                               bearing=name, load_N=w, capacity_N=0.0, speed_hz=0.0)
    own = getattr(internal, "journal_equilibrium", None)
    if own is not None:  # a bore whose wall is not the clearance circle (tilting pads): its own search
        return own((float(load[0]), float(load[1])), omega, start=start)
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
            raise _no_equilibrium(internal, name, load, omega,
                                  f"singular film Jacobian at y = {q[0]:.4g} m, z = {q[1]:.4g} m") from None
        alpha = 1.0
        for _ in range(40):
            trial = q + alpha * step
            inside = (math.hypot(*trial) < eps_max * params.CR if params.geometry.is_full_bore
                      else params.geometry.closure(trial[0], trial[1], params.CR) < eps_max)
            if inside:
                r_trial = residual(trial)
                if float(np.hypot(*r_trial)) < (1.0 - 1e-4 * alpha) * rn or alpha < 1e-6:
                    break
            alpha *= 0.5
        else:
            trial = q + alpha * step
            r_trial = residual(trial)
        q, r = trial, r_trial
    eps = math.hypot(*q) / params.CR
    raise _no_equilibrium(internal, name, load, omega,
                          f"Newton stopped after {max_iter} steps at eccentricity ratio {eps:.4f}, "
                          f"residual {np.hypot(*r):.3g} N")


def _no_equilibrium(internal: Internal, name: str, load: np.ndarray, omega: float, detail: str) -> EquilibriumError:
    """The error for a failed equilibrium: first whether the load exceeds what the bearing
    carries near the wall (then that is the diagnosis), else what Newton did."""
    w = float(np.hypot(*load))
    cap = load_capacity(internal, load, omega)
    hz = float(f"{omega / (2.0 * math.pi):.12g}")  # 22, not 21.999999999999996
    if w > cap:  # False for a nan capacity (the internal refused the state)
        msg = f"equilibrium: {capacity_message(name, w, cap, hz)}: no static equilibrium inside the clearance ({detail})"
    else:
        msg = f"equilibrium: {name}, load {load.tolist()} N at omega = {omega:.4g} rad/s: {detail}"
        if math.isfinite(cap):
            msg += (f"; it carries ~{format_newtons(cap)} at eccentricity {CAPACITY_ECCENTRICITY:g}, "
                    f"more than the {format_newtons(w)} asked")
    return EquilibriumError(msg, bearing=name, load_N=w, capacity_N=cap, speed_hz=hz)


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


def sommerfeld_number(params: BearingParams, load_N: float, speed_hz: float) -> float:
    """Raimondi and Boyd's Sommerfeld number S = (mu N L D / W) (R / C)^2 (ASLE Trans. 1, 1958;
    the S of their design charts and of Shigley's), with N the speed in rev/s [Hz], W the load
    [N], R = D / 2 and C the radial clearance CR. Some authors use pi S or 1 / S instead:
    compare with a table only after checking its definition. ValueError for W <= 0 (S is infinite
    without a load)."""
    if not (load_N > 0.0 and math.isfinite(load_N)):
        raise ValueError(f"Sommerfeld number: the load must be a finite number > 0 N, got {load_N!r}")
    return params.mu * speed_hz * params.L * params.D / load_N * (0.5 * params.D / params.CR) ** 2


def dimensionless_coefficients(params: BearingParams, load_N: float, omega: float, K, C) -> tuple[np.ndarray,
                                                                                                   np.ndarray]:
    """Lund's dimensionless coefficients (K CR / W, C omega CR / W) of the stiffness K [N/m] and
    damping C [N s/m] (``linearize``) under the load W [N] at omega [rad/s], in the axes K and C
    are in. With the load along -z, as the demo applies it, a table whose x points along the load
    and y along the rotation reads K_xx = K_zz, K_yy = K_yy, K_xy = -K_zy, K_yx = -K_yz here (the
    same for C). ValueError for W <= 0."""
    if not (load_N > 0.0 and math.isfinite(load_N)):
        raise ValueError(f"dimensionless coefficients: the load must be a finite number > 0 N, got {load_N!r}")
    s = params.CR / load_N
    return np.asarray(K, float) * s, np.asarray(C, float) * (omega * s)
