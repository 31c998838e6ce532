"""Trajectory: the direct ODE's output with Euler angles, invariants, contact track and turning points.

φ and ψ are unwrapped continuously, also through passages near θ = 0 where they jump by about ±π:
the sample grid always contains the θ-minima (found as events), and any interval over which an angle
changes by more than 2π/3 (wrapped) is bisected on the dense output until none does, so the branch of every
increment is resolved (the swing on each side of a near-vertical passage is about π/2).  A run that unwraps on a
grid coarser than its output spacing (``simulate(..., samples=False)``) also bisects, down to that spacing, every
interval over which the faster of φ̇, ψ̇ at its ends would turn an angle by more than 2π/3: that catches an angle
turning by more than 4π/3 between two samples, which the first test would mistake for a small step.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import Body, LoadedSphere
from rocknroller.analysis.model.diagnostics import azimuth_span, slow_period, span, wrap_angle
from rocknroller.analysis.model.invariants import energy, jellett, routh
from rocknroller.analysis.model.kinematics import angles_from_frame
from rocknroller.numerics.events import DenseOutput, LaneDense, _PointDense, lane_states
from rocknroller.numerics.run_limits import energy_error_bound, energy_scale

if TYPE_CHECKING:
    import pandas

__all__ = ["TurningPoints", "MaximaExtents", "Trajectory", "TurningPointRun"]

#: An interval whose wrapped angle increment exceeds this is bisected before unwrapping.
_UNWRAP_LIMIT = 2.0 * math.pi / 3.0
_TWO_PI = 2.0 * math.pi
_MAX_BISECTIONS = 80
#: An interval no longer than this times max(1, |t|) is not split.
_SHORTEST = 64.0 * np.finfo(float).eps


@dataclass(frozen=True)
class TurningPoints:
    """Samples at the turning points of θ (all maxima, or all minima), in time order.

    ``phi`` and ``psi`` lie on the same unwrapped branch as the trajectory's series.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> start = rr.EulerState.from_omega(0.95 * math.pi, 0.0, 0.0, (0.0, 1e-3, -1e-3))
    >>> maxima = rr.simulate(body, start, 60.0, samples=False).maxima
    >>> print(f"{maxima.t[1] - maxima.t[0]:.4f}", f"{maxima.theta[0] / math.pi:.6f} pi")
    13.2601 0.949999 pi
    >>> print(f"Q_R = {maxima.QR[0]:.4e}, Q_J = {maxima.QJ[0]:.4e}")
    Q_R = -1.2604e-03, Q_J = 4.6919e-04
    """

    t: NDArray[np.float64]
    theta: NDArray[np.float64]
    phi: NDArray[np.float64]
    psi: NDArray[np.float64]
    states: NDArray[np.float64]
    body: Body | LoadedSphere = dataclasses.field(repr=False)

    def __len__(self) -> int:
        return int(self.t.size)

    @functools.cached_property
    def QR(self) -> NDArray[np.float64]:
        """Routh's Q_R at each turning point (paper eq. routh); a ValueError for a LoadedSphere, where the paper's
        Q_R is not defined."""
        return routh(self.body, self.states[:, 0:3].T, self.states[:, 3:6].T)

    @functools.cached_property
    def QJ(self) -> NDArray[np.float64]:
        """Jellett's Q_J at each turning point (paper eq. jellett); a ValueError for a LoadedSphere."""
        return jellett(self.body, self.states[:, 0:3].T, self.states[:, 3:6].T)

    def to_dataframe(self) -> "pandas.DataFrame":
        """One row per turning point: t, θ, φ, ψ, and Q_R, Q_J for a :class:`Body` (needs pandas)."""
        from rocknroller.analysis.model.frames import dataframe

        names = ("t", "theta", "phi", "psi") + (("QR", "QJ") if isinstance(self.body, Body) else ())
        return dataframe({n: getattr(self, n) for n in names})

    @classmethod
    def concatenate(cls, parts: list["TurningPoints"], body: Body | LoadedSphere) -> "TurningPoints":
        """The samples of consecutive stretches of a run of ``body``, in time order (an empty list gives no samples,
        one part itself)."""
        names = [f.name for f in dataclasses.fields(cls) if f.name != "body"]
        if not parts:
            return cls(**{n: np.empty((0, 11) if n == "states" else 0) for n in names}, body=body)
        if len(parts) == 1:
            return parts[0]
        return cls(**{n: np.concatenate([getattr(p, n) for p in parts]) for n in names}, body=body)


