"""The flow's volume along long direct runs of the rock'n'roller, and Livšic's test on its close returns: the
measurement of :mod:`rocknroller.analysis.slow.dynamics.reversibility` that reaches 10⁵ rocks.

L(t) = ∫ div f dt along the direct motion, sampled at the θ-maxima (:func:`divergence_run`).  For any section
Σ_{k<n} log|det DP(x_k)| = L(t_n) + log σ(x₀) − log σ(x_n), σ the flux density of the section, so L and the map's
Lyapunov sum share their limit; L costs one ODE variable, not three variational runs a rock (10⁵ rocks in ~30 s).  A
continuous invariant density ρ(γ, ω) makes L(t) = log ρ(y₀) − log ρ(y(t)): bounded, a function of the point: close
returns, however long, carry equal L (:func:`recurrence_spread`: a close return of n rocks is a pseudo-periodic orbit,
almost never symmetric, and |ΔL| its log Π det; Livšic's test), and L is one smooth function of the section point
(:func:`section_fit`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cache
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

if TYPE_CHECKING:
    from rocknroller.analysis.slow.map.maps import ExactMap

__all__ = ["MAX_ROCKS", "DivergenceRun", "divergence_run", "RecurrenceSpread", "recurrence_spread", "section_fit"]

_U = float(np.finfo(float).eps)
#: Most maxima of one :func:`divergence_run`: its record holds 8 doubles a maximum (64 MB here) and it takes ~0.3 ms
#: a rock (5 min); the measurements use 10⁵.
MAX_ROCKS = 1_000_000


@cache
def _divergence_integrator() -> Any:
    """heyoka's integrator of the (γ, ω) system with L̇ = div f, the θ-maxima its terminal event (once a process;
    heyoka's disk cache keeps it between processes)."""
    import heyoka as hy

    from rocknroller.analysis.model.equations import body_frame_rhs, turning_point_function
    from rocknroller.numerics.backends import check_diskcache
    from rocknroller.numerics.cache import compiling

    y = hy.make_vars("g1", "g2", "g3", "w1", "w2", "w3", "x1", "x2", "x3", "X", "Y")
    rhs = body_frame_rhs(y, [hy.par[i] for i in range(5)])[:6]
    div = hy.sum([hy.diff(rhs[i], y[i]) for i in range(6)])
    event = hy.t_event(turning_point_function(y), direction=hy.event_direction.positive)
    check_diskcache()
    with compiling("the flow-divergence integrator (heyoka)", 6.0):
        return hy.taylor_adaptive(list(zip(y[:6], rhs)) + [(hy.make_vars("L"), div)], np.zeros(7),
                                  pars=np.zeros(5), t_events=[event])


@dataclass(frozen=True)
class DivergenceRun:
    """A direct run sampled at its θ-maxima with L = ∫₀ᵗ div f dt (:func:`divergence_run`).

    Attributes
    ----------
    t : ndarray
        Times of the maxima.
    log_volume : ndarray
        L at the maxima.
    points : ndarray
        (N, 3): (Q_R, Q_J, Θ mod 2π) at the maxima.
    error : bound on L's error: steps · u · max‖state‖∞ (heyoka's tolerance u per step, on the state's ∞-norm).
    """

    t: NDArray[np.float64]
    log_volume: NDArray[np.float64]
    points: NDArray[np.float64]
    error: float

    @property
    def n(self) -> int:  # maxima (rocks)
        return int(self.t.size)

    def mean(self, n: int | None = None) -> float:
        """L after n rocks (default all) divided by n: the map's Lyapunov sum up to the coboundary's O(1/n)."""
        n = self.n if n is None else n
        return float(self.log_volume[n - 1] / n)

    def max_abs(self, n: int | None = None) -> float:
        """max |L| over the first n rocks (default all): bounded with a continuous density, ∝ n without."""
        return float(np.max(np.abs(self.log_volume[: self.n if n is None else n])))


def divergence_run(F: "ExactMap", x0: ArrayLike, n_rocks: int) -> DivergenceRun:
    """The direct motion of F's body from the maximum x0 = (Q_R, Q_J, Θ) (its state as ``ExactMap`` builds it) over
    ``n_rocks`` maxima, with L = ∫ div f dt (heyoka, tolerance u; ~0.3 ms a rock).

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> from rocknroller.analysis.slow.dynamics.flow_volume import divergence_run
    >>> run = divergence_run(rr.ExactMap(rr.Body.paper(0.0), 0.9 * math.pi, 0.03), [0.0, 0.0, 0.002], 200)
    >>> print(run.n, run.max_abs() < 0.1, abs(run.log_volume[-1]) > 100 * run.error)
    200 True True
    """
    from rocknroller.analysis.model.equations import state_from_euler
    from rocknroller.analysis.model.invariants import jellett, routh
    from rocknroller.analysis.slow.map.family import maximum_state
    from rocknroller.numerics.events import start_turning_point

    if isinstance(n_rocks, bool) or not isinstance(n_rocks, (int, np.integer)) or not 1 <= n_rocks <= MAX_ROCKS:
        raise ValueError(f"n_rocks must be a whole number in [1, MAX_ROCKS = {MAX_ROCKS}], got n_rocks={n_rocks!r}")
    x = np.asarray(x0, float)
    st = maximum_state(F.sym, F.eps, F.E, float(x[0]), float(x[1]), 0.5 * float(x[2]))[2]
    y0 = state_from_euler(st.theta, 0.0, st.psi, 0.0, st.phi_dot, st.psi_dot)
    own = start_turning_point(F.member, y0)  # the start's own root, at t = 0 to its rounding: not a rock
    window = own.window if own is not None else -1.0
    ta = _divergence_integrator()
    ta.time, ta.state[:], ta.pars[:] = 0.0, [*y0[:6], 0.0], F.member.params
    ta.reset_cooldowns()
    out, steps, size, k = np.empty((n_rocks, 8)), 0, 0.0, 0
    while k < n_rocks:
        outcome, *_, n_steps = ta.propagate_until(float(ta.time) + 1e6, max_steps=100_000)[:4]
        steps += int(n_steps)
        if int(outcome.value) != -1:
            raise RuntimeError(f"heyoka stopped the divergence run at t={ta.time!r} without a maximum: {outcome}")
        if float(ta.time) <= window:
            continue
        out[k, 0], out[k, 1:] = ta.time, ta.state
        size = max(size, float(np.max(np.abs(ta.state))))
        k += 1
    g, w = out[:, 1:4].T, out[:, 4:7].T
    points = np.column_stack([routh(F.sym, g, w), jellett(F.sym, g, w),
                              np.mod(2.0 * np.arctan2(g[0], g[1]), 2.0 * math.pi)])
    return DivergenceRun(out[:, 0], out[:, 7].copy(), points, steps * _U * size)


