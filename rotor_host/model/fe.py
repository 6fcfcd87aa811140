"""Finite-element matrices of a rotor: Timoshenko shaft element and rigid disk.

Degrees of freedom and signs
----------------------------
Every node has 4 DOFs in the order ``(y, z, theta_y, theta_z)`` (DESIGN.md): ``x`` is the
shaft axis, ``y`` horizontal, ``z`` vertical, ``theta_y`` and ``theta_z`` are small
right-handed rotations of the cross-section about ``y`` and ``z``. A rotation about ``z``
turns the axis ``x`` toward ``+y`` and a rotation about ``y`` turns it toward ``-z``, so for
a slender (Euler-Bernoulli) shaft the slopes are::

    dy/dx = +theta_z          dz/dx = -theta_y

A beam element has 8 DOFs ``(y1, z1, ty1, tz1, y2, z2, ty2, tz2)``.

The element matrices are written once in the textbook plane form, DOFs ``(u1, psi1, u2,
psi2)`` with ``psi`` the cross-section rotation that equals ``du/dx`` when shear is
neglected (Friswell, Penny, Garvey, Lees, "Dynamics of Rotating Machines", CUP 2010,
sec. 5.4; Nelson, "A finite rotating shaft element using Timoshenko beam theory",
J. Mech. Des. 102 (1980) 793-803). They are placed into our DOFs with signed selectors:

* x-y plane: ``(u, psi) = (y, +theta_z)``   (selector ``S_xy``),
* x-z plane: ``(u, psi) = (z, -theta_y)``   (selector ``S_xz``),

so ``K = S_xy^T K_p S_xy + S_xz^T K_p S_xz`` and likewise for ``M``. The two planes' blocks
therefore differ in the sign of every translation-rotation coupling term. Nelson (1980)
uses the same kinematics (translations V, W along y, z; rotations B, Gamma about y, z with
V' = Gamma, W' = -B), so his matrices map onto ours by the permutation
(V, W, B, Gamma) -> (y, z, theta_y, theta_z); Friswell et al. label their axes
differently; their plane matrices enter through the plane form above.

Gyroscopics
-----------
The angular momentum of a thin slice spinning at ``Omega`` about its tilted axis
``(1, theta_z, -theta_y)`` is ``dIp*Omega*(1, theta_z, -theta_y) + dId*(0, dot theta_y,
dot theta_z)``; Euler's law gives

    dId * dd theta_y + dIp * Omega * d theta_z/dt = M_y
    dId * dd theta_z - dIp * Omega * d theta_y/dt = M_z

so in ``M qdd + (C + Omega G) qd + K q = F`` (Omega > 0 = right-handed about x, y -> z)
the rigid disk has ``G[ty, tz] = +Ip``, ``G[tz, ty] = -Ip``, and the shaft element has

    G = (Ip/Id) * (S_xy^T M_r S_xz - S_xz^T M_r S_xy),

with ``M_r`` the rotary-inertia plane matrix (``theta_z = psi_xy``, ``theta_y = -psi_xz``).
For a circular section ``Ip/Id = 2``. With this sign the forward whirl (from +y toward +z)
is stiffened, which tests/test_fe.py checks.

All inputs in SI units: lengths in m, E and G in Pa, density in kg/m^3.
"""

from __future__ import annotations

import math

import numpy as np

# element DOF indices within a node
Y, Z, TY, TZ = 0, 1, 2, 3
DOFS_PER_NODE = 4


def _selectors() -> tuple[np.ndarray, np.ndarray]:
    """Signed 4x8 selectors mapping element DOFs to the plane DOFs (u1, psi1, u2, psi2)."""
    s_xy = np.zeros((4, 8))
    s_xz = np.zeros((4, 8))
    for k, off in enumerate((0, 4)):
        s_xy[2 * k, off + Y] = 1.0       # u = y
        s_xy[2 * k + 1, off + TZ] = 1.0  # psi = +theta_z  (dy/dx = theta_z)
        s_xz[2 * k, off + Z] = 1.0       # u = z
        s_xz[2 * k + 1, off + TY] = -1.0  # psi = -theta_y (dz/dx = -theta_y)
    return s_xy, s_xz


S_XY, S_XZ = _selectors()


# ----------------------------------------------------------------------------- section
def area(od_m: float, id_m: float = 0.0) -> float:
    """Cross-section area [m^2] of a hollow circle."""
    return math.pi / 4.0 * (od_m**2 - id_m**2)


def second_moment(od_m: float, id_m: float = 0.0) -> float:
    """Area moment of inertia about a diameter, I [m^4] (the polar one is 2 I)."""
    return math.pi / 64.0 * (od_m**4 - id_m**4)


