"""What the Taylor surrogate tests share (tests/test_basis.py, test_taylor_fit.py,
test_taylor_internal.py, test_surrogate_file.py): the paper bearing at 22 Hz, an expansion point
near its equilibrium and a box domain; an analytic film force with known derivatives (the truth
the fits are checked against); random surrogates of known coefficients (plain, with the wall
factor, with shape columns); random states; derivatives by central differences."""

import math
from pathlib import Path

import numpy as np

from bearing_fmu.fitting import FitRecipe
from bearing_fmu.physics.params import PAPER_BEARING
from bearing_fmu.surrogates.basis import exponents, n_terms, natural_force_scale
from bearing_fmu.surrogates.surrogate import Domain, Surrogate

P = PAPER_BEARING
OMEGA = 2 * math.pi * 22.0
ROOT = Path(__file__).resolve().parents[1]
Y0, Z0 = 0.2 * P.CR, -0.05 * P.CR  # an expansion point near the paper's 22 Hz equilibrium
BOX = Domain(ecc_max=0.8, pos_center=(0.0, 0.0), pos_radius=0.3, v_max=0.3, box_lo=(-0.3,) * 4, box_hi=(0.3,) * 4)


def R(order, **kw):
    """The recipe of a direct fit_surrogate call here: not anchored unless asked, random CV folds
    of seed 0 (fit_surrogate's own defaults before FitRecipe)."""
    return FitRecipe(order=order, **{"anchor": False, "seed": 0, **kw})


class Smooth:
    """A smooth (analytic) synthetic film force: stiffening spring, cross-coupling, damping
    growing with eccentricity. Not physics: an analytic truth with known derivatives."""

    def __init__(self, params=P):
        self.params = params

    def force(self, y, z, vy, vz, omega):
        cr = self.params.CR
        a, b = y / cr, z / cr
        g = 1.0 / (1.0 - 0.5 * (a * a + b * b))
        k, c = 2e5, 300.0
        fy = -k * g * y - 0.4 * k * z - c * g * vy + 20.0 * a * b
        fz = -k * g * z + 0.4 * k * y - c * g * vz - 15.0 + 10.0 * a * a
        return fy, fz


def random_states(n, seed, r=0.3, v=0.3, y0=Y0, z0=Z0, omega=OMEGA):
    rng = np.random.default_rng(seed)
    u = rng.uniform(-1, 1, size=(n, 4)) * [r, r, v, v]
    return np.column_stack([y0 + u[:, 0] * P.CR, z0 + u[:, 1] * P.CR,
                            u[:, 2] * omega * P.CR, u[:, 3] * omega * P.CR])


def poly_surrogate(order=5, seed=0, scale=1.0):
    e = exponents(order)
    rng = np.random.default_rng(seed)
    coef = rng.normal(size=(2, len(e))) * scale
    return Surrogate(P, OMEGA, Y0, Z0, order, e, coef, natural_force_scale(P, OMEGA), BOX)


def central_jacobian(force, x, omega, rel):
    """Independent check: dF/d(y, z, vy, vz) by central differences of ``force``, steps
    rel * CR and rel * omega * CR; (2, 4)."""
    steps = [rel * P.CR] * 2 + [rel * omega * P.CR] * 2
    jac = np.empty((2, 4))
    for j, h in enumerate(steps):
        xp, xm = np.array(x, float), np.array(x, float)
        xp[j] += h
        xm[j] -= h
        jac[:, j] = (np.array(force(*xp, omega)) - np.array(force(*xm, omega))) / (2 * h)
    return jac


def wall_surrogate(order=3, seed=1, p=1.5, scale=1.0):
    """A known function F = P(u) / (1 - eps^2)^p: a random polynomial behind the wall factor."""
    s = poly_surrogate(order, seed, scale)
    s.wall_power = p
    return s


def shape_surrogate(order=3, r=2, seed=31, p=1.25, scale=0.1):
    """A known function F = P(u) / (1 - eps^2)^p + sum_j (a_j^y S_y + a_j^z S_z) m_j(u), S the
    short-bearing closed form, random coefficients."""
    s = wall_surrogate(order, seed, p, scale)
    s.shape_order = r
    s.shape_coef = np.random.default_rng(seed + 1).normal(size=(4, n_terms(r))) * 0.3
    s.__post_init__()
    return s