def _angle_rates(y: NDArray[np.float64]) -> NDArray[np.float64]:
    """max(|φ̇|, |ψ̇|) at states ``y`` (N, 11): φ̇ = (ω1 γ1 + ω2 γ2)/(γ1² + γ2²), ψ̇ = ω3 − φ̇ γ3 (from
    ω1 = φ̇ sin θ sin ψ + θ̇ cos ψ, ω2 = φ̇ sin θ cos ψ − θ̇ sin ψ, ω3 = φ̇ cos θ + ψ̇ with γ = (sin θ sin ψ,
    sin θ cos ψ, cos θ)); inf at the pole, where φ and ψ are undefined."""
    g1, g2, g3, w1, w2, w3 = y[:, 0], y[:, 1], y[:, 2], y[:, 3], y[:, 4], y[:, 5]
    with np.errstate(divide="ignore", invalid="ignore"):
        phi_dot = (w1 * g1 + w2 * g2) / (g1 * g1 + g2 * g2)
        fastest = np.maximum(np.abs(phi_dot), np.abs(w3 - phi_dot * g3))
    return np.where(np.isnan(fastest), np.inf, fastest)


def _unresolved(t_lo: NDArray, t_hi: NDArray, ang_lo: NDArray, ang_hi: NDArray, rate_lo: NDArray,
                rate_hi: NDArray, fine: NDArray) -> NDArray[np.bool_]:
    """The intervals (t_lo, t_hi) to bisect: φ or ψ changes by more than 2π/3 (wrapped) over them, or, while they
    are longer than ``fine``, would at the faster rate of their ends; unless they are too short to split (64 u of
    t).  The rate test stops at ``fine`` so that its work is bounded (near the pole φ̇ and ψ̇ grow without bound:
    a tilt that stays within 1e-6 of the pole turns φ ~10⁵ times a time unit, which no grid resolves)."""
    jumps = np.any(np.abs(wrap_angle(ang_hi[1:] - ang_lo[1:])) > _UNWRAP_LIMIT, axis=0)
    width = t_hi - t_lo
    fast = (np.maximum(rate_lo, rate_hi) * width > _UNWRAP_LIMIT) & (width > fine)
    return (jumps | fast) & (width > _SHORTEST * np.maximum(1.0, np.abs(t_hi)))


