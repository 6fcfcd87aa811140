"""The tilting-pad bearing (bearing_fmu/physics/bore/pads.py, bearing_fmu/internals/tilting_pad): the
bore's keys and refusals, the film's derivation against its closed form, the moment against the
pressure field, and the properties any tilting-pad bearing has whatever its solver (symmetry, no
circulatory stiffness with massless pads, the pads' moments zero), on coarse grids.

Where the expected values come from: the film of physics/bore/pads.py's docstring written out in the
bearing's frame (independent of the pad frame and the lobe construction the code uses); the moment
as the pressure field's integral about the pivot (independent of the force identity the code uses);
mirror symmetry of a symmetric bearing; for massless pads, a journal motion along a pad's tangent is
followed by the pad's rotation (the film does not change), so every pad's force passes through its
pivot and the reduced impedance is sum_k z_k u_k u_k^T, symmetric at any whirl frequency.
"""

import json
import math
import subprocess
import sys
from dataclasses import replace

import numpy as np
import pytest

from bearing_fmu.internals import registry
from bearing_fmu.internals.tilting_pad.assembly import PadAssembly
from bearing_fmu.internals.tilting_pad.tilting_pad import TiltingPad
from bearing_fmu.physics.bore.geometry import Geometry
from bearing_fmu.physics.bore.pads import PadGeometry
from bearing_fmu.physics.params import BearingFileError, BearingParams

GRID = dict(n_theta=24, n_x=4)
OMEGA = 2 * math.pi * 50.0


def bearing(pivots=(45.0, 135.0, 225.0, 315.0), arc=80.0, offset=0.5, preload=0.5, inertia=0.0):
    pads = PadGeometry(pivots=tuple(math.radians(p) for p in pivots), arc=math.radians(arc), offset=offset,
                       preload=preload, inertia=inertia)
    return BearingParams(D=0.1, L=0.05, CR=75e-6, mu=0.02, geometry=Geometry(pads=pads))


TOML = """[bearing]
D_mm = 100.0
L_mm = 50.0
CR_um = 75.0
mu_Pa_s = 0.02
[geometry]
pads = 4
pad_arc_deg = 80.0
pivots_deg = [45, 135, 225, 315]
pivot_offset = 0.5
preload = 0.5
"""


def write(tmp_path, text):
    path = tmp_path / "b.toml"
    path.write_text(text)
    return path


# ------------------------------------------------------------------ the bore's keys

def test_a_bearing_file_with_pads_reads_and_describes_them(tmp_path):
    p = BearingParams.from_toml(write(tmp_path, TOML))
    g = p.geometry.pads
    assert g.n == 4 and math.degrees(g.arc) == pytest.approx(80.0) and g.preload == 0.5
    assert not p.geometry.is_full_bore and "4 tilting pads" in p.geometry.describe()
    assert p.geometry.as_table()["pivots_deg"] == pytest.approx([45, 135, 225, 315])
    assert g.pad_clearance(p.CR) == pytest.approx(150e-6)  # m = 1 - C_b / C_p


@pytest.mark.parametrize("change, message", [
    (("pivots_deg = [45, 135, 225, 315]", "pivots_deg = [45, 135, 225]"), "pivots_deg has 3 angles for pads = 4"),
    (("pad_arc_deg = 80.0", "pad_arc_deg = 95.0"), "pivots_deg: the pads pivoted at .* overlap"),
    (("pivot_offset = 0.5", "pivot_offset = 1.0"), r"pivot_offset = 1.0 must be .*> 0 and < 1"),
    (("pivot_offset = 0.5", "pivot_offset = 0.0"), r"pivot_offset = 0.0 must be .*> 0 and < 1"),
    (("preload = 0.5", "preload = 1.0"), r"preload = 1.0 must be .*>= 0 and < 1"),
    (("pads = 4", "pads = 2"), r"pads = 2 must be an integer >= 3 and <= 12"),
    (("pads = 4", "pads = 13"), r"pads = 13 must be an integer >= 3 and <= 12"),
    (("preload = 0.5", "preload = 0.5\nlobes = 2"), "a tilting-pad bore has no lobes"),
    (("preload = 0.5", "preload = 0.5\narc_deg = [0, 180]"), "a tilting-pad bore has no arc_deg"),
    (("pads = 4\n", ""), "pad_arc_deg, pivots_deg, pivot_offset need pads"),
    (("pad_arc_deg = 80.0\n", ""), "pads = 4 needs pad_arc_deg"),
    (("preload = 0.5", "preload = 0.5\npad_inertia_kg_m2 = -1.0"), "pad_inertia_kg_m2 = -1.0 must be"),
    (("preload = 0.5", "preload = 0.5\npivot_stiffness_N_m = 0.0"), "pivot_stiffness_N_m = 0.0 must be"),
])
def test_impossible_pads_are_refused_by_name(tmp_path, change, message):
    path = write(tmp_path, TOML.replace(*change))
    with pytest.raises(BearingFileError, match=message) as exc:
        BearingParams.from_toml(path)
    assert str(path) in str(exc.value) and "[geometry]" in str(exc.value)


