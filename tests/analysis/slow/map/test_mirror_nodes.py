"""Half the nodes of a table: the mirror symmetry Q → −Q of the node data (``table._MIRROR_SIGNS``), the grids it
applies to, the tables built on half the nodes against the same tables with every node's three orbits run, and the
region's edge by regula falsi against bisection."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.diagnostics import wrap_angle
from rocknroller.analysis.routh.turning_points import min_potential, turning_points
from rocknroller.analysis.slow.map import region, table
from rocknroller.analysis.slow.map.chart import TABLE_FUNCTIONS, cheb_nodes
from rocknroller.analysis.slow.map.family import rest_energy
from rocknroller.analysis.slow.map.harmonic import _harmonics
from rocknroller.analysis.slow.map.orbit import FIRST_ORDER_NAMES, HARMONIC_PSI, first_order_steps

SYM = Body.paper()
EPS = np.finfo(float).eps
#: Agreement of node data computed two ways, relative to each response's largest harmonic at the node (as in
#: test_harmonic_orbit.py: a hundredth of the tables' accuracy, far above the responses' rounding).
AGREE = 1e-2 * table.REGION_TABLE_ACCURACY
#: Two runs of one orbit, the second mirrored (test_harmonic_orbit.py derives the bound).
ORBITS_AGREE = 1e-12


def _band(nu: int = 16, nv: int = 16):
    return region.region_frame(SYM, rest_energy(SYM, 0.95 * math.pi), axis="band", nu=nu, nv=nv)


def test_node_data_at_minus_Q_follow_the_mirror_signs():
    frame = _band()
    QR, QJ = (q.ravel()[[3, 40, 77, 101]] for q in frame.nodes())
    thX = np.asarray(turning_points(frame.E0, QR, QJ, SYM)[1], float)
    here = table.node_block(SYM, frame.E0, list(zip(QR, QJ, thX)))
    there = table.node_block(SYM, frame.E0, list(zip(-QR, -QJ, thX)))
    mirrored = here * table._MIRROR_SIGNS
    assert np.allclose(there[:, 0], mirrored[:, 0], rtol=0.1 * ORBITS_AGREE, atol=0.0)  # T_θ
    assert np.all(np.abs(wrap_angle(there[:, 1] - mirrored[:, 1])) <= ORBITS_AGREE)  # W mod 2π
    assert np.all(np.abs(wrap_angle(there[:, 2] - mirrored[:, 2], math.pi)) <= ORBITS_AGREE)  # Δφ mod π
    for j in range(len(FIRST_ORDER_NAMES)):
        cols = slice(3 + 3 * j, 6 + 3 * j)
        scale = np.abs(here[:, cols]).max(axis=1, keepdims=True)
        assert np.all(np.abs(there[:, cols] - mirrored[:, cols]) <= AGREE * scale), FIRST_ORDER_NAMES[j]
    # the signs are not all +1 or all -1: the check sees a wrong one
    assert set(table._MIRROR_SIGNS) == {1.0, -1.0}


def test_every_chart_grid_is_mirrored_and_the_check_points_are_not():
    E = rest_energy(SYM, 0.3 * math.pi)
    assert table.mirrored(*region.region_frame(SYM, E, axis="spindle", nu=8, nv=8).nodes())
    assert table.mirrored(*_band(8, 12).nodes())
    assert table.mirrored(*table.release_frame(SYM, 0.9 * math.pi, nu=16, nv=6)[0].nodes())
    x, y = np.array(region._CHECK_POINTS).T
    assert not table.mirrored(*_band().chart(x, y))
    blocks = table.node_blocks(SYM, E, *_band(8, 12).nodes(), np.ones((8, 12)))
    assert [len(b[2]) for b in blocks] == [48] and table.nodes_done(blocks, 96) == [96]  # each counts for two
    QR, QJ = _band().chart(x, y)
    blocks = table.node_blocks(SYM, E, QR, QJ, np.ones(QR.shape))
    assert [len(b[2]) for b in blocks] == [len(x)] and table.nodes_done(blocks, len(x)) == [len(x)]  # for one


def _every_node(frame, theta_X):
    """T, W, Δφ (for a region frame) and the harmonics at every node from three orbits each (``first_order_steps``
    at the three spin angles): the construction of the tables before one orbit per node and half the nodes."""
    QR, QJ = frame.nodes()
    shape = QR.shape + (len(HARMONIC_PSI),)
    steps = first_order_steps(SYM, frame.E0, QR[..., None], QJ[..., None], np.asarray(HARMONIC_PSI),
                              np.asarray(theta_X)[..., None])
    resp = np.stack([_harmonics(np.reshape(steps.d[n], shape)) for n in FIRST_ORDER_NAMES])
    T, dpsi, dphi = (np.reshape(v, shape)[..., 0] for v in (steps.T, steps.dpsi, steps.dphi))
    return T, wrap_angle(2.0 * dpsi), dphi, resp


def _values(tab):
    """The table's functions at its nodes, relative to each function's largest value there."""
    xu, xv = cheb_nodes(tab.coef.shape[1]), cheb_nodes(tab.coef.shape[2])
    vals = np.stack([np.polynomial.chebyshev.chebgrid2d(xu, xv, c) for c in tab.coef])
    return vals, np.abs(vals).max(axis=(1, 2))


@pytest.mark.filterwarnings("ignore::rocknroller.analysis.slow.map.limits.AveragingValidityWarning")  # small grids
@pytest.mark.parametrize("kind", ["region", "release"])
def test_tables_on_half_the_nodes_equal_the_tables_of_every_node(kind):
    """A table of each kind built as the package builds it (one orbit per node, half the nodes) and on the same chart
    from every node's three orbits: each function's values at the nodes within the tables' stated accuracy, relative
    to the function's largest value.  The harmonics that vanish by the mirror symmetry and the tables' parity (c0, c1
    of k_Q; s1 of k_Θ, the time and φ) are rounding in both, below 1e-9 of their response's largest harmonic."""
    if kind == "region":
        frame = _band()
        new = region.build_region_table(SYM, frame.E0, axis="band", nu=16, nv=16, progress=False)
        thX = np.asarray(turning_points(frame.E0, *frame.nodes(), SYM)[1], float)
        old = table.fit_table(frame, *_every_node(frame, thX))
    else:
        frame, T, W, dphi, thX = table.release_frame(SYM, 0.9 * math.pi, nu=16, nv=6)
        new = table.build_table(SYM, 0.9 * math.pi, nu=16, nv=6, progress=False)
        old = table.fit_table(frame, T, W, dphi, _every_node(frame, thX)[3])
    (a, scale), (b, _) = _values(new), _values(old)
    vanish = {"kQR_c0", "kQR_c1", "kQJ_c0", "kQJ_c1", "kTh_s1", "dt_s1", "dphi1_s1"}
    for k, name in enumerate(TABLE_FUNCTIONS):
        if name in vanish:
            triple = scale[[j for j, m in enumerate(TABLE_FUNCTIONS) if m[:-3] == name[:-3]]].max()
            assert np.all(np.abs(a[k]) <= 1e-9 * triple) and np.all(np.abs(b[k]) <= 1e-9 * triple), name
        else:
            assert np.all(np.abs(a[k] - b[k]) <= table.REGION_TABLE_ACCURACY * scale[k]), name


