"""The turning points of θ in a stretch of a run: the events of dγ3/dt = 0, checked and located on the dense output.

A start with θ̇0 = 0 to its rounding is a turning point of its own, not reported (:func:`start_turning_point`).  The
integrator's events (heyoka locates them on the Taylor polynomial of dγ3/dt, scipy on its dense output) are checked
against the sign of dγ3/dt halfway to their neighbours on the stretch's dense output, where the check fails that
interval is rescanned, and every root is located by a safeguarded Newton iteration (:func:`_turning_points`); a sign
within the event function's rounding counts as 0.  Used by :func:`rocknroller.numerics.integrate.simulate`.  The dense
output of several lanes is evaluated together (:func:`lane_states`), here and by the unwrapping of φ and ψ
(:mod:`rocknroller.numerics.trajectory`).
"""

from __future__ import annotations

from typing import Callable, NamedTuple, Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import Body, LoadedSphere
from rocknroller.analysis.model.equations import body_frame_rhs, turning_point_function

__all__ = ["START_ROOT_ULPS", "StartRoot", "start_turning_point", "H_ROUND_ULPS", "THETA_MIN", "lane_states"]

#: Dense output of one run: times (m,) to states (m, 11).
DenseOutput = Callable[[NDArray[np.float64]], NDArray[np.float64]]