def _unwrapped_angles(tt: NDArray[np.float64], yy: NDArray[np.float64], lane_of: NDArray[np.intp], dense: LaneDense,
                      columns: list[int], fill: NDArray[np.float64], starts: list[NDArray[np.float64] | None],
                      fine: ArrayLike) -> NDArray[np.float64]:
    """Unwrapped (θ, φ, ψ), shape (3, m), at the times ``tt`` (m,) of lanes ``lane_of`` (m,: each lane's times
    together and in time order, the lanes in order; states ``yy`` (m, 11) there), refining the grids where needed.

    Each interval to refine (:func:`_unresolved`) is bisected on its own, its halves checked again, down to
    ``_MAX_BISECTIONS`` levels, the midpoints of every lane evaluated together (lane j in column ``columns[j]`` of
    ``dense``, the other columns at their ``fill`` times); the points added are used for the unwrapping and dropped
    from the result.  An interval that still jumps after bisection down to round-off is a passage through θ = 0
    itself (θ_N at round-off level), where φ and ψ are undefined and only φ + ψ is: φ then takes the wrapped jump
    (−π) and ψ the opposite one, so that φ + ψ stays continuous.  ``starts[j]`` = (φ, ψ) on the branch to continue
    at t[j][0] (a previous piece's last unwrapped values); ``fine[j]`` the width below which lane j's rate test stops
    (:func:`_unresolved`).  A lane's result depends only on its own times and states.
    """
    n_lanes = len(starts)
    ang, rate = angles_from_frame(yy[:, 0:3].T, yy[:, 6:9].T), _angle_rates(yy)
    inside = lane_of[:-1] == lane_of[1:]
    fine = np.asarray(fine, float)
    bad = np.flatnonzero(inside & _unresolved(tt[:-1], tt[1:], ang[:, :-1], ang[:, 1:], rate[:-1], rate[1:],
                                              fine[lane_of[1:]]))
    lane, cols = lane_of[bad], np.asarray(columns)
    lo: tuple[NDArray, ...] = (tt[bad], ang[:, bad], rate[bad])
    hi: tuple[NDArray, ...] = (tt[bad + 1], ang[:, bad + 1], rate[bad + 1])
    added: list[tuple[NDArray, NDArray, NDArray]] = []
    for _ in range(_MAX_BISECTIONS):
        if lane.size == 0:
            break
        t_mid = 0.5 * (lo[0] + hi[0])
        y_mid = lane_states(dense, t_mid, lane, cols, fill)  # only the new points: the states elsewhere are kept
        mid = (t_mid, angles_from_frame(y_mid[:, 0:3].T, y_mid[:, 6:9].T), _angle_rates(y_mid))
        added.append((lane, t_mid, mid[1]))
        left = _unresolved(lo[0], mid[0], lo[1], mid[1], lo[2], mid[2], fine[lane])
        right = _unresolved(mid[0], hi[0], mid[1], hi[1], mid[2], hi[2], fine[lane])
        lo = tuple(np.concatenate([a[..., left], b[..., right]], axis=-1) for a, b in zip(lo, mid))
        hi = tuple(np.concatenate([a[..., left], b[..., right]], axis=-1) for a, b in zip(mid, hi))
        lane = np.concatenate([lane[left], lane[right]])
    else:
        if lane.size:
            raise RuntimeError("could not resolve the branch of phi/psi after repeated bisection")
    keep = np.ones(tt.size, bool)
    if added:  # the added points among the lanes' own, each lane in time order (the states of the own suffice)
        lane_of = np.concatenate([lane_of] + [a[0] for a in added])
        order = np.lexsort((np.concatenate([tt] + [a[1] for a in added]), lane_of))
        lane_of = lane_of[order]
        ang = np.concatenate([ang] + [a[2] for a in added], axis=1)[:, order]
        keep = np.concatenate([keep, np.zeros(lane_of.size - keep.size, bool)])[order]
    ends = np.searchsorted(lane_of, np.arange(n_lanes + 1))
    return _branches(ang, _turns(ang, ends), ends, starts)[:, keep]


def _turns(ang: NDArray[np.float64], ends: NDArray[np.intp]) -> NDArray[np.float64]:
    """The whole turns (2, m) of φ and ψ since each lane's first sample, from (θ, φ, ψ) samples ``ang`` of several
    lanes (lane j in columns ends[j]:ends[j + 1]), each fine enough that no step of φ or ψ is ambiguous (see
    :func:`_unwrapped_angles`); each lane's result its own (``_dense.c``'s ``turns`` for the batch lanes)."""
    raw = np.diff(ang[1:], axis=1)
    steps = wrap_angle(raw)
    through_pole = np.flatnonzero(np.any(np.abs(steps) > _UNWRAP_LIMIT, axis=0))
    steps[1, through_pole] = wrap_angle(steps[0, through_pole] + steps[1, through_pole]) - steps[0, through_pole]
    # every chosen step is the raw difference plus a whole number of turns: keep the angles as
    # ang + 2π·(turns), exact integers, so no round-off accumulates along the series
    turns = np.rint((steps - raw) / _TWO_PI)
    lanes = np.flatnonzero(ends[:-1] < ends[1:])  # the lanes with samples
    turns[:, ends[lanes[1:]] - 1] = 0.0  # no step from one lane into the next
    total = np.zeros_like(ang[1:])
    np.cumsum(turns, axis=1, out=total[:, 1:])  # whole numbers: exact
    return total - np.repeat(total[:, ends[lanes]], np.diff(ends)[lanes], axis=1)


