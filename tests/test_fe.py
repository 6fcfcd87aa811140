"""Timoshenko shaft element and rigid disk: matrices, convergence to analytic beam theory, gyroscopics.

Expected values come from closed forms written out below (Timoshenko's frequency equation,
Euler-Bernoulli beam formulas, rigid-body gyroscopic whirl), never from this code's output.
"""

import math

import numpy as np
import pytest
import scipy.linalg

from rotor_host.model import fe
from rotor_host.model.parts import Material, ShaftElement
from rotor_host.model.rotor import Rotor
from rotor_host.model.assembly import assemble

E, RHO, NU = 200e9, 7850.0, 0.3
STEEL = Material(E=E, density=RHO, poisson=NU)


def uniform_shaft(length, od, n_el, id_=0.0, material=STEEL):
    return assemble([ShaftElement(length / n_el, od, id_)] * n_el, [], material)


# ----------------------------------------------------------------------------- element matrices
def iie_shape_functions(xi, L, phi):
    """Interdependent interpolation of the Timoshenko element (Reddy 1997; Friswell et al. sec. 5.4).

    Displacement N(xi) and section rotation Npsi(xi) in plane DOFs (u1, psi1, u2, psi2).
    """
    c = 1.0 / (1.0 + phi)
    N = c * np.array([
        1 - 3 * xi**2 + 2 * xi**3 + phi * (1 - xi),
        L * (xi - 2 * xi**2 + xi**3 + phi / 2 * (xi - xi**2)),
        3 * xi**2 - 2 * xi**3 + phi * xi,
        L * (-xi**2 + xi**3 + phi / 2 * (-xi + xi**2)),
    ])
    Npsi = c * np.array([
        6 / L * (-xi + xi**2),
        1 - 4 * xi + 3 * xi**2 + phi * (1 - xi),
        6 / L * (xi - xi**2),
        -2 * xi + 3 * xi**2 + phi * xi,
    ])
    return N, Npsi


def test_closed_form_plane_matrices_equal_integrated_shape_functions():
    # a stubby element so that phi is large and every phi term matters
    L, od, idm = 0.05, 0.04, 0.015
    A, I = fe.area(od, idm), fe.second_moment(od, idm)
    G = E / (2 * (1 + NU))
    kappa = fe.shear_coefficient(od, idm, NU)
    phi = 12 * E * I / (kappa * G * A * L**2)
    assert phi == pytest.approx(fe.shear_parameter(L, od, idm, E, NU))
    assert phi > 0.5

    xg, wg = np.polynomial.legendre.leggauss(8)  # exact for these polynomial integrands
    xi, w = 0.5 * (xg + 1), 0.5 * wg
    h = 1e-6
    Kq = np.zeros((4, 4)); Mt = np.zeros((4, 4)); Mr = np.zeros((4, 4))
    for x, wt in zip(xi, w):
        N, Npsi = iie_shape_functions(x, L, phi)
        dN = (iie_shape_functions(x + h, L, phi)[0] - iie_shape_functions(x - h, L, phi)[0]) / (2 * h * L)
        dNpsi = (iie_shape_functions(x + h, L, phi)[1] - iie_shape_functions(x - h, L, phi)[1]) / (2 * h * L)
        gamma = dN - Npsi  # shear strain
        Kq += wt * L * (E * I * np.outer(dNpsi, dNpsi) + kappa * G * A * np.outer(gamma, gamma))
        Mt += wt * L * RHO * A * np.outer(N, N)
        Mr += wt * L * RHO * I * np.outer(Npsi, Npsi)
    np.testing.assert_allclose(fe.plane_stiffness(L, E * I, phi), Kq, rtol=1e-6, atol=1e-6 * np.abs(Kq).max())
    np.testing.assert_allclose(fe.plane_mass_translational(L, RHO * A, phi), Mt, rtol=1e-8, atol=1e-10 * np.abs(Mt).max())
    np.testing.assert_allclose(fe.plane_mass_rotary(L, RHO * I, phi), Mr, rtol=1e-8, atol=1e-10 * np.abs(Mr).max())


def test_euler_bernoulli_limit_is_the_textbook_element():
    # phi = 0: Przemieniecki / any FE text: EI/L^3 [12 6L -12 6L; ...], rho A L/420 [156 22L 54 -13L; ...]
    L = 0.3
    K = fe.plane_stiffness(L, 1.0, 0.0) * L**3
    np.testing.assert_allclose(K, [[12, 6 * L, -12, 6 * L], [6 * L, 4 * L**2, -6 * L, 2 * L**2],
                                   [-12, -6 * L, 12, -6 * L], [6 * L, 2 * L**2, -6 * L, 4 * L**2]])
    M = fe.plane_mass_translational(L, 1.0, 0.0) * 420 / L
    np.testing.assert_allclose(M, [[156, 22 * L, 54, -13 * L], [22 * L, 4 * L**2, 13 * L, -3 * L**2],
                                   [54, 13 * L, 156, -22 * L], [-13 * L, -3 * L**2, -22 * L, 4 * L**2]])


