"""The Reynolds solver on bores with grooves, a partial arc or lobes (physics.bore.geometry,
geometry_kernels): derivatives against central differences, the warm start, symmetries,
limits (preload -> 0, no source, supply pressure at rest), and the full bore untouched.
The published tables are in tests/test_geometry_validation.py."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bearing_fmu.physics.bore.geometry import FULL_BORE, Geometry
from bearing_fmu.physics.params import PAPER_BEARING, BearingParams
from bearing_fmu.physics.solver.reynolds import Reynolds

P = PAPER_BEARING
OMEGA = 2 * math.pi * 50.0
D90, D270 = math.radians(90.0), math.radians(270.0)

GEOMETRIES = {
    "two grooves": Geometry(grooves=(D90, D270)),
    "grooves fed at 150 kPa": Geometry(grooves=(D90, D270), supply_pressure=150e3),
    "one groove, 37 deg, fed": Geometry(grooves=(math.radians(37.0),), groove_width=math.radians(13.0),
                                        supply_pressure=50e3),
    "partial arc 120 deg": Geometry(arc=(math.radians(120.0), math.radians(240.0))),
    "lemon": Geometry(grooves=(D90, D270), lobes=2, preload=0.5),
    "offset halves": Geometry(grooves=(D90, D270), lobes=2, preload=0.5, lobe_offset=1.0),
    "three lobes, no groove": Geometry(lobes=3, preload=0.3, lobe_angle=0.2),
}


def bearing(geo: Geometry, **kw) -> BearingParams:
    return BearingParams(kw.get("D", P.D), kw.get("L", P.L), kw.get("CR", P.CR), kw.get("mu", P.mu), geometry=geo)


def state(eps, angle, vr=0.0, vt=0.0, CR=P.CR):
    ur = np.array([math.sin(angle), -math.cos(angle)])
    ut = np.array([math.cos(angle), math.sin(angle)])
    q, v = eps * CR * ur, vr * ur + vt * ut
    return float(q[0]), float(q[1]), float(v[0]), float(v[1])


def rel(a, b):
    a, b = np.asarray(a, float), np.asarray(b, float)
    return float(np.linalg.norm(a - b) / np.linalg.norm(b))


def mirrored(g: Geometry) -> Geometry:
    """The bore seen in the mirror theta -> -theta: leading and trailing edges swap."""
    return Geometry(grooves=tuple(-c for c in g.grooves), groove_width=g.groove_width,
                    supply_pressure=g.supply_pressure,
                    arc=None if g.arc is None else (-g.arc[1], -g.arc[0]), lobes=g.lobes, preload=g.preload,
                    lobe_offset=1.0 - g.lobe_offset, lobe_angle=-g.lobe_angle)


def test_the_full_bore_is_the_original_solver_bit_for_bit():
    explicit = BearingParams(P.D, P.L, P.CR, P.mu, geometry=FULL_BORE)
    a, b = Reynolds(P, 48, 8), Reynolds(explicit, 48, 8)
    assert a._geo is None and b._geo is None
    rng = np.random.default_rng(4)
    for _ in range(10):
        s = state(rng.uniform(0, 0.95), rng.uniform(0, 6.3), *(rng.normal(size=2) * 0.01))
        fa, fb = a.force_and_jacobian(*s, OMEGA), b.force_and_jacobian(*s, OMEGA)
        assert all(np.array_equal(x, y) for x, y in zip(fa, fb))


@pytest.mark.parametrize("name", list(GEOMETRIES))
@pytest.mark.parametrize("cav", ["reynolds", "gumbel"])
def test_jacobian_matches_central_differences(name, cav):
    """Adjoint derivatives with the converged set held fixed vs central differences (steps 1e-6 CR,
    1e-6 CR omega): rel 1e-6 per column, as for the full bore. A column whose step changes the
    cavitated set (a kink of the force, the set being piecewise constant) is not compared; at
    least 14 of the 16 are."""
    r = Reynolds(bearing(GEOMETRIES[name]), 48, 8, cavitation=cav)
    rng = np.random.default_rng(2)
    checked = 0
    for _ in range(4):
        x0 = np.array(state(rng.uniform(0.05, 0.9), rng.uniform(0, 2 * math.pi),
                            *(rng.normal(size=2) * P.CR * OMEGA * 0.1)))
        F, dq, dv = r.force_and_jacobian(*x0, OMEGA)
        assert F.tolist() == list(r.force(*x0, OMEGA))
        J = np.hstack([dq, dv])
        cav0 = r.diagnostics(*x0, OMEGA)["cavitated_fraction"]
        for j in range(4):
            h = 1e-6 * P.CR * (1.0 if j < 2 else OMEGA)
            xp, xm = x0.copy(), x0.copy()
            xp[j] += h
            xm[j] -= h
            if {r.diagnostics(*xp, OMEGA)["cavitated_fraction"], r.diagnostics(*xm, OMEGA)["cavitated_fraction"]} \
                    != {cav0}:
                continue
            fd = (np.array(r.force(*xp, OMEGA)) - np.array(r.force(*xm, OMEGA))) / (2 * h)
            assert np.abs(J[:, j] - fd).max() <= 1e-6 * np.abs(fd).max(), (j, J[:, j], fd)
            checked += 1
    assert checked >= 14


def _orbit(n_steps, e0, a, whirl, dt=1e-4):
    c = e0 * P.CR * np.array([0.3, -1.0]) / math.hypot(0.3, 1.0)
    w = whirl * OMEGA
    calls = []
    for k in range(n_steps):
        t = k * dt
        q = c + a * P.CR * np.array([math.cos(w * t), math.sin(w * t)])
        v = a * P.CR * w * np.array([-math.sin(w * t), math.cos(w * t)])
        calls += [(*q, *v), (*(q + 1e-6 * P.CR), *(v * (1 + 1e-5)))]
    return calls


@pytest.mark.parametrize("name", ["two grooves", "grooves fed at 150 kPa", "partial arc 120 deg", "offset halves",
                                  "three lobes, no groove"])
def test_warm_start_gives_the_cold_result_and_saves_passes(name):
    """The LCP over the film cells has one solution whatever the start (the fixed cells are not
    part of it): warm and cold agree to 1e-12 on a Newton-like orbit and on random jumps, and
    the warm start needs fewer factorizations."""
    rng = np.random.default_rng(7)
    calls = _orbit(100, 0.5, 0.3, 1.0) + [state(rng.uniform(0, 0.95), rng.uniform(0, 6.3),
                                                *(rng.normal(size=2) * P.CR * OMEGA * 0.1)) for _ in range(40)]
    prm = bearing(GEOMETRIES[name])
    warm, cold = Reynolds(prm, 64, 8), Reynolds(prm, 64, 8, warm_start=False)
    for s in calls:
        a = np.hstack([x.ravel() for x in warm.force_and_jacobian(*s, OMEGA)])
        b = np.hstack([x.ravel() for x in cold.force_and_jacobian(*s, OMEGA)])
        assert np.all(np.abs(a - b) <= 1e-12 * np.abs(b).max())
    cw, cc = warm.counts(), cold.counts()
    assert cw["warm_starts"] > 150 and cw["cold_fallbacks"] <= 2  # a fallback is the safety net: same result
    assert cw["passes"] < 0.6 * cc["passes"], (cw, cc)


@pytest.mark.parametrize("name", list(GEOMETRIES))
def test_mirror_image(name):
    """theta -> -theta maps the bore onto its mirror image (offset -> 1 - offset) and the film
    of (y, z, vy, vz, omega) onto that of (-y, z, -vy, vz, -omega): Fy -> -Fy, Fz -> Fz."""
    g = GEOMETRIES[name]
    # 66 cells: every bore here splits them evenly over its film segments (a remainder could
    # fall on another segment in the mirror image, a different grid)
    r, m = Reynolds(bearing(g), 66, 8), Reynolds(bearing(mirrored(g)), 66, 8)
    for s in (state(0.5, 0.8, 0.1 * P.CR * OMEGA, 0.05 * P.CR * OMEGA), state(0.85, 4.0), state(0.3, 2.9)):
        y, z, vy, vz = s
        fy, fz = r.force(y, z, vy, vz, OMEGA)
        gy, gz = m.force(-y, z, -vy, vz, -OMEGA)
        assert rel([gy, gz], [-fy, fz]) < 1e-9


@pytest.mark.parametrize("name", ["two grooves", "partial arc 120 deg", "offset halves", "three lobes, no groove"])
def test_turning_bore_and_journal_together_turns_the_force(name):
    """Turning the bore's angles and the journal's state by the same angle turns the force:
    the grid turns with the edges (to round-off in the cell positions)."""
    g = GEOMETRIES[name]
    r = Reynolds(bearing(g), 66, 8)
    s0 = np.array(state(0.6, 0.3, 0.05 * P.CR * OMEGA, -0.1 * P.CR * OMEGA))
    F0 = np.array(r.force(*s0, OMEGA))
    for a in (0.7, 2.0, 4.4):
        turned = Geometry(grooves=tuple(c + a for c in g.grooves), groove_width=g.groove_width,
                          supply_pressure=g.supply_pressure,
                          arc=None if g.arc is None else (g.arc[0] + a, g.arc[1] + a), lobes=g.lobes,
                          preload=g.preload, lobe_offset=g.lobe_offset, lobe_angle=g.lobe_angle + a)
        # h = CR - e . u(theta) with u(theta) = (-sin, cos): u(theta + a) = Rot(a) u(theta) in (y, z)
        Rm = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
        F = np.array(Reynolds(bearing(turned), 66, 8).force(*(Rm @ s0[:2]), *(Rm @ s0[2:]), OMEGA))
        assert rel(F, Rm @ F0) < 1e-9


def test_preload_to_zero_is_the_circular_bore():
    """m = 0: the lemon bore with grooves is the grooved circular bore (its lobe boundaries cut
    each groove in two cells, so two more cells keep the film cells the same): equal to
    round-off; m -> 0 continuously; three lobes without grooves at m = 0 are the full bore up to
    the grid (cells of 360/129 deg from 60 deg on instead of 360/128 from 0)."""
    grooved = Reynolds(bearing(Geometry(grooves=(D90, D270))), 64, 8)
    lemon0 = Reynolds(bearing(Geometry(grooves=(D90, D270), lobes=2, preload=0.0)), 66, 8)
    lemon_small = Reynolds(bearing(Geometry(grooves=(D90, D270), lobes=2, preload=1e-7)), 66, 8)
    full = Reynolds(P)
    lobes0 = Reynolds(bearing(Geometry(lobes=3, preload=0.0)), 129, 16)
    for s in (state(0.3, 0.2), state(0.7, 3.5, 0.05 * P.CR * OMEGA), state(0.9, 1.0)):
        F = np.array(grooved.force(*s, OMEGA))
        assert rel(lemon0.force(*s, OMEGA), F) < 1e-12
        assert rel(lemon_small.force(*s, OMEGA), F) < 1e-5
        assert rel(lobes0.force(*s, OMEGA), full.force(*s, OMEGA)) < 2e-3


def test_no_source_no_supply_gives_no_force_and_the_central_difference_limit():
    """Centred and still, grooves at ambient: p = 0, F = 0, and the reported Jacobian is the
    central-difference limit (the odd part of the first-order response), as for the full bore."""
    r = Reynolds(bearing(GEOMETRIES["two grooves"]), 48, 8)
    F, dq, dv = r.force_and_jacobian(0.0, 0.0, 0.0, 0.0, 0.0)
    assert F.tolist() == [0.0, 0.0]
    J = np.hstack([dq, dv])
    Jfd = np.empty((2, 4))
    for j in range(4):
        h = 1e-7 * P.CR * (1.0 if j < 2 else OMEGA)
        xp, xm = np.zeros(4), np.zeros(4)
        xp[j], xm[j] = h, -h
        Jfd[:, j] = (np.array(r.force(*xp, 0.0)) - np.array(r.force(*xm, 0.0))) / (2 * h)
    assert np.abs(J - Jfd).max() <= 1e-6 * np.abs(Jfd).max()
    assert np.abs(dq).max() == 0.0 and np.all(np.diag(-dv) > 0)  # no rotation: squeeze damping only
    assert r.pressure(0.0, 0.0, 0.0, 0.0, 0.0)[2].max() == 0.0


def test_supply_pressure_at_rest():
    """Journal centred and still, grooves fed at p_s: the film holds p_s on the grooves and less
    between them (a diffusion problem: 0 <= p <= p_s, maximum principle). Two opposite grooves:
    no net force. One groove at the bottom: the journal is pushed up, by less than p_s over the
    projected area L D and more than p_s over the groove's own chord."""
    ps = 2e5
    two = Reynolds(bearing(Geometry(grooves=(D90, D270), supply_pressure=ps)), 64, 8)
    _, _, p = two.pressure(0.0, 0.0, 0.0, 0.0, 0.0)
    assert p.min() >= 0.0 and p.max() == ps
    grid = two.params.geometry.theta_grid(64)
    assert np.all(p[grid.fixed] == ps) and np.all(p[~grid.fixed] < ps)
    assert np.abs(two.force(0.0, 0.0, 0.0, 0.0, 0.0)).max() < 1e-9 * ps * P.L * P.D
    one = Reynolds(bearing(Geometry(grooves=(math.pi,), supply_pressure=ps)), 64, 8)
    fy, fz = one.force(0.0, 0.0, 0.0, 0.0, 0.0)
    chord = 2 * P.R * math.sin(0.5 * one.params.geometry.groove_width)
    assert abs(fy) < 1e-9 * fz and ps * P.L * chord < fz < ps * P.L * P.D
    # the supply adds to the film's pressure: at any state p >= the unfed bore's
    unfed = Reynolds(bearing(Geometry(grooves=(D90, D270))), 64, 8)
    s = state(0.6, 0.4)
    assert np.all(two.pressure(*s, OMEGA)[2] >= unfed.pressure(*s, OMEGA)[2] - 1e-9 * ps)