def _branches(ang: NDArray[np.float64], total: NDArray[np.float64], ends: NDArray[np.intp],
              starts: list[NDArray[np.float64] | None]) -> NDArray[np.float64]:
    """(θ, φ, ψ) samples ``ang`` of several lanes (lane j in columns ends[j]:ends[j + 1]) unwrapped: φ and ψ moved by
    ``total`` whole turns (:func:`_turns`), lane j's on the branch of ``starts[j]`` (see :func:`_unwrapped_angles`)."""
    lanes = np.flatnonzero(ends[:-1] < ends[1:])  # the lanes with samples
    offset = np.zeros((2, lanes.size))
    for k, j in enumerate(lanes):
        start = starts[j]
        if start is not None:  # the branch of ``start``: start + wrap(ang0 − start) = ang0 + 2π·first
            s0, a0 = np.reshape(start, (2, 1)), ang[1:, ends[j]:ends[j] + 1]
            offset[:, k:k + 1] = np.rint((s0 + wrap_angle(a0 - s0) - a0) / _TWO_PI)
    unwrapped = np.empty_like(ang)
    unwrapped[0] = ang[0]
    unwrapped[1:] = ang[1:] + _TWO_PI * (total + np.repeat(offset, np.diff(ends)[lanes], axis=1))
    return unwrapped


@dataclass(frozen=True)
class _Samples:
    """One stretch of the dense output sampled on a grid that contains its turning points."""

    t: NDArray[np.float64]
    y: NDArray[np.float64]
    angles: NDArray[np.float64]
    i_max: NDArray[np.intp]
    i_min: NDArray[np.intp]

    @classmethod
    def take(cls, dense: DenseOutput, t_grid: ArrayLike, t_maxima: ArrayLike, t_minima: ArrayLike,
             start: NDArray[np.float64] | None = None, fine: float = math.inf) -> "_Samples":
        """Sample ``dense`` on the grid and at the turning points (one lane of :meth:`take_lanes`; ``fine``: where
        the rate test stops, by default nowhere finer than the grid itself)."""
        t_grid = np.asarray(t_grid, float)
        return cls.take_lanes(lambda times: dense(times[:, 0])[:, :, None], [(t_grid, t_maxima, t_minima)], [0],
                              t_grid[:1], [start], [fine])[0]

    @classmethod
    def take_lanes(cls, dense: LaneDense, pieces: list[tuple[ArrayLike, ArrayLike, ArrayLike]], columns: list[int],
                   fill: NDArray[np.float64], starts: list[NDArray[np.float64] | None],
                   fine: ArrayLike) -> list["_Samples"]:
        """Sample several lanes' dense output (``dense``, lane j in column ``columns[j]``, the others at their
        ``fill`` times) on each lane's grid and at its turning points, ``pieces[j]`` = (grid, maxima, minima), the
        lanes evaluated together; ``starts`` and ``fine`` as :func:`_unwrapped_angles`'s."""
        t_all, inverse, sizes = [], [], []
        for t_grid, t_max, t_min in pieces:
            parts = [np.asarray(t_grid, float), np.asarray(t_max, float), np.asarray(t_min, float)]
            ta, inv = np.unique(np.concatenate(parts), return_inverse=True)
            t_all.append(ta)
            inverse.append(inv)
            sizes.append((parts[0].size, parts[1].size))
        tt, lane_of = np.concatenate(t_all), np.repeat(np.arange(len(t_all)), [ta.size for ta in t_all])
        ends = np.cumsum([0] + [ta.size for ta in t_all])
        if isinstance(dense, _PointDense):  # the refinement and the turns in C, each lane's points in one pass
            yy, total = dense.unwrap(tt, np.asarray(columns, np.intp)[lane_of], np.asarray(fine, float)[lane_of],
                                     _UNWRAP_LIMIT, _MAX_BISECTIONS, _SHORTEST)
            angles = _branches(angles_from_frame(yy[:, 0:3].T, yy[:, 6:9].T), total, ends, starts)
        else:
            yy = lane_states(dense, tt, lane_of, columns, fill)
            angles = _unwrapped_angles(tt, yy, lane_of, dense, columns, fill, starts, fine)
        return [cls(ta, yy[a:b], angles[:, a:b], inv[n_grid:n_grid + n_max], inv[n_grid + n_max:])
                for ta, inv, (n_grid, n_max), a, b in zip(t_all, inverse, sizes, ends[:-1], ends[1:])]

    def turning(self, body: Body | LoadedSphere, idx: NDArray[np.intp]) -> TurningPoints:
        theta, phi, psi = self.angles[:, idx]
        return TurningPoints(t=self.t[idx], theta=theta, phi=phi, psi=psi, states=self.y[idx], body=body)