def test_a_flexible_pivot_adds_each_pads_radial_coordinate(tmp_path):
    # read from the file; the model and its checks: tests/test_tilting_pad_pivot.py
    p = BearingParams.from_toml(write(tmp_path, TOML + "pivot_stiffness_N_m = 1e9\n"))
    assert p.geometry.pads.pivot_stiffness == 1e9
    assert TiltingPad(p, **GRID).pads.coordinate_count() == 2 + 2 * 4


def test_other_internals_refuse_a_tilting_pad_bore_by_name():
    p = bearing()
    for name in ("reynolds", "linear"):
        with pytest.raises(ValueError, match=f"the {name} internal does not take a tilting-pad bore.*tilting_pad"):
            registry.create(name, p, {})
    from bearing_fmu.physics.solver.reynolds import Reynolds

    with pytest.raises(ValueError, match="Reynolds: the bore is tilting pads"):
        Reynolds(p)


# ------------------------------------------------------------------ the film and the moment

def test_the_pad_frame_film_is_the_derived_film_in_the_bearing_frame():
    # physics/bore/pads.py: h = C_pad - d cos(t - tp) + y sin t - z cos t - delta (R + C_pad) sin(t - tp),
    # written out here in the bearing's frame, against the pad frame's lobe film at the equivalent state
    p = bearing(pivots=(10.0, 100.0, 190.0, 280.0), offset=0.6, preload=0.4)
    A = PadAssembly(p, **GRID)
    pg, CR, R = p.geometry.pads, p.CR, p.R
    Cp = pg.pad_clearance(CR)
    d = Cp - CR
    frame = A.pad_params.geometry
    y, z, delta = 12e-6, -30e-6, 2e-4
    for k in range(pg.n):
        lead, trail = pg.span(k)
        th = np.linspace(lead, trail, 41)
        tp = pg.pivots[k]
        want = Cp - d * np.cos(th - tp) + y * np.sin(th) - z * np.cos(th) - delta * (R + Cp) * np.sin(th - tp)
        yp, zp, _, _ = A.frame_state(k, (y, z), (0.0, 0.0), delta, 0.0)
        thp = th + pg.frame_angle(k)
        got = CR * frame.base_film(thp, np.zeros(th.shape, int)) + yp * np.sin(thp) - zp * np.cos(thp)
        # R + C_pad vs the first-order arm: identical here (the code uses a = R + C_pad)
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-12 * CR)


def test_a_positive_tilt_closes_the_trailing_part_of_the_pad():
    p = bearing(preload=0.0)
    A = PadAssembly(p, **GRID)
    frame = A.pad_params.geometry
    for k in range(4):
        lead, trail = p.geometry.pads.span(k)
        yp, zp, _, _ = A.frame_state(k, (0.0, 0.0), (0.0, 0.0), 1e-4, 0.0)
        h = lambda t: p.CR * frame.base_film(np.array([t + p.geometry.pads.frame_angle(k)]), np.zeros(1, int))[0] \
            + yp * math.sin(t + p.geometry.pads.frame_angle(k)) - zp * math.cos(t + p.geometry.pads.frame_angle(k))
        assert h(trail) < p.CR < h(lead)


