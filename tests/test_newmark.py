"""Newmark / HHT-alpha + Newton integrator (rotor_host.integrate.newmark) against exact solutions.

Sources of the expected values are written next to each check. Reference for the scheme's
properties: Hughes, "The Finite Element Method", Dover 2000, ch. 9 (Newmark: average
acceleration is second order, unconditionally stable, conserves the quadratic energy of
linear undamped systems, period error (omega h)^2 / 12); Hilber, Hughes, Taylor, Earthquake
Eng. Struct. Dyn. 5 (1977) 283 (HHT-alpha: second order, spectral radius at omega h -> inf
equal to (1 + alpha) / (1 - alpha)).
"""

import math

import numpy as np
import pytest
import scipy.linalg as sla
from scipy.integrate import solve_ivp

from rotor_host.integrate.forces import FunctionForce, LinearForce, StepRejected
from rotor_host.integrate.newmark import IntegrationError, Newmark, NewmarkConfig, NewmarkResult, integrate

# ----------------------------------------------------------------------------- helpers

def sdof_exact(t, m, c, k, q0, v0, F0=0.0, w=0.0):
    """Closed form of m q'' + c q' + k q = F0 cos(w t), underdamped (any textbook, e.g.
    Rao, Mechanical Vibrations, sec. 2.6 and 3.4): homogeneous + steady-state particular."""
    wn = math.sqrt(k / m)
    z = c / (2.0 * math.sqrt(k * m))
    wd = wn * math.sqrt(1.0 - z * z)
    den = (k - m * w * w) ** 2 + (c * w) ** 2
    A = F0 * (k - m * w * w) / den
    B = F0 * c * w / den
    a0 = q0 - A
    b0 = (v0 - B * w + z * wn * a0) / wd
    return np.exp(-z * wn * t) * (a0 * np.cos(wd * t) + b0 * np.sin(wd * t)) + A * np.cos(w * t) + B * np.sin(w * t)


def jeffcott4():
    """A 4-DOF rotor-like system, DOFs (y, z, theta_y, theta_z) of one node: a disk on a
    shaft with translation-rotation coupling, disk gyroscopics (G[ty, tz] = +Ip, as in
    rotor_host/model/fe.py), stiffness-proportional damping, and an anisotropic, cross-coupled
    linear bearing on (y, z) given as a NodalForce with exact derivatives."""
    m, Id, Ip = 2.0, 0.01, 0.02
    k, kc, kr = 4.0e5, 1.0e3, 2.0e3
    M = np.diag([m, m, Id, Id])
    K = np.array([[k, 0, 0, kc], [0, k, -kc, 0], [0, -kc, kr, 0], [kc, 0, 0, kr]], dtype=float)
    G = np.zeros((4, 4))
    G[2, 3], G[3, 2] = Ip, -Ip
    C = 1.5e-5 * K
    Kb = np.array([[2.0e5, 3.0e4], [-5.0e4, 3.0e5]])   # Lund stiffness (cross-coupled, anisotropic)
    Cb = np.array([[300.0, 20.0], [20.0, 400.0]])
    return M, K, C, G, Kb, Cb


def expm_solution(M, K, D, Kb, Cb, bdofs, fu, omega, fw, q0, v0, t):
    """Exact response of M a + D v + (K + P^T Kb P) q + P^T Cb P v = fu (cos wt, sin wt) + fw
    by the matrix exponential of the first-order system augmented with the forcing states
    (c, s, 1): c' = -w s, s' = w c (Van Loan's trick)."""
    n = M.shape[0]
    Kt, Dt = K.copy(), D.copy()
    Kt[np.ix_(bdofs, bdofs)] += Kb
    Dt[np.ix_(bdofs, bdofs)] += Cb
    Mi = np.linalg.inv(M)
    N = 2 * n + 3
    A = np.zeros((N, N))
    A[:n, n:2 * n] = np.eye(n)
    A[n:2 * n, :n] = -Mi @ Kt
    A[n:2 * n, n:2 * n] = -Mi @ Dt
    A[n:2 * n, 2 * n] = Mi @ fu[:, 0]
    A[n:2 * n, 2 * n + 1] = Mi @ fu[:, 1]
    A[n:2 * n, 2 * n + 2] = Mi @ fw
    A[2 * n, 2 * n + 1] = -omega
    A[2 * n + 1, 2 * n] = omega
    x0 = np.concatenate([q0, v0, [1.0, 0.0, 1.0]])
    return np.array([(sla.expm(A * ti) @ x0)[:2 * n] for ti in t])


