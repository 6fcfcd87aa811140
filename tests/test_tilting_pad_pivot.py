"""Tilting pads on flexible pivots (``pivot_stiffness_N_m``: each pad's radial displacement u_k against
its pivot spring k_p, bearing_fmu/physics/bore/pads.py, *A flexible pivot*), on coarse grids.

Where the expected values come from:
(a) k_p -> infinity is the rigid pivot: the reduced coefficients approach the rigid ones with an error
    that falls as 1/k_p (a pivot spring in series with the film: the compliance 1/k_p adds);
(b) the series law at one state, computed independently: each pad's film stiffness with its tilt
    condensed, taken from the RIGID model with the journal shifted by the pad's own u_k (a radial pad
    displacement is a journal shift along its pivot line), put in series with k_p along the pivot line
    (K_k - K_k s s^T K_k / (s^T K_k s + k_p): 1 / (s^T K s) = 1 / k_film + 1 / k_p exactly), and summed
    over the pads, is the flexible model's journal stiffness (all 2N pad coordinates condensed at once);
    and that stiffness is the finite-difference slope of the flexible model's own nonlinear statics;
(c) each pad's film load on its pivot is k_p u_k (the pad's radial balance) to 1e-9.
"""

import json
from pathlib import Path
import math
from dataclasses import replace

import numpy as np
import pytest

from bearing_fmu.internals.tilting_pad.tilting_pad import TiltingPad
from bearing_fmu.physics.bore.geometry import Geometry
from bearing_fmu.physics.bore.pads import PadGeometry
from bearing_fmu.physics.params import BearingParams

GRID = dict(n_theta=24, n_x=4)
OMEGA = 2 * math.pi * 50.0


def bearing(kp=None, pivots=(0.0, 90.0, 180.0, 270.0), arc=80.0, preload=0.3, inertia=0.0):
    """A load-on-pad 4-pad bearing (the weight down on the pad at 180 deg)."""
    pads = PadGeometry(pivots=tuple(math.radians(p) for p in pivots), arc=math.radians(arc), offset=0.5,
                       preload=preload, inertia=inertia, pivot_stiffness=kp)
    return BearingParams(D=0.1, L=0.05, CR=75e-6, mu=0.02, geometry=Geometry(pads=pads))


def point(kp, load=(0.0, -2000.0), **kw):
    tp = TiltingPad(bearing(kp, **kw), **GRID)
    y, z = tp.journal_equilibrium(load, OMEGA)
    return tp, (y, z), tp.coefficients(y, z, OMEGA)


def test_the_pad_frame_film_is_the_derived_film_with_the_pads_radial_displacement():
    # physics/bore/pads.py: h = C_pad - d cos(t - tp) + y sin t - z cos t - delta a sin(t - tp) + u cos(t - tp),
    # the outward pad's film written out in the bearing's frame, against the pad frame's at the equivalent state
    from bearing_fmu.internals.tilting_pad.assembly import PadAssembly

    p = bearing(1e9, pivots=(10.0, 100.0, 190.0, 280.0), preload=0.4)
    A = PadAssembly(p, **GRID)
    pg, CR, R = p.geometry.pads, p.CR, p.R
    Cp = pg.pad_clearance(CR)
    frame = A.pad_params.geometry
    y, z, delta, u = 12e-6, -30e-6, 2e-4, 7e-6
    for k in range(pg.n):
        lead, trail = pg.span(k)
        th = np.linspace(lead, trail, 41)
        tp = pg.pivots[k]
        want = (Cp - (Cp - CR) * np.cos(th - tp) + y * np.sin(th) - z * np.cos(th)
                - delta * (R + Cp) * np.sin(th - tp) + u * np.cos(th - tp))
        yp, zp, _, _ = A.frame_state(k, (y, z), (0.0, 0.0), delta, 0.0, u)
        thp = th + pg.frame_angle(k)
        got = CR * frame.base_film(thp, np.zeros(th.shape, int)) + yp * np.sin(thp) - zp * np.cos(thp)
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-12 * CR)


