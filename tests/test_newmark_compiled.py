"""The integrator's banded linear algebra and its compiled driver (rotor_host.integrate.banded,
newmark_loop) against what they replace.

The banded LU and products are checked against dense numpy on the paper rotor's own step
matrix (gyroscopic, non-symmetric). The compiled driver is checked against the Python driver
(``NewmarkConfig(compiled=False)``) on the same problem: the same kernels in the same order, so
the orbits, forces and Newton statistics must be identical to the bit, also when steps go
back to Python (a state the force refuses, a Newton failure that is cut). The static
equilibrium of the paper rotor cut into 160 elements is checked against the 10-element one:
on two bearings the shaft is statically determinate, so the journals carry the same loads and
sit at the same place whatever the mesh.
"""

import math
from pathlib import Path

import numpy as np
import pytest
from numba import carray, cfunc

from bearing_fmu.internals.compiled import KERNEL_SIG, CompiledForce, evaluate
from bearing_fmu.internals.map.forcemap import ForceMap
from bearing_fmu.internals.map.tablefile import load_map
from bearing_fmu.internals.linear import Linear
from rotor_host.coupling.bearings import DirectBearings
from rotor_host.integrate.banded import BandLU, band_matvec, bandwidth, from_band, to_band
from rotor_host.integrate.equilibrium import static_equilibrium
from rotor_host.integrate.forces import StepRejected
from rotor_host.integrate.loads import RotatingLoads
from rotor_host.integrate.newmark import IntegrationError, Newmark, NewmarkConfig
from rotor_host.model.rotor import Rotor

ROOT = Path(__file__).resolve().parents[1]
OMEGA = 2 * math.pi * 22.0
G = 9.81


@pytest.fixture(scope="module")
def rotor():
    return Rotor.from_toml(ROOT / "rotor_host" / "bundled" / "rotor_paper.toml")


def _pairs(rotor):
    return [(rotor.dof(n, "y"), rotor.dof(n, "z")) for n in rotor.bearing_nodes]


def _loads(rotor, omega=OMEGA, t_on=0.0):
    """Weight plus the paper's unbalance (8.5 g at 37 mm on the disk, node 6)."""
    disk = rotor.disks[0].node
    return RotatingLoads(rotor.weight_vector(G), [(rotor.dof(disk, "y"), rotor.dof(disk, "z"), 8.5e-3 * 37e-3,
                                                  0.0, t_on)], omega)


_MAP = []


def _map_bearings(rotor):
    if not _MAP:  # the shipped map, read and fitted once
        _MAP.append(load_map(ROOT / "rotor_host" / "bundled" / "maps" / "paper_bearing.json"))
    return DirectBearings([ForceMap(p, _MAP[0]) for p in rotor.bearings], _pairs(rotor), OMEGA)


def _run(rotor, bearings, q0, compiled, t_end=0.02, **cfg):
    integ = Newmark(rotor.M, rotor.K, rotor.C, rotor.G, OMEGA, _loads(rotor), bearings,
                    NewmarkConfig(compiled=compiled, **cfg))
    plan = integ._compiled_plan()
    assert (plan is not None) == compiled
    try:
        return integ.run(q0, np.zeros(rotor.n_dof), 0.0, t_end, 1e-4, record_every=3, progress_every=7)
    except IntegrationError as exc:
        return exc


def _assert_same(a, b):
    for key in ("t", "q", "v", "f_nl", "iterations"):
        np.testing.assert_array_equal(getattr(a, key), getattr(b, key), err_msg=key)
    assert (a.n_evaluations, a.n_cuts, a.status) == (b.n_evaluations, b.n_cuts, b.status)


# ------------------------------------------------------------------------------- banded

def test_banded_step_matrix_against_dense(rotor):
    h, c0, c1 = 1e-4, 4.0 / 1e-8, 2.0 / 1e-4  # average acceleration: c0 = 1 / (beta h^2), c1 = gamma / (beta h)
    S = c0 * rotor.M + c1 * (rotor.C + OMEGA * rotor.G) + rotor.K
    w = bandwidth(rotor.M, rotor.K, rotor.C, rotor.G)
    assert w == 7  # 4 DOFs per node, neighbours only (rotor_host/model/rotor.py)
    np.testing.assert_array_equal(from_band(to_band(S, w)), S)
    x = np.random.default_rng(1).standard_normal(rotor.n_dof)
    y = np.empty_like(x)
    band_matvec(to_band(S, w), x, y)
    np.testing.assert_allclose(y, S @ x, rtol=0, atol=1e-14 * np.abs(S).max() * np.abs(x).max() * rotor.n_dof)
    got = BandLU(S, w).solve(x)
    want = np.linalg.solve(S, x)
    assert np.linalg.norm(got - want) <= 1e-13 * np.linalg.cond(S) * np.linalg.norm(want)
    assert np.linalg.norm(S @ got - x) <= 1e-14 * np.linalg.norm(S, 1) * np.linalg.norm(got)
    with pytest.raises(ValueError, match="M is singular"):
        BandLU(np.diag([1.0, 0.0, 1.0]), 0, "M")


