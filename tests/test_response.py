"""The unbalance response (rotor_host.analyses.response): against closed forms and symmetry.

* Jeffcott rotor: a rigid shaft with a central disk on two equal isotropic spring-dampers is a
  single-DOF system in translation (the tilt decouples by symmetry, so the gyroscopic term
  drops out): mass M (the whole rotor), stiffness 2k, damping 2c. Its steady amplitude to an
  unbalance m e at the disk is m e Omega^2 / |2k - M Omega^2 + 2 i c Omega| (any vibration text,
  e.g. Friswell et al. 2010, section 3.6; Den Hartog, Mechanical Vibrations, 2.7), its peak at
  r = 1 / sqrt(1 - 2 zeta^2) of height (m e / M) / (2 zeta sqrt(1 - zeta^2)), and its
  half-power points where (1 / r^2) = 1 - 2 zeta^2 -/+ 2 zeta sqrt(1 - zeta^2) (derived in
  ``_half_power_r`` below from that amplitude).
* API 617's margins worked by hand for given peaks.
* Symmetry: on an isotropic rotor a forward unbalance drives a forward circle only.
"""

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

from bearing_fmu.physics.params import BearingParams
from rotor_host.analyses.response import peaks as pk
from rotor_host.analyses.response.synchronous import Unbalance, node_response, solve
from rotor_host.analyses.response.unbalance import on_grid
from rotor_host.cli import main
from rotor_host.model.parts import Disk, Material, ShaftElement
from rotor_host.model.rotor import Rotor

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "rotor_host" / "bundled" / "rotor_paper.toml"
K_B, ZETA = 2.0e6, 0.05  # each bearing's stiffness [N/m]; the damping ratio of the translation


def _jeffcott():
    """A rigid (E = 1e9 GPa) 400 mm shaft, a 12 kg-class disk at its middle node, bearings at the ends."""
    bearing = BearingParams(D=0.05, L=0.03, CR=50e-6, mu=0.02)  # only its node matters here
    rotor = Rotor(elements=[ShaftElement(0.2, 0.05), ShaftElement(0.2, 0.05)],
                  material=Material(E=1e18, density=7850.0, poisson=0.3, beta=0.0),
                  disks=[Disk(1, 0.25, 0.05, 0.04)], bearing_nodes=[0, 2], bearings=[bearing, bearing])
    M = rotor.mass
    c = ZETA * 2.0 * math.sqrt(2.0 * K_B * M) / 2.0  # each bearing's damping: 2c = 2 zeta sqrt(2k M)
    return rotor, M, c


def _half_power_r(z):
    """Frequency ratios where r^2 / sqrt((1 - r^2)^2 + (2 z r)^2) equals its peak / sqrt 2: with
    u = 1/r^2 the squared amplitude is 1 / ((u - 1)^2 + 4 z^2 u), the peak's square
    1 / (4 z^2 (1 - z^2)); so (u - 1)^2 + 4 z^2 u = 8 z^2 (1 - z^2), u = 1 - 2 z^2 +/- 2 z sqrt(1 - z^2)."""
    u = np.array([1 - 2 * z * z + 2 * z * math.sqrt(1 - z * z), 1 - 2 * z * z - 2 * z * math.sqrt(1 - z * z)])
    return 1.0 / np.sqrt(u)


def test_jeffcott_amplitude_and_phase_closed_form():
    rotor, M, c = _jeffcott()
    unb = [Unbalance(2, 10.0, 100.0)]  # 10 g at 100 mm on the disk's node (1-based 2)
    me = 1e-3
    for f in (5.0, 20.0, 45.0):
        w = 2 * math.pi * f
        X = solve(rotor, w, np.eye(2) * K_B, np.eye(2) * c, unb)
        r = node_response(rotor, X, 1)
        expect = me * w * w / (2 * K_B - M * w * w + 2j * c * w)
        assert r["y_amplitude_m"] == pytest.approx(abs(expect), rel=1e-6)
        assert r["z_amplitude_m"] == pytest.approx(abs(expect), rel=1e-6)
        assert r["y_phase_deg"] == pytest.approx(math.degrees(np.angle(expect)), abs=1e-5)
        assert r["backward_m"] < 1e-9 * r["forward_m"]


