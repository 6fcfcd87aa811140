"""The assembled paper rotor (Table 1), its loads, eigen-analysis and file validation."""

import math
import shutil
from pathlib import Path

import numpy as np
import pytest

from bearing_fmu.physics.params import PAPER_BEARING
from rotor_host.model.rotor import Rotor
from rotor_host.model.parts import RotorFileError

MODELS = Path(__file__).resolve().parents[1] / "rotor_host" / "bundled"
ROTOR_FILE = MODELS / "rotor_paper.toml"


@pytest.fixture(scope="module")
def rotor():
    return Rotor.from_toml(ROTOR_FILE)


# ----------------------------------------------------------------------------- the paper rotor
def test_paper_rotor_layout(rotor):
    assert rotor.n_nodes == 11 and rotor.n_dof == 44
    assert rotor.M.shape == rotor.K.shape == rotor.G.shape == rotor.C.shape == (44, 44)
    assert rotor.bearing_nodes == [2, 8]  # Table 1 / section 3: nodes 3 and 9, 0-based
    assert rotor.bearings == [PAPER_BEARING, PAPER_BEARING]  # Table 2
    # node positions from Table 1 lengths: 40, 10, 10, 266.5, 23.5 mm, ... total 700 mm
    np.testing.assert_allclose(rotor.node_x[[1, 2, 3, 4, 5, 10]], [0.04, 0.05, 0.06, 0.3265, 0.35, 0.70])
    assert [d.node for d in rotor.disks] == [5]  # disk at node 6
    np.testing.assert_allclose(rotor.C, 1.5e-5 * rotor.K)  # C = beta K, beta = 1.5e-5 (section 3)


def test_paper_rotor_mass_by_hand(rotor):
    # Table 1 volumes, pi/4 d^2 l in mm^3:
    #   d 12 mm:   elements 1, 4, 7, 10: l = 40 + 266.5 + 266.5 + 40 = 613 -> 144 * 613 = 88272
    #   d 31 mm:   elements 2, 3, 8, 9:  l = 4 * 10 = 40              -> 961 * 40 = 38440
    #   d 23.5 mm: elements 5, 6:        l = 2 * 23.5 = 47            -> 552.25 * 47 = 25955.75
    #   disk:      (95^2 - 23.5^2) * 47 = 8472.75 * 47 = 398219.25
    # sum 550887 mm^3 * pi/4 = 432 667 mm^3 = 4.32667e-4 m^3; * 7850 kg/m^3 = 3.3964 kg
    expected = math.pi / 4 * 550887e-9 * 7850
    assert rotor.mass == pytest.approx(expected, rel=1e-12)
    assert rotor.mass == pytest.approx(3.3964, abs=1e-4)
    # the assembled M carries the same mass in y and in z
    for d in ("y", "z"):
        u = np.zeros(44)
        u[[rotor.dof(n, d) for n in range(11)]] = 1.0
        assert u @ rotor.M @ u == pytest.approx(expected, rel=1e-12)


def test_global_matrix_properties(rotor):
    M, K, G = rotor.M, rotor.K, rotor.G
    np.testing.assert_allclose(M, M.T, atol=1e-15)
    np.testing.assert_allclose(K, K.T, rtol=0, atol=1e-9 * np.abs(K).max())
    np.testing.assert_allclose(G, -G.T, atol=0)
    assert np.linalg.eigvalsh(M).min() > 0
    ek = np.linalg.eigvalsh(K)
    # free-free: 2 rigid modes per bending plane (translation, rotation), 4 zero eigenvalues
    assert np.sum(np.abs(ek) < 1e-10 * ek.max()) == 4


def test_first_bending_mode_near_paper_22_hz(rotor):
    """Section 3: "The first critical speed is 22 Hz" (2 significant digits, on the hydrodynamic
    bearings, which are softer than our rigid-ish springs). On stiff isotropic springs the first
    bending pair must be near it: we accept 22 +/- 1 Hz."""
    f = rotor.natural_frequencies(1e9)
    print("paper rotor, k = 1e9 N/m, first six [Hz]:", np.round(f, 2))
    assert abs(f[0] - 22.0) < 1.0
    np.testing.assert_allclose(f[0], f[1], rtol=1e-6)  # isotropic: y and z planes alike
    # Rayleigh: stiffer supports never lower a natural frequency
    prev = np.zeros(6)
    for k in (1e5, 1e6, 1e7, 1e8, 1e9):
        f = rotor.natural_frequencies(k)
        assert np.all(f >= prev * (1 - 1e-12))
        prev = f