def shear_coefficient(od_m: float, id_m: float = 0.0, poisson: float = 0.3) -> float:
    """Timoshenko shear coefficient kappa of a hollow circular section.

    Hutchinson, "Shear coefficients for Timoshenko beam theory", J. Appl. Mech. 68 (2001)
    87-92 (identical to Stephen 1980; used in Friswell et al. 2010, Table 5.1)::

        kappa = 6 (1+nu)^2 (1+r^2)^2 / [(7 + 12 nu + 4 nu^2)(1+r^2)^2 + 4 (5 + 6 nu + 2 nu^2) r^2]

    with ``r = id/od``; for a solid section ``6 (1+nu)^2 / (7 + 12 nu + 4 nu^2)``.
    """
    if od_m <= 0.0 or not 0.0 <= id_m < od_m:
        raise ValueError(f"need 0 <= id < od and od > 0, got id={id_m!r} m, od={od_m!r} m")
    r2 = (id_m / od_m) ** 2
    nu = poisson
    a = (1.0 + r2) ** 2
    return 6.0 * (1.0 + nu) ** 2 * a / ((7.0 + 12.0 * nu + 4.0 * nu**2) * a + 4.0 * (5.0 + 6.0 * nu + 2.0 * nu**2) * r2)


def shear_parameter(length_m: float, od_m: float, id_m: float, E_Pa: float, poisson: float) -> float:
    """Phi = 12 E I / (kappa G A L^2), G = E / (2 (1 + nu)); 0 for an Euler-Bernoulli beam."""
    G = E_Pa / (2.0 * (1.0 + poisson))
    kappa = shear_coefficient(od_m, id_m, poisson)
    return 12.0 * E_Pa * second_moment(od_m, id_m) / (kappa * G * area(od_m, id_m) * length_m**2)


# ----------------------------------------------------------------------------- plane matrices
def plane_stiffness(length_m: float, EI: float, phi: float) -> np.ndarray:
    """Timoshenko stiffness in plane DOFs (u1, psi1, u2, psi2) [N/m, N, N m].

    Friswell et al. (2010) sec. 5.4, Przemieniecki (1968); ``phi = 0`` gives Euler-Bernoulli.
    """
    L = length_m
    c = EI / ((1.0 + phi) * L**3)
    return c * np.array([
        [12.0, 6.0 * L, -12.0, 6.0 * L],
        [6.0 * L, (4.0 + phi) * L**2, -6.0 * L, (2.0 - phi) * L**2],
        [-12.0, -6.0 * L, 12.0, -6.0 * L],
        [6.0 * L, (2.0 - phi) * L**2, -6.0 * L, (4.0 + phi) * L**2],
    ])


def plane_mass_translational(length_m: float, rhoA: float, phi: float) -> np.ndarray:
    """Consistent translational mass of the Timoshenko element, plane DOFs (Friswell et al. sec. 5.4)."""
    L, p = length_m, phi
    m1 = 312.0 + 588.0 * p + 280.0 * p**2
    m2 = (44.0 + 77.0 * p + 35.0 * p**2) * L
    m3 = 108.0 + 252.0 * p + 140.0 * p**2
    m4 = -(26.0 + 63.0 * p + 35.0 * p**2) * L
    m5 = (8.0 + 14.0 * p + 7.0 * p**2) * L**2
    m6 = -(6.0 + 14.0 * p + 7.0 * p**2) * L**2
    c = rhoA * L / (840.0 * (1.0 + p) ** 2)
    return c * np.array([
        [m1, m2, m3, m4],
        [m2, m5, -m4, m6],
        [m3, -m4, m1, -m2],
        [m4, m6, -m2, m5],
    ])


def plane_mass_rotary(length_m: float, rhoI: float, phi: float) -> np.ndarray:
    """Consistent rotary-inertia mass of the Timoshenko element, plane DOFs (Friswell et al. sec. 5.4).

    ``rhoI`` is density times the diametral area moment I [kg m].
    """
    L, p = length_m, phi
    m7 = 36.0
    m8 = (3.0 - 15.0 * p) * L
    m9 = (4.0 + 5.0 * p + 10.0 * p**2) * L**2
    m10 = (-1.0 - 5.0 * p + 5.0 * p**2) * L**2
    c = rhoI / (30.0 * (1.0 + p) ** 2 * L)
    return c * np.array([
        [m7, m8, -m7, m8],
        [m8, m9, -m8, m10],
        [-m7, -m8, m7, -m8],
        [m8, m10, -m8, m9],
    ])


def _both_planes(p: np.ndarray) -> np.ndarray:
    return S_XY.T @ p @ S_XY + S_XZ.T @ p @ S_XZ