# ----------------------------------------------------------------------------- linear SDOF

@pytest.mark.parametrize("forced", [False, True])
def test_sdof_damped_against_closed_form(forced):
    m, c, k = 1.0, 0.2, 4.0
    F0, w = (1.0, 1.3) if forced else (0.0, 0.0)
    dt, T = 1e-3, 10.0
    res = integrate(np.array([[m]]), np.array([[k]]), [1.0], [0.5], (0.0, T), dt, C=np.array([[c]]),
                    f_ext=lambda t: np.array([F0 * math.cos(w * t)]))
    ex = sdof_exact(res.t, m, c, k, 1.0, 0.5, F0, w)
    # Newmark's relative period error is (omega h)^2 / 12 (Hughes 2000, eq. 9.3.44); after a
    # time T the phase lag is omega T (omega h)^2 / 12 = 6.7e-6 rad for an amplitude <= 1.3
    bound = 2.0 * 1.3 * 2.0 * T * (2.0 * dt) ** 2 / 12.0
    assert np.max(np.abs(res.q[:, 0] - ex)) < bound
    assert res.t[-1] == pytest.approx(T) and res.t.size == 10001
    # no nonlinear force: the predictor is the exact solution of the step, one pass per step
    assert np.all(res.iterations == 1)


# ----------------------------------------------------------------------------- linear MDOF

def test_jeffcott_gyroscopic_bearing_against_expm():
    M, K, C, G, Kb, Cb = jeffcott4()
    omega = 300.0
    mu_e = 1e-4  # unbalance m e [kg m]
    fu = np.zeros((4, 2))
    fu[0, 0] = mu_e * omega ** 2  # F_y = m e w^2 cos wt
    fu[1, 1] = mu_e * omega ** 2  # F_z = m e w^2 sin wt
    fw = np.array([0.0, -2.0 * 9.81, 0.0, 0.0])
    bdofs = [0, 1]
    bearing = LinearForce(bdofs, Kb, Cb)
    q0 = np.array([1e-5, -2e-5, 1e-4, 0.0])
    v0 = np.array([0.0, 1e-3, 0.0, -0.01])
    dt, T = 2e-5, 0.05

    def f_ext(t):
        return fu[:, 0] * math.cos(omega * t) + fu[:, 1] * math.sin(omega * t) + fw

    res = integrate(M, K, q0, v0, (0.0, T), dt, C=C, G=G, omega=omega, f_ext=f_ext,
                    nodal_force=bearing, record_every=50)
    D = C + omega * G
    ex = expm_solution(M, K, D, Kb, Cb, bdofs, fu, omega, fw, q0, v0, res.t)
    # the highest undamped frequency sets the discretisation error; relative period error
    # (w h)^2 / 12 gives a phase error w T (w h)^2 / 12 (Hughes 2000, eq. 9.3.44)
    Kt = K.copy()
    Kt[:2, :2] += 0.5 * (Kb + Kb.T)
    wmax = math.sqrt(np.max(sla.eigvalsh(Kt, M)))
    amp = np.max(np.abs(ex[:, :4]), axis=0)
    err = np.max(np.abs(res.q - ex[:, :4]), axis=0)
    assert np.all(err <= 3.0 * wmax * T * (wmax * dt) ** 2 / 12.0 * amp + 1e-12)
    verr = np.max(np.abs(res.v - ex[:, 4:]), axis=0)
    assert np.all(verr <= 3.0 * wmax * T * (wmax * dt) ** 2 / 12.0 * np.max(np.abs(ex[:, 4:]), axis=0) * 2)
    # linear force with exact tangent: the linearised predictor solves the step exactly
    assert np.all(res.iterations == 1)
    # the recorded nonlinear force is the bearing force at the recorded states
    np.testing.assert_allclose(res.f_nl, -(res.q[:, :2] @ Kb.T) - res.v[:, :2] @ Cb.T, rtol=1e-9, atol=1e-12)