def test_the_moment_is_the_pressure_field_integrated_about_the_pivot():
    # the torque about the pivot P = (R + C_pad) u(theta_p) of the pressure pushing the pad's surface
    # r = (R + C_pad) u(theta) outward, (r - P) x p dA u(theta), summed over the solver's pressure field
    # in the bearing's frame, with the solver's own quadrature: against the code's M = a F' . t
    p = bearing(offset=0.6, preload=0.3)
    A = PadAssembly(p, **GRID)
    y, z, vy, vz = 5e-6, -25e-6, 1e-3, -2e-3
    delta = np.array([1e-4, 2e-4, 3e-4, 1e-4])
    sol = A.at_tilts(y, z, vy, vz, OMEGA, delta, np.zeros(4))
    R, a, pg = p.R, A.arm, p.geometry.pads
    for k in range(4):
        state = A.frame_state(k, (y, z), (vy, vz), delta[k], 0.0)
        thp, x, pr = A.solvers[k].pressure(*state, OMEGA)
        th = thp - pg.frame_angle(k)  # back to the bearing's angles
        qw = A.solvers[k]._qw  # the solver's axial weights (end-corrected midpoint) of one half
        dA = A.solvers[k]._grid.width[:, None] * np.concatenate([qw, qw[::-1]])[None, :] * R
        u = np.stack([-np.sin(th), np.cos(th)], axis=-1)
        P = a * np.array([-math.sin(pg.pivots[k]), math.cos(pg.pivots[k])])
        arm = a * u - P
        torque = np.sum(pr * dA * (arm[:, 0] * u[:, 1] - arm[:, 1] * u[:, 0])[:, None])
        F = -np.sum((pr * dA)[..., None] * u[:, None, :], axis=(0, 1))
        assert torque == pytest.approx(sol.M[k], rel=1e-10)
        np.testing.assert_allclose(F, sol.pad_F[k], rtol=1e-10, atol=1e-10 * np.abs(sol.pad_F[k]).max())


# ------------------------------------------------------------------ massless pads in equilibrium

def test_massless_pads_settle_to_zero_moment_and_the_force_is_their_sum():
    p = bearing(pivots=(0.0, 72.0, 144.0, 216.0, 288.0), arc=60.0, offset=0.6, preload=0.3)
    A = PadAssembly(p, **GRID)
    sol = A.equilibrate(8e-6, -30e-6, 1e-4, -3e-4, OMEGA)
    scale = A.arm * np.abs(sol.pad_F).max()
    assert np.all(np.abs(sol.M) <= 1e-9 * scale)
    np.testing.assert_allclose(sol.F, sol.pad_F.sum(axis=0), rtol=1e-14)
    # every pad's force passes through its pivot (M = a F . t = 0): along u(theta_p)
    for k, tp in enumerate(p.geometry.pads.pivots):
        u = np.array([-math.sin(tp), math.cos(tp)])
        assert abs(sol.pad_F[k] @ np.array([-u[1], u[0]])) <= 1e-9 * np.abs(sol.pad_F).max()
    # warm start: the same state again takes one Newton step a pad at most and gives the same tilts
    again = A.equilibrate(8e-6, -30e-6, 1e-4, -3e-4, OMEGA)
    assert again.newton <= 2 * A.n
    np.testing.assert_allclose(again.delta, sol.delta, rtol=0, atol=1e-13)


def test_a_pad_started_where_its_film_carries_nothing_finds_its_loaded_tilt():
    # a tilt that opens the pad's converging edge leaves no pressure (M = 0 on a plateau): not the
    # pad's equilibrium; from there and from the centre the same loaded tilts come out
    A = PadAssembly(bearing(), **GRID)
    cold = A.equilibrate(0.0, -21e-6, 0.0, 0.0, OMEGA)
    A._warm[:] = -1.5e-3
    warm = A.equilibrate(0.0, -21e-6, 0.0, 0.0, OMEGA)
    np.testing.assert_allclose(warm.delta, cold.delta, rtol=0, atol=1e-12)
    assert np.all(np.abs(warm.pad_F).sum(axis=1) > 0.0)


def test_load_between_pads_on_a_symmetric_bearing_sinks_straight_down_uncoupled():
    from bearing_fmu.internals.tilting_pad.operating import operating_point

    for pivots, arc in (((45.0, 135.0, 225.0, 315.0), 80.0), ((0.0, 72.0, 144.0, 216.0, 288.0), 60.0)):
        rec = operating_point(bearing(pivots=pivots, arc=arc), (0.0, -2000.0), 50.0, **GRID)
        assert abs(rec["attitude_deg"]) < 1e-6 and abs(rec["y0_m"]) < 1e-9 * 75e-6 * 1e3
        K, C = np.array(rec["K_dimensionless"]), np.array(rec["C_dimensionless"])
        assert abs(K[0, 1]) < 1e-9 * K[1, 1] and abs(K[1, 0]) < 1e-9 * K[1, 1]
        assert abs(C[0, 1]) < 1e-9 * C[1, 1] and abs(C[1, 0]) < 1e-9 * C[1, 1]
        pads = rec["pads"]
        assert np.all(np.abs(pads["moment_N_m"]) <= 1e-9 * 0.05 * max(pads["load_N"]))


