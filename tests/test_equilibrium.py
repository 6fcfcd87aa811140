"""Static equilibrium of a structure held by nonlinear nodal forces (rotor_host.integrate.equilibrium)
against closed forms: Cardano's root of a cubic spring chain, the root of a spring stiffening
to a wall, and the failures it must name (an overloaded bearing against an independent estimate
of its load capacity, zero speed).
"""

import math
from pathlib import Path

import numpy as np
import pytest

from bearing_fmu.physics.statics import EquilibriumError, format_newtons
from rotor_host.integrate.equilibrium import pinned_loads, static_equilibrium
from rotor_host.integrate.forces import FunctionForce, StepRejected


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
    # the host raises bearing_fmu.physics.statics.EquilibriumError (one class for both statics), with
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


ROOT = Path(__file__).resolve().parents[1]
OMEGA = 2 * math.pi * 22.0


def capacity_estimate(p, eps, omega):
    """The short-bearing (Ocvirk) load less the circumferential flow it drops; derivation and
    the factor 1.5 in tests/test_statics.py (capacity_estimate)."""
    from bearing_fmu.physics.solver.shortbearing import short_bearing_load

    return short_bearing_load(p, eps, omega) / (1.0 + (p.L / p.D) ** 2 * eps / (2.0 * (1.0 - eps)))


def test_pinned_loads_are_the_scenes_bearing_loads():
    # the equilibrium's own bearing loads (reactions of the rotor pinned at the force's DOFs)
    # are the scene's (rotor_host.scenes.run.bearing_loads, checked against statics in test_scene.py)
    from rotor_host.model.rotor import Rotor
    from rotor_host.scenes.run import bearing_loads

    rotor = Rotor.from_toml(ROOT / "rotor_host" / "bundled" / "rotor_paper.toml")
    f = rotor.weight_vector(9.81) + rotor.point_load_vector([(8, 30.0, -800.0)])
    dofs = [rotor.dof(n, d) for n in rotor.bearing_nodes for d in ("y", "z")]
    np.testing.assert_allclose(pinned_loads(rotor.K, f, dofs), bearing_loads(rotor, f), rtol=1e-9, atol=1e-9)


def test_overloaded_rotor_bearing_is_named_before_newton(tmp_path, paper_scene):
    # 1e9 N on node 9 (bearing 2): the paper rotor's static equilibrium, as a scene starts it,
    # names bearing 2, its load and what it carries near the wall; bearing 1 (half the
    # weight, 16.7 N) is not blamed.
    from bearing_fmu.physics.params import PAPER_BEARING
    from rotor_host.model.rotor import Rotor
    from rotor_host.scenes.bearings import build_bearings
    from rotor_host.scenes.run import bearing_loads, initial_state
    from rotor_host.scenes.scene import G, load_scene

    scene = load_scene(paper_scene(t_end=2e-4, grid=(48, 8), unbalance_g=None,
                                   static_loads=[{"node": 9, "Fz_N": -1e9}]))
    rotor = Rotor.from_toml(scene.rotor_path)
    f_static = rotor.weight_vector(G) + rotor.point_load_vector(scene.static_loads)
    loads = bearing_loads(rotor, f_static)
    with build_bearings(scene, rotor, loads, tmp_path / "fmu") as bearings:
        with pytest.raises(EquilibriumError) as ei:
            initial_state(scene, rotor, f_static, loads, bearings)
    e = ei.value
    msg = str(e)
    assert "\n" not in msg and msg.startswith("static equilibrium: bearing 2 (node 9) carries at most ~")
    assert "at 22 Hz at eccentricity 0.95; asked for 1e+09 N" in msg and "bearing 1" not in msg
    assert "no equilibrium found: " in msg  # what Newton did, after the diagnosis
    assert e.bearing == "bearing 2 (node 9)" and e.speed_hz == 22.0
    assert e.load_N == pytest.approx(1e9, rel=1e-6)
    assert f"~{format_newtons(e.capacity_N)} " in msg
    assert 1 / 1.5 < e.capacity_N / capacity_estimate(PAPER_BEARING, 0.95, OMEGA) < 1.5
    assert e.q is not None and e.iterations >= 0


def test_rotor_at_zero_speed_carries_no_load():
    # omega = 0: the films carry nothing, the tangent is singular; the error says why
    from bearing_fmu.physics.params import PAPER_BEARING
    from bearing_fmu.physics.solver.reynolds import Reynolds
    from rotor_host.coupling.bearings import DirectBearings
    from rotor_host.model.rotor import Rotor

    rotor = Rotor.from_toml(ROOT / "rotor_host" / "bundled" / "rotor_paper.toml")
    f = rotor.weight_vector(9.81)
    pairs = [(rotor.dof(n, "y"), rotor.dof(n, "z")) for n in rotor.bearing_nodes]
    names = [f"bearing {k + 1} (node {n + 1})" for k, n in enumerate(rotor.bearing_nodes)]
    rey = Reynolds(PAPER_BEARING, n_theta=32, n_x=4)
    bearings = DirectBearings([rey, rey], pairs, 0.0, names)
    with pytest.raises(EquilibriumError) as ei:
        static_equilibrium(rotor.K, f, bearings, np.zeros(rotor.n_dof))
    msg = str(ei.value)
    # half the rotor's weight on each bearing (symmetric rotor)
    half = format_newtons(rotor.mass * 9.81 / 2)
    assert msg.startswith("static equilibrium: bearing 1 (node 3) carries no load at omega = 0 "), msg
    assert f"asked for {half} (also bearing 2 (node 9): asked for {half}); no equilibrium found: " in msg
    assert ei.value.capacity_N == 0.0 and ei.value.speed_hz == 0.0 and ei.value.bearing == "bearing 1 (node 3)"