@pytest.mark.parametrize("name", list(GEOMETRIES))
def test_complementarity_and_pressure_field(name):
    r = Reynolds(bearing(GEOMETRIES[name]), 64, 8)
    grid = r.params.geometry.theta_grid(64)
    for s in (state(0.4, 0.3), state(0.8, 2.5, 0.02 * P.CR * OMEGA)):
        d = r.diagnostics(*s, OMEGA)
        assert d["complementarity_residual"] < 1e-11 and 0 <= d["cavitated_fraction"] < 1  # offset halves: full film
        th, _, p = r.pressure(*s, OMEGA)
        assert np.allclose(th, grid.centre) and p.shape == (64, 8) and p.min() >= 0.0
        assert np.all(p[grid.fixed] == grid.supply[grid.fixed][:, None])


def test_too_few_cells_for_the_bore_is_refused_by_name():
    g = Geometry(grooves=tuple(math.radians(a) for a in range(0, 360, 30)), groove_width=math.radians(8))
    with pytest.raises(ValueError, match=r"Reynolds: n_theta = 16 is too few cells for this bore"):
        Reynolds(bearing(g), n_theta=16)
    Reynolds(bearing(g), n_theta=36)


def test_the_wall_of_a_bore_is_its_own():
    """The journal may go as far as the bore lets it: a lemon bore (lobes at the top and bottom,
    C_pad = 2 CR) is CR away vertically and C_pad = 2 CR at the split, so |e| = 1.5 CR sideways is
    inside it and 1.001 CR downward is not; the refusal names the film closure and the bore. The
    full bore keeps its eccentricity ratio (the same float)."""
    from bearing_fmu.internals.registry import BearingStateError

    assert FULL_BORE.closure(3e-5, -4e-5, 1e-4) == math.hypot(3e-5, -4e-5) / 1e-4
    lemon = Geometry(grooves=(D90, D270), lobes=2, preload=0.5)
    r = Reynolds(bearing(lemon), 64, 8)
    side = lemon.closure(1.5 * P.CR, 0.0, P.CR)
    th = np.radians(np.arange(0.0, 360.0, 0.01))
    th = th[np.abs(np.degrees(th) % 180.0 - 90.0) >= 10.0]  # the film: off the grooves
    assert side == pytest.approx(np.max(-1.5 * np.sin(th) / lemon.base_film(th)), abs=1e-6)  # 0.866 at 240 deg
    assert np.all(np.isfinite(r.force(1.5 * P.CR, 0.0, 0.0, 0.0, OMEGA)))
    assert lemon.closure(0.0, -0.999 * P.CR, P.CR) == pytest.approx(0.999)
    with pytest.raises(BearingStateError, match=r"film closure 1\.001 >= 1: .*eccentricity ratio 1\.001\) .*2 lobes"):
        r.force(0.0, -1.001 * P.CR, 0.0, 0.0, OMEGA)
    # a partial arc at the bottom: the journal lifted 3 CR is far from any film, not at a wall
    arc = Reynolds(bearing(GEOMETRIES["partial arc 120 deg"]), 64, 8)
    assert np.all(np.isfinite(arc.force(0.0, 3 * P.CR, 0.0, 0.0, OMEGA)))


def test_offset_halves_carry_their_load_beyond_CR():
    """Downward, an offset-halves bore's film is C_pad = 2 CR thick (the lower lobe's smallest
    clearance lies in the groove at its trailing edge): the equilibrium of a heavy load lies beyond
    |e| = CR, with a positive film."""
    from bearing_fmu.physics.statics import equilibrium

    g = GEOMETRIES["offset halves"]
    prm = bearing(g)
    r = Reynolds(prm)
    y, z = equilibrium(r, (0.0, -3000.0), OMEGA)
    assert math.hypot(y, z) > 1.2 * P.CR and g.min_film(y, z, P.CR) > 0.0
    assert np.allclose(r.force(y, z, 0.0, 0.0, OMEGA), (0.0, 3000.0), rtol=0, atol=1e-5 * 3000)