@pytest.mark.parametrize("offset", [0.5, 0.6])
def test_massless_pads_have_no_circulatory_stiffness_in_any_load_direction(offset):
    # a journal motion along a pad's tangent is followed by the pad's rotation: the reduced
    # impedance is sum_k z_k(Omega) u_k u_k^T, symmetric: K_yz = K_zy, C_yz = C_zy (no cross-coupled
    # destabilising part) at any load direction and whirl frequency
    tp = TiltingPad(bearing(offset=offset, preload=0.3), **GRID)
    for ang in (0.0, 20.0, 63.0):
        y, z = 0.4 * 75e-6 * math.sin(math.radians(ang)), -0.4 * 75e-6 * math.cos(math.radians(ang))
        for whirl in (OMEGA, 0.5 * OMEGA):
            co = tp.coefficients(y, z, OMEGA, whirl)
            K, C = co["K"], co["C"]
            assert abs(K[0, 1] - K[1, 0]) <= 1e-8 * abs(K).max(), (ang, whirl, K)
            assert abs(C[0, 1] - C[1, 0]) <= 1e-8 * abs(C).max(), (ang, whirl, C)
        if ang:  # and in these axes the symmetric coupling is not zero: the check above can fail
            assert abs(K[0, 1]) > 1e-3 * abs(K).max()


def test_pad_inertia_makes_the_synchronous_coefficients_circulatory():
    # the property above holds for massless pads only: with inertia the pad lags the tangential motion
    p = bearing(offset=0.5, preload=0.3)
    heavy = replace(p, geometry=Geometry(pads=replace(p.geometry.pads, inertia=0.05)))
    tp = TiltingPad(heavy, **GRID)
    K = tp.coefficients(10e-6, -25e-6, OMEGA)["K"]
    assert abs(K[0, 1] - K[1, 0]) > 1e-4 * abs(K).max()


def test_the_quasi_static_jacobian_is_the_zero_frequency_reduction():
    tp = TiltingPad(bearing(offset=0.6, preload=0.3), **GRID)
    F, dq, dv = tp.force_and_jacobian(6e-6, -28e-6, 0.0, 0.0, OMEGA)
    co = tp.coefficients(6e-6, -28e-6, OMEGA, whirl=1e-6 * OMEGA)
    np.testing.assert_allclose(-dq, co["K"], rtol=1e-6, atol=1e-9 * np.abs(dq).max())


# ------------------------------------------------------------------ the pads' states

def test_the_pads_state_derivatives_vanish_at_equilibrium_and_restore_a_disturbed_pad():
    p = bearing(offset=0.6, preload=0.3)
    A = PadAssembly(p, **GRID)
    y, z = 4e-6, -30e-6
    sol = A.equilibrate(y, z, 0.0, 0.0, OMEGA)
    K, C = A.coefficients(sol)
    # massless: state delta, the rate from M(delta, rate) = 0
    F, rate, _ = A.derivatives(sol.delta, y, z, 0.0, 0.0, OMEGA)
    np.testing.assert_allclose(F, sol.F, rtol=1e-12)
    assert np.all(np.abs(rate) <= 1e-9 * OMEGA)
    kick = sol.delta.copy()
    kick[2] += 1e-6
    _, rate, _ = A.derivatives(kick, y, z, 0.0, 0.0, OMEGA)
    # first order: K_pp d delta + C_pp rate = 0 for the kicked pad (the pads are coupled only through the journal)
    assert rate[2] == pytest.approx(-K[4, 4] / C[4, 4] * 1e-6, rel=2e-2)
    assert np.all(np.abs(np.delete(rate, 2)) <= 1e-9 * OMEGA)
    # with inertia: state (delta, rate), d/dt = (rate, M / I)
    heavy = PadAssembly(replace(p, geometry=Geometry(pads=replace(p.geometry.pads, inertia=1e-4))), **GRID)
    assert heavy.state_size() == 8 and A.state_size() == 4
    state = np.concatenate([kick, np.zeros(4)])
    _, d, s2 = heavy.derivatives(state, y, z, 0.0, 0.0, OMEGA)
    np.testing.assert_allclose(d[:4], 0.0)
    assert d[4 + 2] == pytest.approx(-K[4, 4] * 1e-6 / 1e-4, rel=2e-2)  # M = -K_pp d delta


