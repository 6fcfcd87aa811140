"""The Taylor surrogate's basis (bearing_fmu/surrogates/basis.py): the monomials of a given
order in the four scaled variables, their layout and the design matrix.

Expected values come from closed forms written next to each test (binomial counts, products
by hand), never from this code's own output.
"""

import math

import numpy as np
import pytest

from bearing_fmu.surrogates.basis import design_matrix, exponents, n_terms

# ----------------------------------------------------------------------------- basis

@pytest.mark.parametrize("order", range(0, 8))
def test_basis_count_is_binomial(order):
    # number of monomials of degree <= n in 4 variables: C(n + 4, 4); 126 for n = 5
    e = exponents(order)
    assert n_terms(order) == math.comb(order + 4, 4) == len(e)
    assert len({tuple(r) for r in e}) == len(e)
    assert e.sum(axis=1).max(initial=0) <= order
    assert list(e[0]) == [0, 0, 0, 0]


def test_basis_layout():
    assert n_terms(5) == 126
    e = exponents(1)
    # order 1 is Lund's model: constant, dy, dz, dvy, dvz
    assert e.tolist() == [[0, 0, 0, 0], [1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]
    deg = exponents(5).sum(axis=1)
    assert np.all(np.diff(deg) >= 0)  # graded by degree


def test_design_matrix_values():
    u = np.array([[0.5, -2.0, 3.0, 0.25]])
    e = np.array([[0, 0, 0, 0], [2, 1, 0, 0], [0, 0, 1, 3], [5, 0, 0, 0]])
    # by hand: 1, 0.5^2 * -2, 3 * 0.25^3, 0.5^5
    np.testing.assert_allclose(design_matrix(u, e)[0], [1.0, -0.5, 3 / 64, 1 / 32], rtol=1e-15)