@dataclass(frozen=True)
class RecurrenceSpread:
    """|ΔL| between close returns (:func:`recurrence_spread`).

    Attributes
    ----------
    radius : the returns' distance lies in (radius/2, radius] (section coordinates scaled to unit range).
    pairs : close returns found.
    median, maximum : of |L_i − L_j| over them (nan without pairs).
    """

    radius: float
    pairs: int
    median: float
    maximum: float


def recurrence_spread(points: ArrayLike, values: ArrayLike, radius: float, *, min_separation: int = 1000,
                      samples: int = 2000, angles: Sequence[int] = (2,)) -> RecurrenceSpread:
    """Livšic's test on an orbit: the pairs (i, j), i among ``samples`` points spread evenly along the orbit, whose
    distance lies in (radius/2, radius] (each coordinate scaled by its range; angles by 2π, periodic) and whose
    separation is at least ``min_separation`` steps, and |ΔL| = |values_i − values_j| over them.  A continuous density
    makes |ΔL| → 0 with the radius (∝ radius for a Lipschitz one), whatever the separation; mixed dynamics makes it
    grow with the separation instead.

    Examples
    --------
    >>> import numpy as np
    >>> from rocknroller.analysis.slow.dynamics.flow_volume import recurrence_spread
    >>> x = np.random.default_rng(1).random((5000, 2))
    >>> r = recurrence_spread(x, np.sin(6 * x[:, 0]), 0.01, min_separation=10, angles=())
    >>> print(r.pairs > 1000, r.maximum <= 0.06)
    True True
    """
    from scipy.spatial import cKDTree

    X, L = np.asarray(points, float), np.asarray(values, float)
    is_angle = np.isin(np.arange(X.shape[1]), angles)
    Y = (X - np.where(is_angle, 0.0, X.min(axis=0))) / np.where(is_angle, 2.0 * math.pi, np.ptp(X, axis=0))
    Y[:, is_angle] = np.mod(Y[:, is_angle], 1.0)
    tree = cKDTree(Y, boxsize=np.where(is_angle, 1.0, 2.0))  # 2: no wrap within the unit range
    first = np.unique(np.linspace(0, len(Y) - 1, min(samples, len(Y))).astype(int))
    dL: list[NDArray[np.float64]] = []
    for i, near in zip(first, tree.query_ball_point(Y[first], radius, p=math.inf)):
        j = np.asarray(near, int)
        j = j[np.abs(j - i) >= min_separation]
        delta = np.abs(Y[j] - Y[i])
        delta[:, is_angle] = np.minimum(delta[:, is_angle], 1.0 - delta[:, is_angle])
        dL.append(np.abs(L[j[np.max(delta, axis=1) > 0.5 * radius]] - L[i]))
    d = np.concatenate(dL) if dL else np.zeros(0)
    if not d.size:
        return RecurrenceSpread(radius, 0, math.nan, math.nan)
    return RecurrenceSpread(radius, int(d.size), float(np.median(d)), float(np.max(d)))


def section_fit(points: ArrayLike, values: ArrayLike, degree: int, harmonics: int) -> tuple[float, float]:
    """(rms, max) of the least-squares residual of ``values`` (L at the maxima) against one function of the section
    point: polynomials of total degree ≤ ``degree`` in (Q_R, Q_J) (each scaled to [−1, 1]) times Fourier modes
    ≤ ``harmonics`` in Θ.  A smooth density, log ρ = −L + const, makes it fall fast (spectrally) with the degree; a
    drift along the orbit, or a density that is not a function of the point, leaves it at L's own scale.

    Examples
    --------
    >>> import numpy as np
    >>> from rocknroller.analysis.slow.dynamics.flow_volume import section_fit
    >>> x = np.random.default_rng(1).random((2000, 3)) * [0.1, 0.01, 6.0]
    >>> rms, worst = section_fit(x, np.exp(10 * x[:, 0]) * np.cos(x[:, 2]), 8, 1)
    >>> print(rms < 1e-8)
    True
    """
    X, L = np.asarray(points, float), np.asarray(values, float)
    u, v = (X[:, i] / np.max(np.abs(X[:, i])) for i in (0, 1))
    modes = [np.ones_like(u)] + [f(m * X[:, 2]) for m in range(1, harmonics + 1) for f in (np.cos, np.sin)]
    A = np.column_stack([u ** i * v ** j * w for i in range(degree + 1) for j in range(degree + 1 - i) for w in modes])
    r = L - A @ np.linalg.lstsq(A, L, rcond=None)[0]
    return float(np.sqrt(np.mean(r * r))), float(np.max(np.abs(r)))