class MaximaExtents:
    """The extents of Q_R and Q_J over a run's θ-maxima (the samples of the averaged map), for the classes that hold
    the maxima (:class:`Trajectory`, :class:`TurningPointRun`, ``RunSummary``); a ValueError for a LoadedSphere."""

    maxima: TurningPoints

    @property
    def QR_extent(self) -> float:
        """max − min of Q_R over the θ-maxima."""
        return span(self.maxima.QR)

    @property
    def QJ_extent(self) -> float:
        """max − min of Q_J over the θ-maxima."""
        return span(self.maxima.QJ)


class _TurningPointDiagnostics(MaximaExtents):
    """Slow diagnostics from the turning-point samples (shared by Trajectory and TurningPointRun)."""

    maxima: TurningPoints
    minima: TurningPoints
    tolerance: float
    n_steps: int
    body: Body | LoadedSphere

    @property
    def paper_body(self) -> Body:
        """The run's body as the paper's :class:`Body` (the mass centre on the third axis), for what is built on Q_J
        and Q_R (critical lines, regions); a ValueError for a LoadedSphere."""
        if not isinstance(self.body, Body):
            raise ValueError(f"this run's body is a {self.body.kind} (c = {self.body.offset!r}); the paper's Q_J, "
                             "Q_R and what is built on them need a Body, the mass centre on the third axis")
        return self.body

    @property
    def Phi(self) -> float:
        """Azimuth span Φ of the visible half-angle φ mod π at the θ-maxima (paper §7.2)."""
        return azimuth_span(self.maxima.phi)

    @property
    def slow_period(self) -> float | None:
        """Period of Θ = 2ψ sampled at the θ-maxima, from interpolated crossings of the mean
        (:func:`rocknroller.analysis.model.diagnostics.slow_period`); None if not measurable within the run."""
        return slow_period(self.maxima.t, 2.0 * self.maxima.psi)

    @property
    def maxima_spacing(self) -> float | None:
        """Mean time between successive θ-maxima, (t_last − t_first)/(count − 1): the measured T_θ
        (for rocking through θ = 0, half the rocking period).  None with fewer than two maxima."""
        t = self.maxima.t
        return float((t[-1] - t[0]) / (t.size - 1)) if t.size >= 2 else None

    def turning_points_dataframe(self) -> "pandas.DataFrame":
        """Every turning point in time order, with ``kind`` "max" or "min" (needs pandas)."""
        import pandas as pd

        frames = [tp.to_dataframe().assign(kind=kind) for kind, tp in (("max", self.maxima), ("min", self.minima))]
        return pd.concat(frames, ignore_index=True).sort_values("t", kind="stable", ignore_index=True)

    def plot(self, ax: Any = None, kind: str = "orbit") -> Any:
        """Draw the run on ``ax`` (a new pyplot figure without one): ``"orbit"`` the (Q_R, Q_J) orbit with its
        turning points (paper figs. 7-10), ``"phi"`` φ at the θ-maxima (paper fig. 5), ``"track"`` the contact
        track (samples only, paper figs. 5, 6).  Returns the axes."""
        from rocknroller.numerics import trajectory_plots as tp

        plots: dict[str, Callable[..., Any]] = {"orbit": tp.plot_invariant_orbit, "phi": tp.plot_phi_at_maxima,
                                                "track": tp.plot_contact_track}
        if kind not in plots or (kind == "track" and not isinstance(self, Trajectory)):
            allowed = list(plots) if isinstance(self, Trajectory) else ["orbit", "phi"]
            raise ValueError(f"kind must be one of {allowed}, got kind={kind!r}")
        return plots[kind](self, ax=ax)

    @property
    def energy_tolerance(self) -> float:
        """The largest energy error consistent with the integrator's tolerance (:func:`~rocknroller.numerics.run_limits.energy_error_bound`)."""
        return energy_error_bound(self.tolerance, self.n_steps)