def test_rotating_loads_are_the_unbalance_formula():
    f0 = np.array([0.0, -1.0, 0.0, 0.0])
    loads = RotatingLoads(f0, [(0, 1, 3e-4, 0.5, 0.01)], 100.0)
    np.testing.assert_array_equal(loads(0.005), f0)  # before t_on
    t = 0.02
    want = f0 + 3e-4 * 100.0 ** 2 * np.array([math.cos(100.0 * t + 0.5), math.sin(100.0 * t + 0.5), 0.0, 0.0])
    np.testing.assert_allclose(loads(t), want, rtol=1e-15, atol=1e-15)


# ------------------------------------------------------------------------------- compiled driver

def test_compiled_map_run_equals_the_python_driver(rotor):
    q0 = np.zeros(rotor.n_dof)
    a = _run(rotor, _map_bearings(rotor), q0, True, t_end=0.006)
    b = _run(rotor, _map_bearings(rotor), q0, False, t_end=0.006)
    _assert_same(a, b)
    assert a.mean_iterations > 1.5  # a nonlinear start: Newton at work, not the predictor alone


def test_compiled_linear_two_speeds_of_alpha(rotor):
    m = _map_bearings(rotor).internals[0]
    lin = [Linear.at_load(m, (0.0, -16.7), OMEGA) for _ in rotor.bearings]
    for alpha in (0.0, -0.1):
        a = _run(rotor, DirectBearings(lin, _pairs(rotor), OMEGA), np.zeros(rotor.n_dof), True, alpha=alpha)
        b = _run(rotor, DirectBearings(lin, _pairs(rotor), OMEGA), np.zeros(rotor.n_dof), False, alpha=alpha)
        _assert_same(a, b)


def test_newton_failures_go_back_to_python_and_are_cut_the_same(rotor):
    # released at 0.3 CR below the centre with two corrections allowed: the first steps need
    # more, fail and are halved, then the run goes on compiled
    q0 = np.zeros(rotor.n_dof)
    q0[[d for p in _pairs(rotor) for d in p]] = [0.0, -0.3 * rotor.bearings[0].CR] * len(rotor.bearing_nodes)
    a = _run(rotor, _map_bearings(rotor), q0, True, t_end=0.006, max_iter=2)
    b = _run(rotor, _map_bearings(rotor), q0, False, t_end=0.006, max_iter=2)
    assert a.n_cuts > 5
    _assert_same(a, b)


@pytest.mark.parametrize("rotor_file", ["rotor_paper.toml", "rotor_paper_lemon.toml"])
def test_compiled_reynolds_run_equals_the_python_driver(rotor_file):
    # the solver's own kernel on its instance's arrays (internals/reynolds/force.py), its warm start
    # carried between the compiled and the Python calls: released 0.3 CR below the centre with two
    # corrections allowed, so steps fail, go back to Python and are cut (the plain and the lemon bore)
    from bearing_fmu.physics.solver.reynolds import Reynolds

    rot = Rotor.from_toml(ROOT / "rotor_host" / "bundled" / rotor_file)
    q0 = np.zeros(rot.n_dof)
    q0[[d for p in _pairs(rot) for d in p]] = [0.0, -0.3 * rot.bearings[0].CR] * len(rot.bearing_nodes)
    runs = []
    for compiled in (True, False):
        b = DirectBearings([Reynolds(p) for p in rot.bearings], _pairs(rot), OMEGA)
        runs.append((_run(rot, b, q0, compiled, t_end=0.004, max_iter=2), [i.counts() for i in b.internals]))
    (a, ca), (b, cb) = runs
    assert a.n_cuts > 0
    _assert_same(a, b)
    # every solve counted on the instance, the compiled ones too (a step handed back to Python is
    # solved again there: more calls, the same results)
    assert all(c["calls"] == b.n_evaluations for c in cb)
    assert all(c["calls"] >= a.n_evaluations and c["passes"] >= c["calls"] for c in ca)