def test_the_regions_edge_by_regula_falsi_is_the_edge_by_bisection():
    """``region._edge`` against 64 bisections on the rays of a band chart: both inside (min U ≤ level), within a few
    units of r's last place or the distance over which min U moves by its rounding (``_EDGE_ROUNDING``)."""
    E = rest_energy(SYM, 0.95 * math.pi)
    level = E * (1.0 - region.DELTA_MIN_DEFAULT)
    e = region.chart_direction(SYM, "band")
    n = np.array([-e[1], e[0]])
    xs = cheb_nodes(12)
    origins = np.concatenate([np.zeros((1, 2)), xs[:, None] * 0.5 * e, xs[:, None] * 0.5 * e])
    dirs = np.concatenate([e[None, :], np.tile(n, (12, 1)), np.tile(-n, (12, 1))])
    r = region._edge(SYM, E, level, origins, dirs)

    def g(r):
        Q = origins + r[:, None] * dirs
        return min_potential(Q[:, 0], Q[:, 1], SYM) - level

    lo, hi = np.zeros(len(r)), np.full(len(r), 4.0)
    assert np.all(g(hi) > 0)
    for _ in range(64):
        mid = 0.5 * (lo + hi)
        ok = g(mid) <= 0
        lo, hi = np.where(ok, mid, lo), np.where(ok, hi, mid)
    slope = (g(lo + 1e-6) - g(lo - 1e-6)) / 2e-6
    assert np.all(g(r) <= 0)
    assert np.all(np.abs(r - lo) <= 8 * np.spacing(lo) + 2 * region._EDGE_ROUNDING * level / slope)