def test_the_demo_minimum_film_is_the_closed_form_film_of_its_pads():
    # the record's h_min against the film above evaluated on each pad at the record's tilts and displacements
    from bearing_fmu.internals.tilting_pad.operating import operating_point

    p = bearing(3e8)
    rec = operating_point(p, (0.0, -2000.0), 50.0, **GRID)
    pg, CR, R = p.geometry.pads, p.CR, p.R
    Cp = pg.pad_clearance(CR)
    y, z, pads = rec["y0_m"], rec["z0_m"], rec["pads"]
    h = []
    for k in range(pg.n):
        th = np.linspace(*pg.span(k), 20001)
        tp, delta, u = pg.pivots[k], pads["rotation_rad"][k], pads["pivot_deflection_m"][k]
        h.append(np.min(Cp - (Cp - CR) * np.cos(th - tp) + y * np.sin(th) - z * np.cos(th)
                        - delta * (R + Cp) * np.sin(th - tp) + u * np.cos(th - tp)))
    assert rec["h_min_m"] == pytest.approx(min(h), rel=1e-6)


def test_a_stiff_pivot_tends_to_the_rigid_pivot_as_one_over_k_p():
    _, (y0, z0), rigid = point(None)
    errs = []
    for kp in (1e10, 1e11, 1e12):
        _, (y, z), co = point(kp)
        errs.append((np.linalg.norm(co["K"] - rigid["K"]) / np.linalg.norm(rigid["K"]),
                     np.linalg.norm(co["C"] - rigid["C"]) / np.linalg.norm(rigid["C"]),
                     math.hypot(y - y0, z - z0) / 75e-6))
    errs = np.array(errs)
    assert np.all(errs[0] < 0.05)
    # each decade of k_p: the error 10x smaller (first order in 1/k_p), the ratio tending to 10 as the
    # second-order term fades (measured: 11.2, 9.9, 9.99 at 1e10 and 10.1, 9.99, 9.999 at 1e11)
    ratio = errs[:-1] / errs[1:]
    np.testing.assert_allclose(ratio[0], 10.0, rtol=0.15)
    np.testing.assert_allclose(ratio[1], 10.0, rtol=0.02)
    assert np.all(np.abs(ratio[1] - 10.0) <= np.abs(ratio[0] - 10.0))


def test_the_pivot_loads_are_k_p_u_and_the_pads_moments_zero():
    kp = 2e8
    tp, _, co = point(kp)
    sol = co["solution"]
    P = sol.pivot_loads(tp.pads.s)
    assert P.max() > 500.0  # the loaded pad carries most of the 2000 N
    np.testing.assert_allclose(P, kp * sol.u, rtol=0, atol=1e-9 * P.max())
    assert np.max(np.abs(sol.M)) <= 1e-9 * P.max() * tp.pads.arm
    # the coordinates: (y, z, delta_1..4, u_1..4), k_p on the u diagonals with the film's radial stiffness
    assert co["K_full"].shape == (10, 10) and tp.pads.coordinate_names()[6:] == [f"u_{k} [m]" for k in range(1, 5)]
    assert np.all(np.diag(co["K_full"])[6:] > kp)


def test_the_series_law_at_one_state_and_the_statics_slope():
    kp = 3e8
    flex, (y, z), co = point(kp)
    sol = co["solution"]
    K_flex = -flex.pads.quasi_static_jacobian(sol)[0]  # all 2N pad coordinates condensed (zero frequency)
    rigid = TiltingPad(bearing(None), **GRID).pads
    a, total = rigid.arm, np.zeros((2, 2))
    for k in range(4):
        s = flex.pads.s[k]
        # the rigid pad k with the journal shifted by u_k s_k: the same film (its tilt the flexible pad's)
        r = rigid.equilibrate(y + sol.u[k] * s[0], z + sol.u[k] * s[1], 0.0, 0.0, OMEGA)
        assert r.delta[k] == pytest.approx(sol.delta[k], abs=1e-9 * abs(sol.delta).max())
        J, t = r.Jq[k], rigid.t[k]
        Kk = -(J - a * np.outer(J @ t, t @ J) * a / (a * a * t @ J @ t))  # the film's, tilt condensed
        series = Kk - np.outer(Kk @ s, s @ Kk) / (s @ Kk @ s + kp)
        if sol.u[k] > 1e-7:  # a loaded pad: along its pivot line film and pivot in series
            assert 1.0 / (s @ series @ s) == pytest.approx(1.0 / (s @ Kk @ s) + 1.0 / kp, rel=1e-12)
        total += series
    np.testing.assert_allclose(K_flex, total, rtol=1e-7, atol=1e-7 * np.abs(total).max())
    # the slope of the nonlinear statics: the force with the pads (tilts and radial) re-equilibrated
    h = 1e-4 * 75e-6
    for j in range(2):
        dq = np.zeros(2)
        dq[j] = h
        Fp = np.array(flex.force(y + dq[0], z + dq[1], 0.0, 0.0, OMEGA))
        Fm = np.array(flex.force(y - dq[0], z - dq[1], 0.0, 0.0, OMEGA))
        np.testing.assert_allclose(-(Fp - Fm) / (2 * h), K_flex[:, j], rtol=0, atol=2e-5 * np.abs(K_flex).max())


