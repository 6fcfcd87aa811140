"""The film's peak pressure and its angle (``film.peak_pressure``, ``Reynolds.peak_pressure``), the
minimum film's angle (``Geometry.min_film_at``) and where they are reported (``demo``'s record, a
run's record). Each expected value says where it comes from."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from bearing_fmu.physics.bore.geometry import Geometry
from bearing_fmu.physics.operating import operating_point
from bearing_fmu.physics.params import PAPER_BEARING, BearingParams
from bearing_fmu.physics.solver.reynolds import Reynolds

OMEGA = 100.0  # rad/s


def ocvirk_peak(prm: BearingParams, eps: float) -> tuple[float, float]:
    """The short-bearing (Ocvirk) closed form, journal straight below the centre: p = 3 mu omega / c^2
    (L^2/4 - x^2) eps sin(phi) / (1 + eps cos(phi))^3, phi from the thickest film (theta = 0 here);
    its maximum at x = 0, cos(phi) = (1 - sqrt(1 + 24 eps^2)) / (4 eps) (Hamrock, Fundamentals of
    Fluid Film Lubrication, ch. 10; d/dphi of the above set to 0)."""
    phi = math.acos((1.0 - math.sqrt(1.0 + 24.0 * eps * eps)) / (4.0 * eps))
    p = 3.0 * prm.mu * OMEGA / prm.CR ** 2 * prm.L ** 2 / 4.0 * eps * math.sin(phi) / (1.0 + eps * math.cos(phi)) ** 3
    return p, phi


@pytest.mark.parametrize("eps", [0.3, 0.6])
def test_short_bearing_limit(eps):
    """The finite bearing's peak tends to Ocvirk's as L/D -> 0, its error falling as (L/D)^2 (the
    short-bearing theory drops the circumferential flow, of relative size (L/D)^2): within 1 % and
    0.15 deg at L/D = 0.05, and the error at L/D = 0.1 three to five times the one at 0.05."""
    errs = []
    for ld in (0.1, 0.05):
        prm = BearingParams(D=0.1, L=0.1 * ld, CR=1e-4, mu=0.01)
        p, th = Reynolds(prm, n_theta=256, n_x=16).peak_pressure(0.0, -eps * prm.CR, 0.0, 0.0, OMEGA)
        p_ref, th_ref = ocvirk_peak(prm, eps)
        errs.append(p / p_ref - 1.0)
        if ld == 0.05:
            assert abs(errs[-1]) < 0.01 and abs(math.degrees(th - th_ref)) < 0.15, (p, p_ref, th, th_ref)
    assert 3.0 < errs[0] / errs[1] < 5.0, errs


@pytest.mark.parametrize("eps", [0.4, 0.8, 0.9, 0.97])
def test_refined_peak_against_a_fine_grid(eps):
    """Against the 512 x 64 grid's peak (the reference: it moves < 0.1 % from 256 x 32), a coarse
    grid's refined peak is within 5 % at 64 x 8 and 1 % at 128 x 16; up to eps 0.8, where the coarse
    field itself is accurate, it is closer than the largest cell value (which lies O(dtheta^2 + dx^2)
    below the field's maximum); beyond, the coarse field's own error dominates."""
    prm = BearingParams(D=0.1, L=0.1, CR=1e-4, mu=0.01)
    state = (0.0, -eps * prm.CR, 0.0, 0.0, OMEGA)
    ref = Reynolds(prm, n_theta=512, n_x=64).peak_pressure(*state)[0]
    for (nt, nx), tol in (((64, 8), 0.05), ((128, 16), 0.01)):
        r = Reynolds(prm, n_theta=nt, n_x=nx)
        peak, cell = r.peak_pressure(*state)[0], r.pressure(*state)[2].max()
        assert abs(peak / ref - 1) < tol, (nt, peak, ref)
        if eps <= 0.8:
            assert abs(peak / ref - 1) < abs(cell / ref - 1), (nt, peak, cell, ref)


def test_peak_turns_with_the_journal():
    """Symmetry of the full bore: the journal's displacement turned by a whole number of cells turns
    the peak by as much, at the same value (to round-off); the peak lies upstream of the minimum film
    (the converging film builds the pressure, theta increasing with the rotation)."""
    prm, n = BearingParams(D=0.1, L=0.1, CR=1e-4, mu=0.01), 128
    r = Reynolds(prm, n_theta=n, n_x=16)
    e = 0.7 * prm.CR
    base = None
    for k in (0, 16, 37):
        a = k * 2.0 * math.pi / n  # the journal at (y, z) = e (-sin a, cos a) ... turned by a
        y, z = -e * math.sin(math.pi + a), e * math.cos(math.pi + a)
        p, th = r.peak_pressure(y, z, 0.0, 0.0, OMEGA)
        h, th_min = prm.geometry.min_film_at(y, z, prm.CR)
        assert h == pytest.approx(prm.CR - e, rel=1e-12)
        assert math.degrees((th_min - a) % (2 * math.pi)) == pytest.approx(180.0, abs=1e-9)
        assert 0.0 < (th_min - th) % (2 * math.pi) < math.pi / 2
        if base is None:
            base = (p, th)
        else:
            assert p == pytest.approx(base[0], rel=1e-9)
            assert (th - base[1] - a + math.pi) % (2 * math.pi) - math.pi == pytest.approx(0.0, abs=1e-9)


def test_min_film_angle_of_a_lobed_bore():
    """A lemon bore's minimum film found by sampling lies where the sampled film is smallest and
    equals ``min_film``."""
    g = Geometry(lobes=2, preload=0.5)
    h, th = g.min_film_at(10e-6, -20e-6, 1e-4)
    assert h == g.min_film(10e-6, -20e-6, 1e-4)
    hh = 1e-4 * g.base_film(np.array([th]))[0] + 10e-6 * math.sin(th) + 20e-6 * math.cos(th)
    assert hh == pytest.approx(h, rel=1e-12)


def test_demo_record_keys():
    """``demo``'s record: the peak above the unit load W / (L D) (a film carries the load on part of
    the bore), its angle upstream of the minimum film; a map's record gives the Reynolds field's peak at
    its own equilibrium."""
    rec = operating_point(PAPER_BEARING, (0.0, -16.7), 22.0)
    assert rec["peak_pressure_Pa"] > rec["unit_load_Pa"] > 0.0
    up = (rec["min_film_deg"] - rec["peak_pressure_deg"]) % 360.0
    assert 0.0 < up < 90.0
    assert json.dumps({k: rec[k] for k in ("peak_pressure_Pa", "peak_pressure_deg", "min_film_deg")})


def test_run_record_peak_at_the_closest_approach():
    """``run_record.peak_pressures`` reads the recorded state of largest eccentricity and gives the
    Reynolds field's peak there (checked against a direct solve at that state)."""
    from rotor_host.scenes.run_record import peak_pressures

    prm = PAPER_BEARING
    t = np.array([0.0, 0.1, 0.2])
    y = np.array([[1e-6, 5e-6], [10e-6, 0.0], [2e-6, 0.0]])
    z = np.array([[-5e-6, 0.0], [-30e-6, 0.0], [-6e-6, 0.0]])
    v = np.zeros_like(y)
    arrays = {"t": t, "nodes": np.array([3, 7]), "bearing_nodes": np.array([3]), "y": y, "z": z, "vy": v, "vz": v,
              "eccentricity": (np.hypot(y[:, 0], z[:, 0]) / prm.CR)[:, None], "speed_hz": np.full(3, 22.0)}
    out = peak_pressures([prm], arrays)
    p, th = Reynolds(prm).peak_pressure(10e-6, -30e-6, 0.0, 0.0, 2 * math.pi * 22.0)
    assert out["peak_pressure_Pa"] == [p] and out["peak_pressure_t_s"] == [0.1]
    assert out["peak_pressure_deg"][0] == pytest.approx(math.degrees(th))
    arrays["y"][1, 0] = 2 * prm.CR  # beyond the bore: said, not a crash
    arrays["eccentricity"] = (np.hypot(y[:, 0], z[:, 0]) / prm.CR)[:, None]
    out = peak_pressures([prm], arrays)
    assert out["peak_pressure_Pa"] == [None] and "bearing 1" in out["peak_pressure_note"]