def test_shear_coefficient_hutchinson():
    # solid circle: kappa = 6 (1+nu)^2 / (7 + 12 nu + 4 nu^2) (Hutchinson 2001; Stephen's discussion,
    # J. Appl. Mech. 68 (2001) 959: "widely accepted" value for the circular section)
    assert fe.shear_coefficient(0.02, 0.0, 0.3) == pytest.approx(6 * 1.3**2 / (7 + 3.6 + 0.36))
    # thin-walled limit of the same hollow formula, r -> 1: (1 + nu) / (2 + nu) (algebra on the formula)
    assert fe.shear_coefficient(1.0, 0.999999, 0.3) == pytest.approx(1.3 / 2.3, rel=1e-5)


@pytest.mark.parametrize("shear", [True, False])
def test_element_symmetry_definiteness_and_skew_gyroscopic(shear):
    m = fe.beam_matrices(0.04, 0.031, 0.01, E, RHO, NU, shear=shear)
    M, K, G = m["M"], m["K"], m["G"]
    np.testing.assert_allclose(M, M.T, atol=1e-15)
    np.testing.assert_allclose(K, K.T, rtol=1e-12, atol=1e-9 * np.abs(K).max())
    np.testing.assert_allclose(G, -G.T, atol=1e-18)
    assert np.linalg.eigvalsh(M).min() > 0
    ek = np.linalg.eigvalsh(K)
    # 8 DOFs, 2 rigid modes per bending plane (translation + rotation) -> exactly 4 zero eigenvalues
    assert np.sum(np.abs(ek) < 1e-9 * ek.max()) == 4
    assert ek.min() > -1e-9 * ek.max()


def test_slopes_sign_convention():
    """A rigid tilt of a shaft element with dy/dx = theta_z and dz/dx = -theta_y costs no strain energy."""
    L = 0.1
    K = fe.beam_stiffness(L, 0.02, 0.0, E, RHO, NU)
    a = 1e-3
    tilt_xy = np.array([0, 0, 0, a, a * L, 0, 0, a])        # y = a x, theta_z = a
    tilt_xz = np.array([0, 0, a, 0, 0, -a * L, a, 0])       # z = -a x, theta_y = a
    wrong = np.array([0, 0, a, 0, 0, a * L, a, 0])          # z = +a x with theta_y = a: bends the shaft
    for q in (tilt_xy, tilt_xz):
        assert np.linalg.norm(K @ q) < 1e-9 * np.abs(K).max() * a
    assert np.linalg.norm(K @ wrong) > 1e-3 * np.abs(K).max() * a


def test_global_matrices_paper_like_shaft():
    M, K, G, C = uniform_shaft(0.7, 0.012, 10)
    assert np.allclose(M, M.T) and np.allclose(K, K.T, atol=1e-9 * np.abs(K).max())
    np.testing.assert_allclose(G, -G.T)
    assert np.linalg.eigvalsh(M).min() > 0


# ----------------------------------------------------------------------------- beam frequencies
def timoshenko_ss(n, L, od, id_=0.0, E=E, rho=RHO, nu=NU):
    """Simply supported Timoshenko beam, mode n (lower branch) [rad/s].

    w = W sin(k x), psi = Psi cos(k x), k = n pi / L in
        kGA (w'' - psi') = rho A w_tt,    EI psi'' + kGA (w' - psi) = rho I psi_tt
    gives (kGA k^2 - rho A w^2)(EI k^2 + kGA - rho I w^2) - (kGA k)^2 = 0 (Timoshenko 1921;
    Han, Benaroya, Wei, J. Sound Vib. 225 (1999) 935, eq. for the simply supported case).
    """
    A, I = math.pi / 4 * (od**2 - id_**2), math.pi / 64 * (od**4 - id_**4)
    kGA = fe.shear_coefficient(od, id_, nu) * E / (2 * (1 + nu)) * A
    k = n * math.pi / L
    a = rho * A * rho * I
    b = -(rho * A * (E * I * k**2 + kGA) + rho * I * kGA * k**2)
    c = kGA * E * I * k**4
    # lower root of a w^4 + b w^2 + c = 0, written without cancellation: 2c / (-b + sqrt(b^2 - 4ac))
    return math.sqrt(2 * c / (-b + math.sqrt(b * b - 4 * a * c)))


