"""The region tables: the averaged slow map over the whole (Q_R, Q_J) region of one energy, for starts with velocity.
It holds the tables' two charts (:func:`region_frame`, :func:`region_axis`: the "spindle" along Q_J,0^crit, paper
eq. QJcrit_0, and the "band" along Q_J,π^crit, paper eq. QJcrit_pi), their build from variational orbits on one or
more processes (:func:`build_region_table`), their check against direct orbits (:func:`region_interpolation_error`)
and cache (:func:`load_or_build_region_table`), and the bound on the energy, below that of the upright position
(:func:`check_below_top`: E < 2 g a, paper eq. energy).

At energy E the set of (Q_R, Q_J) for which θ oscillates (F > 0 between two simple roots, paper eq.
thetadotsq) is {Q : min_θ U(θ; Q) < E}.  U is a positive quadratic form in Q plus g a (1 − cos θ) for each θ,
so the set is star-shaped about Q = 0; it is a spindle along the critical line Q_J,0^crit (paper eq.
QJcrit_0), whose tips are the sleeping top at θ = 0 spinning with all of E, and its boundary is steady
rolling (a double root of F).

Chart.  The tables use the frame e along Q_J,0^crit, n ⟂ e, and Q = x U e + (c(x) + τ w(x)) n with
coordinates |x|, |τ| ≤ 1 (:class:`rocknroller.analysis.slow.map.chart.SlowMapTable`): across the line, τ = ±1 is
the level set (E − min U)/E = δ_min of the distance to steady rolling; along it, U = ``tip_fraction`` times the tip
of that level set.  The coefficient functions are analytic inside the region but not at the tips (Chebyshev
coefficients along x decay like 1.2^−n when the chart reaches 97 % of the tip), hence the tip fraction.  c (odd)
and w (even) are Chebyshev fits of the level set's two sides, so Q → −Q is (x, τ) → (−x, −τ): the parities that
make the map reversible hold on the grid.  This "spindle" chart fails at high amplitude: there W turns by 2π across
Q_J,π^crit (paper eq. QJcrit_pi) within a layer (width 0.0024 at Q = 0 for the energy of a release from 0.95π,
0.03 near its ends) that crosses the spindle diagonally, and no stretch along or across the spindle follows it.
The "band" chart takes e along Q_J,π^crit instead, c(x) the measured centre of the layer (where W turns fastest;
it bends off the line by up to 0.03) and w(x) the largest half-width about it inside the level set: the sinh
stretch across (β from |∂W/∂v(0)|) then sits on the layer all along it.  It covers the band about Q_J,π^crit, not
the spindle's tips.  ``region_axis`` picks it from the energy of a release at ``BAND_FROM_THETA0`` up.

Data.  T_θ, W = 2(Δψ − π) mod 2π and Δφ mod π come from the same variational orbits as the ε-responses
(:func:`rocknroller.analysis.slow.map.harmonic.harmonic_steps`), not from the quadratures: those lose their
double-precision accuracy near steady rolling and at small amplitude, where these tables reach.
:func:`rocknroller.analysis.slow.map.table.fit_table` lifts W and Δφ to continuous branches and builds the
drift–kick–drift form.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.diagnostics import wrap_angle
from rocknroller.analysis.routh.reduction import E_MAX, NoMotionError, u_ends
from rocknroller.analysis.routh.turning_points import min_potential, solve_turning_points
from rocknroller.analysis.slow.map.chart import CHART_TERMS, TABLE_FUNCTIONS, SlowMapTable, cheb_nodes
from rocknroller.analysis.slow.map.limits import AveragingRangeError
from rocknroller.analysis.slow.map.orbit import symmetric_data
from rocknroller.analysis.slow.map.table import (REGION_TABLE_ACCURACY, cached_table, check_grid, fit_and_check, is_cached,
                                             kick_at_rest, mirrored, orbit_data)
from rocknroller.numerics.parallel import check_processes

__all__ = [
    "check_below_top", "region_axis", "region_options", "chart_direction", "table_chart", "region_frame",
    "build_region_table", "region_interpolation_error", "accuracy_cause", "load_or_build_region_table",
    "DELTA_MIN_RANGE", "DELTA_MIN_DEFAULT", "TIP_FRACTION_RANGE", "AXES", "BAND_FROM_THETA0", "DEFAULT_GRID",
    "SMALL_AMPLITUDE_THETA0", "region_table_cached"
]

#: Allowed least distances (E − min U)/E to steady rolling of a region table, and the default one (the tables of
#: ``load_or_build_region_table`` and of the predictions): nearer steady rolling θ hardly oscillates.
DELTA_MIN_RANGE = (1e-3, 0.5)
DELTA_MIN_DEFAULT = 0.05
#: Allowed fractions of the tip covered along the critical line.
TIP_FRACTION_RANGE = (0.1, 0.95)
#: Nodes of the fit of the level set's sides, and the degree of the chart's c(x) and w(x).
_PROFILE_NODES = CHART_TERMS
_CHART_DEGREE = 8
#: Doublings that bracket the region's edge on a ray, and the most steps that then resolve it (:func:`_edge`; as
#: many bisections would resolve 2^-60 of the bracket).
_BRACKET_DOUBLINGS = 64
_EDGE_STEPS = 60
#: Relative rounding of min U (a few units in the last place): an edge whose bracket's g differ by less is resolved.
#: Measured: along rays through the edge (band and spindle charts, releases at 0.3π and 0.95π) min U scatters about a
#: smooth fit by at most 3.2 ε of the level, with numpy's AVX-512 kernels and without them: 8 ε covers it 2.5 times.
_EDGE_ROUNDING = 8.0 * np.finfo(float).eps


def _check_energy(E: float) -> float:
    E = float(E)
    if not (math.isfinite(E) and 0.0 < E <= E_MAX):
        raise ValueError(f"E must be a finite number in (0, {E_MAX:g}], got E={E!r}")
    return E


#: Charts of the region tables: "spindle" along Q_J,0^crit over the whole region, "band" along Q_J,π^crit.
AXES = ("spindle", "band")
#: "auto" takes the band from the energy of a release from rest at this θ0 up (measured: docs/averaging.md).
BAND_FROM_THETA0 = 0.65 * math.pi
#: Default Chebyshev nodes (along, across) of each chart.
DEFAULT_GRID = {"spindle": (128, 64), "band": (80, 96)}
#: Degree of the band's centre and half-width fits (odd and even parts).
_BAND_DEGREE = 12
#: Layer search across the band: geometric steps (relative), and the points of the refining grid.
_LAYER_STEP, _LAYER_REFINE = 0.04, 201


def check_below_top(body: Body, E: float) -> float:
    """E, or an AveragingRangeError if E ≥ 2 g a, the energy of the upright position θ = π at rest (paper eq.
    energy): from there up, the orbits on Q_J,π^crit pass through the upright position (F(π) ≥ 0 on it), where the
    advance W of the spin is discontinuous, and no table of the energy can hold the map across that line."""
    E, top = _check_energy(E), 2.0 * body.g * body.a
    if E >= top:
        raise AveragingRangeError(
            f"the region tables need an energy below that of the upright position, E < 2 g a = {top:.6g}, got "
            f"E={E:.6g}: above it the orbits on the critical line Q_J,pi^crit pass through theta = pi, where the "
            f"averaged map's twist is discontinuous; run this start by the direct ODE (rocknroller simulate)")
    return E


def region_axis(body: Body, E: float) -> str:
    """The chart "auto" picks for (body, E): "band" from the energy of a release from rest at ``BAND_FROM_THETA0``
    up (where W turns by 2π across Q_J,π^crit within a layer the spindle's stretch cannot follow), else "spindle"."""
    from rocknroller.analysis.slow.map.family import rest_energy

    return "band" if _check_energy(E) >= rest_energy(body.symmetric(), BAND_FROM_THETA0) else "spindle"


def region_options(body: Body, E: float, axis: str = "auto", nu: int | None = None,
                   nv: int | None = None) -> tuple[str, int, int]:
    """(axis, nu, nv) with "auto" and the grid's defaults resolved (``region_axis``, ``DEFAULT_GRID``)."""
    if axis == "auto":
        axis = region_axis(body, E)
    if axis not in AXES:
        raise ValueError(f"axis must be one of {('auto',) + AXES}, got axis={axis!r}")
    dnu, dnv = DEFAULT_GRID[axis]
    return axis, dnu if nu is None else nu, dnv if nv is None else nv


def chart_direction(body: Body, axis: str) -> NDArray[np.float64]:
    """The unit vector e along the line of a region chart: Q_J,0^crit (paper eq. QJcrit_0) for the spindle,
    Q_J,π^crit (paper eq. QJcrit_pi) for the band; their slopes are −u at the ends θ = 0, π for Q = (1, 0)
    (:func:`rocknroller.analysis.routh.reduction.u_ends`, as ``criticality.lines`` has them)."""
    u0, upi = u_ends(1.0, 0.0, body.symmetric())
    e = np.array([1.0, -float(u0 if axis == "spindle" else upi)])
    return e / np.linalg.norm(e)


def table_chart(table: SlowMapTable) -> str | None:
    """The chart of a region table, "spindle" or "band" (its line, :func:`chart_direction`), or None for a release
    table (along the kick direction)."""
    if table.delta_min == 0.0:
        return None
    for axis in AXES:
        if np.array_equal(table.e, chart_direction(table.body, axis)):
            return axis
    return None  # pragma: no cover - region tables are built on one of the charts


def _layer_centres(sym: Body, E: float, points: NDArray[np.float64], n: NDArray[np.float64],
                   lo: NDArray[np.float64], up: NDArray[np.float64], width: float) -> NDArray[np.float64]:
    """Offsets s along n from each point at which W (the quadrature's, paper eq. psidotCJQR) turns fastest across
    Q_J,π^crit, searched within [lo/2, up/2]: a grid geometric about s = 0 (steps ``_LAYER_STEP`` relative, from
    the layer's width at Q = 0), then a uniform one over the steepest cell and its neighbours, and a parabola
    through the largest slope and its two neighbours."""
    from rocknroller.analysis.routh.quadrature import precession

    def W_along(s: NDArray[np.float64]) -> NDArray[np.float64]:
        Q = points[:, None, :] + s[..., None] * n
        pr = precession(E, Q[..., 0].ravel(), Q[..., 1].ravel(), sym, rtol=1e-10)
        if np.any(np.asarray(pr.status) != 0):  # pragma: no cover - the search stays inside δ >= delta_min / 2
            raise AveragingRangeError(f"the quadrature failed while locating the layer of W at E={E!r}")
        return np.unwrap(2.0 * np.asarray(pr.delta_psi).reshape(s.shape), axis=1)

    k = np.arange(1, int(math.ceil(math.log(float(np.max(up - lo)) / width) / _LAYER_STEP)) + 1)
    side = width * np.expm1(_LAYER_STEP * k)
    grid = np.concatenate([-side[::-1], [0.0], side])
    s = np.clip(grid[None, :], 0.5 * lo[:, None], 0.5 * up[:, None])
    slope = np.abs(np.diff(W_along(s), axis=1)) / np.maximum(np.diff(s, axis=1), 1e-300)
    j = np.clip(np.argmax(slope, axis=1), 1, s.shape[1] - 3)
    rows = np.arange(len(points))
    fine = np.linspace(s[rows, j - 1], s[rows, j + 2], _LAYER_REFINE, axis=1)
    d = np.abs(np.diff(W_along(fine), axis=1))
    m = np.clip(np.argmax(d, axis=1), 1, _LAYER_REFINE - 3)
    y0, y1, y2 = d[rows, m - 1], d[rows, m], d[rows, m + 1]
    h = fine[:, 1] - fine[:, 0]
    curv = y0 - 2.0 * y1 + y2
    shift = np.where(curv < 0.0, 0.5 * (y0 - y2) / np.where(curv < 0.0, curv, -1.0), 0.0)
    return 0.5 * (fine[rows, m] + fine[rows, m + 1]) + h * shift


def _edge(sym: Body, E: float, level: float, origins: NDArray[np.float64],
          directions: NDArray[np.float64]) -> NDArray[np.float64]:
    """Distances r from each origin (inside) along each direction to the level set min U = level.

    g(r) = min U − level increases along each ray (min U grows away from Q = 0, and the chart's rays start on the
    line through it, at right angles to it or along it, so |Q|² is |origin|² + r²).  The root is bracketed by
    doubling from √E, then resolved to four units in the last place of r, or until g at the bracket's ends differs
    by no more than min U's rounding (``_EDGE_ROUNDING``), by the Illinois variant of regula falsi
    (the end kept twice in a row has its g halved: superlinear convergence on both ends) with secants in r², in
    which g is nearly linear; a secant that falls outside the bracket is replaced by its midpoint, and one that
    lands on g = 0, or within the last place of the inside end, closes it.  Returns the bracket's inside end
    (g ≤ 0)."""
    def excess(r: NDArray[np.float64]) -> NDArray[np.float64]:
        Q = origins + r[:, None] * directions
        return min_potential(Q[:, 0], Q[:, 1], sym) - level

    lo, hi = np.zeros(len(origins)), np.full(len(origins), math.sqrt(E))
    g_lo, g_hi = excess(lo), excess(hi)
    for _ in range(_BRACKET_DOUBLINGS):
        out = g_hi > 0.0
        if out.all():
            break
        lo, g_lo = np.where(out, lo, hi), np.where(out, g_lo, g_hi)
        hi = np.where(out, hi, 2.0 * hi)
        g_hi = np.where(out, g_hi, excess(hi))
    else:  # pragma: no cover - min U grows like |Q|²: the set is bounded
        raise RuntimeError("the region of oscillation is unbounded")
    kept = np.zeros(len(origins), int)  # +1: lo moved last, −1: hi moved last
    for _ in range(_EDGE_STEPS):
        active = (hi - lo > 4.0 * np.spacing(hi)) & (g_hi - g_lo > _EDGE_ROUNDING * abs(level))
        if not active.any():
            return lo
        with np.errstate(divide="ignore", invalid="ignore"):  # the secant in r², in which g is nearly linear,
            t = g_lo / (g_lo - g_hi)  # as a step from lo that keeps its digits near the edge
            r = lo + t * (hi - lo) * (hi + lo) / (np.sqrt(lo * lo + t * (hi - lo) * (hi + lo)) + lo)
        closed = active & (r <= lo)  # a step from lo below its last place: lo is the edge
        hi, active = np.where(closed, lo, hi), active & ~closed
        r = np.where((r > lo) & (r < hi), r, 0.5 * (lo + hi))
        g = excess(r)
        inside = active & (g <= 0.0)
        outside = active & ~inside
        g_hi = np.where(inside & (kept == 1), 0.5 * g_hi, g_hi)  # Illinois: the stale end's g halved
        g_lo = np.where(outside & (kept == -1), 0.5 * g_lo, g_lo)
        lo, g_lo = np.where(inside, r, lo), np.where(inside, g, g_lo)
        hi, g_hi = np.where(outside | (g == 0.0), r, hi), np.where(outside, g, g_hi)  # g = 0: the edge itself
        kept = np.where(inside, 1, np.where(outside, -1, kept))
    raise RuntimeError(f"the region's edge was not resolved in {_EDGE_STEPS} steps")  # pragma: no cover


def region_frame(body: Body, E: float, *, axis: str = "auto", nu: int | None = None, nv: int | None = None,
                 delta_min: float = DELTA_MIN_DEFAULT, tip_fraction: float = 0.8) -> SlowMapTable:
    """The chart of the region tables of (body, E) (module docstring), as a SlowMapTable without coefficients.

    Raises
    ------
    ValueError
        E, axis, delta_min or tip_fraction out of range (naming it and the range).
    """
    E = check_below_top(body, E)
    axis, nu, nv = region_options(body, E, axis, nu, nv)
    check_grid(nu, nv)
    for name, val, (low, high) in (("delta_min", delta_min, DELTA_MIN_RANGE), ("tip_fraction", tip_fraction,
                                                                               TIP_FRACTION_RANGE)):
        if not low <= val <= high:
            raise ValueError(f"{name} must lie in [{low:g}, {high:g}], got {name}={val!r}")
    sym = body.symmetric()
    e = chart_direction(sym, axis)
    n = np.array([-e[1], e[0]])
    level = E * (1.0 - delta_min)

    # near Q = 0, W ≈ ∇W(0)·Q turns by O(1) over 1/|∂W/∂u| along e and 1/|∂W/∂v| across
    hq = 1e-7
    W = symmetric_data(sym, E, hq * np.array([e[0], -e[0], n[0], -n[0]]), hq * np.array([e[1], -e[1], n[1], -n[1]]))[1]
    dW_du, dW_dv = abs(W[0] - W[1]) / (2.0 * hq), abs(W[2] - W[3]) / (2.0 * hq)
    tip = float(_edge(sym, E, level, np.zeros((1, 2)), e[None, :])[0])
    U = tip_fraction * tip
    xs = cheb_nodes(_PROFILE_NODES)
    on_line = xs[:, None] * U * e[None, :]
    sides = _edge(sym, E, level, np.concatenate([on_line, on_line]),
                  np.concatenate([np.tile(n, (len(xs), 1)), np.tile(-n, (len(xs), 1))]))
    up, lo = sides[:len(xs)], -sides[len(xs):]
    cheb = np.polynomial.chebyshev
    c_coef, w_coef = np.zeros(CHART_TERMS), np.zeros(CHART_TERMS)
    if axis == "spindle":
        # c, w: the level set's two sides; a low-degree chart: the tabulated functions of (x, τ) are resolved with
        # few more nodes than the functions of Q themselves need (a chart of high degree would multiply their
        # Chebyshev content)
        c, w, degree = 0.5 * (up + lo), 0.5 * (up - lo), _CHART_DEGREE
    else:
        # c: the centre of the layer in which W turns by 2π across Q_J,π^crit (it bends off the line), w: the
        # largest half-width about it inside the level set; the stretch across then follows the layer everywhere.
        # W is odd in Q and the profile's nodes are antisymmetric, so c is odd: the first half's centres give the rest
        half = len(xs) // 2  # _PROFILE_NODES is even: the profile's nodes come in pairs x, −x
        c = _layer_centres(sym, E, on_line[:half], n, lo[:half], up[:half], 2.0 / max(dW_dv, 1e-300))
        c = np.concatenate([c, -c[::-1]])
        w, degree = np.minimum(up - c, c - lo), _BAND_DEGREE
    c_coef[:degree + 1] = cheb.chebfit(xs, 0.5 * (c - c[::-1]), degree)
    w_coef[:degree + 1] = cheb.chebfit(xs, 0.5 * (w + w[::-1]), degree)
    c_coef[0::2] = 0.0  # exactly odd
    w_coef[1::2] = 0.0  # exactly even
    cf, wf = cheb.chebval(xs, c_coef), cheb.chebval(xs, w_coef)
    w_coef *= min(1.0, float(np.min(np.minimum(up - cf, cf - lo) / wf)))  # inside the level set at the nodes
    scales = (dW_du * U, dW_dv * float(cheb.chebval(0.0, w_coef)))
    alpha, beta = (math.asinh(s) if s > 1.0 else 0.0 for s in scales)
    # the release angle of this energy, 0 < E < 2 g a (a rounded cos θ0 of ±1 at the ends kept finite: the cache
    # stores finite values only)
    theta0 = math.acos(min(1.0, max(-1.0, 1.0 - E / (sym.g * sym.a))))
    return SlowMapTable(a=sym.a, I1=sym.I1, I3=sym.I3, g=sym.g, theta0=theta0, E0=E, e=e, n=n, U=U,
                        c_coef=c_coef, w_coef=w_coef, coef=np.zeros((len(TABLE_FUNCTIONS), nu, nv)),
                        C0=kick_at_rest(sym, E), kappa=0.0, interp_error=0.0, delta_min=float(delta_min), alpha=alpha,
                        beta=beta)


def _orbit_data(sym: Body, E: float, QR: NDArray, QJ: NDArray, progress: bool | None = False, workers: int = 1):
    """T, W mod 2π, Δφ mod π and the harmonics of the ε-responses at each Q, from one variational orbit with three
    ε-responses per node, half the nodes of a mirrored grid (:func:`rocknroller.analysis.slow.map.table.orbit_data`)."""
    n = np.size(QR) // 2 if mirrored(QR, QJ) else np.size(QR)  # θ_X is even in Q: a mirrored grid's half suffices
    tp = solve_turning_points(E, np.ravel(QR)[:n], np.ravel(QJ)[:n], sym)
    if np.any(np.asarray(tp.status) != 0):
        raise AveragingRangeError(f"some nodes of the region tables of E={E!r} have no oscillation of theta")
    theta_X = np.asarray(tp.theta_X, float)
    theta_X = np.concatenate([theta_X, theta_X[::-1]]) if 2 * n == np.size(QR) else theta_X
    return orbit_data(sym, E, QR, QJ, theta_X.reshape(np.shape(QR)), progress=progress, workers=workers,
                      desc=f"region tables, E={E:.6g}")


#: Off-grid chart points (x, τ) at which a new region table is checked against direct orbits.
_CHECK_POINTS = ((0.37, 0.3), (-0.81, -0.55), (0.93, 0.8), (0.05, -0.97))


def region_interpolation_error(table: SlowMapTable) -> float:
    """Largest error of a region table against direct orbits at ``_CHECK_POINTS``: relative for T_θ, in
    radians for W and Δφ, and relative to the largest harmonic for k_Q (ΔQ with its phase advanced by W/2)."""
    sym, worst = table.body, 0.0
    x, y = np.array(_CHECK_POINTS).T
    QR, QJ = table.chart(x, y)
    T, W, dphi, resp = _orbit_data(sym, table.E0, QR, QJ)
    for k in range(len(x)):
        vals = dict(zip(TABLE_FUNCTIONS, table.evaluate((QR[k], QJ[k]))))
        errs = [abs(vals["T"] / T[k] - 1.0), abs(float(wrap_angle(vals["W"] - W[k]))),
                abs(float(wrap_angle(vals["dphi"] - dphi[k], math.pi)))]
        w = 0.5 * vals["W"]
        for j, name in enumerate(("QR", "QJ")):
            c0, c1, s1 = (vals[f"k{name}_{h}"] for h in ("c0", "c1", "s1"))
            scale = float(np.max(np.abs(resp[j, k])))
            back = (c0, c1 * math.cos(w) + s1 * math.sin(w), -c1 * math.sin(w) + s1 * math.cos(w))
            errs += [abs(b - a) / scale for b, a in zip(back, resp[j, k])]
        worst = float(np.max([worst, *errs]))  # a NaN propagates (max() would drop it)
    return float(worst)


def build_region_table(body: Body, E: float, *, axis: str = "auto", nu: int | None = None, nv: int | None = None,
                       delta_min: float = DELTA_MIN_DEFAULT, tip_fraction: float = 0.8,
                       progress: bool | None = None, workers: int = 1) -> SlowMapTable:
    """Tabulate the reversible first-order slow map of (body, E) over the region of oscillation.

    Parameters
    ----------
    body : Body
        Its symmetric part is used (the tables do not depend on ε).
    E : float
        The energy, > 0 (exact, conserved: the energy of the asymmetric body's start).
    axis : {"auto", "spindle", "band"}
        The chart: along Q_J,0^crit over the whole region ("spindle"), or along Q_J,π^crit over the band about it
        whose stretch follows the layer of W ("band", the one accurate at high amplitude); "auto": ``region_axis``.
    nu, nv : int, optional
        Chebyshev nodes along and across the chart's line (even, ≥ 4); default ``DEFAULT_GRID[axis]``.
    delta_min : float
        Least distance (E − min U)/E to steady rolling covered, in ``DELTA_MIN_RANGE``.
    tip_fraction : float
        Part of the spindle's half-length covered along the critical line, in ``TIP_FRACTION_RANGE``.
    progress : bool or None
        A tqdm bar on stderr over the nodes (one variational orbit each), naming the table and showing the time
        left; None: only if stderr is a terminal.
    workers : int
        Processes that share the nodes, 1 ≤ workers ≤ ``parallel.MAX_PROCESSES``; the table does not depend on it.  More
        than one starts a pool of "spawn" processes, which import the calling script: a script that asks for
        workers must guard its top level with ``if __name__ == "__main__":`` (the ``rocknroller`` command does).
    """
    body.require_gravity("the averaged slow map (its region tables)")
    workers = check_processes(workers, "workers")
    frame = region_frame(body, E, axis=axis, nu=nu, nv=nv, delta_min=delta_min, tip_fraction=tip_fraction)
    QR, QJ = frame.nodes()
    nu, nv = frame.coef.shape[1:]
    try:
        T, W, dphi, resp = _orbit_data(body.symmetric(), frame.E0, QR, QJ, progress, workers)
    except NoMotionError as exc:  # pragma: no cover - the chart lies inside the level set δ = delta_min
        raise AveragingRangeError(str(exc)) from None
    return fit_and_check(frame, T, W, dphi, resp, region_interpolation_error, REGION_TABLE_ACCURACY,
                         f"the region tables of E={E!r} interpolate the coefficients only to {{err:.1e}}: "
                         + accuracy_cause(frame))


#: Release angle below which the default spindle grid interpolates worse than ``REGION_TABLE_ACCURACY`` (paper body,
#: measured: 2.3e-7 at 0.007π, 3.6e-7 at 0.006π, 2.5e-6 at 0.005π, 4.5e-6 at 0.004π; docs/averaging.md, "Starts with
#: velocity").
SMALL_AMPLITUDE_THETA0 = 0.006 * math.pi


def accuracy_cause(table: SlowMapTable) -> str:
    """Why a region table may interpolate worse than ``REGION_TABLE_ACCURACY``, and what to change, by its chart:
    the spindle's grid does not resolve the coefficients towards its tips (the sleeping top, where they are not
    analytic), which matters at small amplitude; the band's does not resolve the layer of W across Q_J,π^crit."""
    nu, nv = table.coef.shape[1:]
    nodes = f"more nodes (nu, nv: now {nu}, {nv}; rocknroller slow --nodes)"
    if table_chart(table) == "band":
        return (f"on the band chart (along Q_J,pi^crit) the grid does not resolve the layer in which the spin advance "
                f"W turns by 2 pi across that line; use {nodes} (docs/slow_validation.md, 'Band chart')")
    small = SMALL_AMPLITUDE_THETA0 / math.pi
    amplitude = (f", the more so at small amplitude (this is the energy of a release from rest at theta0 = "
                 f"{table.theta0 / math.pi:.3g}pi: the default grid falls short below ~{small:g}pi)"
                 if table.theta0 < SMALL_AMPLITUDE_THETA0 else "")
    return (f"on the spindle chart (along Q_J,0^crit) the grid does not resolve the coefficients towards the spindle's "
            f"tips, the sleeping top, where they are not analytic{amplitude}; use a smaller tip_fraction (the part of "
            f"the way to the tips the chart covers, default 0.8; API) or {nodes} (docs/averaging.md, 'Starts with "
            "velocity')")


def load_or_build_region_table(body: Body, E: float, *, build: bool = True, use_cache: bool = True,
                               **grid) -> SlowMapTable:
    """The region tables of (body, E): from memory, from the disk cache, or built (and cached), as
    :func:`rocknroller.analysis.slow.prediction.load_or_build_table` does for a release; ``grid``: the options of
    :func:`build_region_table`."""
    E = check_below_top(body, E)
    axis, nu, nv = region_options(body, E, grid.pop("axis", "auto"), grid.pop("nu", None), grid.pop("nv", None))
    return cached_table(build_region_table, body, E, f"E={E!r}", build=build, use_cache=use_cache, axis=axis, nu=nu,
                        nv=nv, **grid)


def region_table_cached(body: Body, E: float) -> bool:
    """Whether the default region tables of (body, E) are in memory or the disk cache (not read: for estimating the
    work of a call before it starts)."""
    E = check_below_top(body, E)
    axis, nu, nv = region_options(body, E)
    return is_cached(build_region_table, body, E, axis=axis, nu=nu, nv=nv)
