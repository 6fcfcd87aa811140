"""The one vocabulary of the Newton tangent (rotor_host.integrate.forces) and how each side reads it:
the integrator uses the force's own tangent for "bearing" and "frozen" alike, the bearings
compute no Jacobian for "fd" and "linear"; any other word is refused by name."""

import numpy as np
import pytest

from rotor_host.coupling.bearings import DirectBearings
from rotor_host.integrate.forces import FORCE_TANGENTS, NEWTON_TANGENTS, FunctionForce
from rotor_host.integrate.newmark import NewmarkConfig, integrate
from rotor_host.scenes.scene import Scene


class SpringInternal:
    """A bearing internal stand-in: F = -k (y, z), counting the Jacobian requests."""

    def __init__(self, k):
        self.k = k
        self.jacobians = 0

    def force(self, y, z, vy, vz, omega):
        return -self.k * y, -self.k * z

    def force_and_jacobian(self, y, z, vy, vz, omega):
        self.jacobians += 1
        return np.array(self.force(y, z, vy, vz, omega)), -self.k * np.eye(2), np.zeros((2, 2))


def test_the_words():
    assert NEWTON_TANGENTS == ("bearing", "frozen", "fd", "linear")
    assert set(FORCE_TANGENTS) < set(NEWTON_TANGENTS)
    assert Scene.newton_tangent == "bearing" and NewmarkConfig().tangent == "bearing"


@pytest.mark.parametrize("word", ["auto", "exact", "none", "Bearing"])
def test_a_wrong_word_is_refused_with_the_setting_and_the_choices(word):
    choices = "choose one of bearing, frozen, fd, linear"
    with pytest.raises(ValueError, match=f"NewmarkConfig.tangent = '{word}'; {choices}"):
        NewmarkConfig(tangent=word)
    with pytest.raises(ValueError, match=f"DirectBearings tangent = '{word}'; {choices}"):
        DirectBearings([SpringInternal(1.0)], [(0, 1)], 10.0, tangent=word)


def test_the_integrator_reads_bearing_and_frozen_alike():
    # the force decides whether its tangent changes; Newmark uses what it returns either way
    k3 = 2e3
    fn = lambda q, v: (-k3 * q ** 3, np.diag(-3 * k3 * q ** 2), None)
    M, K = np.diag([1.0, 2.0]), np.array([[50.0, -20.0], [-20.0, 40.0]])
    runs = [integrate(M, K, [0.2, -0.1], [1.0, 0.0], (0.0, 0.2), 1e-3, nodal_force=FunctionForce([0, 1], fn),
                      config=NewmarkConfig(tangent=t)) for t in ("bearing", "frozen")]
    np.testing.assert_array_equal(runs[0].q, runs[1].q)
    np.testing.assert_array_equal(runs[0].iterations, runs[1].iterations)


@pytest.mark.parametrize("word", NEWTON_TANGENTS)
def test_the_bearings_skip_their_jacobian_unless_the_tangent_is_theirs(word):
    internal = SpringInternal(3e5)
    b = DirectBearings([internal], [(0, 1)], 10.0, tangent=word)
    b.begin_step(0.0, 1e-4)
    f, dq, dv = b.evaluate(np.array([1e-6, -2e-6]), np.zeros(2))
    np.testing.assert_array_equal(f, [-0.3, 0.6])
    assert b.with_jacobian == (word in ("bearing", "frozen"))
    assert (dq is not None) == b.with_jacobian and (dv is not None) == b.with_jacobian
    assert internal.jacobians == int(b.with_jacobian)