def test_jeffcott_peak_and_half_power_af_refined_between_coarse_grid_points():
    rotor, M, c = _jeffcott()
    fn = math.sqrt(2 * K_B / M) / (2 * math.pi)
    speeds = list(np.arange(0.3, 2.0, 0.1) * fn)  # 0.1 fn steps: the peak (bandwidth 0.1 fn) falls between
    res, _ = on_grid(rotor, [Unbalance(2, 10.0, 100.0)], speeds, lambda s: (np.eye(2) * K_B, np.eye(2) * c),
                     probes=[2])
    assert sorted(p["direction"] for p in res.peaks) == ["y", "z"]
    p = next(p for p in res.peaks if p["direction"] == "y")
    r_peak = 1 / math.sqrt(1 - 2 * ZETA**2)
    assert p["speed_hz"] == pytest.approx(r_peak * fn, rel=1e-5)
    assert p["amplitude_m"] == pytest.approx(1e-3 / M / (2 * ZETA * math.sqrt(1 - ZETA**2)), rel=1e-7)
    r1, r2 = _half_power_r(ZETA)
    assert p["half_power_hz"] == pytest.approx([r1 * fn, r2 * fn], rel=1e-6)
    assert p["amplification_factor"] == pytest.approx(r_peak / (r2 - r1), rel=1e-5)
    assert p["amplification_factor"] == pytest.approx(1 / (2 * ZETA), rel=0.02)  # the light-damping rule, to O(zeta)
    assert p["critical"] is True and p["separation_margin_pct"] is None


def test_heavily_damped_jeffcott_is_not_a_critical():
    """zeta = 0.3: AF = 1.7 < 2.5, reported as critically damped with no margin required."""
    rotor, M, _ = _jeffcott()
    c = 0.3 * math.sqrt(2 * K_B * M)
    fn = math.sqrt(2 * K_B / M) / (2 * math.pi)
    res, _ = on_grid(rotor, [Unbalance(2, 10.0, 100.0)], list(np.arange(0.2, 4.0, 0.2) * fn),
                     lambda s: (np.eye(2) * K_B, np.eye(2) * c), probes=[2], operating_hz=(3 * fn, 3.5 * fn))
    p = res.peaks[0]
    assert p["amplification_factor"] < pk.AF_CRITICAL and p["critical"] is False
    assert p["required_margin_pct"] == 0.0 and p["meets_margin"] is True
    assert "not a critical speed" in pk.peak_words(p)


def test_api_617_margins_by_hand():
    # a peak at 22.34 Hz, AF 10, operating 40-50 Hz: SM = 100 (40 - 22.34) / 40 = 44.15 %;
    # required below the minimum speed: 16 - 6 / (10 - 3) = 15.142857 %
    rec = pk.peak_record(6, "y", 22.34, 1e-4, 21.0, 21.0 + 22.34 / 10.0, (40.0, 50.0), False, True)
    assert rec["amplification_factor"] == pytest.approx(10.0)
    assert rec["separation_margin_pct"] == pytest.approx(44.15)
    assert rec["required_margin_pct"] == pytest.approx(15.142857, abs=1e-6)
    assert rec["side"] == "below" and rec["meets_margin"] is True
    # above the maximum continuous speed: a peak at 60 Hz, AF 8: SM = 20 %, required 26 - 6/5 = 24.8 %: not met
    assert pk.separation_margin(60.0, (40.0, 50.0)) == (pytest.approx(20.0), "above")
    assert pk.required_margin_pct(8.0, "above") == pytest.approx(24.8)
    # 2.5 <= AF <= 3.55: 5 % below, 15 % above; the formula meets them at 3.55 (16 - 6/0.55 = 5.09)
    assert pk.required_margin_pct(3.0, "below") == 5.0 and pk.required_margin_pct(3.0, "above") == 15.0
    assert pk.required_margin_pct(3.56, "below") == pytest.approx(5.2857, abs=1e-4)
    # inside the range: negative margin, the nearer end's requirement
    sm, side = pk.separation_margin(42.0, (40.0, 50.0))
    assert sm == pytest.approx(-5.0) and side == "below"