@dataclass(frozen=True)
class Trajectory(_TurningPointDiagnostics):
    """Direct-ODE solution sampled on a grid that includes every turning point of θ.

    Attributes
    ----------
    body : Body
    method : str
        ``"heyoka"`` or ``"scipy"``.
    t : ndarray (N,)
    states : ndarray (N, 11)
        Body-frame states (γ, ω, e_X, X, Y) of form (i), see :mod:`rocknroller.analysis.model.equations`.
    theta, phi, psi : ndarray (N,)
        Euler angles; φ (full azimuth) and ψ unwrapped and continuous.
    maxima, minima : TurningPoints
        θ-maxima and θ-minima (events dγ3/dt = 0, located to round-off; none at t = t0).
    n_steps : int
        Integration steps taken.
    tolerance : float
        The integrator's relative tolerance (heyoka: its ``tol``, by default the machine epsilon of its precision;
        scipy: rtol).

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> start = rr.EulerState.from_omega(0.95 * math.pi, 0.0, 0.0, (0.0, 1e-3, -1e-3))
    >>> traj = rr.simulate(body, start, 60.0)
    >>> print(type(traj).__name__, traj.method, traj.states.shape[1])
    Trajectory heyoka 11
    >>> print(bool(traj.t[0] == 0.0 and traj.t[-1] == 60.0))
    True
    """

    body: Body | LoadedSphere
    method: str
    t: NDArray[np.float64]
    states: NDArray[np.float64]
    theta: NDArray[np.float64]
    phi: NDArray[np.float64]
    psi: NDArray[np.float64]
    maxima: TurningPoints
    minima: TurningPoints
    dense: DenseOutput = field(repr=False)
    n_steps: int = 0
    tolerance: float = float(np.finfo(float).eps)

    @classmethod
    def from_dense(cls, body: Body | LoadedSphere, method: str, dense: DenseOutput, t_grid: ArrayLike,
                   t_maxima: ArrayLike, t_minima: ArrayLike, *, n_steps: int = 0,
                   tolerance: float = float(np.finfo(float).eps)) -> "Trajectory":
        """Assemble a trajectory from a dense output and the event times."""
        smp = _Samples.take(dense, t_grid, t_maxima, t_minima)
        theta, phi, psi = smp.angles
        return cls(body=body, method=method, t=smp.t, states=smp.y, theta=theta, phi=phi, psi=psi,
                   maxima=smp.turning(body, smp.i_max), minima=smp.turning(body, smp.i_min), dense=dense,
                   n_steps=int(n_steps), tolerance=float(tolerance))

    # ------------------------------------------------------------------ series
    @property
    def gamma(self) -> NDArray[np.float64]:
        """Upward vertical in body components, shape (3, N)."""
        return self.states[:, 0:3].T

    @property
    def omega(self) -> NDArray[np.float64]:
        """Body-frame angular velocity, shape (3, N)."""
        return self.states[:, 3:6].T

    @property
    def X(self) -> NDArray[np.float64]:
        """Contact point X (the geometric centre's horizontal position)."""
        return self.states[:, 9]

    @property
    def Y(self) -> NDArray[np.float64]:
        """Contact point Y."""
        return self.states[:, 10]

    @property
    def E(self) -> NDArray[np.float64]:
        """Total energy along the trajectory (paper eq. energy)."""
        return energy(self.body, self.gamma, self.omega)

    @property
    def QJ(self) -> NDArray[np.float64]:
        """Jellett's quantity along the trajectory (paper eq. JelletandRouth_Qtys)."""
        return jellett(self.body, self.gamma, self.omega)

    @property
    def QR(self) -> NDArray[np.float64]:
        """Routh's quantity along the trajectory (paper eq. JelletandRouth_Qtys)."""
        return routh(self.body, self.gamma, self.omega)

    # ------------------------------------------------------------------ diagnostics
    @property
    def energy_rel_error(self) -> float:
        """max |E(t) − E(0)| / (E(0) + g a) over the samples (every turning point included); see
        :func:`~rocknroller.numerics.run_limits.energy_scale` for why the scale is E + g a and not E."""
        E = self.E
        return float(np.max(np.abs(E - E[0])) / energy_scale(self.body, E[0]))

    def to_dataframe(self) -> "pandas.DataFrame":
        """One row per sample: t, θ, φ, ψ, the contact point X, Y, and E, Q_R, Q_J (needs pandas; the turning
        points alone: :meth:`turning_points_dataframe`)."""
        from rocknroller.analysis.model.frames import dataframe

        names = ("t", "theta", "phi", "psi", "X", "Y", "E") + (("QR", "QJ") if isinstance(self.body, Body) else ())
        return dataframe({n: getattr(self, n) for n in names})

    def state_at(self, t: ArrayLike) -> NDArray[np.float64]:
        """Body-frame state(s) at time(s) ``t`` from the integrator's dense output, shape (..., 11)."""
        t = np.asarray(t, float)
        return self.dense(t.reshape(-1)).reshape(t.shape + (11,))


