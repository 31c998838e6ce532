"""Trajectory: the direct ODE's output with Euler angles, invariants, contact track and turning points.

φ and ψ are unwrapped continuously, also through passages near θ = 0 where they jump by about ±π:
the sample grid always contains the θ-minima (found as events), and any interval over which an angle
changes by more than 2π/3 (wrapped) is bisected on the dense output until none does, so the branch
of every increment is resolved (the swing on each side of a near-vertical passage is about π/2).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.diagnostics import azimuth_span, slow_period, span, wrap_angle
from rocknroller.analysis.model.invariants import energy, jellett, routh
from rocknroller.analysis.model.kinematics import angles_from_frame

if TYPE_CHECKING:
    import pandas

__all__ = ["TurningPoints", "Trajectory", "TurningPointRun", "energy_scale", "energy_error_bound", "ENERGY_SLACK"]

DenseOutput = Callable[[NDArray[np.float64]], NDArray[np.float64]]

#: An interval whose wrapped angle increment exceeds this is bisected before unwrapping.
_UNWRAP_LIMIT = 2.0 * math.pi / 3.0
_TWO_PI = 2.0 * math.pi
_MAX_BISECTIONS = 80


@dataclass(frozen=True)
class TurningPoints:
    """Samples at the turning points of θ (all maxima, or all minima), in time order.

    ``phi`` and ``psi`` lie on the same unwrapped branch as the trajectory's series.
    """

    t: NDArray[np.float64]
    theta: NDArray[np.float64]
    phi: NDArray[np.float64]
    psi: NDArray[np.float64]
    QR: NDArray[np.float64]
    QJ: NDArray[np.float64]
    states: NDArray[np.float64]

    def __len__(self) -> int:
        return int(self.t.size)

    def to_dataframe(self) -> "pandas.DataFrame":
        """One row per turning point: t, θ, φ, ψ, Q_R, Q_J (needs pandas)."""
        from rocknroller.analysis.model.frames import dataframe

        return dataframe({n: getattr(self, n) for n in ("t", "theta", "phi", "psi", "QR", "QJ")})

    @classmethod
    def concatenate(cls, parts: list["TurningPoints"]) -> "TurningPoints":
        """The samples of consecutive stretches, in time order (an empty list gives no samples)."""
        names = [f.name for f in dataclasses.fields(cls)]
        if not parts:
            return cls(**{n: np.empty((0, 11) if n == "states" else 0) for n in names})
        return cls(**{n: np.concatenate([getattr(p, n) for p in parts]) for n in names})


def energy_scale(body: Body, E0: float) -> float:
    """Scale of the energy error: E(0) + g a.

    Every term of E = T + V is bounded by it within a factor 3 (T ≤ E, 0 ≤ V = g a (1 − cos θ) ≤ 2 g a),
    so the round-off of one evaluation of E is a few units of u·(E + g a), and the scale never vanishes:
    g a > 0 for a > 0, and for a = 0 a state with motion has E = T > 0 (rest is refused by ``simulate``).
    Relative to E alone the error of a body released from rest at θ0 → 0 would be measured against
    E ≈ g a θ0²/2 → 0, which the round-off of g a (1 − cos θ) does not follow.
    """
    return abs(float(E0)) + body.g * body.a


def _unwrapped_angles(t: NDArray[np.float64], dense: DenseOutput,
                      start: NDArray[np.float64] | None = None) -> tuple[NDArray, NDArray]:
    """States at ``t`` and the unwrapped (θ, φ, ψ) there, refining the grid where needed.

    An interval that still jumps after bisection down to round-off is a passage through θ = 0
    itself (θ_N at round-off level), where φ and ψ are undefined and only φ + ψ is: φ then takes
    the wrapped jump (−π) and ψ the opposite one, so that φ + ψ stays continuous.
    ``start`` = (φ, ψ) on the branch to continue at t[0] (a previous chunk's last unwrapped values).
    """
    grid = t.copy()
    keep = np.ones(grid.size, bool)
    for _ in range(_MAX_BISECTIONS):
        y = dense(grid)
        ang = angles_from_frame(y[:, 0:3].T, y[:, 6:9].T)
        steps = wrap_angle(np.diff(ang[1:], axis=1))
        jumps = np.any(np.abs(steps) > _UNWRAP_LIMIT, axis=0)
        width = np.diff(grid)
        resolvable = width > 64.0 * np.finfo(float).eps * np.maximum(1.0, np.abs(grid[1:]))
        bad = np.flatnonzero(jumps & resolvable)
        if bad.size == 0:
            through_pole = np.flatnonzero(jumps)
            steps[1, through_pole] = wrap_angle(steps[0, through_pole] + steps[1, through_pole]) - steps[0, through_pole]
            # every chosen step is the raw difference plus a whole number of turns: keep the angles as
            # ang + 2π·(turns), exact integers, so no round-off accumulates along the series
            turns = np.rint((steps - np.diff(ang[1:], axis=1)) / _TWO_PI)
            first = np.zeros((2, 1))
            if start is not None:  # the branch of ``start``: start + wrap(ang0 − start) = ang0 + 2π·first
                s0, a0 = np.reshape(start, (2, 1)), ang[1:, :1]
                first = np.rint((s0 + wrap_angle(a0 - s0) - a0) / _TWO_PI)
            counts = np.concatenate([first, first + np.cumsum(turns, axis=1)], axis=1)
            unwrapped = ang.copy()
            unwrapped[1:] = ang[1:] + _TWO_PI * counts
            return y[keep], unwrapped[:, keep]
        mids = 0.5 * (grid[bad] + grid[bad + 1])
        grid = np.insert(grid, bad + 1, mids)
        keep = np.insert(keep, bad + 1, False)
    raise RuntimeError("could not resolve the branch of phi/psi after repeated bisection")


def energy_error_bound(tolerance: float, n_steps: int) -> float:
    """The relative energy error a run may reach: ``ENERGY_SLACK`` × (tolerance × steps + u).

    Each step of an integrator run at relative tolerance ``tolerance`` commits a local error of at most
    about ``tolerance`` of the state, and in the worst case these add up linearly in the number of steps;
    the energy is evaluated in double precision from states rounded to double, which adds a few units of
    u = 2⁻⁵³·2 (``np.finfo(float).eps``) relative to :func:`energy_scale` whatever the integrator's precision.
    A run whose energy error exceeds this bound has missed the asked tolerance by far (the paper's runs
    stay 10²–10⁴ below it).
    """
    return ENERGY_SLACK * (float(tolerance) * max(int(n_steps), 1) + float(np.finfo(float).eps))


#: Factor of :func:`energy_error_bound` over the linear accumulation of the per-step tolerance.
ENERGY_SLACK = 10.0


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
             start: NDArray[np.float64] | None = None) -> "_Samples":
        t_grid = np.asarray(t_grid, float)
        t_max, t_min = np.asarray(t_maxima, float), np.asarray(t_minima, float)
        t_all, inverse = np.unique(np.concatenate([t_grid, t_max, t_min]), return_inverse=True)
        y, angles = _unwrapped_angles(t_all, dense, start)
        n_grid, n_max = t_grid.size, t_max.size
        return cls(t_all, y, angles, inverse[n_grid:n_grid + n_max], inverse[n_grid + n_max:])

    def turning(self, body: Body, idx: NDArray[np.intp]) -> TurningPoints:
        ys = self.y[idx]
        theta, phi, psi = self.angles[:, idx]
        return TurningPoints(t=self.t[idx], theta=theta, phi=phi, psi=psi,
                             QR=routh(body, ys[:, 0:3].T, ys[:, 3:6].T),
                             QJ=jellett(body, ys[:, 0:3].T, ys[:, 3:6].T), states=ys)


class _TurningPointDiagnostics:
    """Slow diagnostics from the turning-point samples (shared by Trajectory and TurningPointRun)."""

    maxima: TurningPoints
    minima: TurningPoints
    tolerance: float
    n_steps: int

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

    @property
    def QR_extent(self) -> float:
        """max − min of Q_R over the θ-maxima (the samples of the averaged map)."""
        return span(self.maxima.QR)

    @property
    def QJ_extent(self) -> float:
        """max − min of Q_J over the θ-maxima (the samples of the averaged map)."""
        return span(self.maxima.QJ)

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
        """The largest energy error consistent with the integrator's tolerance (:func:`energy_error_bound`)."""
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
        The integrator's relative tolerance (heyoka: the unit round-off of its precision; scipy: rtol).
    """

    body: Body
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
    def from_dense(cls, body: Body, method: str, dense: DenseOutput, t_grid: ArrayLike,
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
        :func:`energy_scale` for why the scale is E + g a and not E."""
        E = self.E
        return float(np.max(np.abs(E - E[0])) / energy_scale(self.body, E[0]))

    def to_dataframe(self) -> "pandas.DataFrame":
        """One row per sample: t, θ, φ, ψ, the contact point X, Y, and E, Q_R, Q_J (needs pandas; the turning
        points alone: :meth:`turning_points_dataframe`)."""
        from rocknroller.analysis.model.frames import dataframe

        return dataframe({n: getattr(self, n) for n in ("t", "theta", "phi", "psi", "X", "Y", "E", "QR", "QJ")})

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
    """

    body: Body
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