def test_isotropic_rotor_y_and_z_equal_and_90_degrees_apart():
    """The paper rotor with gyroscopics on isotropic bearings, two unbalances at different angles:
    every node whirls on a forward circle (A_y = A_z, phi_z = phi_y - 90 deg)."""
    rotor = Rotor.from_toml(PAPER)
    unb = [Unbalance(6, 1.0, 40.0, 0.0), Unbalance(3, 0.5, 20.0, 70.0)]
    for f in (15.0, 22.0, 60.0):
        X = solve(rotor, 2 * math.pi * f, np.eye(2) * 3e6, np.eye(2) * 2e3, unb)
        for node in range(rotor.n_nodes):
            r = node_response(rotor, X, node)
            assert r["z_amplitude_m"] == pytest.approx(r["y_amplitude_m"], rel=1e-9)
            assert (r["y_phase_deg"] - r["z_phase_deg"]) % 360.0 == pytest.approx(90.0, abs=1e-6)
            assert r["backward_m"] <= 1e-9 * r["forward_m"]


def test_cross_coupled_bearing_breaks_the_circle():
    """The check above can fail: with a cross-coupled (or anisotropic) bearing the orbit is an ellipse."""
    rotor = Rotor.from_toml(PAPER)
    K = np.array([[3e6, 1e6], [-1e6, 6e6]])
    X = solve(rotor, 2 * math.pi * 22.0, K, np.eye(2) * 2e3, [Unbalance(6, 1.0, 40.0)])
    r = node_response(rotor, X, 5)
    assert r["backward_m"] > 1e-3 * r["forward_m"]
    assert r["z_amplitude_m"] != pytest.approx(r["y_amplitude_m"], rel=1e-3)


# ----------------------------------------------------------------------------- command line

def _cli(capsys, *argv):
    try:
        code = main(["response", *map(str, argv)])
    except SystemExit as exc:
        code = exc.code
    out = capsys.readouterr()
    return code, out.out, out.err


@pytest.mark.parametrize("argv, words", [
    (["--unbalance", "6:1"], ["--unbalance", "NODE:MASS_G:RADIUS_MM"]),
    (["--unbalance", "6:-1:40"], ["--unbalance", "a mass > 0 g"]),
    (["--unbalance", "6:1:40", "--operating-hz", "50:40"], ["--operating-hz", "MIN:MAX"]),
    (["--unbalance", "12:1:40"], ["--unbalance 12:1:40", "1..11"]),
])
def test_cli_bad_input_named_exit_2(tmp_path, capsys, argv, words):
    code, _, err = _cli(capsys, PAPER, "--speeds-hz", "10:20:5", "--internal", "map", *argv, "--out", tmp_path)
    assert code == 2 and "Traceback" not in err
    line = err.strip().splitlines()[-1]
    for w in words:
        assert w in line


@pytest.mark.slow
def test_cli_paper_rotor_writes_the_issue_keys(tmp_path, capsys):
    code, out, _ = _cli(capsys, PAPER, "--speeds-hz", "14:50:4", "--unbalance", "6:1:40", "--unbalance", "3:0.5:20:90",
                        "--internal", "map", "--operating-hz", "40:50", "--out", tmp_path)
    assert code == 0
    data = json.loads((tmp_path / "response.json").read_text())
    assert data["speeds_hz"] == [14.0, 18.0, 22.0, 26.0, 30.0, 34.0, 38.0, 42.0, 46.0, 50.0]
    assert set(data["nodes"]) == {str(n) for n in range(1, 12)}
    for key in ("y_amplitude_m", "z_amplitude_m", "y_phase_deg", "z_phase_deg"):
        assert len(data["nodes"]["6"][key]) == 10
    assert data["unstable"][-1] is True and data["unstable"][0] is False  # the threshold lies near 43 Hz
    crit = [p for p in data["peaks"] if p["node"] == 6]
    assert crit and all(20.0 < p["speed_hz"] < 24.0 and p["speed_hz"] not in data["speeds_hz"] for p in crit)
    for p in data["peaks"]:
        assert {"node", "direction", "speed_hz", "amplitude_m", "amplification_factor", "separation_margin_pct",
                "required_margin_pct"} <= set(p)
    assert re.search(r"node 6 [yz]: 2\d\.\d+ Hz", out)
    for n in (3, 6, 9):
        assert (tmp_path / f"bode_node{n}.png").stat().st_size > 0 and (tmp_path / f"polar_node{n}.png").exists()
    assert "## Peaks" in (tmp_path / "response.md").read_text()


# ----------------------------------------------------------------------------- undamped critical speed map