# ----------------------------------------------------------------------------- shaft element
def beam_matrices(
    length_m: float,
    od_m: float,
    id_m: float,
    E_Pa: float,
    density_kg_m3: float,
    poisson: float,
    *,
    shear: bool = True,
    rotary_inertia: bool = True,
) -> dict[str, np.ndarray]:
    """8x8 matrices ``M``, ``K``, ``G`` of a hollow circular Timoshenko shaft element.

    DOFs ``(y1, z1, ty1, tz1, y2, z2, ty2, tz2)``; ``G`` multiplies ``Omega`` [rad/s] in
    ``M qdd + (C + Omega G) qd + K q = F``. ``shear=False`` and ``rotary_inertia=False``
    reduce it to the Rayleigh / Euler-Bernoulli element (for tests).
    """
    if length_m <= 0.0:
        raise ValueError(f"element length must be > 0, got {length_m!r} m")
    A = area(od_m, id_m)
    I = second_moment(od_m, id_m)
    phi = shear_parameter(length_m, od_m, id_m, E_Pa, poisson) if shear else 0.0
    Kp = plane_stiffness(length_m, E_Pa * I, phi)
    Mt = plane_mass_translational(length_m, density_kg_m3 * A, phi)
    Mr = plane_mass_rotary(length_m, density_kg_m3 * I, phi)
    M = _both_planes(Mt + Mr) if rotary_inertia else _both_planes(Mt)
    K = _both_planes(Kp)
    # theta_z = psi_xy, theta_y = -psi_xz; polar moment Ip = 2 I
    G = 2.0 * (S_XY.T @ Mr @ S_XZ - S_XZ.T @ Mr @ S_XY)
    return {"M": M, "K": K, "G": G}


def beam_mass(length_m, od_m, id_m, E_Pa, density_kg_m3, poisson, **kw) -> np.ndarray:
    """8x8 mass matrix [kg, kg m, kg m^2] (translational + rotary inertia)."""
    return beam_matrices(length_m, od_m, id_m, E_Pa, density_kg_m3, poisson, **kw)["M"]


def beam_stiffness(length_m, od_m, id_m, E_Pa, density_kg_m3, poisson, **kw) -> np.ndarray:
    """8x8 stiffness matrix with shear deformation [N/m, N, N m]."""
    return beam_matrices(length_m, od_m, id_m, E_Pa, density_kg_m3, poisson, **kw)["K"]


def beam_gyroscopic(length_m, od_m, id_m, E_Pa, density_kg_m3, poisson, **kw) -> np.ndarray:
    """8x8 skew-symmetric gyroscopic matrix [kg m^2] (to be multiplied by Omega)."""
    return beam_matrices(length_m, od_m, id_m, E_Pa, density_kg_m3, poisson, **kw)["G"]


# ----------------------------------------------------------------------------- rigid disk
def disk_properties(od_m: float, id_m: float, width_m: float, density_kg_m3: float) -> tuple[float, float, float]:
    """Mass [kg], diametral Id and polar Ip [kg m^2] of a hollow cylindrical disk.

    Ip = m (ro^2 + ri^2) / 2,  Id = m (ro^2 + ri^2) / 4 + m w^2 / 12 (about its centre).
    """
    if width_m <= 0.0 or od_m <= 0.0 or not 0.0 <= id_m < od_m:
        raise ValueError(f"disk needs 0 <= id < od and width > 0, got id={id_m!r}, od={od_m!r}, width={width_m!r} m")
    m = density_kg_m3 * area(od_m, id_m) * width_m
    r2 = (od_m**2 + id_m**2) / 4.0  # ro^2 + ri^2
    Ip = 0.5 * m * r2
    Id = 0.25 * m * r2 + m * width_m**2 / 12.0
    return m, Id, Ip


def disk_matrices(mass_kg: float, Id_kg_m2: float, Ip_kg_m2: float) -> dict[str, np.ndarray]:
    """4x4 ``M`` and ``G`` of a rigid disk at one node, DOFs (y, z, theta_y, theta_z).

    ``G[ty, tz] = +Ip`` and ``G[tz, ty] = -Ip`` (see the module docstring).
    """
    M = np.diag([mass_kg, mass_kg, Id_kg_m2, Id_kg_m2]).astype(float)
    G = np.zeros((4, 4))
    G[TY, TZ] = Ip_kg_m2
    G[TZ, TY] = -Ip_kg_m2
    return {"M": M, "G": G}


def disk_mass(mass_kg: float, Id_kg_m2: float, Ip_kg_m2: float) -> np.ndarray:
    return disk_matrices(mass_kg, Id_kg_m2, Ip_kg_m2)["M"]


def disk_gyroscopic(mass_kg: float, Id_kg_m2: float, Ip_kg_m2: float) -> np.ndarray:
    return disk_matrices(mass_kg, Id_kg_m2, Ip_kg_m2)["G"]