def test_a_journal_closing_a_pad_at_its_pivot_is_refused_by_name():
    tp = TiltingPad(bearing(), **GRID)
    # toward the pivot at 225 deg (u = (sin 45, -cos 45)... = (0.707, -0.707)): 1.02 CR closes the film there
    u = np.array([-math.sin(math.radians(225)), math.cos(math.radians(225))])
    y, z = 1.02 * 75e-6 * u
    with pytest.raises(registry.BearingStateError, match="eccentricity ratio 1.02: .* pad pivoted at 225 deg"):
        tp.force(y, z, 0.0, 0.0, OMEGA)
    # between pads the journal may pass C_bearing (the wall is each pad's film): 1.05 CR toward 180 deg
    Fy, Fz = tp.force(0.0, -1.05 * 75e-6, 0.0, 0.0, OMEGA)
    assert Fz > 0 and math.isfinite(Fy)


# ------------------------------------------------------------------ the demo

@pytest.mark.slow  # a run or a build end to end (1-4 s): the full suite's, out of the quick loop
def test_demo_json_of_a_tilting_pad_bearing(tmp_path):
    path = write(tmp_path, TOML)
    out = subprocess.run([sys.executable, "-m", "bearing_fmu.cli", "demo", "--bearing", str(path), "--speed-hz", "50",
                          "--load-z", "-2000", "--json"], capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr
    rec = json.loads(out.stdout)
    assert rec["internal"] == "tilting_pad"
    for key in ("eccentricity", "attitude_deg", "K_dimensionless", "C_dimensionless", "K_N_m", "C_N_s_m",
                "friction_power_W", "inflow_m3_s", "side_flow_m3_s", "h_min_m"):
        assert rec[key] is not None, key
    pads = rec["pads"]
    assert np.shape(pads["K_full"]) == (6, 6) and np.shape(pads["C_full"]) == (6, 6)
    assert len(pads["rotation_rad"]) == 4 and len(pads["load_N"]) == 4
    # the bottom pads carry the load: their vertical forces sum with the top pads' to the 2000 N
    assert sum(f[1] for f in pads["force_N"]) == pytest.approx(2000.0, rel=1e-8)
    assert 0.2 < rec["eccentricity"] < 0.5
    bad = subprocess.run([sys.executable, "-m", "bearing_fmu.cli", "demo", "--bearing", str(path), "--supply-c", "40"],
                         capture_output=True, text=True, timeout=600)
    # isoviscous: a supply temperature needs the [oil] table (with one: tests/test_pad_thermal.py)
    assert bad.returncode == 2 and "needs the bearing's [oil] table" in bad.stderr


# ------------------------------------------------------------------ the rotor on tilting pads

def test_the_bearing_fmus_parameters_hold_the_pads_and_refuse_a_flexible_pivot_by_name():
    # the Python FMU carries the pads (tests/test_pad_fmu.py): its parameters are the bore's, back to the same
    # PadGeometry; a flexible pivot (not carried by the FMUs) is refused naming the key
    from dataclasses import replace
    from types import SimpleNamespace

    from bearing_fmu.fmu.ports import GEOMETRY_ROWS, PAD_ROWS, geometry_of, port_defaults
    from bearing_fmu.physics.bore.geometry import Geometry

    b = bearing()
    values = {r[0]: r[4] for r in GEOMETRY_ROWS + PAD_ROWS}
    values.update(port_defaults(b, pads=True))
    assert values["pads"] == b.geometry.pads.n and geometry_of(SimpleNamespace(**values)) == b.geometry
    flexible = replace(b, geometry=Geometry(pads=replace(b.geometry.pads, pivot_stiffness=1e8)))
    with pytest.raises(ValueError, match="pivot_stiffness_N_m = 1e[+]08: a flexible pivot is not carried by the bear"):
        port_defaults(flexible, pads=True)
    with pytest.raises(ValueError, match="the native bearing FMU does not carry tilting pads yet"):
        port_defaults(b)  # the native FMU's call


def test_the_paper_rotor_on_five_tilting_pads_has_no_threshold_where_the_plain_bore_whirls():
    # the paper rotor on its plain bearings crosses its oil-whirl threshold near 43 Hz (docs/campbell.md);
    # on five tilting pads (massless: no circulatory stiffness) every mode stays damped at 60 Hz, and the
    # coefficients the analysis took are the synchronously reduced ones (symmetric: K_yz = K_zy)
    from pathlib import Path

    from rotor_host.analyses.linear.stability import Stability
    from rotor_host.analyses.linear.inputs import read_rotor

    root = Path(__file__).resolve().parents[1] / "rotor_host" / "bundled"
    rotor, loads = read_rotor(root / "rotor_paper_5pad_lbp.toml")
    pads = Stability(rotor, "tilting_pad", {"n_theta": 24, "n_x": 4})
    point, q = pads.at(60.0)
    assert point.ok and point.least_log_dec > 0.0
    K, C = pads.linearise(q, 2 * math.pi * 60.0)
    for k in range(2):
        assert abs(K[k, 0, 1] - K[k, 1, 0]) <= 1e-8 * abs(K[k]).max()
        assert abs(C[k, 0, 1] - C[k, 1, 0]) <= 1e-8 * abs(C[k]).max()
    rotor, _ = read_rotor(root / "rotor_paper.toml")
    plain, _ = Stability(rotor, "reynolds", {"n_theta": 32, "n_x": 4}).at(60.0)
    assert plain.least_log_dec < 0.0  # the same rotor whirls on its plain bearings: the check can fail


def test_a_scene_on_tilting_pads_runs_in_process(tmp_path):
    from pathlib import Path

    from rotor_host.scenes.run import run_scene
    from rotor_host.scenes.scene import load_scene

    scene = load_scene(Path(__file__).resolve().parents[1] / "rotor_host" / "bundled" / "scenes" / "paper_5pad_lbp_44hz.toml")
    scene = scene.with_internal("tilting_pad", options={"reynolds": {"n_theta": 24, "n_x": 4}}, t_end_s=0.003)
    res = run_scene(scene, out_dir=tmp_path)
    assert res.ok, res.meta
    ecc = np.asarray(res.arrays["eccentricity"])
    assert np.all(np.isfinite(res.arrays["Fy"])) and 0.05 < ecc.max() < 0.5


def test_the_mirror_image_turning_the_other_way_is_the_mirror_force():
    # a bearing symmetric about the vertical (pivots at +-45, +-135 deg, centred): the journal at
    # (-y, z) turning at -omega is the mirror image of (y, z) at omega, so Fy changes sign, Fz not
    # (the pads' equilibria are found from opposite sides of their plateaus: omega's sign matters)
    tp = TiltingPad(bearing(preload=0.3), **GRID)
    y, z, vy, vz = 9e-6, -27e-6, 2e-4, -1e-4
    Fy, Fz = tp.force(y, z, vy, vz, OMEGA)
    delta = tp.last.delta.copy()
    Gy, Gz = tp.force(-y, z, -vy, vz, -OMEGA)
    assert Gy == pytest.approx(-Fy, rel=1e-9) and Gz == pytest.approx(Fz, rel=1e-9)
    # pad k at theta_k mirrors to the pad at -theta_k, its tilt reversed: 45 <-> 315, 135 <-> 225 deg
    np.testing.assert_allclose(tp.last.delta[::-1], -delta, rtol=1e-8, atol=1e-14)


def _forced_response(inertia: float, n_per: int, periods: int):
    """The journal driven along y at half speed, y = y0 + a cos(W t), the pads' states integrated in time
    (``PadAssembly.derivatives``, RK4): the fundamental of the journal force, and what the reduced
    impedance says it is, -(K_red + i W C_red) (a, 0) (Lund's pad assembly in the frequency domain)."""
    p = bearing(offset=0.6, preload=0.3)
    if inertia:
        p = replace(p, geometry=Geometry(pads=replace(p.geometry.pads, inertia=inertia)))
    A = PadAssembly(p, **GRID)
    y0, z0, amp, W = 4e-6, -30e-6, 1e-3 * p.CR, 0.5 * OMEGA
    sol = A.equilibrate(y0, z0, 0.0, 0.0, OMEGA)
    Kr, Cr = A.reduce(*A.coefficients(sol), W)
    dt = 2 * math.pi / W / n_per

    def f(t, s):
        F, d, _ = A.derivatives(s, y0 + amp * math.cos(W * t), z0, -amp * W * math.sin(W * t), 0.0, OMEGA)
        return F, d

    s = sol.delta.copy() if not inertia else np.concatenate([sol.delta, np.zeros(A.n)])
    got = np.zeros(2, complex)
    for i in range(n_per * periods):
        t = i * dt
        F, k1 = f(t, s)
        if i >= n_per * (periods - 1):  # the last period, the pads' own transient gone
            got += 2.0 / n_per * F * np.exp(-1j * W * t)
        _, k2 = f(t + dt / 2, s + dt / 2 * k1)
        _, k3 = f(t + dt / 2, s + dt / 2 * k2)
        _, k4 = f(t + dt, s + dt * k3)
        s = s + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    return got, -(Kr + 1j * W * Cr) @ np.array([amp, 0.0])


@pytest.mark.slow  # a run or a build end to end (1-4 s): the full suite's, out of the quick loop
def test_the_massless_pads_in_time_give_the_reduced_impedance_at_half_speed_whirl():
    # time domain (the pads' first-order states, their squeeze balancing the moment) against the
    # frequency domain (the (2 + N) coefficients condensed at W): two independent routes
    got, want = _forced_response(0.0, 120, 4)
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-4 * np.abs(want).max())