def _uniform_beam(n_el=20, length=1.0, d=0.02):
    bearing = BearingParams(D=0.05, L=0.03, CR=50e-6, mu=0.02)  # only its node matters here
    return Rotor(elements=[ShaftElement(length / n_el, d)] * n_el,
                 material=Material(E=200e9, density=7850.0, poisson=0.3), bearing_nodes=[0, n_el],
                 bearings=[bearing, bearing])


def test_ucs_stiff_supports_tend_to_pinned_pinned_beam():
    """Euler-Bernoulli pinned-pinned beam: omega_n = (n pi / L)^2 sqrt(E I / (rho A)) (e.g. Blevins,
    Formulas for Natural Frequency and Mode Shape, table 8-1); slender (L/d = 50), so shear,
    rotary and gyroscopic inertia change it by O((n d / L)^2) < 0.5 % for n <= 2."""
    from rotor_host.analyses.response.ucs import forward_criticals

    L, d = 1.0, 0.02
    f, _ = forward_criticals(_uniform_beam(length=L, d=d), 1e13, 2)
    EI, rhoA = 200e9 * math.pi * d**4 / 64, 7850.0 * math.pi * d**2 / 4
    for n in (1, 2):
        assert f[n - 1] == pytest.approx((n * math.pi / L) ** 2 * math.sqrt(EI / rhoA) / (2 * math.pi), rel=5e-3)


def test_ucs_soft_supports_tend_to_rigid_body_modes():
    """On springs k far softer than the beam: bounce sqrt(2 k / m) and, forward synchronous, rocking
    sqrt(2 k (L/2)^2 / (I_t - I_p)) with I_t = m L^2 / 12 + m d^2 / 16 and I_p = m d^2 / 8
    (rigid cylinder about its centre)."""
    from rotor_host.analyses.response.ucs import forward_criticals

    L, d, k = 1.0, 0.02, 10.0
    rotor = _uniform_beam(length=L, d=d)
    m = rotor.mass
    f, _ = forward_criticals(rotor, k, 2)
    assert f[0] == pytest.approx(math.sqrt(2 * k / m) / (2 * math.pi), rel=1e-3)
    rock = math.sqrt(2 * k * (L / 2) ** 2 / (m * L**2 / 12 + m * d**2 / 16 - m * d**2 / 8))
    assert f[1] == pytest.approx(rock / (2 * math.pi), rel=1e-3)


@pytest.mark.slow
def test_cli_ucs_paper_rotor(tmp_path, capsys):
    try:
        code = main(["ucs", str(PAPER), "--internal", "map", "--points", "9", "--speeds-hz", "10:40:5",
                     "--out", str(tmp_path)])
    except SystemExit as exc:
        code = exc.code
    out = capsys.readouterr().out
    assert code == 0
    data = json.loads((tmp_path / "ucs.json").read_text())
    assert len(data["criticals_hz"]) == 9 and len(data["bearing_Kyy_N_m"]) == 7
    first = [c for c in data["crossings"] if c["mode"] == 1]
    assert first and 18.0 < first[0]["speed_hz"] < 26.0  # the Campbell's first critical is 22.3 Hz
    assert "critical 1 on the bearings" in out
    assert (tmp_path / "ucs_map.png").stat().st_size > 0 and (tmp_path / "ucs_modes.png").stat().st_size > 0


def test_ucs_agrees_with_the_campbell_eigenvalues_at_each_critical():
    """At a forward critical Omega_c the state-space modes at spin Omega_c (``Rotor.modes``, the
    Campbell diagram's solver) hold a forward mode of frequency Omega_c: the Friswell rotor (no
    shaft damping, disks of 280 and 350 mm whose gyroscopics move the criticals by percents)."""
    from rotor_host.analyses.response.ucs import forward_criticals

    rotor = Rotor.from_toml(ROOT / "rotor_host" / "bundled" / "rotor_friswell.toml")
    f, _ = forward_criticals(rotor, 1e7, 3)
    for fc in f:
        freq, _, shapes = rotor.modes(2 * math.pi * fc, np.eye(2) * 1e7, np.zeros((2, 2)))
        j = int(np.argmin(np.abs(freq - fc)))
        assert freq[j] == pytest.approx(fc, rel=1e-7)
        node = int(np.argmax(np.abs(shapes[0::4, j])))
        assert rotor.whirl(shapes[:, j], node) > 0.99
    still = rotor.natural_frequencies(1e7, 0.0, 8)  # without spin: the gyroscopic term must matter here
    assert abs(f[2] / still[np.argmin(np.abs(still - f[2]))] - 1) > 0.01


