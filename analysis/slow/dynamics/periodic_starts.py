"""Periodic starts: a release from rest that lies on a periodic orbit of the slow map, reported as that orbit.

A release at ψ0 = 0 or π/2 (mod π) rocks in a principal plane (pure rocking, the map's fixed point), and any other
release that the map sends to itself or to its mirror image S x in one step lies on a fixed point or the S-symmetric
period-2 orbit; :func:`periodic_start` finds it with the machinery of
:mod:`rocknroller.analysis.slow.dynamics.periodic_orbits` (Newton's method on the map, multipliers, Greene's residue).
"""

from __future__ import annotations

import math

import numpy as np

from rocknroller.analysis.model.body import Body, float_or_nan
from rocknroller.analysis.model.diagnostics import wrap_angle
from rocknroller.analysis.slow.dynamics.periodic_orbits import (_ANGLE, _NEWTON_ITERATIONS, _RESIDUAL_ULPS, K_MAX,
                                                                PeriodicOrbit, PeriodicOrbitError, _newton, _orbit,
                                                                _Problem)
from rocknroller.analysis.slow.map.limits import AveragingRangeError

__all__ = ["on_rocking_axis", "periodic_start"]


def on_rocking_axis(psi0: float) -> bool:
    """True if ψ0 is 0 or π/2 (mod π) to within a few ulp of 2ψ0: a release from rest there rocks in a principal plane
    (pure rocking, Q = 0 at every maximum, by the symmetry S)."""
    r = float(np.mod(2.0 * float(psi0), math.pi))
    return min(r, math.pi - r) <= 8.0 * math.ulp(max(math.pi, abs(2.0 * float(psi0))))


def periodic_start(body: Body, theta0: float, psi0: float, *, order: int | None = None,
                   workers: int = 1) -> PeriodicOrbit | None:
    """The periodic orbit a release from rest at (θ0, ψ0) lies on, or None.  Released with ψ0 = 0 or π/2 (mod π,
    :func:`on_rocking_axis`) the body rocks in a principal plane (pure rocking, Q = 0 at every maximum, by the symmetry
    S): the map's fixed point there (Newton's method from the start; it lies within the tables' interpolation error of
    Q = 0), stable about the axis of :func:`rocknroller.analysis.slow.map.limits.stable_rocking_psi`, unstable about the
    other.  Any other start x = (0, 0, 2ψ0) of the slow map of ``order`` (body with its own ε) is reported as a fixed
    point if one step returns it to itself, and as the S-symmetric period-2 orbit if one step carries it to S x (module
    docstring), each to the residual ``_RESIDUAL_ULPS`` ulp of 4π that :func:`~rocknroller.analysis.slow.dynamics.periodic_orbits.periodic_orbit` solves to.  Its
    multipliers, Greene's residue and stability are :func:`~rocknroller.analysis.slow.dynamics.periodic_orbits.periodic_orbit`'s.  None for ε = 0 (Routh's sphere: every
    release is pure rocking, without a map to linearise) or K = εκ beyond ``K_MAX``.

    Raises
    ------
    ValueError
        θ0 outside ``THETA0_RANGE``, a non-finite ψ0, or order not 1 or 2 (naming it; default
        :func:`~rocknroller.analysis.slow.map.limits.default_order`, 2 on the release tables).
    """
    from rocknroller.analysis.slow.map.limits import check_map_theta0

    theta0 = check_map_theta0(theta0)
    psi0 = float_or_nan(psi0)
    if not math.isfinite(psi0):
        raise ValueError(f"psi0 must be finite, got psi0={psi0!r}")
    eps = body.epsilon
    if eps <= 0.0:
        return None
    from rocknroller.analysis.slow.map.tables_at_once import release_tables

    if eps * abs(release_tables(body, theta0, 1)[0].kappa) > K_MAX:
        return None
    problem = _Problem(body, theta0, eps, "slow", order, workers)
    x = np.array([0.0, 0.0, float(np.mod(2.0 * psi0, 2.0 * math.pi))])
    tol = _RESIDUAL_ULPS * np.finfo(float).eps * 4.0 * math.pi
    if on_rocking_axis(psi0):
        # pure rocking by the symmetry S of the body; the map's own fixed point lies within its tables' interpolation
        # error of Q = 0 (order 2: |F(x) - x| up to 1e-11 in Θ at K = 3.9, the harmonics of k₂ cancel at Q = 0 only to
        # that accuracy), found by Newton's method from the start
        x[_ANGLE] = 0.0 if abs(wrap_angle(x[_ANGLE])) < 0.5 * math.pi else math.pi
        try:
            x, k = _newton(problem, x, tol)
        except PeriodicOrbitError:
            k = _NEWTON_ITERATIONS  # reported with its residual, which says how far from a fixed point it is
        return _orbit(problem, x, 1, k, tol)
    try:
        fixed = problem.step(x) - x
    except AveragingRangeError:  # the first step leaves the release tables: no periodic orbit there
        return None
    fixed[_ANGLE] = float(wrap_angle(fixed[_ANGLE]))
    if float(np.max(np.abs(fixed))) <= tol:
        return _orbit(problem, x, 1, 0, tol)
    if float(np.max(np.abs(problem.G(x)))) <= tol:
        return _orbit(problem, x, 2, 0, tol)
    return None
