"""The second-order kick k₂ of the drift–kick–drift slow map, at a point and in tables.  It holds k₂ at a point from
the step's second ε-derivatives and a first-order table (:func:`second_order_kick`, with the table's first-order
kick and drifts: :func:`first_order_kick`, :func:`drift_derivatives`), its harmonics in Θ_a
(:func:`k2_harmonics`; at many points at once, their orbits in the batch integrator's lanes: :func:`k2_harmonics_at`,
:func:`second_order_kicks`), the check of the formula against the exact step (:func:`dkd_residual`), and the tables of
k₂ on the chart of a release table (:func:`build_second_order_table`, :func:`load_or_build_second_order_table`) or
of the region table of an energy (:func:`build_second_order_region_table`,
:func:`load_or_build_second_order_region_table`).

The first-order map (:mod:`rocknroller.analysis.slow.prediction`) is D(W/2) ∘ K ∘ D(W/2): half twists
Θ += W(Q)/2 around an implicit-midpoint kick x_b = x_a + ε k(m), m = (x_a + x_b)/2, x = (Q, Θ), with the time and
φ advanced by ½ (T_θ(Q) + T_θ(Q')) + ε k_t(m) and ½ (Δφ(Q) + Δφ(Q')) + ε k_φ(m).  Carried to second order,
k = k₁ + ε k₂.  The exact step at fixed (E, Q_n, Θ_n) is Q' = Q + ε A₁ + ε² A₂ + …, Θ' = Θ + W + ε B₁ + ε² B₂ + …
(and C for t, D for φ); expanding the composition (all functions at (Q, Θ_a = Θ + W/2)) and matching gives

    k₂_Q = A₂ − ½ [(∂_Q k₁_Q) k₁_Q + (∂_Θ k₁_Q) k₁_Θ],
    k₂_X = X₂ − ½ ∇F·A₂ − ¼ k₁_Qᵀ (∇²F) k₁_Q − ½ [(∂_Q k₁_X)·k₁_Q + (∂_Θ k₁_X) k₁_Θ],

for X = Θ, t, φ with F = W, T_θ, Δφ.  The ½ ∇F·A₂ and ¼ k₁ᵀ∇²F k₁ terms are what the second half-drift already
produces when evaluated at the kicked Q: near Q = 0, where W turns by ~2π over a width ~2/|∇W(0)|, they carry most
of the exact step's large second derivative (docs/averaging.md, "The exact one-step map").

A₂ … D₂ are half the second ε-derivatives of the step at fixed (E, Q, ψ), from the second-order variational
equations (:func:`rocknroller.analysis.slow.map.orbit.second_order_step`; checked against extrapolated differences of
the exact step, :func:`~rocknroller.analysis.slow.map.exact_step.eps_derivatives`), k₁ and its derivatives and the
drifts' gradients and Hessians come from a first-order table (:class:`rocknroller.analysis.slow.map.chart.SlowMapTable`).
:func:`dkd_residual` checks the formula: the exact step minus one step of the first-order map, over ε², tends to
k₂ (plus ½ ∇F·k₂_Q for X = Θ, t, φ) as ε → 0 (``tests/analysis/slow/map/test_second_order.py``).
:class:`rocknroller.analysis.slow.map.chart.SecondOrderTable` holds k₂'s harmonics 0, 1, 2 in Θ_a on the chart of a
release table, or of the region table of an energy (starts with velocity); the compiled kernel adds ε k₂ to the
kick (:func:`rocknroller.analysis.slow.map.compiled_map.iterate_slow_map` with ``second=``).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.diagnostics import wrap_angle
from rocknroller.analysis.routh.turning_points import turning_points
from rocknroller.analysis.slow.map.chart import (_HARM, _IDX, _ODD, SecondOrderTable, SlowMapTable, _basis, cheb_basis,
                                             cheb_fit_matrix, cheb_nodes)
from rocknroller.analysis.slow.map.exact_step import STEP_NAMES, exact_step
from rocknroller.analysis.slow.map.orbit import second_order_steps
from rocknroller.analysis.slow.map.table import cached_table, load_or_build_table
from rocknroller.numerics.parallel import check_processes, map_blocks

__all__ = [
    "first_order_kick", "drift_derivatives", "second_order_kick", "second_order_kicks", "dkd_residual",
    "K2_HARMONICS", "K2_FUNCTIONS", "K2_ACCURACY", "K2_REGION_ACCURACY", "k2_harmonics", "k2_harmonics_at",
    "build_second_order_table", "load_or_build_second_order_table",
    "build_second_order_region_table", "load_or_build_second_order_region_table", "k2_block", "k2_blocks", "fit_k2",
    "k2_check_error",
    "check_k2_nu", "k2_spec"
]

#: Table prefix of each kick component, in ``STEP_NAMES`` order (Q_R, Q_J, Θ, t, φ), and the drift of the last three.
_PREFIX = ("kQR", "kQJ", "kTh", "dt", "dphi1")
_DRIFT = ("W", "T", "dphi")
#: Step, in the chart's coordinates (ξ, η), of the central differences of the chart's inverse Jacobian that give its
#: curvature (zero on a release table's rectangle; on a region table's the stretches and sides are smooth on the scale
#: 1/α ≳ 0.1: truncation ~(α h)² ≲ 1e-8 relative, rounding ~1e-16/h).
_H_CHART = 1e-5

#: Derivative series of a table's functions: ∂/∂ξ, ∂/∂η, ∂²/∂ξ², ∂²/∂ξ∂η, ∂²/∂η² (numpy's ``chebder``).
Derivatives = tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64],
                    NDArray[np.float64]]


def _derivative_coefficients(table: SlowMapTable) -> Derivatives:
    """The Chebyshev coefficients of the first and second derivatives in (ξ, η) of every table function
    (``Derivatives``), formed once per table (numpy's ``chebder`` along the axes of ``table.coef``)."""
    cheb = np.polynomial.chebyshev
    c = table.coef
    d_xi, d_eta = cheb.chebder(c, axis=1), cheb.chebder(c, axis=2)
    return tuple(np.asarray(d, float) for d in (d_xi, d_eta, cheb.chebder(d_xi, axis=1), cheb.chebder(d_xi, axis=2),
                                                 cheb.chebder(d_eta, axis=2)))  # type: ignore[return-value]


def _series(d: NDArray[np.float64], xi: float, eta: float) -> NDArray[np.float64]:
    """The Chebyshev series ``d`` (F, terms in ξ, terms in η) at (ξ, η)."""
    return (d @ cheb_basis(eta, d.shape[2])) @ cheb_basis(xi, d.shape[1])


def _chart_gradients(table: SlowMapTable, xi: float, eta: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """∇_Q ξ and ∇_Q η (each (2,)) at the chart point (ξ, η): ξ depends on u alone, Q = u e + v n."""
    dxi_du, deta_du, deta_dv = (float(v) for v in table.inverse_jacobian(xi, eta))
    e, n = np.asarray(table.e, float), np.asarray(table.n, float)
    return dxi_du * e, deta_du * e + deta_dv * n


def _jet(table: SlowMapTable, dcoef: Derivatives,
         Q: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """All ``TABLE_FUNCTIONS`` at Q (raising outside the table) and their (∂/∂Q_R, ∂/∂Q_J), shape (F, 2): the
    chart's (∂/∂ξ, ∂/∂η) (``dcoef``: :func:`_derivative_coefficients`) by the chain rule (:func:`_chart_gradients`)."""
    vals = table.evaluate(Q)
    xi, eta = table.coordinates(Q)
    g_xi, g_eta = _chart_gradients(table, xi, eta)
    return vals, _series(dcoef[0], xi, eta)[:, None] * g_xi + _series(dcoef[1], xi, eta)[:, None] * g_eta


def _hessians(table: SlowMapTable, dcoef: Derivatives, Q: NDArray[np.float64], rows: list[int]) -> NDArray[np.float64]:
    """Hessians (len(rows), 2, 2) in (Q_R, Q_J) of the table functions ``rows`` at Q, by the chain rule through the
    chart: H = Σ_ab f_ab ∇a ∇bᵀ + Σ_a f_a ∇∇a over a, b ∈ {ξ, η}, the series' second derivatives exact
    (``dcoef``), the chart's curvature ∇∇a by central differences of :func:`_chart_gradients` (step ``_H_CHART``;
    exactly zero on a release table's rectangle), symmetrised.  (Differences of the gradients in Q, step 1e-6, left
    the release charts past 0.97π, 0.002 U wide across: 1.3e-5 at 0.98π.)"""
    table.evaluate(Q)  # the range check
    xi, eta = table.coordinates(Q)
    d = [_series(dc[rows], xi, eta) for dc in dcoef]  # f_ξ, f_η, f_ξξ, f_ξη, f_ηη
    g = _chart_gradients(table, xi, eta)
    centre = [min(max(c, -1.0 + _H_CHART), 1.0 - _H_CHART) for c in (xi, eta)]
    curv = []  # ∇∇ξ, ∇∇η: ∂_k ∇a along each chart coordinate k, turned by ∇k
    for a in range(2):
        rows_k = []
        for k in range(2):
            ahead, behind = list(centre), list(centre)
            ahead[k] += _H_CHART
            behind[k] -= _H_CHART
            rows_k.append((_chart_gradients(table, *ahead)[a] - _chart_gradients(table, *behind)[a]) / (2 * _H_CHART))
        curv.append(np.outer(rows_k[0], g[0]) + np.outer(rows_k[1], g[1]))
    gg = [[np.outer(g[i], g[j]) for j in range(2)] for i in range(2)]
    H = (d[2][:, None, None] * gg[0][0] + d[3][:, None, None] * (gg[0][1] + gg[1][0]) + d[4][:, None, None] * gg[1][1]
         + d[0][:, None, None] * curv[0] + d[1][:, None, None] * curv[1])
    return 0.5 * (H + np.swapaxes(H, 1, 2))


_KICK_ROWS = [[_IDX[f"{pre}_{h}"] for h in _HARM] for pre in _PREFIX]
_DRIFT_ROWS = [_IDX[name] for name in _DRIFT]


def _kick_from_jet(vals: NDArray[np.float64], grads: NDArray[np.float64],
                   theta_a: float) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """k₁ (5,), its Q-gradient (5, 2) and Θ-derivative (5,) at Θ_a from the table's harmonics c0 + c1 cos Θ_a +
    s1 sin Θ_a and their gradients (:func:`_jet`)."""
    c, s = math.cos(theta_a), math.sin(theta_a)
    h = vals[_KICK_ROWS]  # (5, 3): c0, c1, s1
    g = grads[_KICK_ROWS]  # (5, 3, 2)
    return (h[:, 0] + h[:, 1] * c + h[:, 2] * s, g[:, 0] + g[:, 1] * c + g[:, 2] * s, -h[:, 1] * s + h[:, 2] * c)


def first_order_kick(table: SlowMapTable, Q: ArrayLike,
                     theta_a: float) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """k₁ at (Q, Θ_a) for the components of ``STEP_NAMES`` (Q_R, Q_J, Θ, t, φ), its Q-gradient (5, 2) and its
    Θ-derivative (5,), from the table's harmonics c0 + c1 cos Θ_a + s1 sin Θ_a."""
    return _kick_from_jet(*_jet(table, _derivative_coefficients(table), np.asarray(Q, float)), theta_a)


def drift_derivatives(table: SlowMapTable, name: str, Q: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Gradient (2,) and Hessian (2, 2) in (Q_R, Q_J) of the drift ``name`` (W, T or dphi): the gradient by the
    chain rule through the chart, the Hessian from the second-derivative series the same way (:func:`_hessians`)."""
    Q, dcoef = np.asarray(Q, float), _derivative_coefficients(table)
    return _jet(table, dcoef, Q)[1][_IDX[name]], _hessians(table, dcoef, Q, [_IDX[name]])[0]


def second_order_kicks(table: SlowMapTable, Q: ArrayLike, theta_a: ArrayLike) -> NDArray[np.float64]:
    """k₂ at the points Q (M, 2) and the angles Θ_a (M, K), shape (M, K, 5) for the components of ``STEP_NAMES``
    (module docstring), at the table's energy: the M·K exact steps' second derivatives by the second-order
    variational equations, run in the batch integrator's lanes
    (:func:`~rocknroller.analysis.slow.map.orbit.second_order_steps`, the M maxima θ_X from one vectorised
    turning-point solve); the first-order kick, the drifts'
    gradients and Hessians once per point, from the table's derivative series formed once."""
    Q = np.asarray(Q, float).reshape(-1, 2)
    theta_a = np.asarray(theta_a, float).reshape(len(Q), -1)
    dcoef = _derivative_coefficients(table)
    jets = [_jet(table, dcoef, q) for q in Q]
    hess = [_hessians(table, dcoef, q, _DRIFT_ROWS) for q in Q]
    W = np.array([vals[_IDX["W"]] for vals, _ in jets])
    theta_X = turning_points(table.E0, Q[:, 0], Q[:, 1], table.body)[1]
    shape = theta_a.shape
    d2 = second_order_steps(table.body, table.E0, np.broadcast_to(Q[:, :1], shape), np.broadcast_to(Q[:, 1:], shape),
                            0.5 * (theta_a - 0.5 * W[:, None]), np.broadcast_to(np.asarray(theta_X)[:, None], shape))
    A2 = 0.5 * np.stack([d2[k] for k in STEP_NAMES], axis=-1).reshape(shape + (5,))
    k2 = np.empty(shape + (5,))
    for m, ((vals, grads), H) in enumerate(zip(jets, hess)):
        g = grads[_DRIFT_ROWS]
        for j, ta in enumerate(theta_a[m]):
            k1, dk_dq, dk_dth = _kick_from_jet(vals, grads, float(ta))
            kq, a2 = k1[:2], A2[m, j]
            k = a2 - 0.5 * (dk_dq @ kq + dk_dth * k1[2])
            k[2:] -= 0.5 * g @ a2[:2] + 0.25 * np.einsum("i,dij,j->d", kq, H, kq)
            k2[m, j] = k
    return k2


def second_order_kick(table: SlowMapTable, Q: ArrayLike, theta_a: float) -> NDArray[np.float64]:
    """k₂ at (Q, Θ_a) for the components of ``STEP_NAMES`` (module docstring), at the table's energy; the exact
    step's second derivatives by the second-order variational equations (one orbit; :func:`second_order_kicks`)."""
    return second_order_kicks(table, np.asarray(Q, float)[None, :], [[float(theta_a)]])[0, 0]


def dkd_residual(table: SlowMapTable, eps: float, Q: ArrayLike, theta: float) -> NDArray[np.float64]:
    """(exact step − one step of the first-order map)/ε² from the maximum (Q, Θ) at the table's energy, for the
    components of ``STEP_NAMES`` (angle differences wrapped): → k₂_Q and k₂_X + ½ ∇F·k₂_Q as ε → 0."""
    from rocknroller.analysis.slow.map.compiled_map import iterate_slow_map

    Q = np.asarray(Q, float)
    exact = exact_step(table.body, eps, table.E0, float(Q[0]), float(Q[1]), 0.5 * theta)
    s = iterate_slow_map(table, eps, 0.5 * theta, 1e6, Q0=Q, n_steps=1)
    first = np.array([s.QR[0], s.QJ[0], s.Theta[0], s.t[0], s.phi[0]])
    r = exact - first
    r[2] = float(wrap_angle(r[2]))
    r[4] = float(wrap_angle(r[4], math.pi))  # the map's φ is continued modulo its jumps of π
    return r / (eps * eps)


# ----------------------------------------------------------------------------- tables of k₂
#: Harmonics of k₂ in Θ_a: the second-order response holds the harmonics 0, 2 and 4 of ψ (0, 1, 2 of Θ = 2ψ).
K2_HARMONICS = ("c0", "c1", "s1", "c2", "s2")
#: The tabulated functions, component-major (``STEP_NAMES`` order).
K2_FUNCTIONS = tuple(f"{p}_{h}" for p in _PREFIX for h in K2_HARMONICS)
#: Θ_a of the five evaluations that fix the harmonics (a discrete Fourier transform).
_K2_THETA_A = tuple(2.0 * math.pi * k / 5.0 for k in range(5))
#: Components odd in Q (reversibility: (Q, Θ) → (−Q, Θ)), as for k₁; the others are even.
_K2_ODD = tuple(f"{p}_c0" in _ODD for p in _PREFIX)
#: Off-grid chart points (ξ, η) where a new table is checked against direct evaluations, and the largest error
#: (relative to each component's largest harmonic on the grid) accepted without a warning: k₂ enters the step
#: multiplied by ε², so 1e-3 of it is 1e-7 of a step at ε = 1e-2, below the map's O(ε³) error.
_K2_CHECK_POINTS = ((0.37, 0.3), (-0.81, -0.55), (0.93, 0.8))
K2_ACCURACY = 1e-3
#: The same for a table on a region table's chart (a start with velocity; docs/slow_validation.md, "Second order on the
#: region tables").
#: On the band chart of the paper's reversal starts k₂ interpolates to 5e-3–8e-3 with the default 16 × 32 nodes and
#: no better with more (16 × 48, 32 × 32, 16 × 64: 3.4e-3 to 5.6e-3), yet what it predicts does not depend on it:
#: from rest at 0.95π, ψ0 = π/4 (the fig. 7 start), 1000 time units, the order-2 maxima on 16 × 32 and on 16 × 48
#: or 32 × 32 differ by ≤ 7e-8 of the Q_R extent and 2.5e-7 in Θ at ε = 1e-3 and 5e-4, a thousandth of the map's
#: own error against the ODE (6e-5, 2e-4), and 1/30 of it at ε = 1e-2; and the observables are as close to the
#: ODE as on the release tables (k₂ to 7e-5): slow period 3.5e-6, Q_R and Q_J extents 3.0e-5 and 4.6e-4 on both
#: at ε = 1e-3.  Twice the largest interpolation error measured is accepted without a warning.
K2_REGION_ACCURACY = 2e-2


def k2_harmonics(table: SlowMapTable, Q: ArrayLike) -> NDArray[np.float64]:
    """The harmonics ``K2_HARMONICS`` of k₂ in Θ_a at Q, shape (5 components, 5 harmonics), from
    :func:`second_order_kick` at five Θ_a (five second-order variational orbits and the starts' 25 solves)."""
    return k2_harmonics_at(table, np.asarray(Q, float)[None, :])[0]


def k2_harmonics_at(table: SlowMapTable, Q: ArrayLike) -> NDArray[np.float64]:
    """:func:`k2_harmonics` at M points Q (M, 2), shape (M, 5, 5): their 5 M orbits in the batch integrator's lanes
    (:func:`second_order_kicks`)."""
    Q = np.asarray(Q, float).reshape(-1, 2)
    vals = second_order_kicks(table, Q, np.broadcast_to(np.array(_K2_THETA_A), (len(Q), len(_K2_THETA_A))))
    return np.swapaxes(np.linalg.solve(_basis(np.array(_K2_THETA_A))[None], vals), 1, 2)


def _first_table(body: Body, where: float, kind: str, **run: Any) -> SlowMapTable:
    """The first-order table whose chart a second-order table uses: the release table of θ0 = ``where`` or the
    (default) region table of the energy E = ``where``; ``run``: how to build it if needed (progress, workers)."""
    if kind == "release":
        return load_or_build_table(body, where, **run)
    from rocknroller.analysis.slow.map.region import load_or_build_region_table

    return load_or_build_region_table(body, where, **run)


def k2_block(first: SlowMapTable, nodes: list[tuple[float, float]]) -> NDArray[np.float64]:
    """k₂'s harmonics at ``nodes`` (Q_R, Q_J) on the first-order table ``first``, one row per node."""
    return k2_harmonics_at(first, nodes).reshape(len(nodes), -1)


def check_k2_nu(nu: int) -> None:
    """ValueError naming nu unless it is an even integer in [8, 256] (the second-order tables' nodes along)."""
    if isinstance(nu, bool) or int(nu) != nu or nu % 2 or not 8 <= nu <= 256:
        raise ValueError(f"nu must be an even integer in [8, 256], got nu={nu!r}")


#: Nodes per task of a second-order build (those of a task share the batch integrator's lanes).
_K2_BLOCK_NODES = 16


def k2_blocks(first: SlowMapTable, nu: int, nv: int) -> list[tuple[SlowMapTable, list[tuple[float, float]]]]:
    """The arguments of :func:`k2_block` for the computed half of the nu × nv Chebyshev nodes on ``first``'s chart
    (ξ ≤ 0, in C order), in blocks of ``_K2_BLOCK_NODES``; nu and nv checked (ValueError naming them)."""
    check_k2_nu(nu)
    if isinstance(nv, bool) or int(nv) != nv or not 2 <= nv <= first.coef.shape[2]:
        raise ValueError(f"nv must be an integer in [2, {first.coef.shape[2]}] (the first-order table's terms "
                         f"across), got nv={nv!r}")
    XI, ETA = np.meshgrid(cheb_nodes(nu), cheb_nodes(nv), indexing="ij")
    QR, QJ = first.chart(XI, ETA)
    half = [(float(QR[i, j]), float(QJ[i, j])) for i in range(nu // 2) for j in range(nv)]
    return [(first, half[k:k + _K2_BLOCK_NODES]) for k in range(0, len(half), _K2_BLOCK_NODES)]


def _build_k2(body: Body, where: float, kind: str, nu: int, nv: int, workers: int,
              progress: bool | None) -> SecondOrderTable:
    """k₂ on the chart of the first-order table (:func:`_first_table`): half the nodes computed, the others by the
    parity (module docstring of :func:`build_second_order_table`), checked at off-grid points."""
    check_k2_nu(nu)
    workers = check_processes(workers, "workers")
    first = _first_table(body, where, kind, progress=progress, workers=workers)
    blocks = k2_blocks(first, nu, nv)
    rows = map_blocks(k2_block, blocks, [len(b[1]) for b in blocks], processes=workers, unit="node",
                      desc=(f"second-order tables, theta0={where / math.pi:.6g}pi" if kind == "release" else
                            f"second-order tables, E={where:.6g}"),
                      progress=progress)
    return fit_k2(first, where, kind, nu, nv, rows)


def fit_k2(first: SlowMapTable, where: float, kind: str, nu: int, nv: int, rows: list[NDArray[np.float64]], *,
           check: bool = True) -> SecondOrderTable:
    """The second-order table on ``first`` (a ``kind`` "release" table of θ0 = ``where`` or "region" table of
    E = ``where``) from the rows of
    :func:`k2_block` for :func:`k2_blocks`' blocks: the other half of the nodes by the parity, the Chebyshev fit,
    and with ``check`` the check at off-grid points (:func:`k2_check_error`; above ``K2_ACCURACY``, or
    ``K2_REGION_ACCURACY``, an AveragingValidityWarning; without it ``interp_error`` is NaN)."""
    from rocknroller.analysis.slow.map.limits import AveragingRangeError, AveragingValidityWarning

    data = np.empty((nu, nv, 5, 5))
    data[: nu // 2] = np.concatenate(rows).reshape(nu // 2, nv, 5, 5)
    sign = np.where(np.array(_K2_ODD), -1.0, 1.0)[:, None]
    data[nu // 2:] = sign * data[: nu // 2][::-1, ::-1]
    if not np.all(np.isfinite(data)):
        raise AveragingRangeError(f"the second-order orbits of {np.count_nonzero(~np.isfinite(data).all(axis=(2, 3)))} "
                                  f"of the {nu * nv} nodes gave non-finite data; the tables are not built")
    Au, Av = cheb_fit_matrix(nu), cheb_fit_matrix(nv)
    flat = data.reshape(nu, nv, 25)
    coef = np.stack([Au @ flat[:, :, k] @ Av.T for k in range(25)])
    table = SecondOrderTable(theta0=float(first.theta0) if kind == "release" else math.nan, E0=float(first.E0),
                             coef=coef)
    if not check:
        return table
    err = k2_check_error(first, table, np.abs(data).max(axis=(0, 1, 3)))
    if not math.isfinite(err):
        raise AveragingRangeError(f"the check of the second-order tables against direct orbits gave {err!r}; the "
                                  "tables are not used")
    limit = K2_ACCURACY if kind == "release" else K2_REGION_ACCURACY
    if err > limit:
        if kind == "release":
            what, advice = f"theta0={where!r}", (
                f"use more nodes (nu, nv of load_or_build_second_order_table: now {nu}, {nv}; then pass the table as "
                "predict_slow_motion's second=)")
        else:
            what, advice = f"E={where!r}", (
                "more nodes do not bring it down here (docs/averaging.md, 'Second order in eps'): check the "
                "prediction against the direct ODE (rocknroller slow --check), or use the first-order map "
                "(--order 1, order=1)")
        warnings.warn(f"the second-order tables for {what} interpolate k2 only to {err:.1e} (relative, above "
                      f"{limit:g}); {advice}", AveragingValidityWarning, stacklevel=3)
    return replace(table, interp_error=err)


def k2_check_error(first: SlowMapTable, table: SecondOrderTable, scale: NDArray[np.float64] | None = None) -> float:
    """The largest error of ``table``'s k₂ harmonics against k₂ computed directly (:func:`k2_harmonics`: the
    second-order variational orbits) at the off-grid chart points ``_K2_CHECK_POINTS`` of ``first``, relative to each
    component's largest harmonic, ``scale`` (5,), by default the table's own over its nodes."""
    if scale is None:
        nu, nv = table.coef.shape[1:]
        at_nodes = np.array([np.polynomial.chebyshev.chebgrid2d(cheb_nodes(nu), cheb_nodes(nv), c) for c in table.coef])
        scale = np.abs(at_nodes.reshape(5, 5, nu, nv)).max(axis=(1, 2, 3))
    err = 0.0
    for x, y in _K2_CHECK_POINTS:
        q = np.array([float(c) for c in first.chart(x, y)])
        diff = np.abs(table.harmonics(first, q) - k2_harmonics(first, q)).max(axis=1)
        err = float(np.max([err, (diff / scale).max()]))  # a NaN propagates (max() would drop it)
    return err


def build_second_order_table(body: Body, theta0: float, *, nu: int = 64, nv: int = 6,
                             workers: int = 1, progress: bool | None = None) -> SecondOrderTable:
    """Tabulate k₂ on the chart of the release table of (body, θ0) (built and cached if needed).

    Only half the Chebyshev nodes are computed: the grid is symmetric under (ξ, η) → (−ξ, −η), Q → −Q, where each
    component keeps or flips its sign (``_K2_ODD``), which makes the map reversible.  ``workers`` processes share
    the nodes (the table does not depend on how many); ``progress``: a tqdm bar on stderr naming the table (None:
    only if stderr is a terminal).  Checked at off-grid points against direct evaluations; above ``K2_ACCURACY`` an
    AveragingValidityWarning.  Cost: five second-order variational orbits per computed node, those of 16 nodes
    together in the batch integrator's lanes (:func:`k2_harmonics_at`).

    Raises
    ------
    ValueError
        θ0 outside ``THETA0_RANGE``, or nu (even, 8–256), nv (2–6, the release table's terms across) or workers out
        of range, naming them.
    """
    return _build_k2(body, theta0, "release", nu, nv, workers, progress)


def build_second_order_region_table(body: Body, E: float, *, nu: int = 16, nv: int = 32, workers: int = 1,
                                    progress: bool | None = None) -> SecondOrderTable:
    """Tabulate k₂ on the chart of the default region table of (body, E) (a start with velocity), as
    :func:`build_second_order_table` does on a release table's; nv up to that table's terms across.

    On the band chart of the paper's reversal starts the default 16 × 32 nodes (256 computed; the cost: docs/performance.md)
    interpolate k₂ to 5e-3–8e-3 of each component's largest harmonic, and more nodes do not go below ~5e-3 (16 × 48,
    32 × 32, 16 × 64 measured), where the release tables' reach 7e-5; yet the order-2 predictions are as close to the
    direct ODE on either (``K2_REGION_ACCURACY``, against which the build checks; docs/averaging.md, "Second order
    in ε")."""
    return _build_k2(body, E, "region", nu, nv, workers, progress)


def load_or_build_second_order_table(body: Body, theta0: float, *, build: bool = True, use_cache: bool = True,
                                     **grid: Any) -> SecondOrderTable:
    """The second-order table of (body, θ0) from memory, the disk cache, or built (:func:`build_second_order_table`,
    options ``grid``) and cached, as :func:`rocknroller.analysis.slow.map.table.load_or_build_table` does."""
    from rocknroller.analysis.slow.map.limits import check_map_theta0

    theta0 = check_map_theta0(theta0)

    return cached_table(build_second_order_table, body, theta0, f"theta0={theta0!r}", build=build,
                        use_cache=use_cache, table_type=SecondOrderTable, spec_of=k2_spec, **grid)


def load_or_build_second_order_region_table(body: Body, E: float, *, build: bool = True, use_cache: bool = True,
                                            **grid: Any) -> SecondOrderTable:
    """The second-order table on the region table of (body, E), from memory, the disk cache, or built
    (:func:`build_second_order_region_table`) and cached."""
    from rocknroller.analysis.slow.map.region import check_below_top

    E = check_below_top(body, E)
    return cached_table(build_second_order_region_table, body, E, f"E={E!r}", build=build, use_cache=use_cache,
                        table_type=SecondOrderTable, spec_of=_k2_region_spec, unstored={"theta0": math.nan}, **grid)


def k2_spec(opts: dict[str, Any]) -> dict[str, tuple[int, ...]]:
    """The fields of a release's second-order table file, in checksum order."""
    return {"theta0": (), **_k2_region_spec(opts)}


def _k2_region_spec(opts: dict[str, Any]) -> dict[str, tuple[int, ...]]:
    """The fields of a region's second-order table file: all but θ0, which such a table does not have (NaN, and
    the cache holds finite values only)."""
    return {"E0": (), "coef": (len(K2_FUNCTIONS), opts["nu"], opts["nv"]), "interp_error": ()}