# ----------------------------------------------------------------------------- API 617 Level I

def test_anticipated_cross_coupling_equals_api_617_us_form_by_hand():
    """API 617 prints q_A = HP B_c C / (D_c H_c N) (rho_d / rho_s), C = 63, in klbf/in with hp, in and rpm:
    2000 hp, 10000 rpm, D_c 15 in, H_c 0.5 in, density ratio 1.6: 2000 * 3 * 63 / (15 * 0.5 * 10000) * 1.6
    = 8.064 klbf/in = 8.064 * 175126.8 N/m (C = 63 rounds 63025 / 1000: 4e-4)."""
    from rotor_host.analyses.response.level1 import anticipated_cross_coupling

    stage = {"node": 0, "power_kw": 2000 * 0.745699872, "density_ratio": 1.6, "diameter_mm": 15 * 25.4,
             "restrictive_mm": 0.5 * 25.4, "kind": "centrifugal"}
    QA, q = anticipated_cross_coupling([stage, {**stage, "kind": "axial"}], 10000 / 60)
    assert q[0] == pytest.approx(8.064 * 175126.8, rel=1e-3)
    assert q[1] == pytest.approx(q[0] / 2 / 1.6) and QA == pytest.approx(q[0] + q[1])  # axial: B 1.5, no ratio


def test_level1_jeffcott_q0_closed_form():
    """Jeffcott rotor with the cross-coupling Q at the disk: in r = y + i z, M r'' + c_t r' + (k_t - i Q) r = 0
    (the force (-Q z, Q y) is i Q r), so the forward root crosses the imaginary axis at
    Q_0 = c_t sqrt(k_t / M), and at any Q the log dec is -2 pi Re(s) / Im(s) of the root of
    M s^2 + c_t s + k_t - i Q with Im(s) > 0."""
    from rotor_host.analyses.response.level1 import level1

    rotor, M, c = _jeffcott()
    rotor.stages = [{"node": 1, "power_kw": 50.0, "density_ratio": 1.2, "diameter_mm": 250.0, "restrictive_mm": 10.0,
                     "kind": "centrifugal"}]
    r = level1(rotor, 50.0, np.eye(2) * K_B, np.eye(2) * c, points=11)
    kt, ct = 2 * K_B, 2 * c
    assert r.Q_0 == pytest.approx(ct * math.sqrt(kt / M), rel=1e-5)

    def log_dec(Q):
        s = np.roots([M, ct, kt - 1j * Q])
        s = s[np.argmax(s.imag)]
        return -2 * math.pi * s.real / s.imag

    assert r.delta_0 == pytest.approx(log_dec(0.0), rel=1e-4)  # the FE shaft is rigid to ~1e-5
    assert r.delta_A == pytest.approx(log_dec(r.Q_A), rel=1e-4, abs=1e-6)


def test_anticipated_cross_coupling_reproduces_ross_report_example():
    """ROSS's former report module (Report.stability_level_1, its docstring example) gives
    Q_A = 23022.32 N/m for two stages of 10 kW, D 0.35 m, H 0.08 m, density ratios 1.11 and 1.14 at
    1000 rpm, with C = 9.55 (60 / 2 pi = 9.5493 here: 6e-5)."""
    from rotor_host.analyses.response.level1 import anticipated_cross_coupling

    stages = [{"node": 0, "power_kw": 10.0, "density_ratio": r, "diameter_mm": 350.0, "restrictive_mm": 80.0}
              for r in (1.11, 1.14)]
    assert anticipated_cross_coupling(stages, 1000 / 60)[0] == pytest.approx(23022.32142857143, rel=1e-4)