def test_rigid_pivots_are_unchanged_by_the_flexible_model():
    # the rigid bearing has no radial coordinates; its full coefficients stay (2 + N) x (2 + N)
    tp, _, co = point(None)
    assert co["K_full"].shape == (6, 6) and co["solution"].u is None
    assert tp.pads.coordinate_names()[-1] == "delta_4 [rad]"


def test_the_pads_model_exchange_states_refuse_a_flexible_pivot_by_name():
    tp = TiltingPad(bearing(1e9), **GRID)
    with pytest.raises(ValueError, match="pivot_stiffness_N_m = 1e[+]09: the pads' Model Exchange states"):
        tp.pads.derivatives(np.zeros(4), 0.0, -1e-5, 0.0, 0.0, OMEGA)


def test_demo_json_has_the_pivot_deflections(tmp_path, capsys):
    from bearing_fmu.cli import main as bearing_fmu

    path = tmp_path / "b.toml"
    path.write_text("[bearing]\nD_mm = 100.0\nL_mm = 50.0\nCR_um = 75.0\nmu_Pa_s = 0.02\n[geometry]\npads = 4\n"
                    "pad_arc_deg = 80.0\npivots_deg = [0, 90, 180, 270]\npreload = 0.3\npivot_stiffness_N_m = 3e8\n")
    assert bearing_fmu(["demo", str(path), "--speed-hz", "50", "--load-z", "-2000", "--json"]) == 0
    rec = json.loads(capsys.readouterr().out)
    pads = rec["pads"]
    assert pads["pivot_stiffness_N_m"] == 3e8 and len(pads["pivot_deflection_m"]) == 4
    np.testing.assert_allclose(pads["pivot_load_N"], 3e8 * np.array(pads["pivot_deflection_m"]), rtol=0,
                               atol=1e-9 * max(pads["pivot_load_N"]))
    assert pads["full_coordinates"][-1] == "u_4 [m]" and np.array(pads["K_full"]).shape == (10, 10)


# ------------------------------------------------------------------ the pads' radial coordinates in the eigenproblem

def _rotor_on_flexible_pivots(tmp_path, kp):
    from pathlib import Path

    from rotor_host.analyses.linear.inputs import read_rotor
    from rotor_host.analyses.linear.stability import Stability

    bundled = Path(__file__).resolve().parents[1] / "rotor_host" / "bundled"
    text = (bundled / "bearing_paper_5pad_lbp.toml").read_text()
    if kp is not None:
        text = text.replace("preload = 0.3", f"preload = 0.3\npivot_stiffness_N_m = {kp!r}")
    (tmp_path / "bearing_paper_5pad_lbp.toml").write_text(text)
    (tmp_path / "rotor.toml").write_text((bundled / "rotor_paper_5pad_lbp.toml").read_text())
    rotor, _ = read_rotor(tmp_path / "rotor.toml")
    return Stability(rotor, "tilting_pad", GRID)


