"""The native FMU's Reynolds solver (bearing_fmu/fmu/native/c/reynolds_solver.c) against the
Python internal (bearing_fmu/physics/solver/reynolds.py, the numba kernels it ports line by line).

The expected values are the Python solver's own at the same state, grid, cavitation model and
bore: force and Jacobian within 1e-10 relative (issue 24) at random states (eccentricity, or
closure for the other bores, 0.05-0.97, any attitude, velocities up to omega CR), the same
active-set passes along a replayed transient (the warm start makes the same decisions). The C
library is compiled once (zig) and kept in pytest's cache folder, named by a hash of its sources.
"""

import math

import numpy as np
import pytest

from bearing_fmu.fmu.native.solver_lib import NativeReynolds, solver_library
from bearing_fmu.physics.bore.geometry import Geometry
from bearing_fmu.physics.params import BearingParams
from bearing_fmu.physics.solver.reynolds import Reynolds

RTOL = 1e-10  # issue 24: force and Jacobian within 1e-10 relative
PAPER = dict(D=0.031, L=0.02, CR=90e-6, mu=0.05)  # paper Table 2
BORES = {
    "full": Geometry(),
    "grooves with supply": Geometry(grooves=(math.pi / 2, 3 * math.pi / 2), supply_pressure=80e3),
    "lemon": Geometry(grooves=(math.pi / 2, 3 * math.pi / 2), lobes=2, preload=0.5),
    "partial arc": Geometry(arc=(math.radians(100.0), math.radians(260.0))),
    "offset halves": Geometry(grooves=(math.pi / 2, 3 * math.pi / 2), lobes=2, preload=0.4, lobe_offset=1.0),
    "three lobes": Geometry(lobes=3, preload=0.3, lobe_angle=0.2),
}


@pytest.fixture(scope="session")
def lib(request, tmp_path_factory):
    cache = getattr(request.config, "cache", None)
    folder = cache.mkdir("native-reynolds") if cache is not None else tmp_path_factory.mktemp("native_reynolds")
    return solver_library(folder)


def random_states(params: BearingParams, n: int, seed: int):
    """(y, z, vy, vz, omega): closure (the eccentricity ratio of the full bore) uniform in
    0.05-0.97, attitude uniform, velocities uniform up to omega CR, omega 20-600 rad/s."""
    rng = np.random.default_rng(seed)
    g, CR = params.geometry, params.CR
    out = []
    while len(out) < n:
        phi = rng.uniform(0.0, 2.0 * math.pi)
        unit = g.closure(CR * math.cos(phi), CR * math.sin(phi), CR)  # closure of |e| = CR in that direction
        if unit < 0.2:  # a direction that never closes the film (away from a partial arc)
            continue
        r = rng.uniform(0.05, 0.97) / unit * CR
        omega = rng.uniform(20.0, 600.0)
        vy, vz = rng.uniform(-1.0, 1.0, 2) * omega * CR
        out.append((r * math.cos(phi), r * math.sin(phi), vy, vz, omega))
    return out


def worst_difference(py, c, states) -> float:
    """The largest relative difference of F, dF/dq, dF/dv (each against its own largest entry)."""
    worst = 0.0
    for s in states:
        a = py.force_and_jacobian(*s)
        b = c.force_and_jacobian(*s)
        for x, ref in zip(b, a):
            scale = np.max(np.abs(ref))
            worst = max(worst, float(np.max(np.abs(x - ref)) / scale) if scale > 0 else float(np.max(np.abs(x))))
    return worst


def both(lib, geometry, grid, cavitation, warm_start=True):
    params = BearingParams(**PAPER, geometry=geometry)
    return (params, Reynolds(params, *grid, cavitation=cavitation, warm_start=warm_start),
            NativeReynolds(lib, params, *grid, cavitation=cavitation, warm_start=warm_start))


@pytest.mark.parametrize("cavitation", ["reynolds", "gumbel"])
def test_small_grid_random_states(lib, cavitation):
    params, py, c = both(lib, BORES["full"], (16, 4), cavitation)
    assert worst_difference(py, c, random_states(params, 60, 1)) <= RTOL
    assert c.counts() == py.counts()


@pytest.mark.slow
@pytest.mark.parametrize("cavitation", ["reynolds", "gumbel"])
def test_small_grid_1000_states(lib, cavitation):
    """Issue 24's comparison at a small grid: 1000 random states (the benchmark's at 32 x 4 .. 128 x 16)."""
    params, py, c = both(lib, BORES["full"], (16, 4), cavitation)
    assert worst_difference(py, c, random_states(params, 1000, 11)) <= RTOL
    assert c.counts() == py.counts()


