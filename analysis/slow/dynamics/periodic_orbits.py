"""Periodic orbits of the one-step map near pure rocking and their bifurcation: the rocking fixed points about
either principal axis and, past the period doubling, the period-2 orbit, on the averaged slow map
(:func:`rocknroller.analysis.slow.map.compiled_map.iterate_slow_map`) and on the exact one-step map
(:func:`rocknroller.analysis.slow.map.exact_step.exact_step`), found by Newton's method (:func:`periodic_orbit`,
:class:`PeriodicOrbit`) and continued in ε (:func:`continue_orbit`, :class:`Branch`), with their multipliers and
Greene's residue.

The map.  At the energy E of the release from rest at θ0 a maximum of θ is (Q_R, Q_J, Θ = 2ψ): the map is
three-dimensional (E is fixed by the release and is not a variable; the package knows no other invariant of the
asymmetric body), written here in
the release table's chart x = (u, v, Θ), Q = u e + v n (e the kick direction at Q = 0, n across it; the slow orbits
stay within |v| ≲ 6e-4 |u|).  It is not area-preserving but has two symmetries, checked on both maps to round-off:

* time reversal R: (Q, Θ) → (−Q, Θ) is a reversor (R F R = F⁻¹; docs/averaging.md, "Reversible drift–kick–drift");
* the reflection of the body in a principal plane S: (Q, Θ) → (−Q, −Θ) commutes with the map (F S = S F).

Hence the multipliers of an orbit symmetric under R come in pairs (λ, 1/λ), and in three dimensions one of them is
1: {1, λ, 1/λ}.  The 1 is the direction of a one-parameter family of such orbits (the second reversor R S:
Θ → −Θ has a two-dimensional fixed set), across the kick direction.  The "area-preserving 2-d reduction" is the pair
(λ, 1/λ): the map's linearisation transverse to the family, the standard map's Jacobian near Q = 0.  Greene's residue
of an orbit of period p with M = D(Fᵖ) is therefore R = (2 − (λ + 1/λ))/4 = (3 − tr M)/4: the orbit is stable
(elliptic) for 0 < R < 1, R passes 1 where the pair reaches −1 (period doubling) and 0 where it reaches +1.

The orbits.  The rocking fixed points (0, 0, Θ*), Θ* = 0 (about the i axis) or π (about j), are invariant under S;
the period-2 orbit born at the period doubling of the stable one is carried into itself by S: its second point is
S of its first, F(x₁) = S x₁ (then F²(x₁) = F(S x₁) = S F(x₁) = x₁).  Both kinds are the zeros of

    G(x) = F(x) − S x      (Θ component wrapped to (−π, π]),

three equations in three unknowns, which Newton's method solves without the singular direction of F²(x) − x
(DG = DF + 1 is singular only where DF has the multiplier −1: at the period doubling itself).  Since DF(S x) = DF(x)
(S is −1 as a linear map), M = DF(x₁)² for the period-2 orbit.  The period-2 points lie on the fixed set of R S,
Θ = Θ* at the maxima, to round-off (it is not imposed): the points differ in Q, ±u along the kick direction.  The
standard map's angle, the phase at the kick of the drift–kick–drift split, ϑ = Θ + W(Q)/2 (W the symmetric body's
twist, from the release table), is π ± δ: the ordinate of the bifurcation diagram.  The standard map's δ,
K sin δ = 4δ (K = εκ), is not the map's even near the threshold K = 4 (the cubic term of W(Q) counts like that of
sin: δ = 0.102 against 0.173 at K = 4.02, 0.95π); the period-2 start is found on the line (u, 0, Θ*) instead
(:meth:`_Problem.start`).

The maps are :class:`rocknroller.analysis.slow.map.maps.SlowMap` and :class:`~rocknroller.analysis.slow.map.maps.ExactMap`;
their Jacobians (Newton's, and the multipliers) are the maps' exact tangents: the compiled kernel's tangent map of
the slow step, the variational equations of the direct ODE through the exact one.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import Body, float_or_nan
from rocknroller.analysis.model.diagnostics import wrap_angle
from rocknroller.analysis.slow.map.chart import TABLE_FUNCTIONS, SlowMapTable
from rocknroller.analysis.slow.map.limits import (K_PERIOD_DOUBLING, AveragingRangeError, default_order,
                                                  eps_period_doubling, stable_rocking_psi)
from rocknroller.analysis.slow.map.maps import EVALUATION_ULPS, ExactMap, SlowMap

if TYPE_CHECKING:
    import pandas

__all__ = ["MAPS", "K_MAX", "PeriodicOrbitError", "PeriodicOrbit", "periodic_orbit", "Branch", "continue_orbit",
           "greene_residue"]

#: The maps whose orbits are found: the averaged slow map (first order, or second with its table) and the exact
#: one-step map of the direct ODE.
MAPS = ("slow", "exact")
#: Largest K = εκ accepted: twice the period doubling, where the period-2 orbit still lies inside the release table
#: (|u| ≤ 0.24 U at 1.5 ε_pd, 0.9π and 0.95π; measured).  The first-order map's implicit kick may stop converging
#: before (on the period-2 orbit at 0.9π from K ≈ 6.6, measured; 0.95π reaches K_MAX): an AveragingRangeError says so.
K_MAX = 2.0 * K_PERIOD_DOUBLING
#: Newton's method: most iterations, and the residual ‖G‖∞ accepted: the maps' evaluation error
#: (:data:`rocknroller.analysis.slow.map.maps.EVALUATION_ULPS` ulp of 4π), the floor Newton can reach.
_NEWTON_ITERATIONS = 30
#: Most values of ε on a branch of :func:`continue_orbit` (each orbit costs 13–20 steps of the map).
MAX_BRANCH_POINTS = 2000
_RESIDUAL_ULPS = EVALUATION_ULPS
_ANGLE = 2
#: The scan for the period-2 start: u from 1e-4 to 1 times the table's half-width U (2.5 times the standard map's
#: libration at K = 4), geometrically.
_SCAN = (1e-4, 1.0, 64)


class PeriodicOrbitError(ValueError):
    """Newton's method did not converge to a periodic orbit of the asked period (a bad start, or a continuation
    step too large)."""


def greene_residue(M: NDArray[np.float64]) -> float:
    """Greene's residue of the pair (λ, 1/λ) of a 3 × 3 map Jacobian M whose third multiplier is 1 (module
    docstring): R = (3 − tr M)/4."""
    return float((3.0 - np.trace(M)) / 4.0)


@dataclass(frozen=True)
class PeriodicOrbit:
    """A periodic orbit of period 1 or 2 of one map at one ε, symmetric under S (module docstring).

    Attributes
    ----------
    map : ``"slow"`` or ``"exact"``.
    order : the slow map's order (1 or 2; 0 for the exact map).
    theta0, eps : the release angle (its energy) and the asymmetry.
    K : εκ.
    period : 1 or 2.
    points : ndarray (period, 3)
        (u, v, Θ) of the orbit's points at the maxima, in the release table's chart (Θ wrapped to [0, 2π)).
    Q : ndarray (period, 2)
        (Q_R, Q_J) of the points.
    kick_phase : ndarray (period,)
        ϑ = Θ + W(Q)/2 mod 2π in [−π/2, 3π/2), the standard map's angle (π ± δ for the period-2 orbit, 0 and π
        for the fixed points).
    multipliers : ndarray (3,) complex
        The eigenvalues of M = D(F^period).
    residue : Greene's residue (3 − tr M)/4.
    stable : 0 < residue < 1 (elliptic).
    residual : ‖G(x)‖∞ = ‖F(x) − S x‖∞ at the first point, what Newton's method solved.
    residual_bound : the residual it was asked for (``_RESIDUAL_ULPS`` ulp of 4π).
    periodicity : ‖F^period(x) − x‖∞ (Θ wrapped): ≤ (1 + ‖DF‖∞) ``residual`` for the period-2 orbit
        (F(x) = S x + g gives F²(x) = S F(x) + DF g = x + S g + DF g to first order in g = G(x)).
    iterations : Newton iterations taken.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> fixed = rr.periodic_orbit(rr.Body.paper(), 0.95 * math.pi, 0.005, period=1)
    >>> print(fixed.map, fixed.period, fixed.stable, fixed.points.shape)
    slow 1 True (1, 3)
    >>> print(fixed.residual <= fixed.residual_bound)
    True
    """

    map: str
    order: int
    theta0: float
    eps: float
    K: float
    period: int
    points: NDArray[np.float64]
    Q: NDArray[np.float64]
    kick_phase: NDArray[np.float64]
    multipliers: NDArray[np.complex128]
    residue: float
    stable: bool
    residual: float
    residual_bound: float
    periodicity: float
    iterations: int

    def to_dataframe(self) -> "pandas.DataFrame":
        """One row per point of the orbit: map, order, ε, K, the point's index, (u, v, Θ), Q_R, Q_J, the kick phase,
        and the orbit's residue and stability (needs pandas)."""
        from rocknroller.analysis.model.frames import dataframe

        n = self.period
        return dataframe({"map": [self.map] * n, "order": np.full(n, self.order), "eps": np.full(n, self.eps),
                          "K": np.full(n, self.K), "point": np.arange(n), "u": self.points[:, 0],
                          "v": self.points[:, 1], "Theta": self.points[:, 2], "QR": self.Q[:, 0], "QJ": self.Q[:, 1],
                          "kick_phase": self.kick_phase, "residue": np.full(n, self.residue),
                          "stable": np.full(n, self.stable)})

    def plot(self, ax: Any = None) -> Any:
        """Draw the orbit's points in the (Q_R, Q_J) plane on ``ax`` (a new pyplot figure without one; filled if
        stable), its period, ε and residue in the legend.  Returns the axes."""
        from rocknroller.analysis.slow.dynamics.result_plots import plot_periodic_orbit

        return plot_periodic_orbit(self, ax)