@pytest.mark.parametrize("tilt_inertia", [0.0, 2e-6])
def test_every_mode_on_flexible_pivots_is_the_fixed_point_of_its_own_reduction(tmp_path, tilt_inertia):
    # the (2 + 2N) coordinates per bearing in the eigenproblem (tilt and radial of a pad coupled: the
    # descriptor form) against the independent route of tests/test_pad_modes.py: the bearing's impedance
    # reduced at a mode's own complex eigenvalue, iterated with the rotor solved alone; massless pads
    # (first-order tilts and radial), and tilts with inertia (second order) beside massless radial rows
    from rotor_host.analyses.linear import pad_modes as pm

    analysis = _rotor_on_flexible_pivots(tmp_path, 1e6)
    om = 2 * math.pi * 60.0
    q = analysis.equilibrium(om)
    blocks = pm.pad_blocks(analysis.internals, analysis.pairs, q, om)
    assert blocks[0].K.shape == (12, 12) and blocks[0].coupled()
    blocks = [replace(b, inertia=np.concatenate([np.full(5, tilt_inertia), np.zeros(5)])) for b in blocks]
    lam, _ = pm.eigenvalues(analysis.rotor, om, blocks)
    K, C = pm.reduced_coefficients(blocks, complex(0.0, om))
    freq, ld, _ = analysis.rotor.modes(om, K, C)
    starts = [complex(-d * f, 2 * math.pi * f) for f, d in zip(freq, ld) if d < 1.0][:3]
    assert len(starts) == 3
    for s0 in starts:
        s, its = pm.iterate_mode(analysis.rotor, om, blocks, s0)
        assert np.min(np.abs(lam - s)) <= 1e-9 * abs(s), (s0, s)


def test_stiff_pivots_give_the_rigid_pivots_modes(tmp_path):
    # the descriptor form with k_p -> infinity against the rigid pads' first-order rows (state_matrix's
    # other path): the lightly damped modes agree to O(1/k_p)
    from rotor_host.analyses.linear import pad_modes as pm

    om = 2 * math.pi * 60.0
    out = []
    for kp in (None, 1e11):
        analysis = _rotor_on_flexible_pivots(tmp_path / str(kp), kp) if (tmp_path / str(kp)).mkdir() is None else None
        q = analysis.equilibrium(om)
        f, ld, _ = pm.modes(analysis.rotor, om, pm.pad_blocks(analysis.internals, analysis.pairs, q, om))
        out.append((f[ld < 1.0][:3], ld[ld < 1.0][:3]))
    np.testing.assert_allclose(out[1][0], out[0][0], rtol=1e-5)
    np.testing.assert_allclose(out[1][1], out[0][1], rtol=1e-4)


@pytest.mark.parametrize("tilt_inertia", [0.0, 2e-6])
def test_flexible_pivots_in_the_band_are_the_dense_pad_modes(tmp_path, tilt_inertia):
    # band_modes_with_pads (the sparse descriptor pencil, the tilt-radial couplings in App, Bpp) against the
    # dense pad_modes.modes (checked above against the per-mode reduction): every dense mode in the disk
    from rotor_host.analyses.linear import pad_modes as pm
    from rotor_host.model import band_modes as bm

    analysis = _rotor_on_flexible_pivots(tmp_path, 1e6)
    omega = 2 * math.pi * 60.0
    band = 120.0
    blocks = pm.pad_blocks(analysis.internals, analysis.pairs, analysis.equilibrium(omega), omega)
    blocks = [replace(b, inertia=np.concatenate([np.full(5, tilt_inertia), np.zeros(5)])) for b in blocks]
    fd, ld, _ = pm.modes(analysis.rotor, omega, blocks)
    fs, ls, _ = bm.band_modes_with_pads(analysis.rotor, omega, blocks, band)
    lam_d, lam_s = -ld * fd + 2j * math.pi * fd, -ls * fs + 2j * math.pi * fs
    sigma, radius = 0.5j * 2 * math.pi * band, bm.DISK_RADIUS * 2 * math.pi * band
    inside = np.abs(lam_d - sigma) <= radius
    assert 0 < inside.sum() and lam_s.size == inside.sum(), (fd, fs)
    np.testing.assert_allclose(lam_s, lam_d[inside], rtol=1e-7)


