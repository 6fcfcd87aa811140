"""Static equilibrium of a structure held by nonlinear nodal forces (rotor_host.equilibrium)
against closed forms: Cardano's root of a cubic spring chain, the root of a spring stiffening
to a wall, and the failures it must name.
"""

import math

import numpy as np
import pytest

from bearing_fmu.statics import EquilibriumError
from rotor_host.equilibrium import static_equilibrium
from rotor_host.forces import FunctionForce, StepRejected


class Recorder:
    """Wraps a force and logs the protocol calls (as tests/test_newmark.py's, without rejection)."""

    def __init__(self, dofs, fn):
        self.dofs = np.asarray(dofs)
        self.fn = fn
        self.log = []

    def begin_step(self, t, dt):
        self.log.append(("begin", t, dt))

    def evaluate(self, q, v):
        self.log.append(("eval", q.copy()))
        return self.fn(q, v)

    def accept_step(self):
        self.log.append(("accept",))

    def reject_step(self):
        self.log.append(("reject",))


def test_static_equilibrium_cubic_chain_against_cardano():
    # DOF0 held by a nonlinear spring f = -(kb q0 + k3 q0^3), DOF0-DOF1 by a linear spring k
    # (K alone is singular: a free chain). Loads F0, F1. Sum of forces: kb q0 + k3 q0^3 = F0 + F1,
    # a depressed cubic q^3 + p q - s = 0 with one real root (Cardano):
    # q = cbrt(s/2 + sqrt(s^2/4 + p^3/27)) + cbrt(s/2 - sqrt(s^2/4 + p^3/27)); q1 = q0 + F1 / k.
    k, kb, k3, F0, F1 = 1e4, 2e3, 5e7, 30.0, -80.0
    K = np.array([[k, -k], [-k, k]])
    force = FunctionForce([0], lambda q, v: (-(kb * q + k3 * q ** 3), np.diag(-(kb + 3 * k3 * q ** 2)), None))
    q = static_equilibrium(K, [F0, F1], force, [0.0, 0.0])
    p, s = kb / k3, (F0 + F1) / k3
    d = math.sqrt(s * s / 4 + p ** 3 / 27)
    q0 = np.cbrt(s / 2 + d) + np.cbrt(s / 2 - d)
    assert q[0] == pytest.approx(q0, rel=1e-10)
    assert q[1] == pytest.approx(q0 + F1 / k, rel=1e-10)
    # no derivatives: finite differences, same root
    force_nd = FunctionForce([0], lambda q, v: -(kb * q + k3 * q ** 3))
    q_nd = static_equilibrium(K, [F0, F1], force_nd, [0.0, 0.0])
    assert q_nd[0] == pytest.approx(q0, rel=1e-8)


def test_static_equilibrium_line_search_stays_inside_the_clearance():
    # f = -k q / (1 - (q/c)^2) (stiffening to the wall |q| = c, rejected beyond). Equilibrium
    # with a load F: k q / (1 - q^2/c^2) = F  <=>  (F/c^2) q^2 + k q - F = 0, root
    # q = (-k + sqrt(k^2 + 4 F^2 / c^2)) / (2 F / c^2). The first Newton step from 0 is F/k = 3c:
    # outside, so the line search must cut it.
    k, c, F = 1e6, 1e-4, 300.0

    def fn(q, v):
        if abs(q[0]) >= c:
            raise StepRejected(f"|q| = {abs(q[0]):.3g} >= c")
        u = 1 - (q / c) ** 2
        return -k * q / u, np.diag(-k / u - 2 * k * q ** 2 / (c * c * u * u)), None

    rec = Recorder([0], fn)
    q = static_equilibrium(np.zeros((1, 1)), [F], rec, [0.0])
    root = (-k + math.sqrt(k * k + 4 * F * F / c ** 2)) / (2 * F / c ** 2)
    assert q[0] == pytest.approx(root, rel=1e-10)
    assert rec.log[0] == ("begin", 0.0, 0.0) and rec.log[-1] == ("accept",)
    assert rec.log[-2][1][0] == q[0]  # evaluated last at the answer


def test_static_equilibrium_reports_failure():
    # a free mass with no force: singular tangent, named in the error
    with pytest.raises(EquilibriumError, match="singular tangent"):
        static_equilibrium(np.zeros((1, 1)), [1.0], None, [0.0])
    # a force that cannot balance the load (|f| = |q| / sqrt(1 + q^2) < 1 < 5)
    sat = FunctionForce([0], lambda q, v: (-q / np.sqrt(1 + q * q), np.diag(-(1 + q * q) ** -1.5), None))
    with pytest.raises(EquilibriumError, match="residual"):
        static_equilibrium(np.zeros((1, 1)), [5.0], sat, [0.0], max_iter=20)


def test_one_equilibrium_error_with_the_last_iterate():
    # the host raises bearing_fmu.statics.EquilibriumError (one class for both statics), with
    # the last iterate, its residual and the iterations done
    sat = FunctionForce([0], lambda q, v: (-q / np.sqrt(1 + q * q), np.diag(-(1 + q * q) ** -1.5), None))
    with pytest.raises(EquilibriumError) as ei:
        static_equilibrium(np.zeros((1, 1)), [5.0], sat, [0.0], max_iter=20)
    e = ei.value
    # |f| < 1 everywhere, so the residual |5 - f| stays above 4
    assert f"iteration {e.iterations} " in str(e) and 0 < e.iterations <= 20
    assert e.q.shape == (1,) and e.residual > 4.0 and f"{e.residual:.3e}" in str(e)
    plain = EquilibriumError("no equilibrium")
    assert plain.q is None and plain.iterations == 0 and np.isnan(plain.residual)