def test_gyroscopic_splitting_on_paper_rotor(rotor):
    """The conical (disk-tilting) pair splits with speed: forward up, backward down."""
    k = 1e8
    f0 = rotor.natural_frequencies(k)
    conical0 = f0[2]
    for hz in (25.0, 50.0):
        f = rotor.natural_frequencies(k, speed=2 * math.pi * hz)
        assert f[2] < conical0 < f[3]
        fm, ld, shapes = rotor.modes(2 * math.pi * hz, np.eye(2) * k, None, n=4)
        np.testing.assert_allclose(fm, f[:4], rtol=1e-3)  # lightly damped (beta only)
        disk = 5
        assert rotor.whirl(shapes[:, 2], disk, tilt=True) < -0.99  # lower branch: backward
        assert rotor.whirl(shapes[:, 3], disk, tilt=True) > 0.99   # upper branch: forward


def test_proportional_damping_free_free_closed_form(rotor):
    """Without bearings C = beta K is proportional, so every flexible mode has
    lam = -beta w^2 / 2 +/- i w sqrt(1 - (beta w / 2)^2): damped frequency w sqrt(1 - zeta^2)
    and log decrement 2 pi zeta / sqrt(1 - zeta^2) with zeta = beta w / 2 (w undamped)."""
    beta = 1.5e-5
    w = 2 * math.pi * rotor.natural_frequencies(0.0, n=16)
    np.testing.assert_array_equal(w[:4], 0.0)  # 4 rigid modes, reported as 0
    w = w[4:]
    zeta = beta * w / 2
    fd, ld, _ = rotor.modes(0.0, None, None, n=len(w))
    np.testing.assert_allclose(fd, w * np.sqrt(1 - zeta**2) / (2 * math.pi), rtol=1e-7)
    np.testing.assert_allclose(ld, 2 * math.pi * zeta / np.sqrt(1 - zeta**2), rtol=1e-5)


def test_cross_coupled_bearing_stiffness_destabilises_forward_whirl(rotor):
    """Bearing force -K q with K = [[k, q], [-q, k]], q > 0: over a forward circular orbit
    (y, z) = (cos, sin) the force does work pi (K_yz - K_zy) = 2 pi q > 0 per cycle, feeding the
    forward mode and damping the backward one."""
    k, q = 1e6, 0.3e6
    ld_ref = rotor.modes(0.0, np.eye(2) * k, None, n=2)[1]
    assert np.all(ld_ref > 0)
    f, ld, shapes = rotor.modes(0.0, [[k, q], [-q, k]], None, n=2)
    fwd = [rotor.whirl(shapes[:, i], 5) for i in range(2)]
    i_f, i_b = int(np.argmax(fwd)), int(np.argmin(fwd))
    assert fwd[i_f] > 0.9 and fwd[i_b] < -0.9
    assert ld[i_f] < 0 < ld[i_b]
    # per-bearing matrices are accepted too and give the same result
    Ks = [[[k, q], [-q, k]]] * 2
    np.testing.assert_allclose(rotor.modes(0.0, Ks, np.zeros((2, 2, 2)), n=2)[1], ld)


# ----------------------------------------------------------------------------- loads
def test_weight_vector(rotor):
    g = 9.81
    W = rotor.weight_vector(g)
    z = [rotor.dof(n, "z") for n in range(11)]
    y = [rotor.dof(n, "y") for n in range(11)]
    assert W[z].sum() == pytest.approx(-rotor.mass * g, rel=1e-12)
    assert np.abs(W[y]).max() == 0.0
    # moments about the y axis through node 1 (x = 0): r x F = (x,0,0) x (0,0,Fz) = -x Fz e_y,
    # plus the nodal moments; must equal that of the total weight at the centre of mass,
    # x_cg = 0.35 m by the symmetry of Table 1: -0.35 * (-m g)
    ty = [rotor.dof(n, "ty") for n in range(11)]
    My = np.sum(-rotor.node_x * W[z]) + W[ty].sum()
    assert My == pytest.approx(0.35 * rotor.mass * g, rel=1e-10)


def test_unbalance_force(rotor):
    # paper section 3: 8.5 g at 37 mm on the disk (node 6 -> 5), 22 Hz
    m, r, om = 8.5e-3, 37e-3, 2 * math.pi * 22.0
    amp = m * r * om**2
    iy, iz = rotor.dof(5, "y"), rotor.dof(5, "z")
    F0 = rotor.unbalance_force(0.0, om, m, r, 5)
    assert F0[iy] == pytest.approx(amp) and F0[iz] == pytest.approx(0.0, abs=1e-12)
    assert np.count_nonzero(F0) == 1
    Fq = rotor.unbalance_force(math.pi / 2 / om, om, m, r, 5)  # a quarter turn later: +z
    assert Fq[iz] == pytest.approx(amp) and abs(Fq[iy]) < 1e-12 * amp
    Fp = rotor.unbalance_force(0.0, om, m, r, 5, phase=math.pi / 2)
    np.testing.assert_allclose(Fp, Fq, atol=1e-12 * amp)
    for t in np.linspace(0, 0.1, 7):
        F = rotor.unbalance_force(t, om, m, r, 5)
        assert math.hypot(F[iy], F[iz]) == pytest.approx(amp)


