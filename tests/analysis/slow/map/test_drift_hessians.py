"""The drifts' Hessians that k₂ uses (``analysis/slow/map/second_order.py``: :func:`drift_derivatives`): exact on a
release table's rectangle, the chart's curvature included on a region table's, and the second-order tables of the
thin release charts near θ0 = π, which differences in Q left."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow import prediction as av
from rocknroller.analysis.slow.map import region as sr
from rocknroller.analysis.slow.map.chart import _IDX, cheb_nodes
from rocknroller.analysis.slow.map.second_order import build_second_order_table, drift_derivatives

SYM = Body.paper()
CHEB = np.polynomial.chebyshev


def _release_hessian(table, name, Q):
    """The Hessian of a release table's function on its rectangle Q = ξ U e + η V n: numpy's chebval2d of the
    second derivative series, turned by the constant Jacobian (an independent evaluation)."""
    xi, eta = table.coordinates(Q)
    c = table.coef[_IDX[name]]
    f_xx, f_yy = (CHEB.chebval2d(xi, eta, CHEB.chebder(c, 2, axis=k)) for k in (0, 1))
    f_xy = CHEB.chebval2d(xi, eta, CHEB.chebder(CHEB.chebder(c, axis=0), axis=1))
    gx, gy = table.e / table.U, table.n / table.w_coef[0]
    return (f_xx * np.outer(gx, gx) + f_xy * (np.outer(gx, gy) + np.outer(gy, gx)) + f_yy * np.outer(gy, gy))


@pytest.mark.parametrize("node", [(0, 0), (31, 5), (20, 2)])
@pytest.mark.parametrize("name", ["W", "T", "dphi"])
def test_release_hessians_are_exact(name, node):
    """At nodes of the k₂ grid (64 × 6), one at the chart's end, the Hessians equal the closed form to rounding:
    two sums of ≤ 128 × 6 terms whose second-derivative coefficients grow like k⁴, bounded by 1e-12 relative (the
    differences in Q they replace were off by up to 3e-7)."""
    table = av.load_or_build_table(SYM, 0.95 * math.pi)
    QR, QJ = table.chart(*np.meshgrid(cheb_nodes(64), cheb_nodes(6), indexing="ij"))
    Q = np.array([QR[node], QJ[node]])
    ref = _release_hessian(table, name, Q)
    H = drift_derivatives(table, name, Q)[1]
    assert np.abs(H - ref).max() <= 1e-12 * np.abs(ref).max()


def test_region_hessians_include_the_chart_curvature():
    """On a region table's stretched, curved chart the Hessians match Richardson-extrapolated central differences
    of the gradients in Q (steps 1e-5 and 5e-6: truncation ~h⁴ f⁽⁵⁾, rounding ~1e-16 |∇F|/h) to 1e-6 relative; without
    the curvature term they miss by far more."""
    from rocknroller.analysis.criticality.starts import critical_start
    from rocknroller.analysis.slow.map.family import first_maximum
    from rocknroller.analysis.slow.map.second_order import _derivative_coefficients, _jet

    body = Body.paper(1e-3)
    start = critical_start(body, 0.95 * math.pi, math.pi / 4, "pi", psi_dot0=0.002).state()  # the fig. 8 start
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", av.AveragingValidityWarning)  # a coarse grid: the chart is what matters
        table = sr.build_region_table(SYM, first_maximum(body, start).E, nu=16, nv=8)
    assert table.alpha > 0 or table.beta > 0 or np.any(table.c_coef[1:])  # a curved chart
    dcoef = _derivative_coefficients(table)
    Q = np.array([float(c) for c in table.chart(0.3, -0.4)])
    for name in ("W", "T", "dphi"):
        def central(h):
            grad = [(_jet(table, dcoef, Q + h * e)[1][_IDX[name]] - _jet(table, dcoef, Q - h * e)[1][_IDX[name]])
                    / (2 * h) for e in np.eye(2)]
            return np.array(grad).T
        ref = (4.0 * central(5e-6) - central(1e-5)) / 3.0
        ref = 0.5 * (ref + ref.T)
        H = drift_derivatives(table, name, Q)[1]
        assert np.abs(H - ref).max() <= 1e-6 * np.abs(ref).max(), (name, np.abs(H - ref).max() / np.abs(ref).max())


def test_second_order_tables_build_on_thin_charts():
    """At θ0 = 0.98π the release chart is 1.3e-5 wide across the kick direction and its nodes lie 4.5e-7 from its
    sides: a difference step of 1e-6 in Q left it (AveragingRangeError/ChartWidthError on the old main).  The table
    now builds (a coarse grid along, the default across) and k₂ is finite."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", av.AveragingValidityWarning)  # a coarse grid along: the build is the point
        second = build_second_order_table(SYM, 0.98 * math.pi, nu=8, nv=6, progress=False)
    assert second.coef.shape == (25, 8, 6) and np.all(np.isfinite(second.coef))