def simply_supported_fe(L, od, n_el, n_modes, id_=0.0):
    M, K, _, _ = uniform_shaft(L, od, n_el, id_)
    ends = [0, 1, 4 * n_el, 4 * n_el + 1]  # y, z of the first and last node pinned
    keep = [i for i in range(M.shape[0]) if i not in ends]
    w2 = scipy.linalg.eigh(K[np.ix_(keep, keep)], M[np.ix_(keep, keep)], eigvals_only=True)
    w = np.sqrt(w2)
    np.testing.assert_allclose(w[0::2], w[1::2], rtol=1e-8)  # y and z planes identical
    return w[0::2][:n_modes]


def test_simply_supported_stubby_shaft_converges_to_timoshenko():
    """Rayleigh-Ritz: FE frequencies lie above the exact ones and converge to them.

    The element's shear strain is constant along it, so where shear energy matters the
    frequency error falls as h^2 (bending alone would give h^4): we check the order and that
    Richardson extrapolation of the two finest meshes lands on the analytic value.
    """
    L, od, idm = 0.25, 0.05, 0.02  # L/D = 5: shear and rotary inertia matter
    exact = np.array([timoshenko_ss(n, L, od, idm) for n in (1, 2, 3)])
    # the same shaft as Euler-Bernoulli, (n pi/L)^2 sqrt(EI/rho A): clearly different here
    A, I = math.pi / 4 * (od**2 - idm**2), math.pi / 64 * (od**4 - idm**4)
    eb = np.array([(n * math.pi / L) ** 2 * math.sqrt(E * I / (RHO * A)) for n in (1, 2, 3)])
    assert np.all(eb / exact - 1 > 0.03)

    meshes = (4, 8, 16, 32, 64)
    w = np.array([simply_supported_fe(L, od, n_el, 3, idm) for n_el in meshes])
    err = w / exact - 1
    assert np.all(err > 0)                       # upper bounds
    assert np.all(np.diff(err, axis=0) < 0)      # monotone convergence
    order = np.log2(err[-2] / err[-1])
    assert np.all((order > 1.9) & (order < 2.1)), order
    assert np.abs(err[-1]).max() < 5e-4          # 64 elements
    richardson = (4 * w[-1] - w[-2]) / 3
    np.testing.assert_allclose(richardson, exact, rtol=2e-6)


@pytest.mark.parametrize("slenderness, rtol", [(100, 2e-3), (1000, 3e-5)])
def test_slender_shaft_tends_to_euler_bernoulli(slenderness, rtol):
    """(n pi/L)^2 sqrt(EI/rho A); the gap that remains is Timoshenko's correction, of order
    (n pi / L)^2 (D/4)^2 (1 + E / kappa G) / 2 = 1.1e-3 for n = 3, L/D = 100."""
    L = 1.0
    od = L / slenderness
    A, I = math.pi / 4 * od**2, math.pi / 64 * od**4
    eb = np.array([(n * math.pi / L) ** 2 * math.sqrt(E * I / (RHO * A)) for n in (1, 2, 3)])
    w = simply_supported_fe(L, od, 40, 3)
    np.testing.assert_allclose(w, eb, rtol=rtol)
    assert np.all(w < eb)  # shear and rotary inertia lower the frequencies
    exact = np.array([timoshenko_ss(n, L, od) for n in (1, 2, 3)])
    np.testing.assert_allclose(w, exact, rtol=1e-5)


def test_free_free_beam_has_four_rigid_modes_and_euler_bernoulli_first_mode():
    """Our element has only bending DOFs (no axial, no torsion), so the rigid motions of a free
    shaft are translation and rotation in each of the two bending planes: 2 per plane, 4 in all.
    (Not "4 per plane": a plane beam has 2 rigid modes, translation and rotation.)"""
    L, od, n_el = 1.0, 0.01, 20
    M, K, _, _ = uniform_shaft(L, od, n_el)
    w2 = scipy.linalg.eigh(K, M, eigvals_only=True)
    scale = w2.max()
    assert np.sum(np.abs(w2) < 1e-10 * scale) == 4
    # first flexible mode, twice (y and z): Euler-Bernoulli free-free beta1 L = 4.730040745
    # (Blevins, Formulas for Natural Frequency and Mode Shape, table 8-1)
    A, I = math.pi / 4 * od**2, math.pi / 64 * od**4
    w1 = (4.730040745 / L) ** 2 * math.sqrt(E * I / (RHO * A))
    np.testing.assert_allclose(np.sqrt(w2[4:6]), w1, rtol=1e-3)


# ----------------------------------------------------------------------------- disk and gyroscopics
def test_disk_properties_hollow_cylinder():
    od, idm, w = 0.095, 0.0235, 0.047
    m, Id, Ip = fe.disk_properties(od, idm, w, RHO)
    ro, ri = od / 2, idm / 2
    assert m == pytest.approx(RHO * math.pi * (ro**2 - ri**2) * w)
    assert Ip == pytest.approx(m * (ro**2 + ri**2) / 2)          # hollow cylinder about its axis
    assert Id == pytest.approx(m * (3 * (ro**2 + ri**2) + w**2) / 12)  # about a diameter through the centre


