"""The accuracy knob of the direct runs: heyoka's tolerance ``tol``, its range and what follows from it.

heyoka's Taylor integrator takes one tolerance, relative and absolute at once: each step keeps its local error within
``tol`` · max(1, ‖y‖∞).  It sets the Taylor order, p = ⌈−ln(tol)/2⌉ + 1 (20 at tol = ε = 2u, the default; 14 at 1e-11,
12 at 1e-9, 8 at 1e-6), and the step follows from the series' radius of convergence, so the energy error comes in
levels, one per order, rather than in proportion to ``tol``.

What scales with ``tol``
------------------------
* The energy check (:func:`rocknroller.numerics.trajectory.energy_error_bound`): ``ENERGY_SLACK`` × (tol · n_steps + u).
  Its derivation holds at any tolerance: each step errs by at most tol of max(1, ‖y‖∞) (the unit vectors γ and e_X
  make ‖y‖∞ ≥ 1), the errors add at most linearly over n steps, and the energy, evaluated in double precision from
  the states, adds a few u relative to its scale.
* The smallest tilt resolved (:func:`theta_min`): ``THETA_MIN`` = 2¹⁰ u rests on the state's absolute error of u per
  step (:mod:`rocknroller.numerics.events`); at tolerance tol that error is tol/2 per step, so the smallest tilt at
  which the turning points keep a relative error ≤ 2⁻¹⁰ is 2¹⁰ · tol/2, ``THETA_MIN`` · tol/ε.
* The turning points: each run's are within n_steps · tol · max(1, ‖y‖∞) · S of the exact ones (S the amplification
  of an error by the flow), as at the default with tol for 2u (tests/numerics/test_batch.py derives the bound).

What does not: the location of the turning points on the dense output (to the rounding of t), the unwrapping grid,
the limits on a run's size, and the work estimate (a looser tolerance takes about as many steps of a lower order,
so :data:`rocknroller.numerics.budget.HEYOKA_SECONDS_PER_RADIAN`, measured at ε, bounds it).

Range
-----
``TOL_RANGE`` = [ε, 1e-6] in double precision (the unit round-off 2u of the precision run, and 1e-6).  Below ε heyoka
would ask its steps for more than their arithmetic holds; above 1e-6 the order drops below 8 and the energy bound,
10 tol per step, allows 1 % of the energy within 10³ steps: a run no longer worth its turning points.

Compilation
-----------
The compiled code depends on the order only, not on ``tol`` itself: heyoka's caches (in memory, and on disk in
``HEYOKA_CACHE_DIR``, both keyed by the generated code) hold one integrator per order.  A tolerance of an order not
yet compiled on the machine compiles once (measured: 0.4-0.9 s CPU for the scalar or the 8-lane batch integrator at
orders 9-10, 1.6 s for the batch one at order 14; the default order 20 ≈ 3 s, docs/performance.md), after which every
process loads it from the disk cache in ≈ 0.02 s CPU, and another tolerance of the same order is a hit in memory.
Each tolerance used keeps its own integrator per process and thread (≈ the default's memory).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from rocknroller.numerics.events import THETA_MIN

__all__ = ["DEFAULT_TOL", "TOL_MAX", "check_tol", "theta_min"]

#: heyoka's default tolerance in double precision: the machine epsilon ε = 2u = 2⁻⁵².
DEFAULT_TOL = float(np.finfo(float).eps)
#: The loosest tolerance accepted (module docstring, "Range").
TOL_MAX = 1e-6


def check_tol(tol: Any, name: str = "tol", lowest: float = DEFAULT_TOL) -> float:
    """``tol`` as a float, checked to lie in [``lowest``, ``TOL_MAX``].

    Parameters
    ----------
    tol : float
        The tolerance asked for.
    name : str
        The parameter as the user typed it (``"tol"``, or ``"--tol"`` on the command line).
    lowest : float
        The machine epsilon of the precision run (default double's, ``DEFAULT_TOL``).

    Raises
    ------
    ValueError
        Naming ``name`` and the range, for anything but a real number in the range.
    """
    try:
        value = float(tol) if not isinstance(tol, (bool, str, bytes)) else math.nan
    except (TypeError, ValueError, OverflowError):
        value = math.nan
    if not lowest <= value <= TOL_MAX:  # False for NaN
        raise ValueError(f"{name} must be a number in [{lowest:.6g}, {TOL_MAX:g}] (from the machine epsilon of the "
                         f"precision to {TOL_MAX:g}), got {name}={tol!r}")
    return value


def theta_min(tol: float) -> float:
    """The smallest amplitude of θ whose turning points a run at tolerance ``tol`` resolves: ``THETA_MIN`` at the
    default tolerance and below it (extended precision: the state is rounded to double), ``THETA_MIN`` · tol/ε above
    (module docstring)."""
    return THETA_MIN * max(1.0, tol / DEFAULT_TOL)