YLIM = 2e-6  # m: the test spring refuses y beyond it


@cfunc(KERNEL_SIG)
def _spring_kernel(dp, y, z, vy, vz, omega, op):
    d = carray(dp, 3)
    if y > YLIM:
        return 1
    out = carray(op, 10)
    k, k3, c = d[0], d[1], d[2]
    out[0] = -k * y - k3 * y * y * y - c * vy
    out[1] = -k * z - k3 * z * z * z - c * vz
    for i in range(8):
        out[2 + i] = 0.0
    out[2] = -k - 3.0 * k3 * y * y
    out[7] = -k - 3.0 * k3 * z * z
    out[4] = -c
    out[9] = -c
    return 0


class _Springs(DirectBearings):
    """Cubic springs with dampers at the bearings, refusing y > YLIM, in Python and compiled."""

    def __init__(self, rotor, k=2e6, k3=1e17, c=300.0):
        super().__init__([object()] * len(rotor.bearings), _pairs(rotor), OMEGA)
        self.par = np.array([k, k3, c])

    def _bearing(self, k, y, z, vy, vz):
        status, F, dq, dv = evaluate(CompiledForce(_spring_kernel, self.par), y, z, vy, vz, self.omega)
        if status:
            raise StepRejected(f"y = {y:.3g} m > {YLIM:g} m")
        return F, dq, dv

    def compiled(self):
        return tuple(CompiledForce(_spring_kernel, self.par) for _ in range(self.n)), self.omega


def test_a_refused_state_goes_back_to_python_and_fails_the_same(rotor):
    q0 = np.zeros(rotor.n_dof)
    a = _run(rotor, _Springs(rotor), q0, True, t_end=0.05)
    b = _run(rotor, _Springs(rotor), q0, False, t_end=0.05)
    assert isinstance(a, IntegrationError) and isinstance(b, IntegrationError)
    assert str(a) == str(b) and a.t == b.t and "y = " in str(a)
    _assert_same(a.result, b.result)
    assert a.result.t.size > 10  # it ran compiled for a while before the wall


@pytest.mark.slow
def test_equilibrium_of_the_rotor_in_160_elements(rotor):
    # ~1 s: two equilibria with the map; the fine one failed its tolerance before the residual
    # was scaled by |K| |q| (rotor_host/integrate/equilibrium.py)
    def journals(r):
        f = r.weight_vector(G)
        q0 = np.zeros(r.n_dof)
        q0[[d for p in _pairs(r) for d in p]] = [0.0, -4e-6] * len(r.bearing_nodes)
        q = static_equilibrium(r.K, f, _map_bearings(r), q0)
        return q[[d for p in _pairs(r) for d in p]]

    coarse, fine = journals(rotor), journals(rotor.refined(16))
    assert rotor.refined(16).n_dof == 644
    np.testing.assert_allclose(fine, coarse, rtol=1e-7, atol=1e-7 * np.abs(coarse).max())


@pytest.mark.slow
@pytest.mark.filterwarnings("ignore:state outside the surrogate's fitted domain")  # the run's own, counted below
def test_taylor_scene_with_excursions_equals_the_python_driver(paper_scene, monkeypatch):
    # ~1 s: 40 g of unbalance drives the 22 Hz surrogate out of its fitted domain (two warned
    # excursions, then a state beyond domain_limit ends the run): the compiled kernel answers
    # inside, the guard outside, and the run is the Python driver's to the bit
    import functools

    from rotor_host.scenes import run as scene_run
    from rotor_host.scenes.scene import load_scene

    surrogate = ROOT / "rotor_host" / "bundled" / "surrogates" / "paper_22hz_16.7N.json"
    scene = load_scene(paper_scene(internal="taylor", taylor={"surrogate": str(surrogate)}, unbalance_g=40.0,
                                   t_end=0.05))
    runs = []
    for compiled in (True, False):
        monkeypatch.setattr(scene_run, "NewmarkConfig", functools.partial(NewmarkConfig, compiled=compiled))
        runs.append(scene_run.run_scene(scene, None))
    a, b = runs
    for key in ("t", "y", "z", "vy", "vz", "Fy", "Fz"):
        np.testing.assert_array_equal(a.arrays[key], b.arrays[key], err_msg=key)
    for key in ("status", "message", "internal_warnings", "force_evaluations", "step_cuts", "out_of_domain_fraction"):
        assert a.meta[key] == b.meta[key], key
    assert a.meta["internal_warnings"]["count"] == 2 and a.meta["status"] == "failed"
