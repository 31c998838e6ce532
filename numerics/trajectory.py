"""Trajectory: the direct ODE's output with Euler angles, invariants, contact track and turning points.

φ and ψ are unwrapped continuously, also through passages near θ = 0 where they jump by about ±π:
the sample grid always contains the θ-minima (found as events), and any interval over which an angle
changes by more than 2π/3 (wrapped) is bisected on the dense output until none does, so the branch
of every increment is resolved (the swing on each side of a near-vertical passage is about π/2).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from analysis.body import Body
from analysis.invariants import energy, jellett, routh
from analysis.kinematics import angles_from_frame
from analysis.quadrature import wrap_angle
from analysis.slow_diagnostics import azimuth_span, slow_period, span

__all__ = ["TurningPoints", "Trajectory"]

DenseOutput = Callable[[NDArray[np.float64]], NDArray[np.float64]]

#: An interval whose wrapped angle increment exceeds this is bisected before unwrapping.
_UNWRAP_LIMIT = 2.0 * math.pi / 3.0
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


def _unwrapped_angles(t: NDArray[np.float64], dense: DenseOutput) -> tuple[NDArray, NDArray]:
    """States at ``t`` and the unwrapped (θ, φ, ψ) there, refining the grid where needed.

    An interval that still jumps after bisection down to round-off is a passage through θ = 0
    itself (θ_N at round-off level), where φ and ψ are undefined and only φ + ψ is: φ then takes
    the wrapped jump (−π) and ψ the opposite one, so that φ + ψ stays continuous.
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
            unwrapped = ang.copy()
            unwrapped[1:, 1:] = ang[1:, :1] + np.cumsum(steps, axis=1)
            return y[keep], unwrapped[:, keep]
        mids = 0.5 * (grid[bad] + grid[bad + 1])
        grid = np.insert(grid, bad + 1, mids)
        keep = np.insert(keep, bad + 1, False)
    raise RuntimeError("could not resolve the branch of phi/psi after repeated bisection")


@dataclass(frozen=True)
class Trajectory:
    """Direct-ODE solution sampled on a grid that includes every turning point of θ.

    Attributes
    ----------
    body : Body
    method : str
        ``"heyoka"`` or ``"scipy"``.
    t : ndarray (N,)
    states : ndarray (N, 11)
        Body-frame states (γ, ω, e_X, X, Y) of form (i), see :mod:`numerics.equations`.
    theta, phi, psi : ndarray (N,)
        Euler angles; φ (full azimuth) and ψ unwrapped and continuous.
    maxima, minima : TurningPoints
        θ-maxima and θ-minima (events dγ3/dt = 0, located to round-off; none at t = t0).
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

    @classmethod
    def from_dense(cls, body: Body, method: str, dense: DenseOutput, t_grid: ArrayLike,
                   t_maxima: ArrayLike, t_minima: ArrayLike) -> "Trajectory":
        """Assemble a trajectory from a dense output and the event times."""
        t_grid = np.asarray(t_grid, float)
        t_max, t_min = np.asarray(t_maxima, float), np.asarray(t_minima, float)
        t_all, inverse = np.unique(np.concatenate([t_grid, t_max, t_min]), return_inverse=True)
        y, (theta, phi, psi) = _unwrapped_angles(t_all, dense)

        def turning(idx: NDArray[np.intp]) -> TurningPoints:
            ys = y[idx]
            return TurningPoints(t=t_all[idx], theta=theta[idx], phi=phi[idx], psi=psi[idx],
                                 QR=routh(body, ys[:, 0:3].T, ys[:, 3:6].T),
                                 QJ=jellett(body, ys[:, 0:3].T, ys[:, 3:6].T), states=ys)

        n_grid, n_max = t_grid.size, t_max.size
        return cls(body=body, method=method, t=t_all, states=y, theta=theta, phi=phi, psi=psi,
                   maxima=turning(inverse[n_grid:n_grid + n_max]), minima=turning(inverse[n_grid + n_max:]),
                   dense=dense)

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
        """max |E(t) − E(0)| / |E(0)| over the samples (every turning point included)."""
        E = self.E
        return float(np.max(np.abs(E - E[0])) / abs(E[0]))

    @property
    def Phi(self) -> float:
        """Azimuth span Φ of the visible half-angle φ mod π at the θ-maxima (paper §7.2)."""
        return azimuth_span(self.maxima.phi)

    @property
    def slow_period(self) -> float | None:
        """Period of Θ = 2ψ sampled at the θ-maxima, from interpolated crossings of the mean
        (:func:`analysis.slow_diagnostics.slow_period`); None if not measurable within the run."""
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

    def state_at(self, t: ArrayLike) -> NDArray[np.float64]:
        """Body-frame state(s) at time(s) ``t`` from the integrator's dense output, shape (..., 11)."""
        t = np.asarray(t, float)
        return self.dense(t.reshape(-1)).reshape(t.shape + (11,))