@pytest.mark.parametrize("rho, Q0, verdict", [
    (None, 5e5, "SCREENING CHART NEEDED"),
    (10.0, 5e5, "LEVEL I PASSED"),       # Q_0 / Q_A = 5, CSR 2.5 not above the boundary 2.5: region A
    (50.0, 5e5, "LEVEL II REQUIRED"),    # boundary 2.69 - 0.0115 * 50 = 2.115 < CSR 2.5: region B
    (70.0, 5e5, "LEVEL II REQUIRED"),    # beyond 60 kg/m^3 every CSR is region B
])
def test_level1_screening_chart(rho, Q0, verdict):
    from rotor_host.analyses.response.level1 import Level1, csr_boundary

    r = Level1(100.0, np.zeros(2), np.zeros(2), np.zeros(2), 1e5, [1e5], Q0, 0.5, 0.6, 40.0, gas_density_kg_m3=rho)
    assert r.csr == 2.5  # 100 / 40
    assert r.verdict()[0] == verdict
    assert csr_boundary(16.53) == 2.5 and csr_boundary(50.0) == pytest.approx(2.115) and csr_boundary(60.0) == 0.0


@pytest.mark.parametrize("Q0, delta_A, verdict", [
    (1.5e5, 0.5, "LEVEL II REQUIRED"),      # Q_0 / Q_A = 1.5 < 2
    (5e5, 0.05, "LEVEL II REQUIRED"),       # delta_A < 0.1
    (5e5, 0.5, "SCREENING CHART NEEDED"),   # 2 <= 5 <= 10: region B of the chart decides
    (2e6, 0.5, "LEVEL I PASSED"),           # 20 > 10 and delta_A >= 0.1
    (None, 0.5, "LEVEL I PASSED"),          # never unstable
])
def test_level1_verdict_api_617_rules(Q0, delta_A, verdict):
    from rotor_host.analyses.response.level1 import Level1

    r = Level1(100.0, np.zeros(2), np.zeros(2), np.zeros(2), 1e5, [1e5], Q0, delta_A, 0.6, 50.0)
    assert r.verdict()[0] == verdict and r.csr == 2.0


def test_level1_refuses_a_rotor_without_stages(tmp_path, capsys):
    try:
        code = main(["level1", str(PAPER), "--operating-hz", "25:30", "--internal", "map", "--out", str(tmp_path)])
    except SystemExit as exc:
        code = exc.code
    err = capsys.readouterr().err
    assert code == 2 and "[[stages]]" in err and "power_kw" in err and str(PAPER) in err


@pytest.mark.slow
def test_cli_level1_log_dec_at_zero_is_the_stability_analysis(tmp_path, capsys):
    """At Q = 0 the first forward mode's log dec equals the least stable forward mode of
    ``rotor-host stability``'s point at the same speed (its SpeedPoint)."""
    from rotor_host.analyses.linear.modal import band_hz
    from rotor_host.analyses.linear.stability import Stability
    from rotor_host.analyses.linear.inputs import internal_options, read_rotor

    text = PAPER.read_text().replace('bearing = "bearing_paper.toml"', f'bearing = "{ROOT / "rotor_host" / "bundled" / "bearing_paper.toml"}"')
    rotor_file = tmp_path / "rotor.toml"
    rotor_file.write_text(text + "\n[[stages]]\nnode = 6\npower_kw = 5.0\ndensity_ratio = 1.3\ndiameter_mm = 95.0\n"
                                 "restrictive_mm = 5.0\n")
    code = main(["level1", str(rotor_file), "--operating-hz", "25:30", "--internal", "map", "--out", str(tmp_path)])
    assert code == 0
    data = json.loads((tmp_path / "level1.json").read_text())
    rotor, loads = read_rotor(rotor_file)
    p, _ = Stability(rotor, "map", internal_options("map"), loads).at(30.0)
    fwd = [i for i in range(p.freq_hz.size) if p.whirl[i] > 0 and p.freq_hz[i] <= band_hz(30.0)]
    assert data["log_dec_at_0"] == pytest.approx(min(p.log_dec[i] for i in fwd), rel=1e-9)
    # Q_A by hand: 3 * (5000 W / (2 pi 30 rad/s)) / (0.095 m * 0.005 m) * 1.3
    assert data["Q_A_N_m"] == pytest.approx(3 * 5000 / (2 * math.pi * 30) / (0.095 * 0.005) * 1.3)
    assert data["verdict"] == "LEVEL II REQUIRED" and (tmp_path / "level1.png").stat().st_size > 0