@runtime_checkable
class _PointDense(Protocol):
    """A dense output of several lanes that evaluates (time, lane) pairs and unwraps φ and ψ itself
    (numerics/ensembles/batch.py)."""

    def points(self, t: NDArray[np.float64], col: NDArray[np.intp]) -> NDArray[np.float64]:
        """The states (m, 11) at times ``t`` (m,) of lanes ``col`` (m,)."""

    def unwrap(self, t: NDArray[np.float64], col: NDArray[np.intp], fine: NDArray[np.float64], limit: float,
               max_bisections: int, shortest: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The states (m, 11) at times ``t`` (m,) of lanes ``col`` (m,), each lane's together and in time order, and
        the whole turns (2, m) of φ and ψ since each lane's first, refined and counted as
        ``trajectory._unwrapped_angles`` does with these arguments (``_dense.c``'s ``turns``)."""


#: Dense output of lanes: times (rows, W), one column per lane, to states (rows, 11, W); or a ``_PointDense``.
LaneDense = Callable[[NDArray[np.float64]], NDArray[np.float64]] | _PointDense


def lane_states(dense: LaneDense, t: NDArray[np.float64], lane: NDArray[np.intp], columns: ArrayLike,
                fill: ArrayLike) -> NDArray[np.float64]:
    """The states (m, 11) at times ``t`` (m,) of lanes ``lane`` (m,), evaluated together: lane j is column
    ``columns[j]`` of ``dense``, the other columns at their ``fill`` times; the k-th time of a lane goes in row k."""
    lane = np.asarray(lane, np.intp)
    if lane.size == 0:
        return np.empty((0, 11))
    if isinstance(dense, _PointDense):
        return dense.points(t, np.asarray(columns, np.intp)[lane])
    order = np.argsort(lane, kind="stable")  # row of each time: its rank among its lane's
    rank = np.empty_like(order)
    rank[order] = np.arange(order.size) - np.searchsorted(lane[order], lane[order], "left")
    cols = np.asarray(columns, np.intp)[lane]
    grid = np.repeat(np.asarray(fill, float)[None, :], int(rank.max()) + 1, axis=0)
    grid[rank, cols] = t
    return np.asarray(dense(grid))[rank, :, cols]

#: Unit round-off of double precision, u = 2⁻⁵³.
_U = float(np.finfo(float).eps) / 2.0
#: Smallest amplitude of θ at which the turning points are resolved (2¹⁰ u ≈ 1.1e-13 rad).  The integrator keeps
#: its state to an absolute error of about u per step: its tolerance applies to max(1, ‖y‖∞), and the unit vectors
#: γ and e_X make ‖y‖∞ ≈ 1.  Near the pole the tilt lives in γ1, γ2 ≈ θ, so the turning points, the roots of
#: dγ3/dt = γ1 ω2 − γ2 ω1 ≈ −θ θ̇ (whose terms are of order θ_X² Ω), and every quantity sampled there carry a
#: relative error ≈ u/θ_X (their times ≈ u/(θ_X Ω)); at θ_X ≥ 2¹⁰ u this is ≤ 2⁻¹⁰ ≈ 1e-3.  Measured on 60 time
#: units from rest against 80-bit extended precision: time errors 6.6e-18/θ0 (6.6e-8 at θ0 = 1e-10, 1.5e-6 at
#: 1e-13, 3.5e-4 at 1e-14), θ at the maxima to 5e-5 of θ0 at 1e-13.  (γ3 = cos θ rounds to 1 below θ ≈ 1.5e-8,
#: but dγ3/dt is computed from γ1, γ2 and ω, which keep their relative precision.)
THETA_MIN = 1024.0 * _U


#: A start is itself a turning point of θ (θ̇0 = 0 to its rounding) when |h0| ≤ START_ROOT_ULPS · u ·
#: (|γ1 ω2| + |γ2 ω1|), h = dγ3/dt = γ1 ω2 − γ2 ω1.  Derivation: from Euler rates with θ̇0 = 0,
#: ``omega_from_rates`` gives ω1 = fl(γ1 φ̇), ω2 = fl(γ2 φ̇) from the same rounded γ1 = fl(s sin ψ), γ2 = fl(s cos ψ),
#: so each product γ1 ω2, γ2 ω1 is γ1 γ2 φ̇ with two roundings and h0 = fl(difference) ≤ 2 γ_2 |γ1 γ2 φ̇| ≈
#: 2 u (|γ1 ω2| + |γ2 ω1|); × 4 (margin, which also covers a start whose ω was given to a few ulps).
#: ``rocknroller.analysis.slow.map.family.first_maximum`` classifies a start by the same bound.
START_ROOT_ULPS = 8.0


class StartRoot(NamedTuple):
    """A start that is itself a turning point of θ (:func:`start_turning_point`)."""

    kind: int
    """+1 a maximum (dγ3/dt rising through 0), −1 a minimum, 0 neither to first order (d²γ3/dt² = 0 too)."""
    window: float
    """Roots of dγ3/dt in (0, window] with direction ``kind`` are the start's own, not reported."""


def _h_and_rate(y: NDArray[np.float64], params: tuple[float, ...]) -> tuple[NDArray, NDArray]:
    """h = dγ3/dt and dh/dt = γ̇1 ω2 + γ1 ω̇2 − γ̇2 ω1 − γ2 ω̇1 at states ``y`` of shape (11, ...) (exact: h is
    bilinear in γ and ω)."""
    f = body_frame_rhs(y, params)
    return turning_point_function(y), f[0] * y[4] + y[0] * f[4] - f[1] * y[3] - y[1] * f[3]


def start_turning_point(body: Body | LoadedSphere, y0: ArrayLike) -> StartRoot | None:
    """Whether a start is itself a turning point of θ (θ̇0 = 0 to its rounding, ``START_ROOT_ULPS``), and of which kind.

    Such a start is not reported as a turning point (:func:`simulate`): the root of dγ3/dt that its rounding puts
    at t = ±1e-17 or so is the start's own.

    Parameters
    ----------
    body : Body
    y0 : array (11,)
        The initial body-frame state.

    Returns
    -------
    StartRoot or None
        None if the start is not a turning point.  Otherwise its kind (the sign of d²γ3/dt²) and the window after
        t = 0 in which the integrator may place the start's own root: the root of h0 + ḣ0 t lies within
        |h0|/|ḣ0| ≤ B/|ḣ0| of the start (B the bound above), and the integrator evaluates h0 with another rounding
        (≤ B/4); × 4 (margin, and the curvature of h over so short a time) gives 4 B/|ḣ0|.
    """
    y0 = np.asarray(y0, float)
    bound = START_ROOT_ULPS * _U * (abs(y0[0] * y0[4]) + abs(y0[1] * y0[3]))
    h0, rate = (float(v) for v in _h_and_rate(y0, body.params))
    if not abs(h0) <= bound:
        return None
    kind = int(np.sign(rate))
    return StartRoot(kind, 4.0 * bound / abs(rate) if kind else 0.0)


#: Most points of a grid on which dγ3/dt is scanned for the roots in one interval (a refinement step past it fails).
_MAX_SCAN = 2**18


#: Most iterations of the safeguarded Newton method that locates a root of dγ3/dt in its bracket (Newton takes 1 to 3
#: from the integrator's event; bisection alone, log2(width/(4 u t)): 53 for a bracket of a few time units at t ≈ 1).
_MAX_POLISH = 100


#: dγ3/dt from a dense-output state is resolved (its sign known) where |h| > H_ROUND_ULPS · u · (|γ1| + |γ2|)
#: (|ω1| + |ω2|).  Derivation: each component is a Taylor polynomial of order p = 20 evaluated by Horner's rule, which
#: rounds by ≤ γ_2p Σ|c_k Δ^k| ≈ 2p u × the component's scale (|γ1| + |γ2| for γ1, γ2, the scale of the tilt; the
#: same for ω), so each product in h = γ1 ω2 − γ2 ω1 carries ≤ (4p + 1) u of (|γ1| + |γ2|)(|ω1| + |ω2|) and h twice
#: that, 162 u; × 4 (margin).  Below it the sign is round-off: steady rolling, θ constant to the last digits, has no
#: turning points (the integrator reported a dozen per 50 time units there).
H_ROUND_ULPS = 648.0


def _resolved_sign(y: NDArray[np.float64]) -> NDArray[np.int_]:
    """The sign of dγ3/dt at states ``y`` (shape (11, N)), 0 where it is round-off (``H_ROUND_ULPS``)."""
    h = turning_point_function(y)
    noise = H_ROUND_ULPS * _U * (np.abs(y[0]) + np.abs(y[1])) * (np.abs(y[3]) + np.abs(y[4]))
    return np.where(np.abs(h) > noise, np.sign(h), 0.0).astype(int)


def _sign_changes(t: NDArray[np.float64], s: NDArray[np.int_]) -> tuple[NDArray, NDArray, NDArray]:
    """Brackets (lo, hi) and directions of the changes of the signs ``s`` sampled at ``t``, zeros skipped."""
    nz = np.flatnonzero(s)
    i = np.flatnonzero(s[nz][1:] != s[nz][:-1])
    return t[nz[i]], t[nz[i + 1]], s[nz[i + 1]]


def _scan(lo: float, hi: float, dense: DenseOutput) -> tuple[NDArray, NDArray, NDArray]:
    """Every sign change of dγ3/dt in (lo, hi) on the dense output: grids of 64, 1024, ... points until two
    successive ones find the same number (roots are spaced by a fraction of a rocking period, far above the
    grid spacing at which the count settles)."""
    found, n = None, 64
    while True:
        t = np.linspace(lo, hi, n + 1)
        brackets = _sign_changes(t, _resolved_sign(dense(t).T))
        if found is not None and brackets[0].size == found[0].size:
            return brackets
        if n >= _MAX_SCAN:
            raise RuntimeError(f"could not resolve the turning points of theta in ({lo!r}, {hi!r}) on {n} points")
        found, n = brackets, 16 * n


def _locate(lo: NDArray, hi: NDArray, d: NDArray, guess: NDArray, lane: NDArray, dense: LaneDense, columns: list[int],
            fill: NDArray, params: NDArray) -> NDArray[np.float64]:
    """The roots of dγ3/dt in the brackets (lo, hi) of lanes ``lane`` (as :func:`lane_states`), where it changes sign
    in direction d, on the dense output: Newton's method from ``guess``, kept inside the shrinking bracket by
    bisection, to the rounding of t; every lane's roots together.  ``params``: each lane's (a, I1, I2, I3, g), (L, 5).
    """
    lo, hi, t = lo.astype(float), hi.astype(float), np.clip(guess, lo, hi).astype(float)
    active = np.arange(t.size)
    for _ in range(_MAX_POLISH):
        if active.size == 0:
            break
        ta, da = t[active], d[active]
        h, rate = _h_and_rate(lane_states(dense, ta, lane[active], columns, fill).T, tuple(params[lane[active]].T))
        below = da * h < 0  # before the root
        lo[active] = np.where(below, ta, lo[active])
        hi[active] = np.where(da * h > 0, ta, hi[active])
        with np.errstate(divide="ignore", invalid="ignore"):
            newton = ta - h / rate
        inside = (newton >= lo[active]) & (newton <= hi[active])  # False for a NaN or infinite step
        new = np.where(h == 0.0, ta, np.where(inside, newton, 0.5 * (lo[active] + hi[active])))
        t[active] = new
        tol = 4.0 * _U * np.abs(ta)
        done = (h == 0.0) | (inside & (np.abs(new - ta) <= tol)) | (hi[active] - lo[active] <= tol)
        active = active[~done]
    return t


def _turning_points(raw: list[tuple[float, int]], t_a: float, t_b: float, dense: DenseOutput,
                    params: tuple[float, ...], start: StartRoot | None) -> list[tuple[float, int]]:
    """The turning points of θ in (t_a, t_b] as (time, direction), from the integrator's events checked and located
    on the dense output: :func:`_turning_points_lanes` for one lane."""
    return _turning_points_lanes([raw], [t_a], [t_b], lambda times: dense(times[:, 0])[:, :, None], [0],
                                 np.array([t_b]), [params], [start])[0]


def _turning_points_lanes(raws: list[ArrayLike], t_a: list[float], t_b: list[float], dense: LaneDense,
                          columns: list[int], fill: NDArray[np.float64], params: list[tuple[float, ...]],
                          starts: list[StartRoot | None]) -> list[list[tuple[float, int]]]:
    """The turning points of θ in (t_a[j], t_b[j]] of each lane j as (time, direction), from the integrator's events
    ``raws[j]`` (pairs (time, direction), in any order) checked and located on the dense output (lane j in column
    ``columns[j]`` of ``dense``, the other columns at their ``fill`` times; every lane's evaluations together).

    The integrator finds the roots of dγ3/dt on the Taylor polynomial of the event function, truncated at the
    integrator's order.  dγ3/dt ≈ −θ θ̇ is a product of two series of the motion's frequency, so near the pole
    (tilt θ_X ≪ 1) it varies twice as fast as the state and its truncated series errs, relative to its size, by
    ≈ 2^(p+2) e^(−2(p+1))/θ_X (order p = 20 in double: ≈ 2.4e-12/θ_X; measured 4.9e-4 time units at θ_X = 1e-9,
    the root at the far end of a step): roots near the end of a step are then misplaced, or reported twice, or
    missed, across two steps (one in 10⁵ at θ_X = 1e-8).  The dense output evaluates the state's own series, as
    accurate as the state.  So each event is checked against the sign of dγ3/dt on the dense output half way to
    its neighbours (and at the ends of the stretch), and located there by a safeguarded Newton method; an
    interval where the check fails is scanned on the dense output for its sign changes.  A root at t_a belongs to
    the previous stretch; at the start of the run, the start's own root (``start``) to no one.
    """
    n_lanes = len(raws)
    raw = [np.asarray(r, float).reshape(-1, 2) for r in raws]
    ev_lane = np.repeat(np.arange(n_lanes), [r.shape[0] for r in raw])
    t_ev, d_ev = (np.concatenate([r[:, i] for r in raw]) for i in (0, 1))
    d_ev = d_ev.astype(int)
    lo_edge, kind = np.array(t_a, float), np.zeros(n_lanes, int)
    has_start = np.array([start is not None for start in starts], bool)
    for j, start in enumerate(starts):
        if start is not None:
            lo_edge[j], kind[j] = t_a[j] + start.window, start.kind
    own = (t_ev <= np.asarray(t_a, float)[ev_lane]) | ((t_ev <= lo_edge[ev_lane]) & (d_ev == kind[ev_lane])
                                                       & has_start[ev_lane])
    order = np.lexsort((d_ev[~own], t_ev[~own], ev_lane[~own]))  # by lane, time, then direction
    times, dirs, ev_lane = t_ev[~own][order], d_ev[~own][order], ev_lane[~own][order]
    # each lane's checks: its start (after the start's own root), half way between its events, its end; lane j's
    # come after those of the lanes before it, max(n_j, 1) + 1 of them, and its i-th event lies between its checks
    # i and i + 1
    n_ev = np.bincount(ev_lane, minlength=n_lanes)
    first_check = np.concatenate([[0], np.cumsum(np.maximum(n_ev, 1) + 1)])
    left = first_check[ev_lane] + np.arange(times.size) - np.concatenate([[0], np.cumsum(n_ev)])[ev_lane]
    checks = np.empty(first_check[-1])
    checks[first_check[:-1]] = lo_edge
    checks[first_check[1:] - 1] = t_b
    inner = np.flatnonzero(ev_lane[1:] == ev_lane[:-1]) + 1  # events after another of their lane
    checks[left[inner]] = 0.5 * (times[inner] + times[inner - 1])
    check_lane = np.repeat(np.arange(n_lanes), np.diff(first_check))
    signs = _resolved_sign(lane_states(dense, checks, check_lane, columns, fill).T)
    signs[first_check[:-1][has_start]] = kind[has_start]  # dγ3/dt at a start is round-off: after its root, the kind
    ok = (signs[left] == -dirs) & (signs[left + 1] == dirs)
    # brackets (lo, hi, direction, first guess, lane): the checked events', then those of each run of neighbouring
    # failed checks, scanned as one interval (without events: the whole stretch, if dγ3/dt changes sign over it)
    parts = [(checks[left][ok], checks[left + 1][ok], dirs[ok], times[ok], ev_lane[ok])]
    bad = np.zeros(checks.size - 1, bool)  # interval (checks[i], checks[i + 1]) to scan (never across lanes)
    bad[left[~ok]] = True
    empty = np.flatnonzero(n_ev == 0)
    bad[first_check[empty]] = signs[first_check[empty]] != signs[first_check[empty] + 1]
    runs = np.flatnonzero(np.diff(np.concatenate([[0], bad.astype(np.int8), [0]])))
    for i, k in zip(runs[::2], runs[1::2]):
        j = int(check_lane[i])

        def lane_dense(t: NDArray[np.float64], j: int = j) -> NDArray[np.float64]:
            return lane_states(dense, t, np.full(np.size(t), j), columns, fill)

        s_lo, s_hi, s_d = _scan(checks[i], checks[k], lane_dense)
        parts.append((s_lo, s_hi, s_d, 0.5 * (s_lo + s_hi), np.full(s_lo.size, j)))
    lo, hi, d, guess, lane = (np.concatenate(column) for column in zip(*parts))
    roots = _locate(lo, hi, d, guess, lane.astype(np.intp), dense, columns, fill, np.asarray(params, float))
    order = np.lexsort((roots, lane))  # stable: each lane's roots in time order
    ends = np.searchsorted(lane[order], np.arange(n_lanes + 1))
    pairs = list(zip(roots[order].tolist(), d[order].astype(int).tolist()))
    return [pairs[a:b] for a, b in zip(ends[:-1], ends[1:])]
