"""The film's axial cells: the half length of a plain bore, or one land of a bore fed by a
circumferential groove (``[geometry] circumferential_groove_mm``), and the groove's flow into the lands.

The Reynolds solver (``reynolds.py``) solves one axial half of the film: for the plain bore from the
end (p = 0, j = 0) to the mid-plane (zero flux by symmetry, j = m - 1); for a circumferential groove
of width w at mid-length, one land of l' = (L - w) / 2 from its outer end (p = 0) to the groove's
edge (p = p_s, the supply pressure): the two lands are mirror images for an aligned journal (the film
h(theta) does not depend on x and the groove's pressure is uniform), so one land with its inner edge
at p_s is the whole film, as the handbooks' two half-bearings of length l' (Shigley's pressure-fed
bearing). The groove itself is deep: its pressure p_s acts all round (no net force) and it shears no
film (the Couette torque and flux are the lands' only, length L - w).

Both Dirichlet faces take the second-order one-sided gradient of the quadratic through the face
value and the two nearest cell centres: (9 p0 - p1) / (3 dx) at the outer end, and
(8 p_s - 9 p_{m-1} + p_{m-2}) / (3 dx) toward the groove at the inner one; each such row is scaled
by 3/4 (A stays symmetric), which leaves 3 p0 - p1 and 3 p_{m-1} - p_{m-2} - 2 p_s. The force
quadrature is the midpoint sum with the Euler-Maclaurin correction (dx^2 / 24) (p'(b) - p'(a)) at
every Dirichlet end (its p_s part is a constant along theta: no force, no torque).
"""

from __future__ import annotations

import numpy as np

from ..params import BearingParams

__all__ = ["axial_stencil", "film_length", "groove_inflow", "has_lands", "land_cells"]


def has_lands(params: BearingParams) -> bool:
    """Whether the film is two lands fed by a circumferential groove."""
    return bool(params.geometry.circumferential_groove)


def film_length(params: BearingParams) -> float:
    """The axial length [m] the film covers: L, less a circumferential groove's width."""
    return params.L - params.geometry.circumferential_groove if has_lands(params) else params.L


def land_cells(params: BearingParams, n_x: int) -> tuple[float, np.ndarray]:
    """(dx [m], x [m] of the n_x cell centres over the whole length): n_x / 2 cells over the half
    length, or over each land (the groove's cells are not cells of the film)."""
    m = n_x // 2
    if not has_lands(params):
        dx = params.L / n_x
        return dx, -0.5 * params.L + (np.arange(n_x) + 0.5) * dx
    if m < 2:
        raise ValueError(f"n_x = {n_x}: a bore with a circumferential groove needs n_x >= 4 (at least 2 cells per "
                         "land: the land has a Dirichlet face at both ends)")
    dx = 0.5 * film_length(params) / m
    left = -0.5 * params.L + (np.arange(m) + 0.5) * dx
    return dx, np.concatenate([left, -left[::-1]])


def axial_stencil(m: int, dx: float, land: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(tdiag, rs, qw) of the m axial cells (module docstring): the axial row's diagonal in units of
    h^3 dtheta / dx, the row scaling, and the force quadrature weights [m] of one half (both halves:
    x 2). ``land``: Dirichlet at both ends (a circumferential groove's land), else the end and the
    symmetry plane."""
    td = np.full(m, 2.0)
    rs = np.ones(m)
    qw = np.full(m, dx)
    if m == 1:
        # one cell per half: symmetric quadratic p0 (L^2/4 - x^2) / (3 L^2 / 16)
        td[0] = 8.0 / 3.0
        qw[0] = 8.0 / 9.0 * dx
        return td, rs, qw
    td[0] = 3.0
    td[-1] = 3.0 if land else 1.0
    rs[0] = 0.75
    # axial quadrature: midpoint sum with the Euler-Maclaurin end correction
    # -(dx^2 / 24) p'(end), p'(end) = (9 p0 - p1) / (3 dx); p' = 0 at the symmetry plane
    qw[0] -= dx / 8.0
    qw[1] += dx / 72.0
    if land:
        rs[-1] = 0.75
        qw[-1] -= dx / 8.0
        qw[-2] += dx / 72.0
    return td, rs, qw


def groove_inflow(params: BearingParams, y: float, z: float, p_half: np.ndarray, dx: float, centre: np.ndarray,
                  width: np.ndarray) -> np.ndarray:
    """The flow [m^3/s] from the circumferential groove into both lands at every cell column (the
    cells' centres and widths [rad]; negative where the film's pressure pushes oil back into the
    groove), with the solver's own inner-edge gradient (8 p_s - 9 p_{m-1} + p_{m-2}) / (3 dx)."""
    hc = params.CR + y * np.sin(centre) - z * np.cos(centre)
    grad = (8.0 * params.geometry.supply_pressure - 9.0 * p_half[:, -1] + p_half[:, -2]) / (3.0 * dx)
    return 2.0 * hc ** 3 / (12.0 * params.mu) * grad * params.R * width
