"""The steady synchronous (1x) response of the linearised rotor to its unbalances.

The conventions are those of docs/conventions.md: x the shaft axis, y horizontal, z vertical,
4 DOFs per node (y, z, theta_y, theta_z), Omega > 0 turning from +y toward +z, the bearing
coefficients in Lund's sign (film force = -K q - C qd at (y, z) of the bearing node).

**Equation.** About the static equilibrium, with the bearings' K_b(Omega), C_b(Omega) at that
speed (``stability.Stability``: the equilibrium under the weight and static loads, each film
linearised there), the rotor's shaft damping C (= beta K) and its gyroscopic matrix G::

    M qdd + (C + C_b + Omega G) qd + (K + K_b) q = F(t)

**Force.** An unbalance of mass m [kg] at radius r [m] and angle phi on node n
(``Rotor.unbalance_force``) pushes with ``m r Omega^2 (cos, sin)(Omega t + phi)`` on (y, z):
at t = 0, phi = 0 along +y, turning with the shaft. Written F(t) = Re(F^ e^{i Omega t})::

    F^_y = m r Omega^2 e^{i phi},   F^_z = -i m r Omega^2 e^{i phi}

(sin a = Re(-i e^{i a})). Several unbalances add their F^.

**Steady response.** q(t) = Re(X e^{i Omega t}) with::

    (K + K_b - Omega^2 M + i Omega (C + C_b + Omega G)) X = F^

one complex linear solve per speed (the matrix is not Hermitian: G is skew, K_b and C_b need
not be symmetric). This is the particular solution; it is what the machine does only where the
homogeneous part decays, i.e. below the stability threshold (every log decrement > 0).

**Amplitude and phase per direction.** With X_y = A_y e^{i phi_y}::

    y(t) = A_y cos(Omega t + phi_y),   z(t) = A_z cos(Omega t + phi_z)

``y_amplitude_m`` = A_y = |X_y| is the 0-peak amplitude and ``y_phase_deg`` = phi_y =
arg X_y in degrees (-180, 180], the angle the response leads the reference: the response
peaks along +y when the shaft has turned by -phi_y from the moment the reference (an
unbalance at angle 0) points along +y. A probe's phase *lag*, as a vibration analyser
plots it, is -phi.

**Forward and backward whirl.** The orbit y + i z is the sum of two circles::

    y + i z = X_f e^{i Omega t} + conj(X_b) e^{-i Omega t},   X_f = (X_y + i X_z) / 2,
                                                              X_b = (X_y - i X_z) / 2

|X_f| the forward radius (the orbit turns with the shaft), |X_b| the backward one; the orbit
is an ellipse with semi-axes |X_f| + |X_b| (``major_m``, the largest excursion from the
equilibrium in any direction) and ||X_f| - |X_b|| (``minor_m``); it turns forward when
|X_f| > |X_b|. On an isotropic rotor (K_b, C_b multiples of the identity, no cross-coupling)
a forward unbalance drives only the forward circle: X_z = -i X_y, so A_y = A_z and
phi_z = phi_y - 90 deg, X_b = 0 (tests/test_response.py checks it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...model.rotor import Rotor


@dataclass(frozen=True)
class Unbalance:
    """One unbalance: ``node`` 1-based as in the rotor file, ``mass_g`` [g] at ``radius_mm``
    [mm] and angle ``phase_deg`` [deg] from +y toward +z at t = 0."""

    node: int
    mass_g: float
    radius_mm: float
    phase_deg: float = 0.0

    @property
    def moment_kg_m(self) -> float:
        """m r [kg m]."""
        return self.mass_g * 1e-3 * self.radius_mm * 1e-3

    def label(self) -> str:
        return f"{self.mass_g:g} g at {self.radius_mm:g} mm, {self.phase_deg:g} deg, node {self.node}"

    def as_dict(self) -> dict:
        return {"node": self.node, "mass_g": self.mass_g, "radius_mm": self.radius_mm, "phase_deg": self.phase_deg}


def check_unbalances(rotor: Rotor, unbalances, where: str = "rotor") -> list[Unbalance]:
    """The unbalances as ``Unbalance`` (from tuples node, mass_g, radius_mm[, phase_deg]), their
    nodes inside the rotor's; ValueError naming the one outside."""
    out = []
    for u in unbalances:
        u = u if isinstance(u, Unbalance) else Unbalance(*u)
        if not 1 <= int(u.node) <= rotor.n_nodes:
            raise ValueError(f"--unbalance {u.node}:{u.mass_g:g}:{u.radius_mm:g}: node {u.node} is outside the "
                             f"rotor's nodes 1..{rotor.n_nodes} ({where})")
        out.append(u)
    if not out:
        raise ValueError("--unbalance: give at least one NODE:MASS_G:RADIUS_MM[:PHASE_DEG]")
    return out


def force_amplitude(rotor: Rotor, unbalances, omega: float) -> np.ndarray:
    """F^ [N] (complex, n_dof) of the unbalances at ``omega`` [rad/s]: F(t) = Re(F^ e^{i omega t})."""
    F = np.zeros(rotor.n_dof, complex)
    for u in unbalances:
        f = u.moment_kg_m * omega**2 * np.exp(1j * math.radians(u.phase_deg))
        F[rotor.dof(u.node - 1, "y")] += f
        F[rotor.dof(u.node - 1, "z")] += -1j * f
    return F


def dynamic_stiffness(rotor: Rotor, omega: float, bearing_K, bearing_C) -> np.ndarray:
    """K + K_b - omega^2 M + i omega (C + C_b + omega G) [N/m], n_dof x n_dof complex."""
    Kt = rotor.K + rotor.bearing_matrix(bearing_K)
    Ct = rotor.C + rotor.bearing_matrix(bearing_C) + omega * rotor.G
    return Kt - omega**2 * rotor.M + 1j * omega * Ct


def solve(rotor: Rotor, omega: float, bearing_K, bearing_C, unbalances) -> np.ndarray:
    """X [m, rad] (complex, n_dof): the steady response q = Re(X e^{i omega t}) (module docstring)."""
    return np.linalg.solve(dynamic_stiffness(rotor, omega, bearing_K, bearing_C),
                           force_amplitude(rotor, unbalances, omega))


def node_response(rotor: Rotor, X: np.ndarray, node0: int) -> dict:
    """At 0-based ``node0``: 0-peak amplitudes [m] and phases [deg] per direction, the forward and
    backward radii and the orbit's semi-axes [m] (module docstring)."""
    Y, Z = X[rotor.dof(node0, "y")], X[rotor.dof(node0, "z")]
    f, b = abs(Y + 1j * Z) / 2.0, abs(Y - 1j * Z) / 2.0
    return {"y_amplitude_m": abs(Y), "z_amplitude_m": abs(Z), "y_phase_deg": math.degrees(np.angle(Y)),
            "z_phase_deg": math.degrees(np.angle(Z)), "forward_m": f, "backward_m": b, "major_m": f + b,
            "minor_m": abs(f - b)}


FIELDS = ("y_amplitude_m", "z_amplitude_m", "y_phase_deg", "z_phase_deg", "forward_m", "backward_m", "major_m",
          "minor_m")


__all__ = ["Unbalance", "check_unbalances", "force_amplitude", "dynamic_stiffness", "solve", "node_response",
           "FIELDS"]