@pytest.mark.parametrize("bore", ["grooves with supply", "lemon", "partial arc"])
def test_small_grid_bores(lib, bore):
    params, py, c = both(lib, BORES[bore], (24, 4), "reynolds")
    assert worst_difference(py, c, random_states(params, 15, 2)) <= RTOL


@pytest.mark.parametrize("state", [(0.0, 0.0, 0.0, 0.0, 100.0), (2e-5, -3e-5, 50.0 * -3e-5, -50.0 * 2e-5, 100.0)],
                         ids=["centred and still", "half-speed whirl"])
def test_no_source(lib, state):
    """No source at all: the odd part of the first-order response (reynolds.py, Derivatives)."""
    for cavitation in ("reynolds", "gumbel"):
        _params, py, c = both(lib, BORES["full"], (16, 4), cavitation)
        a, b = py.force_and_jacobian(*state), c.force_and_jacobian(*state)
        assert np.max(np.abs(a[1])) > 0.0  # the state has a stiffness: the comparison is not 0 == 0
        for x, ref in zip(b, a):
            np.testing.assert_allclose(x, ref, rtol=0.0, atol=RTOL * max(np.max(np.abs(ref)), 1e-300))


def test_replayed_transient_same_passes(lib):
    """An orbit replayed through both with the warm start: the same passes and the same starts
    (warm, cold fallbacks), call by call, and the same forces."""
    params, py, c = both(lib, BORES["full"], (32, 4), "reynolds")
    omega, CR = 2 * math.pi * 22.0, params.CR
    whirl = 0.3 * omega  # forward whirl, slower than half speed (at half speed the source vanishes)
    for k in range(60):
        t = k * 2e-4
        r = CR * (0.5 + 0.3 * math.sin(40.0 * t))
        y, z = r * math.cos(whirl * t), r * math.sin(whirl * t)
        vy, vz = -whirl * z, whirl * y
        for newton in range(2):  # a Newton iterate near the step's state
            s = (y * (1 + 1e-3 * newton), z, vy, vz, omega)
            a, b = py.force_and_jacobian(*s), c.force_and_jacobian(*s)
            assert c.counts() == py.counts()
            np.testing.assert_allclose(b[0], a[0], rtol=RTOL)
    assert py.counts()["warm_starts"] > 60  # the warm start was exercised


@pytest.mark.slow
@pytest.mark.parametrize("cavitation", ["reynolds", "gumbel"])
@pytest.mark.parametrize("grid", [(32, 4), (64, 8), (128, 16)])
def test_three_grids_random_states(lib, grid, cavitation):
    params, py, c = both(lib, BORES["full"], grid, cavitation)
    assert worst_difference(py, c, random_states(params, 300, 3)) <= RTOL
    assert c.counts() == py.counts()


@pytest.mark.slow
@pytest.mark.parametrize("cavitation", ["reynolds", "gumbel"])
@pytest.mark.parametrize("bore", [b for b in BORES if b != "full"])
def test_every_bore(lib, bore, cavitation):
    params, py, c = both(lib, BORES[bore], (64, 8), cavitation)
    assert worst_difference(py, c, random_states(params, 100, 4)) <= RTOL


@pytest.mark.parametrize("bore", ["full", "lemon"])
@pytest.mark.parametrize("cavitation", ["reynolds", "gumbel"])
def test_omega_derivative(lib, bore, cavitation):
    """dF/domega (the FMU's directional derivative along omega) against central differences of
    the Python force, step 1e-6 omega (the active set does not change within it)."""
    params, py, c = both(lib, BORES[bore], (24, 4), cavitation)
    for s in random_states(params, 5, 5):
        h = 1e-6 * s[4]
        fp = np.array(py.force(*s[:4], s[4] + h))
        fm = np.array(py.force(*s[:4], s[4] - h))
        fd = (fp - fm) / (2 * h)
        np.testing.assert_allclose(c.omega_derivative(*s), fd, rtol=0, atol=1e-6 * np.max(np.abs(fd)))


def test_grid_too_coarse_for_the_bore(lib):
    params = BearingParams(**PAPER, geometry=Geometry(grooves=tuple(math.radians(a) for a in (0, 90, 180, 270)),
                                                      groove_width=math.radians(10.0)))
    with pytest.raises(ValueError, match="n_theta = 10 is too few cells for this bore: it needs at least 12"):
        NativeReynolds(lib, params, 10, 4)