@pytest.mark.slow
def test_pads_with_inertia_in_time_give_the_reduced_impedance_with_their_inertia():
    # I = 0.1 kg m^2 (heavy, so that explicit RK4 resolves the pads' own mode): the -W^2 I term of
    # the reduction, against the pads' (delta, rate) states integrated in time; not the massless answer
    got, want = _forced_response(0.1, 240, 5)
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-4 * np.abs(want).max())
    massless, _ = _forced_response(0.0, 120, 4)
    assert np.abs(got - massless).max() > 0.05 * np.abs(want).max()  # Fz: 1.0 N of 12 N apart


def test_three_and_twelve_pads_off_centre_loads_find_their_equilibrium():
    # 3 pads of 110 deg pivoted at 0.7 of their arc, 12 unpreloaded pads of 25 deg (no film force with
    # the journal centred: Newton starts along the load): the film forces balance the load
    from bearing_fmu.internals.tilting_pad.operating import operating_point

    for pivots, arc, offset, preload in (((0.0, 120.0, 240.0), 110.0, 0.7, 0.2),
                                         (tuple(range(15, 360, 30)), 25.0, 0.5, 0.0)):
        p = bearing(pivots=pivots, arc=arc, offset=offset, preload=preload)
        rec = operating_point(p, (300.0, -2000.0), 50.0, **GRID)
        np.testing.assert_allclose(np.sum(rec["pads"]["force_N"], axis=0), [-300.0, 2000.0], rtol=1e-8)
        assert np.all(np.abs(rec["pads"]["moment_N_m"]) <= 1e-9 * 0.05 * max(rec["pads"]["load_N"]))


def test_pads_pivoted_near_an_edge_find_no_balance_and_say_so():
    # the pressure of a pad's converging film lies downstream of its leading edge whatever the tilt, so
    # a pad pivoted there balances its moment only by carrying nothing: no equilibrium under a load
    from bearing_fmu.internals.tilting_pad.operating import operating_point
    from bearing_fmu.physics.statics import EquilibriumError

    p = bearing(pivots=(0.0, 120.0, 240.0), arc=119.9, offset=0.02, preload=0.6)
    with pytest.raises(EquilibriumError, match="found no static equilibrium"):
        operating_point(p, (0.0, -2000.0), 50.0, **GRID)
    # pivoted at 0.95 of the arc: the pad would close its trailing edge on the journal to balance
    tp = TiltingPad(bearing(pivots=(0.0, 120.0, 240.0), arc=110.0, offset=0.95, preload=0.2), **GRID)
    with pytest.raises(registry.BearingStateError, match="finds no tilt that balances its moment with its film open"):
        tp.force(0.0, -20e-6, 0.0, 0.0, OMEGA)
