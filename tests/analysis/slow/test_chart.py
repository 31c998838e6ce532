"""The Chebyshev pieces of the tables' chart (``analysis/slow/chart.py``): numpy's, where numpy has them (issue 25,
item 16)."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.polynomial import chebyshev as cheb

from rocknroller.analysis.slow.chart import _cheb_basis, _cheb_fit_matrix, _cheb_nodes


@pytest.mark.parametrize("n", [4, 6, 8, 16, 64, 80, 96, 128, 256])
def test_nodes_are_exactly_antisymmetric(n):
    """The tables symmetrise each function by F[::-1, ::-1] (the node at −x is the mirror of the node at x): true
    to the bit for numpy's ``chebpts1``, not for the cosines used before (off by up to 2.8e-16)."""
    x = _cheb_nodes(n)
    assert np.array_equal(x, -x[::-1]) and np.all(np.diff(x) < 0)
    np.testing.assert_allclose(x, np.cos(np.pi * (np.arange(n) + 0.5) / n), rtol=0, atol=4 * np.finfo(float).eps)


def test_fit_matrix_interpolates_and_matches_numpy():
    """c = A f is the interpolant at the nodes: it reproduces f there, and equals numpy's ``chebinterpolate``."""
    n = 24
    f = np.exp(_cheb_nodes(n)) * np.sin(3 * _cheb_nodes(n))
    c = _cheb_fit_matrix(n) @ f
    np.testing.assert_allclose(cheb.chebval(_cheb_nodes(n), c), f, rtol=0, atol=20 * np.finfo(float).eps)
    ref = cheb.chebinterpolate(lambda x: np.exp(x) * np.sin(3 * x), n - 1)
    np.testing.assert_allclose(c, ref, rtol=0, atol=20 * np.finfo(float).eps)


def test_basis_is_chebvander_with_the_index_first_and_clipped():
    x = np.linspace(-1.2, 1.2, 13).reshape(13, 1) * np.ones((1, 3))
    B = _cheb_basis(x, 7)
    assert B.shape == (7, 13, 3)
    np.testing.assert_array_equal(B, np.moveaxis(cheb.chebvander(np.clip(x, -1, 1), 6), -1, 0))
    assert _cheb_basis(0.3, 5).shape == (5,)  # a scalar: the basis alone