@dataclass(frozen=True)
class Branch:
    """A branch of periodic orbits continued in ε (:func:`continue_orbit`).

    Attributes
    ----------
    orbits : the orbits, in the order of ``eps``.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> branch = rr.continue_orbit(rr.Body.paper(), 0.95 * math.pi, [0.004, 0.006], period=1)
    >>> print(len(branch.orbits), [o.stable for o in branch.orbits])
    2 [True, True]
    """

    orbits: tuple[PeriodicOrbit, ...]

    @property
    def eps(self) -> NDArray[np.float64]:
        """ε of the orbits."""
        return np.array([o.eps for o in self.orbits])

    @property
    def residue(self) -> NDArray[np.float64]:
        """Greene's residues."""
        return np.array([o.residue for o in self.orbits])

    @property
    def stable(self) -> NDArray[np.bool_]:
        """Stability (0 < R < 1)."""
        return np.array([o.stable for o in self.orbits])

    @property
    def kick_phase(self) -> NDArray[np.float64]:
        """ϑ of the points, shape (len(orbits), period)."""
        return np.array([o.kick_phase for o in self.orbits])

    def to_dataframe(self) -> "pandas.DataFrame":
        """One row per point of every orbit, in the order of ε (:meth:`PeriodicOrbit.to_dataframe`; needs pandas)."""
        from rocknroller.analysis.model.frames import dataframe

        frames = [o.to_dataframe() for o in self.orbits]  # a clear ImportError without pandas
        if not frames:
            return dataframe({})
        import pandas as pd

        return pd.concat(frames, ignore_index=True)

    def plot(self, ax: Any = None, kind: str = "kick_phase", **kwargs: Any) -> Any:
        """Draw the branch against ε on ``ax`` (a new pyplot figure without one): ``"kick_phase"`` ϑ of each point
        or ``"residue"`` Greene's residue, solid where stable and dashed where not
        (:func:`rocknroller.analysis.slow.dynamics.result_plots.plot_branch`, which takes ``x_scale``, ``color`` and
        ``label``).  Returns the axes."""
        from rocknroller.analysis.slow.dynamics.result_plots import plot_branch

        return plot_branch(self, ax, kind, **kwargs)