def test_composite_force_equals_one_force_and_record_options(tmp_path):
    M, K, C, G, Kb, Cb = jeffcott4()
    Kb = np.diag([2e5, 3e5])
    Cb = np.diag([300.0, 400.0])
    q0 = np.array([1e-5, -2e-5, 1e-4, 0.0])
    one = LinearForce([0, 1], Kb, Cb)
    two = [LinearForce([0], Kb[:1, :1], Cb[:1, :1]), LinearForce([1], Kb[1:, 1:], Cb[1:, 1:])]
    calls = []
    kw = dict(C=C, G=G, omega=100.0)
    r1 = integrate(M, K, q0, np.zeros(4), (0.0, 0.01), 1e-4, nodal_force=one, **kw)
    r2 = integrate(M, K, q0, np.zeros(4), (0.0, 0.01), 1e-4, nodal_force=two, record_dofs=[1, 3],
                   record_every=10, progress=calls.append, progress_every=25, **kw)
    np.testing.assert_allclose(r2.q, r1.q[::10][:, [1, 3]], rtol=1e-12, atol=1e-18)
    assert r2.t.size == 11 and r2.q.shape == (11, 2) and r2.f_nl.shape == (11, 2)
    assert calls == pytest.approx([0.0025, 0.005, 0.0075, 0.01])
    path = r2.save(tmp_path / "run.npz")
    back = NewmarkResult.load(path)
    np.testing.assert_array_equal(back.q, r2.q)
    np.testing.assert_array_equal(back.dofs, [1, 3])
    assert back.status == "ok" and back.iterations.size == 100


# ----------------------------------------------------------------------------- energy

def test_average_acceleration_conserves_quadratic_energy():
    # Undamped, unforced, gyroscopic (G skew: no work) with a symmetric spring through the
    # protocol: the trapezoidal rule conserves E = v'Mv/2 + q'(K + P'KbP)q/2 exactly
    # (Hughes 2000, sec. 9.3.2), so only round-off remains, even at a large step.
    M, K, _, G, _, _ = jeffcott4()
    Kb = np.array([[2e5, 5e4], [5e4, 3e5]])
    q0 = np.array([1e-4, 0.0, 0.0, 1e-3])
    v0 = np.array([0.0, 0.05, 0.1, 0.0])
    res = integrate(M, K, q0, v0, (0.0, 0.5), 1e-3, G=G, omega=500.0, nodal_force=LinearForce([0, 1], Kb))
    q, v = res.q, res.v
    E = 0.5 * np.einsum("ti,ij,tj->t", v, M, v) + 0.5 * np.einsum("ti,ij,tj->t", q, K, q) \
        + 0.5 * np.einsum("ti,ij,tj->t", q[:, :2], Kb, q[:, :2])
    assert np.max(np.abs(E - E[0])) / E[0] < 1e-10


# ----------------------------------------------------------------------------- order, HHT

def _order_errors(alpha):
    m, c, k = 1.0, 0.3, 25.0
    errs = []
    for dt in (0.02, 0.01, 0.005):
        res = integrate(np.array([[m]]), np.array([[k]]), [1.0], [0.0], (0.0, 4.0), dt, C=np.array([[c]]),
                        f_ext=lambda t: np.array([2.0 * math.cos(3.0 * t)]), config=NewmarkConfig(alpha=alpha))
        errs.append(np.max(np.abs(res.q[:, 0] - sdof_exact(res.t, m, c, k, 1.0, 0.0, 2.0, 3.0))))
    return errs


@pytest.mark.parametrize("alpha", [0.0, -0.1, -0.3])
def test_second_order_in_dt(alpha):
    e = _order_errors(alpha)
    orders = [math.log2(e[0] / e[1]), math.log2(e[1] / e[2])]
    assert all(1.85 < p < 2.15 for p in orders), (e, orders)