@dataclass(frozen=True)
class TurningPointRun(_TurningPointDiagnostics):
    """A direct-ODE run that kept only its turning points (``simulate(..., samples=False)``).

    Memory does not grow with the number of samples: the dense output is processed in stretches and
    dropped.  The energy error is measured on every sample of the unwrapping grid and every turning point.

    Attributes
    ----------
    body, method : as for :class:`Trajectory`.
    t_end : float
    maxima, minima : TurningPoints
    energy_rel_error : float
        max |E − E(0)| / (E(0) + g a) over all samples examined.
    n_steps : int
    tolerance : float

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> start = rr.EulerState.from_omega(0.95 * math.pi, 0.0, 0.0, (0.0, 1e-3, -1e-3))
    >>> run = rr.simulate(body, start, 60.0, samples=False)
    >>> print(type(run).__name__, len(run.maxima.t), run.energy_rel_error < 1e-12)
    TurningPointRun 4 True
    """

    body: Body | LoadedSphere
    method: str
    t_end: float
    maxima: TurningPoints
    minima: TurningPoints
    energy_rel_error: float
    n_steps: int
    tolerance: float

    def to_dataframe(self) -> "pandas.DataFrame":
        """Every turning point in time order (:meth:`turning_points_dataframe`; needs pandas)."""
        return self.turning_points_dataframe()