class _Problem:
    """One map (:class:`rocknroller.analysis.slow.map.maps.SlowMap` or :class:`~rocknroller.analysis.slow.map.maps.ExactMap`)
    in the chart coordinates x = (u, v, Θ) of the release table of (body, θ0), at one ε: F_chart = Bᵀ F B with B the
    chart's rotation, and its Jacobian Bᵀ DF B (the map's exact tangent)."""

    def __init__(self, body: Body, theta0: float, eps: float, map: str, order: int | None, workers: int) -> None:
        from rocknroller.analysis.slow.map.tables_at_once import release_tables

        if map not in MAPS:
            raise ValueError(f"map must be one of {MAPS}, got map={map!r}")
        order = default_order(theta0) if order is None else order  # the one default: 2 on the release tables
        if order not in (1, 2) or isinstance(order, bool):
            raise ValueError(f"order must be 1 or 2, got order={order!r}")
        self.table: SlowMapTable = release_tables(body, theta0, 1)[0]
        self.theta0, self.map = float(theta0), map
        self.kappa = float(self.table.kappa)
        eps = float_or_nan(eps)
        e_max = K_MAX / abs(self.kappa)
        if not 0.0 < eps <= e_max:
            raise ValueError(f"eps must lie in (0, {e_max:.6g}] (K = eps*kappa <= K_MAX = {K_MAX:g}, kappa = "
                             f"{self.kappa:.6g} at theta0={theta0!r}), got eps={eps!r}")
        if eps >= body.I3 / body.I1 - 1.0:
            raise ValueError(f"eps must be below the largest the moments allow (I2 < I3: eps < "
                             f"{body.I3 / body.I1 - 1.0:.6g}), got eps={eps!r}")
        self.eps = eps
        self.e, self.n = np.asarray(self.table.e, float), np.asarray(self.table.n, float)
        self.B = np.eye(3)
        self.B[:2, 0], self.B[:2, 1] = self.e, self.n
        self.theta_star = 2.0 * stable_rocking_psi(self.kappa)
        self.order = 0 if map == "exact" else order
        self.F: SlowMap | ExactMap = (SlowMap(body, theta0, eps, order, workers=workers) if map == "slow"
                                      else ExactMap(body, theta0, eps))

    def Q(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        return x[0] * self.e + x[1] * self.n

    def step(self, x: NDArray[np.float64], failed: str = "raise") -> NDArray[np.float64]:
        """One step of the map from x = (u, v, Θ), or from each row of an array (N, 3) (the map's ``failed``); Θ
        continued from the start (within π of it).  Bᵀ F(B x) one row at a time (stacked matrix-vector products)."""
        y = self.F(np.matmul(self.B, x[..., None])[..., 0], failed=failed)
        return np.matmul(self.B.T, y[..., None])[..., 0]

    def G(self, x: NDArray[np.float64], failed: str = "raise") -> NDArray[np.float64]:
        """F(x) − S x, Θ wrapped (module docstring); of each row of an array (N, 3) (the map's ``failed``)."""
        d = self.step(x, failed) + x
        d[..., _ANGLE] = wrap_angle(d[..., _ANGLE])
        return d

    def jacobian(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """DF in the chart: Bᵀ DF(B x) B."""
        return self.B.T @ self.F.jacobian(self.B @ x) @ self.B

    def kick_phase(self, x: NDArray[np.float64]) -> float:
        W = float(self.table.evaluate(self.Q(x))[TABLE_FUNCTIONS.index("W")])
        return float(np.mod(x[2] + 0.5 * W + 0.5 * math.pi, 2.0 * math.pi) - 0.5 * math.pi)

    def start(self, period: int, theta_star: float) -> NDArray[np.float64]:
        """The start of Newton's method: the fixed point itself, or for the period-2 orbit the first u > 0 of the
        scan ``_SCAN`` on the line (u, 0, Θ*) where h(u) = u' + u changes sign (F(x) = S x has u' = −u; near the
        fixed point h ≈ (J_uu + 1) u), refined by Brent's method."""
        from scipy.optimize import brentq

        if period == 1:
            return np.array([0.0, 0.0, theta_star])
        K = self.eps * abs(self.kappa)
        if K <= K_PERIOD_DOUBLING:
            raise ValueError(f"no period-2 orbit at K = eps*kappa = {K:.6g} <= {K_PERIOD_DOUBLING:g} (eps={self.eps!r}"
                             f" <= 4/kappa = {eps_period_doubling(self.kappa):.6g}) to first order: give a start")

        def h(u: float) -> float:
            return float(self.G(np.array([u, 0.0, theta_star]))[0])

        us = float(self.table.U) * np.geomspace(_SCAN[0], _SCAN[1], _SCAN[2])
        # the slow map scans the line in one array call (the same values, ~5x faster: benchmarks/bench_map_arrays.py;
        # NaN where a step leaves the table, evaluated alone to raise its error); the exact map's steps cost the same
        # either way, so it runs no more of them than the scan needs
        line = np.column_stack([us, np.zeros_like(us), np.full_like(us, theta_star)])
        hs = self.G(line, failed="nan")[:, 0] if self.map == "slow" else np.full_like(us, np.nan)
        prev = h(float(us[0])) if math.isnan(hs[0]) else float(hs[0])
        for a, b, cur in zip(us[:-1], us[1:], hs[1:].tolist()):
            try:
                cur = h(float(b)) if math.isnan(cur) else cur
            except AveragingRangeError:
                break
            if prev * cur <= 0.0:
                return np.array([brentq(h, a, b, xtol=1e-12 * float(b)), 0.0, theta_star])
            prev = cur
        raise PeriodicOrbitError(f"no period-2 orbit found on the line (u, 0, Theta*) of the {self.map} map at "
                                 f"eps={self.eps!r} (u' + u keeps its sign from {us[0]:.3g} to the table's end): give "
                                 "a start")


def _reflect(x: NDArray[np.float64]) -> NDArray[np.float64]:
    """S x = (−u, −v, −Θ), Θ in [0, 2π)."""
    return np.array([-x[0], -x[1], float(np.mod(-x[_ANGLE], 2.0 * math.pi))])


def _newton(problem: _Problem, x: NDArray[np.float64], tol: float) -> tuple[NDArray[np.float64], int]:
    """A zero of G from x: Newton with the Jacobian DG = DF + 1 (the map's exact tangent), halving a step that does not
    decrease ‖G‖∞ or leaves the slow map's table."""
    g = problem.G(x)
    r = float(np.max(np.abs(g)))
    for k in range(_NEWTON_ITERATIONS):
        if r <= tol:
            return x, k
        dx = np.linalg.solve(problem.jacobian(x) + np.eye(3), -g)
        for _ in range(30):
            x1 = x + dx
            try:
                g1 = problem.G(x1)
            except AveragingRangeError:  # the trial left the slow map's table: a shorter step
                dx = 0.5 * dx
                continue
            r1 = float(np.max(np.abs(g1)))
            if r1 < r:
                break
            dx = 0.5 * dx
        else:
            break
        x, g, r = x1, g1, r1
    if r <= tol:
        return x, _NEWTON_ITERATIONS
    raise PeriodicOrbitError(f"Newton's method did not reach the residual {tol:.3g} on the {problem.map} map at "
                             f"eps={problem.eps!r}, theta0={problem.theta0!r} (last |F(x) - S x| = {r:.3g} at "
                             f"x=(u, v, Theta)={tuple(float(c) for c in x)}): start nearer (smaller continuation steps)")


def _orbit(problem: _Problem, x: NDArray[np.float64], period: int, iterations: int, tol: float) -> PeriodicOrbit:
    x = np.array(x, float)
    x[_ANGLE] = float(np.mod(x[_ANGLE], 2.0 * math.pi))
    J = problem.jacobian(x)
    M = J if period == 1 else J @ J
    pts = np.array([x] if period == 1 else [x, _reflect(x)])
    y = x
    for _ in range(period):
        y = problem.step(y)
    d = y - x
    d[_ANGLE] = float(wrap_angle(d[_ANGLE]))
    R = greene_residue(M)
    return PeriodicOrbit(map=problem.map, order=problem.order, theta0=problem.theta0, eps=problem.eps,
                         K=problem.eps * problem.kappa, period=period, points=pts,
                         Q=np.array([problem.Q(p) for p in pts]),
                         kick_phase=np.array([problem.kick_phase(p) for p in pts]),
                         multipliers=np.linalg.eigvals(M).astype(complex), residue=R, stable=bool(0.0 < R < 1.0),
                         residual=float(np.max(np.abs(problem.G(x)))), residual_bound=tol,
                         periodicity=float(np.max(np.abs(d))), iterations=iterations)


def periodic_orbit(body: Body, theta0: float, eps: float, period: int = 2, *, map: str = "slow", order: int | None = None,
                   axis: str = "stable", start: Sequence[float] | None = None, workers: int = 1) -> PeriodicOrbit:
    """The S-symmetric periodic orbit of ``period`` (1: pure rocking; 2: the orbit born at its period doubling) of the
    ``map`` of (body with I2 = (1 + ε) I1, the energy of the release from rest at θ0), by Newton's method on
    G(x) = F(x) − S x (module docstring).

    Parameters
    ----------
    body : any member of the family (its a, I1, I3, g are used).
    theta0 : the release angle in ``THETA0_RANGE`` (its release table is built and cached if needed).
    eps : ε in (0, K_MAX/κ], below I3/I1 − 1.
    period : 1 or 2.
    map : ``"slow"`` (the averaged map of ``order``) or ``"exact"`` (the direct ODE, one exact step per evaluation).
    order : 1 or 2, of the slow map (2 needs the second-order table, built by ``workers`` processes and cached);
        default :func:`~rocknroller.analysis.slow.map.limits.default_order`, 2 on the release tables.
    axis : ``"stable"`` or ``"unstable"``: the rocking axis the orbit is about (Θ* = 2ψ_s or 2ψ_s + π; the period-2
        orbit exists about the stable one only).
    start : (u, v, Θ) to start from (default: the first-order point, module docstring).

    Raises
    ------
    ValueError
        A parameter out of its range, naming it; or no period-2 orbit to first order and no ``start``.
    PeriodicOrbitError
        Newton's method did not converge, or converged to the fixed point when asked for the period-2 orbit.
    AveragingRangeError
        The slow map's iteration left its table.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> orbit = rr.periodic_orbit(rr.Body.paper(), 0.95 * math.pi, 0.01, period=2)
    >>> print(orbit.period, orbit.stable, f"residue = {orbit.residue:.4f}")
    2 True residue = 0.4206
    """
    if period not in (1, 2) or isinstance(period, bool):
        raise ValueError(f"period must be 1 or 2, got period={period!r}")
    if axis not in ("stable", "unstable"):
        raise ValueError(f"axis must be 'stable' or 'unstable', got axis={axis!r}")
    if period == 2 and axis == "unstable":
        raise ValueError("the period-2 orbit is born at the period doubling of the stable rocking: axis='stable'")
    problem = _Problem(body, theta0, eps, map, order, workers)
    theta_star = problem.theta_star if axis == "stable" else float(np.mod(problem.theta_star + math.pi, 2 * math.pi))
    x0 = problem.start(period, theta_star) if start is None else np.asarray(start, float)
    if x0.shape != (3,) or not np.all(np.isfinite(x0)):
        raise ValueError(f"start must be three finite numbers (u, v, Theta), got start={start!r}")
    tol = _RESIDUAL_ULPS * np.finfo(float).eps * 4.0 * math.pi
    x, k = _newton(problem, x0, tol)
    orbit = _orbit(problem, x, period, k, tol)
    if period == 2 and float(np.max(np.abs(problem.step(x) - x))) < 1e3 * tol:
        raise PeriodicOrbitError(f"Newton's method converged to the fixed point, not a period-2 orbit, at eps={eps!r} "
                                 f"on the {map} map: start farther from it (K = {orbit.K:.6g})")
    return orbit


def continue_orbit(body: Body, theta0: float, eps_values: ArrayLike, period: int = 2, *, map: str = "slow",
                   order: int | None = None, axis: str = "stable", start: Sequence[float] | None = None,
                   workers: int = 1) -> Branch:
    """Natural-parameter continuation in ε: the orbit of :func:`periodic_orbit` at each of ``eps_values`` in turn,
    started from the secant through the previous two solutions (the first from ``start`` or the default start, the
    second from the first).  Where Newton's method fails from there (near the period doubling the branch grows like
    √(ε − ε_pd), and the fixed point also solves G = 0; or the prediction leaves the slow map's table), the default
    start is tried before giving up.

    Raises
    ------
    ValueError
        ``eps_values`` empty, longer than ``MAX_BRANCH_POINTS``, or not strictly monotonic; the errors of
        :func:`periodic_orbit`.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> branch = rr.continue_orbit(rr.Body.paper(), 0.95 * math.pi, [0.0095, 0.0100, 0.0105])
    >>> print([f"{o.residue:.4f}" for o in branch.orbits])
    ['0.0946', '0.4206', '0.6434']
    """
    eps = np.asarray(eps_values, float)
    if eps.ndim != 1 or not 1 <= eps.size <= MAX_BRANCH_POINTS:
        raise ValueError(f"eps_values must be 1 to {MAX_BRANCH_POINTS} values, got shape {eps.shape}")
    d = np.diff(eps)
    if not (np.all(d > 0) or np.all(d < 0)):
        raise ValueError("eps_values must be strictly monotonic (each orbit starts from the previous one)")
    orbits: list[PeriodicOrbit] = []
    for e in eps:
        x: Any = start
        if len(orbits) == 1:
            x = orbits[0].points[0]
        elif len(orbits) >= 2:
            a, b = orbits[-2], orbits[-1]
            x = b.points[0] + (b.points[0] - a.points[0]) * (e - b.eps) / (b.eps - a.eps)
        kw: dict[str, Any] = dict(map=map, order=order, axis=axis, workers=workers)
        try:
            o = periodic_orbit(body, theta0, float(e), period, start=x, **kw)
        except (PeriodicOrbitError, AveragingRangeError):
            if x is None:
                raise
            o = periodic_orbit(body, theta0, float(e), period, **kw)
        orbits.append(o)
    return Branch(orbits=tuple(orbits))
