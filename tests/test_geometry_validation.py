"""The Reynolds solver on grooved, partial-arc and lobed bores against published tables and
independent limits. Every expected number says where it comes from; docs/geometry.md shows the
tables side by side (``benchmarks/geometry_validation.py`` prints them).

Frames. Lund & Thomsen put x along the (downward) load and y horizontal, the journal turning
from x toward y. Here the load is -z and positive omega turns the journal surface from the
bottom (theta = 180 deg) toward +y (theta = 270 deg), so x = -z, y = y:
K_xx = K_zz, K_xy = -K_zy, K_yx = -K_yz, K_yy = K_yy (Lund's sign K = -dF/dq; damping alike).
Dimensionless as in their tables, with the PAD clearance C_p: S = mu N L D (R / C_p)^2 / W
(N in rev/s), eps = e / C_p, K = k C_p / W, B = c C_p omega / W.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from bearing_fmu.physics.geometry import Geometry
from bearing_fmu.physics.params import BearingParams
from bearing_fmu.physics.reynolds import Reynolds
from bearing_fmu.physics.statics import equilibrium, linearize

D90, D270 = math.radians(90.0), math.radians(270.0)

# Lund, J. W. & Thomsen, K. K. (1978), "A calculation method and data for the dynamic coefficients
# of oil-lubricated journal bearings", in Topics in Fluid Film Bearing and Rotor Bearing System
# Design and Optimization, ASME, pp. 1-28: isoviscous, Swift-Stieber (Reynolds) cavitation,
# two 20 deg axial grooves at the horizontal split (two 160 deg pads), grooves at ambient pressure.
# Rows: (S, eps, phi [deg], Kxx, Kxy, Kyx, Kyy, Bxx, Bxy (= Byx), Byy).
# L/D = 0.5: 16 rows as transcribed in github.com/VictorLier/Tribology, Assignment2/Someya.py
# ("Tabletest"; its rows at S = 1.656, 0.917, 0.580, 0.378(0.379), 0.244 are the 5 that
# github.com/petrobras/ross, ross/tests/test_fluid_film_literature.py, transcribes from Lund &
# Thomsen, equal digit for digit but ROSS's S = 0.379 where the other has 0.378).
# L/D = 1: the 5 rows of the ROSS transcription (which leaves out the S = 0.358 row, whose Kyy
# breaks the column's trend: a scan error in the table, says ROSS).
LT_TWO_AXIAL_GROOVE = {
    0.5: [
        (6.430, 0.071, 81.89, 1.55, 14.41, -6.60, 1.88, 28.75, 1.89, 13.31),
        (3.937, 0.114, 77.32, 1.57, 9.27, -4.20, 1.89, 18.44, 1.93, 8.58),
        (2.634, 0.165, 72.36, 1.61, 6.74, -3.01, 1.91, 13.36, 2.00, 6.28),
        (2.030, 0.207, 68.75, 1.65, 5.67, -2.50, 1.93, 11.18, 2.07, 5.33),
        (1.656, 0.244, 65.85, 1.69, 5.06, -2.20, 1.95, 9.93, 2.15, 4.80),
        (0.917, 0.372, 57.45, 2.12, 4.01, -1.30, 1.85, 7.70, 2.06, 3.23),
        (0.580, 0.477, 51.01, 2.67, 3.70, -0.78, 1.75, 6.96, 1.94, 2.40),
        (0.379, 0.570, 45.43, 3.33, 3.64, -0.43, 1.68, 6.76, 1.87, 1.89),
        (0.244, 0.655, 40.25, 4.21, 3.74, -0.13, 1.64, 6.87, 1.82, 1.54),
        (0.194, 0.695, 37.72, 4.78, 3.84, 0.01, 1.62, 7.03, 1.80, 1.40),
        (0.151, 0.734, 35.20, 5.48, 3.98, 0.15, 1.61, 7.26, 1.79, 1.27),
        (0.133, 0.753, 33.93, 5.89, 4.07, 0.22, 1.60, 7.41, 1.79, 1.20),
        (0.126, 0.761, 33.42, 6.07, 4.11, 0.25, 1.60, 7.48, 1.79, 1.18),
        (0.116, 0.772, 32.65, 6.36, 4.17, 0.30, 1.60, 7.59, 1.79, 1.15),
        (0.086, 0.809, 30.04, 7.51, 4.42, 0.47, 1.59, 8.03, 1.79, 1.03),
        (0.042, 0.879, 24.41, 11.45, 5.23, 0.92, 1.60, 9.48, 1.80, 0.82),
    ],
    1.0: [
        (0.991, 0.150, 70.58, 1.56, 7.29, -2.16, 1.52, 14.66, 1.58, 4.49),
        (0.635, 0.224, 63.54, 1.62, 5.33, -1.57, 1.56, 10.80, 1.70, 3.41),
        (0.235, 0.460, 49.27, 2.19, 3.57, -0.80, 1.55, 7.36, 1.89, 2.19),
        (0.159, 0.559, 44.33, 2.73, 3.36, -0.48, 1.48, 6.94, 1.78, 1.74),
        (0.108, 0.650, 39.72, 3.45, 3.34, -0.23, 1.44, 6.89, 1.72, 1.43),
    ],
}
# Lund & Thomsen (1978), elliptical (lemon) bore, preload 0.5, L/D = 1, two 20 deg grooves at
# the horizontal split, load through the middle of the lower lobe; eps, S, K, B on the pad
# clearance. Rows as transcribed by ROSS (same file). The S = 0.161 row prints phi = 83.29 deg
# where its neighbours' trend gives ~85 deg (ROSS widens its tolerance for it); this solver
# gives 85.25 deg.
LT_ELLIPTICAL = [
    (0.211, 0.260, 87.79, 6.65, 4.36, -3.21, 0.86, 13.09, -2.23, 3.70),
    (0.161, 0.304, 83.29, 5.63, 3.84, -2.32, 1.01, 10.75, -1.02, 3.07),
    (0.120, 0.350, 81.80, 4.99, 3.54, -1.52, 1.14, 9.04, -0.01, 2.49),
    (0.097, 0.381, 78.65, 4.82, 3.46, -1.01, 1.21, 8.26, 0.56, 2.10),
]
LT_PHI_MISPRINT = {0.161: 2.5}  # [deg]: the tolerance of the row above
COEFFS = ("Kxx", "Kxy", "Kyx", "Kyy", "Bxx", "Bxy", "Byy")

# the journal of the tables' dimensionless numbers (any bearing gives the same numbers)
LT_D, LT_MU, LT_N = 0.1, 0.02, 50.0  # [m], [Pa s], [rev/s]


def lund_thomsen_row(geometry: Geometry, l_over_d: float, pad_clearance: float, S: float,
                     n_theta: int | None = None, n_x: int | None = None) -> dict:
    """eps, phi [deg] and the 7 coefficients (Lund & Thomsen's frame and scaling) of the bearing
    at Sommerfeld number S (on the pad clearance), from its static equilibrium under a downward
    load."""
    cr = pad_clearance * (1.0 - geometry.preload)  # CR is the assembled clearance
    prm = BearingParams(LT_D, l_over_d * LT_D, cr, LT_MU, geometry=geometry)
    r = Reynolds(prm, n_theta, n_x)
    om = 2 * math.pi * LT_N
    W = LT_MU * LT_N * prm.L * LT_D * (prm.R / pad_clearance) ** 2 / S
    y, z = equilibrium(r, (0.0, -W), om)
    K, C = linearize(r, y, z, om)
    k = np.array([K[1, 1], -K[1, 0], -K[0, 1], K[0, 0]]) * pad_clearance / W
    b = np.array([C[1, 1], -C[1, 0], -C[0, 1], C[0, 0]]) * pad_clearance * om / W
    out = {"eps": math.hypot(y, z) / pad_clearance, "phi": math.degrees(math.atan2(y, -z))}
    out.update(zip(("Kxx", "Kxy", "Kyx", "Kyy"), k))
    out.update({"Bxx": b[0], "Bxy": b[1], "Byx": b[2], "Byy": b[3]})
    return out


def published(row) -> dict:
    return dict(zip(("S", "eps", "phi", *COEFFS), row))


def coefficient_ok(value: float, ref: float) -> bool:
    """3 % of the published value, or 0.03 where that is less (a cross term near its sign change:
    Kyx = 0.01, the tables print two decimals)."""
    return abs(value - ref) <= 0.03 * abs(ref) + 0.03


@pytest.mark.parametrize("l_over_d", [0.5, 1.0])
def test_lund_thomsen_two_axial_groove(l_over_d):
    """Default grid: eps within 0.005, the attitude within 0.3 deg, each of the 8 coefficients
    within 3 % (+ 0.03); Bxy = Byx (the table prints one). Measured: eps to 0.001, phi to 0.11 deg,
    coefficients to 3.8 % at most (docs/geometry.md)."""
    geo = Geometry(grooves=(D90, D270), groove_width=math.radians(20.0))
    for row in LT_TWO_AXIAL_GROOVE[l_over_d]:
        ref = published(row)
        got = lund_thomsen_row(geo, l_over_d, 1e-4, ref["S"])
        assert abs(got["eps"] - ref["eps"]) <= 0.005, (ref["S"], got["eps"], ref["eps"])
        assert abs(got["phi"] - ref["phi"]) <= 0.3, (ref["S"], got["phi"], ref["phi"])
        for name in COEFFS:
            assert coefficient_ok(got[name], ref[name]), (ref["S"], name, got[name], ref[name])
        assert abs(got["Byx"] - got["Bxy"]) <= 0.01 * abs(got["Bxy"]) + 1e-3


def test_lund_thomsen_elliptical():
    """Lemon bore (2 lobes, preload 0.5, lobes centred at the top and bottom), L/D = 1, grooves of
    20 deg at the split: eps within 0.005, phi within 0.3 deg (2.5 deg at the misprinted row),
    the coefficients within 3 % (+ 0.03). Measured: phi to 0.1 deg (1.96 deg at the misprint),
    coefficients to 1.5 %."""
    geo = Geometry(grooves=(D90, D270), lobes=2, preload=0.5, lobe_angle=0.0)
    for row in LT_ELLIPTICAL:
        ref = published(row)
        got = lund_thomsen_row(geo, 1.0, 2e-4, ref["S"])
        assert abs(got["eps"] - ref["eps"]) <= 0.005, (ref["S"], got["eps"], ref["eps"])
        assert abs(got["phi"] - ref["phi"]) <= LT_PHI_MISPRINT.get(ref["S"], 0.3), (ref["S"], got["phi"])
        for name in COEFFS:
            assert coefficient_ok(got[name], ref[name]), (ref["S"], name, got[name], ref[name])


# ------------------------------------------------------------------------ partial arcs


def short_arc_force(prm: BearingParams, arc, y, z, vy, vz, omega, n=100_000) -> np.ndarray:
    """The short-bearing (Ocvirk) force of a partial arc, by quadrature: p = -3 mu (omega dh/dth +
    2 dh/dt) (L^2/4 - x^2) / h^3 where positive, inside the arc; F = R L^3 / 6 int p~ (sin, -cos)."""
    a0, a1 = arc
    th = a0 + (np.arange(n) + 0.5) * (a1 - a0) / n
    h = prm.CR + y * np.sin(th) - z * np.cos(th)
    g = np.maximum(0.0, -3.0 * prm.mu * (omega * (y * np.cos(th) + z * np.sin(th))
                                         + 2.0 * (vy * np.sin(th) - vz * np.cos(th))) / h ** 3)
    w = prm.R * prm.L ** 3 / 6.0 * (a1 - a0) / n
    return np.array([np.sum(g * np.sin(th)), -np.sum(g * np.cos(th))]) * w


@pytest.mark.parametrize("arc_deg", [(90.0, 270.0), (120.0, 240.0)])
def test_partial_arc_tends_to_the_short_bearing(arc_deg):
    """No published partial-arc table could be reached (Raimondi & Boyd's 180 and 120 deg tables
    are not quoted here from memory); the independent check is the short-bearing limit.
    The arc's edges hold p = 0 over a boundary layer ~L wide that the short theory lacks, so the
    difference falls like L/D: from L/D = 0.1 to 0.05 it halves (ratio 1.8 .. 2.2), and the
    extrapolation 2 F(0.05) - F(0.1) meets the short-bearing force within 2.5 % (measured
    0.3 .. 2.1 %; gumbel cavitation, as the short theory's positive part)."""
    arc = tuple(math.radians(a) for a in arc_deg)
    cases = [(0.3, 0.0, 0.0), (0.6, 0.5, 0.0), (0.6, -0.6, 0.0), (0.8, 0.3, 0.002)]
    for eps, turn, vr in cases:
        F, err = {}, {}
        for ld in (0.1, 0.05):
            prm = BearingParams(0.1, 0.1 * ld, 1e-4, 0.05, geometry=Geometry(arc=arc))
            ang = math.pi + turn
            y, z = eps * prm.CR * math.sin(ang), -eps * prm.CR * math.cos(ang)
            vy, vz = vr * math.sin(ang), -vr * math.cos(ang)
            ref = short_arc_force(prm, arc, y, z, vy, vz, 100.0) / prm.L ** 3
            F[ld] = np.array(Reynolds(prm, 256, 16, cavitation="gumbel").force(y, z, vy, vz, 100.0)) / prm.L ** 3
            err[ld] = np.linalg.norm(F[ld] - ref) / np.linalg.norm(ref)
        assert 1.8 <= err[0.1] / err[0.05] <= 2.2, (eps, turn, err)
        assert np.linalg.norm(2 * F[0.05] - F[0.1] - ref) <= 0.025 * np.linalg.norm(ref), (eps, turn, err)


def raimondi_boyd_case(arc_deg: float, l_over_d: float, eps: float, n_theta=None, n_x=None):
    """(S, phi [deg]) of a centrally loaded partial arc (arc_deg wide, centred on the downward
    load) at eccentricity eps, found as the journal position whose film force is vertical."""
    half = math.radians(arc_deg) / 2
    geo = Geometry(arc=(math.pi - half, math.pi + half))
    prm = BearingParams(0.1, 0.1 * l_over_d, 1e-4, 0.01, geometry=geo)
    r = Reynolds(prm, n_theta, n_x)
    om = 100.0

    def horizontal(phi):
        fy, _ = r.force(eps * prm.CR * math.sin(phi), -eps * prm.CR * math.cos(phi), 0.0, 0.0, om)
        return fy

    lo, hi = 0.0, 0.5 * math.pi  # the journal turns from the load line toward +y (the rotation)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if horizontal(mid) * horizontal(lo) > 0:
            lo = mid
        else:
            hi = mid
    phi = 0.5 * (lo + hi)
    fy, fz = r.force(eps * prm.CR * math.sin(phi), -eps * prm.CR * math.cos(phi), 0.0, 0.0, om)
    S = (prm.R / prm.CR) ** 2 * prm.mu * (om / (2 * math.pi)) / (math.hypot(fy, fz) / (prm.L * prm.D))
    return S, math.degrees(phi)


@pytest.mark.slow  # a grid-convergence study: several fine grids
@pytest.mark.parametrize("arc_deg", [180.0, 120.0])
def test_partial_arc_grid_convergence(arc_deg):
    """Raimondi & Boyd's centrally loaded partial bearings at L/D = 1 (the configuration of their
    180 and 120 deg tables): S and phi on the default grid against the grid refined 2x in both
    directions, within 0.5 % and 0.2 deg (the values are in docs/geometry.md)."""
    for eps in (0.2, 0.5, 0.8):
        S1, p1 = raimondi_boyd_case(arc_deg, 1.0, eps)
        S2, p2 = raimondi_boyd_case(arc_deg, 1.0, eps, 256, 32)
        assert abs(S1 / S2 - 1) < 0.005 and abs(p1 - p2) < 0.2, (eps, S1, S2, p1, p2)


# ------------------------------------------------------------------------ offset halves


@pytest.mark.slow  # a grid-convergence study: several fine grids
@pytest.mark.parametrize("offset", [0.5, 1.0])
def test_lobed_bores_grid_convergence(offset):
    """No published offset-halves table could be reached: its checks are independent ones. The
    lemon (offset 0.5) and offset-halves (1.0) bores of preload 0.5 with 20 deg grooves at the
    split, L/D = 1: default grid within 0.5 % of the grid refined 4x in both directions (force,
    eps 0.3 .. 0.9 of the assembled clearance, journal below and turned toward the rotation).
    The other independent checks: preload -> 0 gives the grooved circular bore, offset -> 1 -
    offset is the mirror image (tests/test_reynolds_geometry.py), the film is the gap between
    the circles (tests/test_geometry.py), and the lemon bore matches Lund & Thomsen above."""
    geo = Geometry(grooves=(D90, D270), lobes=2, preload=0.5, lobe_offset=offset)
    prm = BearingParams(0.1, 0.1, 1e-4, 0.02, geometry=geo)
    grids = {f: Reynolds(prm, 128 * f, 16 * f) for f in (1, 4)}
    for eps in (0.3, 0.6, 0.9):
        for turn in (0.3, 1.0):
            y, z = eps * prm.CR * math.sin(math.pi + turn), -eps * prm.CR * math.cos(math.pi + turn)
            F = {f: np.array(g.force(y, z, 0.0, 0.0, 300.0)) for f, g in grids.items()}
            assert np.linalg.norm(F[1] - F[4]) <= 0.005 * np.linalg.norm(F[4]), (eps, turn, F)
