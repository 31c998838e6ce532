"""The second-order tables' batched evaluation of k₂ (``analysis/slow/map/second_order.py``: :func:`k2_harmonics_at`, the
orbits of many nodes in the batch integrator's lanes, the chart's derivative series formed once per table) against
the scalar path it replaced, kept here as the reference: one start's turning-point solve and one orbit per Θ_a,
the table's gradients by ``SlowMapTable.gradient`` (numpy's chebder and chebval2d per point)."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow import prediction as av
from rocknroller.analysis.slow.map import region as sr
from rocknroller.analysis.slow.map.chart import _IDX, _basis, cheb_nodes
from rocknroller.analysis.slow.map.exact_step import STEP_NAMES
from rocknroller.analysis.slow.map.orbit import second_order_step
from rocknroller.analysis.slow.map.second_order import _K2_THETA_A, k2_harmonics_at

SYM = Body.paper()
PREFIX = ("kQR", "kQJ", "kTh", "dt", "dphi1")
H = 1e-6  # the reference Hessians' difference step in Q (Richardson-extrapolated from H and H/2)


def _grad(table, name, Q):
    gu, gv = (float(g) for g in table.gradient(name, Q))
    return gu * np.asarray(table.e, float) + gv * np.asarray(table.n, float)


def _richardson(diff):
    """(4 D(H/2) − D(H))/3 of a central difference D(h): truncation O(H⁴)."""
    return (4.0 * diff(0.5 * H) - diff(H)) / 3.0


def _k2_scalar(table, Q, theta_a):
    """k₂ at (Q, Θ_a) by the module docstring's formula, one point and one orbit at a time."""
    vals = table.evaluate(Q)
    d2 = second_order_step(table.body, table.E0, float(Q[0]), float(Q[1]), 0.5 * (theta_a - 0.5 * vals[_IDX["W"]]))
    A2 = 0.5 * np.array([d2[k] for k in STEP_NAMES])
    c, s = math.cos(theta_a), math.sin(theta_a)
    k1, dk_dq, dk_dth = np.zeros(5), np.zeros((5, 2)), np.zeros(5)
    for i, pre in enumerate(PREFIX):
        c0, c1, s1 = (vals[_IDX[f"{pre}_{h}"]] for h in ("c0", "c1", "s1"))
        k1[i], dk_dth[i] = c0 + c1 * c + s1 * s, -c1 * s + s1 * c
        g0, g1, g2 = (_grad(table, f"{pre}_{h}", Q) for h in ("c0", "c1", "s1"))
        dk_dq[i] = g0 + g1 * c + g2 * s
    k2 = A2 - 0.5 * (dk_dq @ k1[:2] + dk_dth * k1[2])
    for i, drift in zip((2, 3, 4), ("W", "T", "dphi")):
        Hm = np.array([_richardson(lambda h: (_grad(table, drift, Q + h * e) - _grad(table, drift, Q - h * e)) / (2 * h))
                       for e in np.eye(2)]).T
        Hm = 0.5 * (Hm + Hm.T)
        k2[i] -= 0.5 * _grad(table, drift, Q) @ A2[:2] + 0.25 * k1[:2] @ Hm @ k1[:2]
    return k2


def _k2_harmonics_scalar(table, Q):
    vals = np.array([_k2_scalar(table, Q, ta) for ta in _K2_THETA_A])
    return np.linalg.solve(_basis(np.array(_K2_THETA_A)), vals).T


def _release_table():
    return av.load_or_build_table(SYM, 0.95 * math.pi)


def _region_table():
    from rocknroller.analysis.criticality.starts import critical_start
    from rocknroller.analysis.slow.map.family import first_maximum

    body = Body.paper(1e-3)
    start = critical_start(body, 0.95 * math.pi, math.pi / 4, "pi", psi_dot0=0.002).state()  # the fig. 8 start
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", av.AveragingValidityWarning)  # a coarse grid: the chart is what matters
        return sr.build_region_table(SYM, first_maximum(body, start).E, nu=16, nv=8)


@pytest.mark.parametrize("make, grid, picks", [
    (_release_table, (64, 6), ((0, 0), (31, 5))),  # an end of the chart and the node next to Q = 0
    (_region_table, (16, 32), ((2, 7), (7, 16))),
], ids=["release", "region"])
def test_batched_k2_agrees_with_the_scalar_path(make, grid, picks):
    """At nodes of a second-order table of each kind, the batched k₂ harmonics equal the scalar path's to 1e-6 of
    each component's largest harmonic, far inside the tables' stated accuracy (``K2_ACCURACY`` = 1e-3 of the same
    scale; ``K2_REGION_ACCURACY`` on region charts).  The paths differ by the reference's Hessians (Richardson-
    extrapolated differences in Q; the module's are exact series) and rounding: the lanes' vector kernels (~1e-14),
    amplified by the start's second difference in ε (1/h² = 1e6) and the reference's differences (1/H = 1e6)."""
    table = make()
    XI, ETA = np.meshgrid(cheb_nodes(grid[0]), cheb_nodes(grid[1]), indexing="ij")
    QR, QJ = table.chart(XI, ETA)
    nodes = np.array([(QR[i, j], QJ[i, j]) for i, j in picks])
    batched = k2_harmonics_at(table, nodes)
    for q, new in zip(nodes, batched):
        ref = _k2_harmonics_scalar(table, q)
        scale = np.abs(ref).max(axis=1)
        assert np.all(np.abs(new - ref).max(axis=1) <= 1e-6 * scale), (np.abs(new - ref).max(axis=1) / scale)