def test_rigid_disk_tilt_whirl_closed_form():
    """A disk on tilt springs k_t: Id w^2 -/+ Ip Omega w - k_t = 0 (forward: minus sign).

    From Id tdd_y + Ip Omega td_z + k_t t_y = 0, Id tdd_z - Ip Omega td_y + k_t t_z = 0 with the
    axis tip (t_z, -t_y) = (cos w t, sin w t) for forward whirl.
    """
    m, Id, Ip = 2.0, 0.01, 0.015
    k, kt = 1e6, 2e3
    d = fe.disk_matrices(m, Id, Ip)
    Kd = np.diag([k, k, kt, kt])
    Om = 300.0
    A = np.block([[np.zeros((4, 4)), np.eye(4)], [-np.linalg.solve(d["M"], Kd), -Om * np.linalg.solve(d["M"], d["G"])]])
    lam, vec = np.linalg.eig(A)
    pos = lam.imag > 0
    w = np.sort(lam.imag[pos])
    fwd = (Ip * Om + math.sqrt((Ip * Om) ** 2 + 4 * Id * kt)) / (2 * Id)
    bwd = (-Ip * Om + math.sqrt((Ip * Om) ** 2 + 4 * Id * kt)) / (2 * Id)
    np.testing.assert_allclose(sorted([bwd, math.sqrt(k / m), math.sqrt(k / m), fwd]), w, rtol=1e-10)
    assert fwd > math.sqrt(kt / Id) > bwd
    # the eigenvector of the rising root whirls forward: tip (Y, Z) = (t_z, -t_y), |Y + iZ| >> |Y - iZ|
    i = np.argmin(np.abs(lam - 1j * fwd))
    Y, Z = vec[3, i], -vec[2, i]
    assert abs(Y + 1j * Z) > 1e6 * abs(Y - 1j * Z)


def test_rigid_cylinder_on_springs_gyroscopic_closed_form_and_whirl_direction():
    """A very stiff shaft on equal springs k at both ends behaves as a rigid cylinder:
    bounce sqrt(2 k / m), conical Id w^2 -/+ Ip Omega w - k L^2 / 2 = 0 with
    Id = m (D^2/16 + L^2/12), Ip = m D^2 / 8 (solid cylinder about its centre)."""
    L, D, n_el, k = 0.3, 0.1, 6, 1e6
    stiff = Material(E=1000 * E, density=RHO, poisson=NU)
    rotor = Rotor(elements=[ShaftElement(L / n_el, D)] * n_el, material=stiff)
    m = RHO * math.pi / 4 * D**2 * L
    Id, Ip = m * (D**2 / 16 + L**2 / 12), m * D**2 / 8
    M, K, G = rotor.M, rotor.K.copy(), rotor.G
    for node in (0, n_el):
        for d in ("y", "z"):
            K[rotor.dof(node, d), rotor.dof(node, d)] += k
    assert np.ones(M.shape[0])[0::4] @ M[0::4, 0::4] @ np.ones(n_el + 1) == pytest.approx(m)

    prev = None
    for Om in (0.0, 500.0, 2000.0):
        A = np.block([[np.zeros_like(M), np.eye(len(M))], [-np.linalg.solve(M, K), -Om * np.linalg.solve(M, G)]])
        lam, vec = np.linalg.eig(A)
        sel = lam.imag > 0
        lam, vec = lam[sel], vec[: len(M), sel]
        order = np.argsort(lam.imag)
        lam, vec = lam[order][:4], vec[:, order][:, :4]
        bounce = math.sqrt(2 * k / m)
        fwd = (Ip * Om + math.sqrt((Ip * Om) ** 2 + 2 * Id * k * L**2)) / (2 * Id)
        bwd = (-Ip * Om + math.sqrt((Ip * Om) ** 2 + 2 * Id * k * L**2)) / (2 * Id)
        np.testing.assert_allclose(lam.imag, sorted([bounce, bounce, bwd, fwd]), rtol=1e-6)
        if Om > 0:
            i_f = int(np.argmin(np.abs(lam.imag - fwd)))
            i_b = int(np.argmin(np.abs(lam.imag - bwd)))
            # end node orbit and axis tilt of the rising branch: forward; of the falling one: backward
            assert rotor.whirl(vec[:, i_f], n_el) > 0.999 and rotor.whirl(vec[:, i_f], 0, tilt=True) > 0.999
            assert rotor.whirl(vec[:, i_b], n_el) < -0.999 and rotor.whirl(vec[:, i_b], 0, tilt=True) < -0.999
            assert fwd > prev[1] and bwd < prev[0]
        prev = (bwd, fwd)
