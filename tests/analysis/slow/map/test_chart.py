"""The Chebyshev pieces of the tables' chart (``analysis/slow/map/chart.py``): numpy's, where numpy has them (issue 25,
item 16)."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.polynomial import chebyshev as cheb

from rocknroller.analysis.slow.map.chart import cheb_basis, cheb_fit_matrix, cheb_nodes


@pytest.mark.parametrize("n", [4, 6, 8, 16, 64, 80, 96, 128, 256])
def test_nodes_are_exactly_antisymmetric(n):
    """The tables symmetrise each function by F[::-1, ::-1] (the node at −x is the mirror of the node at x): true
    to the bit for numpy's ``chebpts1``, not for the cosines used before (off by up to 2.8e-16)."""
    x = cheb_nodes(n)
    assert np.array_equal(x, -x[::-1]) and np.all(np.diff(x) < 0)
    np.testing.assert_allclose(x, np.cos(np.pi * (np.arange(n) + 0.5) / n), rtol=0, atol=4 * np.finfo(float).eps)


def test_fit_matrix_interpolates_and_matches_numpy():
    """c = A f is the interpolant at the nodes: it reproduces f there, and equals numpy's ``chebinterpolate``.

    Bounds: each c_k is a sum of n products (2/n) T_k(x_j) f_j with |T_k| ≤ 1 and T_k within k ≤ n ulps
    (``chebvander``'s recurrence), so each computation errs by at most (n + n)·u·(2/n)·Σ|f| = 4·u·Σ|f|; the two
    differ by twice that, doubled as a margin.  The interpolant's value at a node sums n terms c_k T_k: n·u·Σ|c_k|,
    plus the coefficients' own error n times, doubled."""
    n = 24
    u = np.finfo(float).eps / 2
    x = cheb_nodes(n)
    f = np.exp(x) * np.sin(3 * x)
    c = cheb_fit_matrix(n) @ f
    coef_bound = 2.0 * 2.0 * (n + n) * u * (2.0 / n) * np.sum(np.abs(f))
    ref = cheb.chebinterpolate(lambda t: np.exp(t) * np.sin(3 * t), n - 1)
    np.testing.assert_allclose(c, ref, rtol=0, atol=coef_bound)
    np.testing.assert_allclose(cheb.chebval(x, c), f, rtol=0,
                               atol=2.0 * (n * u * np.sum(np.abs(c)) + n * coef_bound))


def test_basis_is_chebvander_with_the_index_first_and_clipped():
    x = np.linspace(-1.2, 1.2, 13).reshape(13, 1) * np.ones((1, 3))
    B = cheb_basis(x, 7)
    assert B.shape == (7, 13, 3)
    np.testing.assert_array_equal(B, np.moveaxis(cheb.chebvander(np.clip(x, -1, 1), 6), -1, 0))
    assert cheb_basis(0.3, 5).shape == (5,)  # a scalar: the basis alone
