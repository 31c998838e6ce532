"""The harmonics in Θ = 2ψ_n of the one-step ε-responses at a point Q, and the first-order coefficients of one step
there: the orbit stage of the averaging tables (:mod:`rocknroller.analysis.slow.map.table`).

By the rotational symmetry of Routh's sphere the first-order response of Q_R, Q_J, Θ, the time and φ to ε
(I2 = (1 + ε) I1) contains only the harmonics 0 and 2 of ψ_n (0 and 1 of Θ_n), so its values from three spin angles
ψ_n = 0, π/3, 2π/3 (``HARMONIC_PSI``) determine it (:func:`_harmonics`).  The three starts need not be three orbits:
the symmetry f(S y) = S f(y), S a turn about the axis (:func:`rocknroller.analysis.slow.map.orbit.rotate_about_axis`),
makes the orbit from ψ_k the turned orbit from 0, and its ε-response S_k ẑ_k with ẑ_k integrated along the orbit from
0 under the turned-back forcing S_kᵀ ∂f/∂ε(S_k y); its start, S_kᵀ z_k(0) = ∂y₀/∂θ_X ∂θ_X/∂ε, differs only in
∂θ_X/∂ε, which depends on ψ_k through ∂E/∂ε.  One orbit with three tangent systems (44 components,
``orbit._harmonic_system``) then replaces three orbits of 22, sharing the orbit and its Jacobian (the cost: the
performance page, ``benchmarks/bench_tables.py``), and the responses,
invariant under S, are read off the one orbit.  :func:`rocknroller.analysis.slow.map.orbit.first_order_steps` from the
three spin angles is the second formulation it is checked against (tests/analysis/slow/map/test_harmonic_orbit.py).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.diagnostics import wrap_angle
from rocknroller.analysis.routh.turning_points import turning_points
from rocknroller.analysis.slow.map.orbit import (FIRST_ORDER_NAMES, HARMONIC_PSI, FirstOrderStep, _phi_of, _psi_of,
                                              _responses, _start, _theta_shift, _to_next_maxima, rotate_about_axis,
                                              symmetric_data)

__all__ = ["StepCoefficients", "harmonic_steps", "step_coefficients"]


@dataclass(frozen=True)
class StepCoefficients:
    """First-order one-step coefficients at a given Q (paper-body units).

    Attributes
    ----------
    QR, QJ : float
    T : float
        T_θ(Q), time between maxima of the symmetric body (quadrature).
    W : float
        2(Δψ − π) wrapped to (−π, π] (quadrature, per T_θ).
    dphi : float
        Δφ per T_θ mod π in (−π/2, π/2] (quadrature).
    harmonics : dict
        For each name of ``FIRST_ORDER_NAMES``, (c0, c1, s1) with
        ε-response(Θ_n) = c0 + c1 cos Θ_n + s1 sin Θ_n, Θ_n = 2ψ_n.
    steps : tuple of FirstOrderStep
        The steps from the three spin angles ψ_n in ``HARMONIC_PSI``: one orbit turned (the same T, Δψ, Δφ and θ_X),
        each with its own ε-responses.
    """

    QR: float
    QJ: float
    T: float
    W: float
    dphi: float
    harmonics: dict[str, tuple[float, float, float]]
    steps: tuple[FirstOrderStep, ...] = field(repr=False)

    def response(self, name: str, psi: ArrayLike) -> NDArray[np.float64]:
        """ε-response ``name`` at spin angle(s) ψ_n."""
        c0, c1, s1 = self.harmonics[name]
        Th = 2.0 * np.asarray(psi, float)
        return c0 + c1 * np.cos(Th) + s1 * np.sin(Th)


def _harmonics(values: ArrayLike) -> NDArray[np.float64]:
    """(c0, c1, s1) from values at Θ = 0, 2π/3, 4π/3 (last axis)."""
    v = np.asarray(values, float)
    Th = 2.0 * np.asarray(HARMONIC_PSI)
    return np.stack([v.mean(axis=-1), (2.0 / 3.0) * (v * np.cos(Th)).sum(axis=-1),
                     (2.0 / 3.0) * (v * np.sin(Th)).sum(axis=-1)], axis=-1)


def harmonic_steps(body: Body, E: float, QR: ArrayLike, QJ: ArrayLike, theta_X: ArrayLike | None = None, *,
                   lanes: int | None = None) -> tuple[FirstOrderStep, NDArray[np.float64]]:
    """The steps from the three spin angles (ψ_n in ``HARMONIC_PSI``) at each of N points Q and the harmonics
    (c0, c1, s1) of their ε-responses, shape (len(FIRST_ORDER_NAMES), N, 3); the steps' fields are arrays (N, 3), in
    which T, Δψ, Δφ and θ_X repeat across the three (one orbit, turned).  θ_X as in
    :func:`~rocknroller.analysis.slow.map.orbit.first_order_steps`.

    One orbit per Q carries the three: by Routh's sphere's symmetry the orbit from ψ_k is S_k y(t), y(t) the one
    from ψ = 0 (:func:`~rocknroller.analysis.slow.map.orbit.rotate_about_axis`), and its ε-response S_k ẑ_k, with ẑ_k integrated along y(t) under the
    forcing turned back by S_k (``orbit._harmonic_system``, in the batch integrator's lanes: ``lanes``).  The outputs
    (Q_R, Q_J, ψ and φ advances, the event time) do not change under S_k, so each is read off (y, ẑ_k) at the next
    maximum.  Three orbits each with its own response (:func:`~rocknroller.analysis.slow.map.orbit.first_order_steps`) give the same numbers to the
    integration's accuracy (tests/analysis/slow/map/test_harmonic_orbit.py)."""
    sym = body.symmetric()
    given = [v for v in (QR, QJ, theta_X) if v is not None]
    flat = [np.ravel(v) for v in np.broadcast_arrays(*(np.asarray(v, float) for v in given))]
    QR, QJ = flat[0], flat[1]
    theta_X = flat[2] if theta_X is not None else np.asarray(turning_points(E, QR, QJ, sym)[1], float)
    y0, dy_dth, dU = _start(sym, theta_X, QR, QJ, np.zeros_like(QR))
    # the start from ψ_k is S_k y₀ and its ε-derivative S_k ∂y₀/∂θ_X ∂θ_X/∂ε, turned back by S_kᵀ
    starts = [y0] + [dy_dth * _theta_shift(sym, np.array(rotate_about_axis(y0, psi)), dU) for psi in HARMONIC_PSI]
    t1, out = _to_next_maxima("harmonic", sym, np.concatenate(starts), lanes)
    Y = out[:11]
    d = [_responses(sym, Y, out[11 * (k + 1):11 * (k + 2)]) for k in range(len(HARMONIC_PSI))]

    def grid(v: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.repeat(np.asarray(v, float)[:, None], len(HARMONIC_PSI), axis=1)

    st = FirstOrderStep(QR=grid(QR), QJ=grid(QJ), psi=np.broadcast_to(HARMONIC_PSI, (len(QR), 3)).copy(),
                        theta_X=grid(theta_X), T=grid(t1), dpsi=grid(wrap_angle(_psi_of(Y), math.pi)),
                        dphi=grid(wrap_angle(_phi_of(Y) - _phi_of(y0), math.pi)),
                        d={name: np.stack([dk[name] for dk in d], axis=1) for name in FIRST_ORDER_NAMES})
    return st, np.stack([_harmonics(st.d[name]) for name in FIRST_ORDER_NAMES])


def step_coefficients(body: Body, E: float, QR: float, QJ: float) -> StepCoefficients:
    """The first-order one-step coefficients at energy E and Q = (Q_R, Q_J) (:func:`harmonic_steps`)."""
    sym = body.symmetric()
    T, W, dphi, theta_X = (float(x) for x in symmetric_data(sym, E, QR, QJ))
    st, resp = harmonic_steps(sym, E, QR, QJ, theta_X)
    steps = tuple(st.at(0, k) for k in range(len(HARMONIC_PSI)))
    harm = {name: (float(c0), float(c1), float(s1)) for name, (c0, c1, s1) in zip(FIRST_ORDER_NAMES, resp[:, 0])}
    return StepCoefficients(QR=float(QR), QJ=float(QJ), T=T, W=W, dphi=dphi, harmonics=harm, steps=steps)