def hht_amplification(alpha, wh):
    """Amplification matrix of HHT-alpha on q'' + w^2 q = 0 with h = 1, state (q, v, a),
    written from the defining equations (Hilber et al. 1977):
    a1 + (1+alpha) w^2 q1 - alpha w^2 q0 = 0, q1 = q0 + v0 + (1/2 - beta) a0 + beta a1,
    v1 = v0 + (1 - gamma) a0 + gamma a1."""
    b, g, w2 = (1 - alpha) ** 2 / 4, 0.5 - alpha, wh ** 2
    A = np.zeros((3, 3))
    for j in range(3):
        q0, v0, a0 = np.eye(3)[j]
        a1 = (-(1 + alpha) * w2 * (q0 + v0 + (0.5 - b) * a0) + alpha * w2 * q0) / (1 + (1 + alpha) * w2 * b)
        A[:, j] = [q0 + v0 + (0.5 - b) * a0 + b * a1, v0 + (1 - g) * a0 + g * a1, a1]
    return A


@pytest.mark.parametrize("alpha", [0.0, -0.1, -1.0 / 3.0])
def test_hht_damps_stiff_mode_with_the_published_spectral_radius(alpha):
    wh = 1.0e3  # a mode far beyond the resolved range: omega h = 1000
    k, h, N = wh ** 2, 1.0, 80
    res = integrate(np.eye(1), k * np.eye(1), [1.0], [0.0], (0.0, N * h), h, config=NewmarkConfig(alpha=alpha))
    # the integrator reproduces the discrete HHT solution x_n = A^n x_0 (consistent a0 = -k q0)
    A = hht_amplification(alpha, wh)
    x = np.array([1.0, 0.0, -k])
    ref = [x[0]]
    for _ in range(N):
        x = A @ x
        ref.append(x[0])
    np.testing.assert_allclose(res.q[:, 0], ref, rtol=1e-8, atol=1e-9 * np.max(np.abs(ref)))
    # ... whose spectral radius tends to (1 + alpha) / (1 - alpha) as omega h -> inf (Hilber et al. 1977)
    rho_inf = (1 + alpha) / (1 - alpha)
    assert max(abs(np.linalg.eigvals(hht_amplification(alpha, 1e8)))) == pytest.approx(rho_inf, rel=1e-3)
    # so the stiff mode's energy decays like rho_inf^(2n) once the start-up overshoot of HHT has
    # passed (alpha = -1/3 has a double root, hence a slower approach); alpha = 0 conserves it
    E = 0.5 * res.v[:, 0] ** 2 + 0.5 * k * res.q[:, 0] ** 2
    if alpha == 0.0:
        assert np.max(np.abs(E / E[0] - 1.0)) < 1e-9
    else:
        rate = (E[N] / E[N // 2]) ** (1.0 / N)
        assert rate == pytest.approx(rho_inf, rel=0.03)
        assert E[N] / E[0] < 1e-8


def test_hht_keeps_the_slow_mode_and_kills_the_fast_one():
    # two uncoupled modes, 1 rad/s and 1e4 rad/s, h = 0.01: HHT alpha = -0.3 leaves the slow
    # mode within its O(h^2) error and removes the fast one
    M = np.eye(2)
    K = np.diag([1.0, 1e8])
    res = integrate(M, K, [1.0, 1.0], [0.0, 0.0], (0.0, 2.0), 0.01, config=NewmarkConfig(alpha=-0.3))
    assert np.max(np.abs(res.q[:, 0] - np.cos(res.t))) < 1e-4
    assert abs(res.q[-1, 1]) < 1e-40


# ----------------------------------------------------------------------------- Newton

def cubic_force(k3, exact=True):
    def fn(q, v):
        f = -k3 * q ** 3
        return (f, np.diag(-3.0 * k3 * q ** 2), None) if exact else (f, None, None)
    return fn


def test_newton_quadratic_rate_with_exact_tangent_and_convergence_without():
    m, k, k3, dt = 1.0, 1.0, 100.0, 0.05
    cfg = NewmarkConfig(rtol_force=1e-13, rtol_disp=1e-13, trace=True)
    res = integrate(np.array([[m]]), np.array([[k]]), [1.0], [0.0], (0.0, 2.0), dt,
                    nodal_force=FunctionForce([0], cubic_force(k3)), config=cfg)
    # Newton on R(q) = S0 q - b + k3 q^3 (S0 = 4m/dt^2 + k): r_{k+1} ~ R''/(2 R'^2) r_k^2 with
    # R'' = 6 k3 q, R' >= S0, |q| <= 1 (energy bound of the hardening oscillator)
    S0 = 4.0 * m / dt ** 2 + k
    C = 6.0 * k3 * 1.0 / (2.0 * S0 ** 2)
    ratios = []
    for r in res.residual_history:
        for a, b in zip(r[:-1], r[1:]):
            if b > 1e-11:  # above round-off
                ratios.append(b / a ** 2)
    assert len(ratios) > 10
    assert max(ratios) < 2.0 * C
    assert res.iterations.max() <= 4
    # reference: the same ODE to 1e-12 by DOP853 (scipy), a Newmark step error O(dt^2) apart
    ivp = solve_ivp(lambda t, y: [y[1], -(k * y[0] + k3 * y[0] ** 3) / m], (0, 2.0), [1.0, 0.0],
                    method="DOP853", rtol=1e-12, atol=1e-12, dense_output=True)
    fine = integrate(np.array([[m]]), np.array([[k]]), [1.0], [0.0], (0.0, 2.0), dt / 8,
                     nodal_force=FunctionForce([0], cubic_force(k3)), record_every=8)
    e_coarse = np.max(np.abs(res.q[:, 0] - ivp.sol(res.t)[0]))
    e_fine = np.max(np.abs(fine.q[:, 0] - ivp.sol(fine.t)[0]))
    assert e_coarse / e_fine == pytest.approx(64.0, rel=0.1)  # second order: 8^2

    # without a tangent: modified Newton with the linear tangent (contraction 3 k3 q^2 / S0
    # <= 0.19), converges, with more iterations
    lin = integrate(np.array([[m]]), np.array([[k]]), [1.0], [0.0], (0.0, 2.0), dt,
                    nodal_force=FunctionForce([0], cubic_force(k3, exact=False)), config=cfg)
    assert lin.n_cuts == 0
    assert lin.mean_iterations > res.mean_iterations + 1
    np.testing.assert_allclose(lin.q, res.q, atol=1e-10)
    # finite-difference tangent instead: nearly as few iterations as the exact one, and fewer
    # evaluations in all (FD ones included) than modified Newton
    fd = integrate(np.array([[m]]), np.array([[k]]), [1.0], [0.0], (0.0, 2.0), dt,
                   nodal_force=FunctionForce([0], cubic_force(k3, exact=False)),
                   config=NewmarkConfig(rtol_force=1e-13, rtol_disp=1e-13, tangent="fd"))
    np.testing.assert_allclose(fd.q, res.q, atol=1e-10)
    assert fd.mean_iterations < res.mean_iterations + 1.5
    assert fd.n_evaluations < lin.n_evaluations


def test_two_dof_nonlinear_with_velocity_tangent_hht():
    # a squeeze-film-like force f = -c3 v^3 - k3 q^3 on both DOFs, with its full tangent
    # (df/dv exercises the c1 df/dv part): compare with DOP853 (scipy)
    M = np.diag([1.0, 2.0])
    K = np.array([[50.0, -20.0], [-20.0, 40.0]])
    k3, c3 = 2e3, 0.5

    def fn(q, v):
        return -k3 * q ** 3 - c3 * v ** 3, np.diag(-3 * k3 * q ** 2), np.diag(-3 * c3 * v ** 2)

    q0, v0 = np.array([0.2, -0.1]), np.array([1.0, 0.0])
    res = integrate(M, K, q0, v0, (0.0, 2.0), 1e-3, nodal_force=FunctionForce([0, 1], fn),
                    config=NewmarkConfig(alpha=-0.05))

    def rhs(t, y):
        q, v = y[:2], y[2:]
        f = -k3 * q ** 3 - c3 * v ** 3
        return np.concatenate([v, np.linalg.solve(M, f - K @ q)])

    ivp = solve_ivp(rhs, (0, 2.0), np.concatenate([q0, v0]), method="DOP853", rtol=1e-11, atol=1e-12,
                    dense_output=True)
    assert np.max(np.abs(res.q - ivp.sol(res.t)[:2].T)) < 2e-4
    assert res.mean_iterations < 3.0


class ReusedBuffers:
    """Returns the same f, df/dq arrays at every call, as rotor_host.coupling.bearings.BearingSet does."""

    def __init__(self, dofs, k3, exact):
        self.dofs = np.asarray(dofs)
        m = len(dofs)
        self.k3, self.exact = k3, exact
        self._f, self._dq = np.zeros(m), np.zeros((m, m))

    def begin_step(self, t, dt):
        pass

    def evaluate(self, q, v):
        self._f[:] = -self.k3 * q ** 3
        np.fill_diagonal(self._dq, -3 * self.k3 * q ** 2)
        return self._f, (self._dq if self.exact else None), None

    def accept_step(self):
        pass

    def reject_step(self):
        pass


@pytest.mark.parametrize("tangent", ["bearing", "fd"])
def test_forces_that_reuse_their_buffers(tangent):
    M, K = np.diag([1.0, 2.0]), np.array([[50.0, -20.0], [-20.0, 40.0]])
    cfg = NewmarkConfig(tangent=tangent)
    a = integrate(M, K, [0.2, -0.1], [1.0, 0.0], (0.0, 0.5), 1e-3, config=cfg,
                  nodal_force=ReusedBuffers([0, 1], 2e3, exact=tangent == "bearing"))
    b = integrate(M, K, [0.2, -0.1], [1.0, 0.0], (0.0, 0.5), 1e-3, config=cfg,
                  nodal_force=FunctionForce([0, 1], cubic_force(2e3, exact=tangent == "bearing")))
    np.testing.assert_array_equal(a.q, b.q)
    np.testing.assert_array_equal(a.f_nl, b.f_nl)
    np.testing.assert_allclose(a.f_nl, -2e3 * a.q ** 3, rtol=1e-12)


# ----------------------------------------------------------------------------- step cutting

class Recorder:
    """Wraps a force, logs the protocol calls, rejects states on demand."""

    def __init__(self, dofs, fn, reject=None):
        self.dofs = np.asarray(dofs)
        self.fn = fn
        self.reject = reject or (lambda t, dt, q, v: False)
        self.log = []
        self.t = self.dt = None

    def begin_step(self, t, dt):
        self.t, self.dt = t, dt
        self.log.append(("begin", t, dt))

    def evaluate(self, q, v):
        self.log.append(("eval", q.copy()))
        if self.reject(self.t, self.dt, q, v):
            raise StepRejected(f"state q = {q} refused")
        return self.fn(q, v)

    def accept_step(self):
        self.log.append(("accept",))

    def reject_step(self):
        self.log.append(("reject",))


def _linear_spring(kb):
    return lambda q, v: (-kb * q, np.array([[-kb]]), None)


def test_step_rejected_in_a_window_is_cut_and_reaches_the_end():
    # reject every step longer than dt/4 while 0.3 <= t < 0.5: each of those 20 grid steps is
    # halved, its halves halved again: 1 + 2 = 3 cuts per grid step
    dt = 0.01
    rec = Recorder([0], _linear_spring(3.0), reject=lambda t, h, q, v: 0.3 - 1e-9 <= t < 0.5 - 1e-9 and h > dt / 4 + 1e-15)
    res = integrate(np.eye(1), np.eye(1), [1.0], [0.0], (0.0, 1.0), dt, nodal_force=rec)
    assert res.n_cuts == 3 * 20
    assert res.t.size == 101 and res.t[-1] == pytest.approx(1.0)
    assert np.all(res.iterations[30:50] > res.iterations[0])
    # exact: q = cos(2 t) for q'' + (1 + 3) q = 0
    assert np.max(np.abs(res.q[:, 0] - np.cos(2 * res.t))) < 2.0 * 2.0 * (2 * dt) ** 2 / 12 * 1.0 + 1e-9
    # protocol: begin, ..., accept after the evaluate of the accepted state; reject before a cut
    kinds = [e[0] for e in rec.log]
    assert kinds[:2] == ["begin", "eval"]
    for i, kk in enumerate(kinds):
        if kk == "accept":
            assert kinds[i - 1] == "eval"
            j = i + 1
            if j < len(kinds):
                assert kinds[j] == "begin"
        if kk == "reject":
            assert kinds[i + 1] == "begin" and rec.log[i + 1][2] < dt
    accepted = [rec.log[i - 1][1][0] for i, kk in enumerate(kinds) if kk == "accept"]
    # steps without cuts: the accepted states are the recorded ones
    np.testing.assert_allclose(accepted[:30], res.q[1:31, 0], rtol=0, atol=0)


def test_modified_newton_divergence_is_cured_by_halving():
    # q'' + kb q = 0 with kb through the protocol and no tangent: the fixed-point iteration
    # contracts by kb / S0 with S0 = 4 / h^2; 600 / 400 = 1.5 at h = 0.1 diverges, 600 / 1600
    # converges; every step is then done as two steps h / 2 = the same scheme at dt / 2.
    kb = 600.0
    fn = lambda q, v: (-kb * q, None, None)
    res = integrate(np.eye(1), np.zeros((1, 1)), [1.0], [0.0], (0.0, 1.0), 0.1,
                    nodal_force=FunctionForce([0], fn), config=NewmarkConfig(max_iter=30))
    assert res.n_cuts >= 10
    half = integrate(np.eye(1), np.zeros((1, 1)), [1.0], [0.0], (0.0, 1.0), 0.05,
                     nodal_force=LinearForce([0], [[kb]]), record_every=2)
    np.testing.assert_allclose(res.q, half.q, atol=1e-7)


def test_impossible_state_raises_with_partial_result():
    # free oscillation q = sin 2t (q'' + (1 + 3) q = 0, q0 = 0, v0 = 2) through a force that
    # refuses |q| > 0.9: the solution must pass there (at t = asin(0.9) / 2), no step size helps
    rec = Recorder([0], _linear_spring(3.0), reject=lambda t, h, q, v: abs(q[0]) > 0.9)
    with pytest.raises(IntegrationError) as ei:
        integrate(np.eye(1), np.eye(1), [0.0], [2.0], (0.0, 3.0), 0.01, nodal_force=rec,
                  config=NewmarkConfig(max_halvings=3))
    e = ei.value
    msg = str(e)
    assert "t = " in msg and "iterations" in msg and "residual" in msg and "refused" in msg
    t_cross = math.asin(0.9) / 2.0  # q = sin(2t) reaches 0.9
    assert abs(e.t - t_cross) < 0.011
    assert e.result.status == "failed" and e.result.message == msg
    assert e.result.t[-1] <= e.t + 1e-12 and e.result.t.size >= int(t_cross / 0.01)
    np.testing.assert_allclose(e.result.q[:, 0], np.sin(2 * e.result.t), atol=1e-3)
    assert e.state[0] == e.t and e.state[0] >= e.result.t[-1]  # last accepted (sub-)step
    assert rec.log[-1] == ("reject",)


def test_non_convergent_force_raises_with_iterations_and_residual():
    # a force that flips sign at every call never lets the residual settle
    calls = [0]

    def fn(q, v):
        calls[0] += 1
        return np.array([(-1.0) ** calls[0] * 10.0]), None, None

    with pytest.raises(IntegrationError) as ei:
        integrate(np.eye(1), np.eye(1), [0.0], [0.0], (0.0, 1.0), 0.01, nodal_force=FunctionForce([0], fn),
                  config=NewmarkConfig(max_iter=5, max_halvings=2))
    e = ei.value
    assert e.iterations == 6 and math.isfinite(e.residual) and e.residual > 0
    assert f"{e.residual:.3e}" in str(e) and "6 iterations" in str(e) and "t = 0 s" in str(e)
    assert e.result.t.size == 1  # only the initial state


def test_bad_input_is_refused():
    with pytest.raises(ValueError, match="alpha"):
        NewmarkConfig(alpha=-0.5)
    with pytest.raises(ValueError, match="whole number"):
        integrate(np.eye(1), np.eye(1), [0.0], [0.0], (0.0, 1.0), 0.3)
    with pytest.raises(ValueError, match="distinct"):
        FunctionForce([1, 1], lambda q, v: q)
    nm = Newmark(np.eye(2), np.eye(2), nodal_force=FunctionForce([0], lambda q, v: np.zeros(2)))
    with pytest.raises(ValueError, match="shape"):
        nm.run([0, 0], [0, 0], 0.0, 0.1, 0.01)