def test_both_bearing_fmus_refuse_a_flexible_pivot_by_name():
    # the FMUs carry rigid pivots only (the pads' Model Exchange states above); the Python FMU's parameters
    # (tests/test_tilting_pad.py) and the native generator refuse before anything is built
    from bearing_fmu.fmu.native.generators.tilting_pad import tilting_pad_model

    with pytest.raises(ValueError, match="pivot_stiffness_N_m = 1e[+]09: a flexible pivot is not carried by the"):
        tilting_pad_model(bearing(1e9), None, None, {})


def test_the_films_temperature_with_a_flexible_pivot_is_refused_by_name(tmp_path):
    # the pivots' springs do not scale with mu: the viscosity-scaled internal (stability, a run's film
    # temperature) and the demo's thermal point refuse, naming the key
    from bearing_fmu.internals.scaled import ViscosityScaled
    from bearing_fmu.internals.tilting_pad.operating import operating_point

    with pytest.raises(ValueError, match="pivot_stiffness_N_m = 1e[+]09: the film's temperature"):
        ViscosityScaled(TiltingPad(bearing(1e9), **GRID))
    ViscosityScaled(TiltingPad(bearing(None), **GRID))  # rigid pivots: scaled exactly
    path = tmp_path / "b.toml"
    path.write_text("[bearing]\nD_mm = 100.0\nL_mm = 50.0\nCR_um = 75.0\n[geometry]\npads = 4\npad_arc_deg = 80.0\n"
                    "pivots_deg = [0, 90, 180, 270]\npreload = 0.3\npivot_stiffness_N_m = 1e9\n"
                    "[oil]\ngrade = \"ISO VG 32\"\nsupply_C = 45.0\n")
    with pytest.raises(ValueError, match="pivot_stiffness_N_m = 1e[+]09: the film's temperature"):
        operating_point(BearingParams.from_toml(path), (0.0, -2000.0), 50.0, **GRID)


@pytest.mark.slow
def test_the_pads_map_on_flexible_pivots_follows_the_reynolds_pads():
    # every pad from the pads' partial-arc map (padmap): the flexible pivot is a journal shift the map covers
    # as it covers a tilt. At light load, k_p = 2e6 N/m (the pivots move the eccentricity from 0.177 to 0.245),
    # the equilibrium on a 40^3 map (~10 s to build) is the Reynolds pads'. Measured: eps 0.24459 against
    # 0.24451 (rigid pivots on the same map 0.17719 against 0.17706), the pad loads within 0.002 N of 16.7 N.
    # A 24^3 map holds the pad at 288 deg on a spurious no-load root of the map's moment near the film's
    # no-pressure tilts (docs/geometry.md, Flexible pivots): the map's resolution, not the pivot's model
    from bearing_fmu.internals.tilting_pad.padmap import PadMapSolver, build_pad_map

    p = BearingParams.from_toml(Path(__file__).resolve().parents[1] / "rotor_host" / "bundled"
                                / "bearing_paper_5pad_lbp.toml")
    table = build_pad_map(p, n_theta=24, n_x=4, n_eps=40, n_phi=40, n_beta=40, workers=2)
    om, out = 2 * math.pi * 44.0, {}
    for kp in (None, 2e6):
        q = replace(p, geometry=replace(p.geometry, pads=replace(p.geometry.pads, pivot_stiffness=kp)))
        for on_map in (False, True):
            tp = TiltingPad(q, 24, 4)
            if on_map:
                tp.pads.use_solver(PadMapSolver(q, table))
            y, z = tp.journal_equilibrium((0.0, -16.7), om)
            sol = tp.pads.equilibrate(y, z, 0.0, 0.0, om)
            out[kp, on_map] = (math.hypot(y, z) / p.CR, np.hypot(*sol.pad_F.T))
    rigid_gap = abs(out[None, True][0] - out[None, False][0])
    assert abs(out[2e6, True][0] - out[2e6, False][0]) <= 3 * rigid_gap
    assert out[2e6, False][0] - out[None, False][0] > 0.05  # the pivots matter here
    np.testing.assert_allclose(out[2e6, True][1], out[2e6, False][1], rtol=0, atol=0.002 * 16.7)