def test_point_loads_and_dof(rotor):
    F = rotor.point_load_vector({2: (0.0, -500.0), 8: (10.0, -500.0)})
    G = rotor.point_load_vector([(2, 0.0, -500.0), (8, 10.0, -500.0)])
    np.testing.assert_array_equal(F, G)
    assert F[rotor.dof(2, "z")] == -500.0 and F[rotor.dof(8, "y")] == 10.0 and F.sum() == -990.0
    assert [rotor.dof(5, d) for d in ("y", "z", "ty", "tz")] == [20, 21, 22, 23]
    with pytest.raises(ValueError, match="0..10"):
        rotor.dof(11, "y")
    with pytest.raises(ValueError, match="direction"):
        rotor.dof(0, "x")
    with pytest.raises(ValueError, match="0..10"):
        rotor.point_load_vector({11: (0.0, 1.0)})


# ----------------------------------------------------------------------------- bad files
def _variant(tmp_path, old, new):
    text = ROTOR_FILE.read_text()
    assert old in text
    shutil.copy(MODELS / "bearing_paper.toml", tmp_path / "bearing_paper.toml")
    p = tmp_path / "rotor.toml"
    p.write_text(text.replace(old, new, 1))
    return p


@pytest.mark.parametrize(
    "old, new, pattern",
    [
        ("density_kg_m3 = 7850.0\n", "", r"\[material\].*missing key.*density_kg_m3"),
        ("od_mm = 12.0, length_mm = 40.0", "od_mm = -12.0, length_mm = 40.0",
         r"\[\[elements\]\] 1 od_mm = -12.0 must be a finite number > 0"),
        ("id_mm = 0.0, od_mm = 31.0", "id_mm = 35.0, od_mm = 31.0",
         r"\[\[elements\]\] 2 id_mm = 35 must be < od_mm = 31"),
        ("length_mm = 266.5 }", "length_mm = 0 }", r"\[\[elements\]\] 4 length_mm = 0 must be a finite number > 0"),
        ("node = 9\n", "node = 12\n", r"\[\[bearings\]\] 2 node = 12 is outside the rotor's nodes 1\.\.11"),
        ("node = 6\n", "node = 0\n", r"\[\[disks\]\] 1 node = 0 is outside the rotor's nodes 1\.\.11"),
        ("width_mm = 47.0\n", "width_mm = 47.0\ncolour = 'red'\n", r"\[\[disks\]\] 1: unknown key.*colour"),
        ("nodes = [6, 7]", "nodes = [6, 8]", r"\[\[elements\]\] 6 nodes = \[6, 8\] must be \[6, 7\]"),
        ('bearing = "bearing_paper.toml"', 'bearing = "nope.toml"',
         r"\[\[bearings\]\] 1 bearing = .nope\.toml.: bearing file .*nope\.toml not found"),
        ("poisson = 0.3", "poisson = 0.7", r"\[material\] poisson = 0\.7 must be a finite number > -1 and < 0\.5"),
        ('name = "paper rotor (Table 1)"', 'name = "x"\nspeed_Hz = 3', r"unknown key.*speed_Hz"),
    ],
)
def test_bad_rotor_files_name_the_key(tmp_path, old, new, pattern):
    p = _variant(tmp_path, old, new)
    with pytest.raises(RotorFileError, match=pattern):
        Rotor.from_toml(p)


def test_elements_after_a_table_header_are_reported(tmp_path):
    # a classic TOML slip: keys written after [material] belong to it
    text = ROTOR_FILE.read_text()
    start, end = text.index("elements = ["), text.index("[material]")
    moved = text[:start] + text[end:].replace("[[disks]]", text[start:end] + "[[disks]]", 1)
    shutil.copy(MODELS / "bearing_paper.toml", tmp_path / "bearing_paper.toml")
    (tmp_path / "r.toml").write_text(moved)
    with pytest.raises(RotorFileError, match="missing key.*elements"):
        Rotor.from_toml(tmp_path / "r.toml")


def test_bad_bearing_file_is_reported_with_the_rotor_entry(tmp_path):
    p = _variant(tmp_path, "node = 3\n", "node = 3\n")
    (tmp_path / "bearing_paper.toml").write_text("[bearing]\nD_mm = 31.0\nL_mm = 20.0\nCR_um = 90.0\n")
    with pytest.raises(RotorFileError,
                       match=r"\[\[bearings\]\] 1 bearing = .*bearing_paper\.toml: \[bearing\]: missing key.*mu_Pa_s"):
        Rotor.from_toml(p)