def test_half_power_not_found_on_a_shoulder_of_a_higher_peak():
    """Two resonances of a sum of Lorentzians, the first 1/5 of the second's height: the first's
    right side climbs into the second before falling to half power, so its AF is unknown (not
    a made-up bandwidth), while the second's half-power points are the Lorentzian's f0 -/+ g (to
    the first's small tail)."""
    def amp(f):
        return 0.2 / (1 + ((f - 10.0) / 0.5) ** 2) ** 0.5 + 1.0 / (1 + ((f - 12.0) / 0.2) ** 2) ** 0.5

    s = np.arange(8.0, 16.0, 0.25)
    a = np.array([amp(x) for x in s])
    assert len(pk.grid_peaks(a)) == 2
    n1, n2 = pk.half_power_speeds(amp, s, a, 10.0, amp(10.0))
    assert n1 is not None and n2 is None
    m1, m2 = pk.half_power_speeds(amp, s, a, 12.0, amp(12.0))
    assert m1 == pytest.approx(11.8, abs=0.02) and m2 == pytest.approx(12.2, abs=0.02)


# ----------------------------------------------------------------------------- linear against the run-up

@pytest.mark.slow
def test_linear_response_is_the_runup_1x_where_the_orbit_is_small(tmp_path):
    """Far below the first critical, a small unbalance and a slow ramp: the journal barely moves in the
    film, so the nonlinear run-up's 1x forward radius (order-tracked) is the linear steady response
    to 0.5 %; the linear curve comes from solving the linearised rotor, the run-up from
    integrating the map's force in time, two different computations."""
    from rotor_host.analyses.response.runup import compare
    from rotor_host.scenes.scene import load_scene

    text = (ROOT / "rotor_host" / "bundled" / "scenes" / "paper_runup_10_60hz.toml").read_text()
    text = text.replace('rotor = "../rotor_paper.toml"', f'rotor = "{(ROOT / "rotor_host" / "bundled" / "rotor_paper.toml").as_posix()}"')
    text = text.replace('map = "../maps/paper_bearing.json"',
                        f'map = "{(ROOT / "rotor_host" / "bundled" / "maps" / "paper_bearing.json").as_posix()}"')
    text = text.replace("times_s = [0.0, 10.0]", "times_s = [0.0, 2.0]").replace("speeds_hz = [10.0, 60.0]",
                                                                                "speeds_hz = [12.0, 15.0]")
    text = text.replace("t_end_s = 10.0", "t_end_s = 2.0").replace('via = "fmu"', 'via = "direct"')
    path = tmp_path / "slow_ramp.toml"
    path.write_text(text)
    res = compare(load_scene(path), [0.1], None, window_s=0.5)
    row = res["scales"][0]["nodes"]["6"]
    s_lin = np.asarray(res["scales"][0]["linear_speeds_hz"])
    lin = np.interp(row["runup_speeds_hz"], s_lin, [v for v in row["linear_forward_m"]])
    ratio = np.asarray(row["runup_1x_m"])[1:] / lin[1:]  # the first window holds the start's transient
    assert np.all(np.abs(ratio - 1) < 0.005), ratio


@pytest.mark.slow
def test_cli_api_report_one_file_with_every_part(tmp_path, capsys):
    text = PAPER.read_text().replace('bearing = "bearing_paper.toml"', f'bearing = "{ROOT / "rotor_host" / "bundled" / "bearing_paper.toml"}"')
    rotor_file = tmp_path / "rotor.toml"
    rotor_file.write_text(text + "\n[[stages]]\nnode = 6\npower_kw = 0.05\ndensity_ratio = 1.1\ndiameter_mm = 95.0\n"
                                 "restrictive_mm = 10.0\n")
    out = tmp_path / "report"
    code = main(["api-report", str(rotor_file), "--speeds-hz", "12:36:4", "--unbalance", "6:1:40", "--operating-hz",
                 "28:32", "--internal", "map", "--out", str(out)])
    assert code == 0
    text = (out / "api_report.md").read_text()
    for heading in ("## Campbell diagram and stability threshold", "## Unbalance response", "## Undamped critical speed map",
                    "## API 617 Level I stability"):
        assert heading in text
    for name in ("stability.json", "response.json", "ucs.json", "level1.json", "campbell.png", "bode_node6.png",
                 "ucs_map.png", "level1.png"):
        assert (out / name).stat().st_size > 0
    # each figure named in the report exists
    for link in re.findall(r"!\[[^]]*\]\(([^)]+)\)", text):
        assert (out / link).exists(), link
