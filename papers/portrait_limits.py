"""The limits of a phase portrait (:func:`rocknroller.papers.portrait.slow_portrait`), checked before any work: the
number of map orbits and direct starts, and the θ-maxima all of them keep (memory and CSV size), with the grids'
ranges.  Each bad value is a ValueError naming the parameter and the limit.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import Body

__all__ = ["MAX_PORTRAIT_ORBITS", "MAX_ODE_STARTS", "MAX_PORTRAIT_MAXIMA", "BYTES_PER_MAXIMUM", "CSV_BYTES_PER_ROW",
           "check_portrait_size"]

#: Most map orbits of one portrait (grid points; each ~1 ms per 1000 time units).
MAX_PORTRAIT_ORBITS = 10_000
#: Most direct-ODE starts overlaid on one portrait.
MAX_ODE_STARTS = 100
#: Most θ-maxima one portrait may keep, over all its orbits and direct runs (each orbit is kept whole, drawn and
#: written, one CSV row a maximum): t_end/T_θ(0) an orbit (:func:`rocknroller.analysis.slow.work.map_maxima`).
MAX_PORTRAIT_MAXIMA = 1_000_000
#: Peak memory per θ-maximum of a portrait made, drawn and written (:func:`~rocknroller.papers.portrait_output.write_portrait`): 563 bytes measured
#: (20 orbits of 3e5 time units, 4.6e5 maxima).
BYTES_PER_MAXIMUM = 600
#: Bytes of one row of ``portrait.csv``: 147 measured (the same run).
CSV_BYTES_PER_ROW = 150


def _check_grid(name: str, values: ArrayLike, lo: float, hi: float) -> NDArray[np.float64]:
    a = np.atleast_1d(np.asarray(values, float))
    if a.ndim != 1 or a.size == 0 or not np.all(np.isfinite(a)) or np.any((a < lo) | (a > hi)):
        raise ValueError(f"{name} must be a non-empty 1-D grid of finite values in [{lo:.6g}, {hi:.6g}], "
                         f"got {values!r}")
    return a


def _size(n: float) -> str:
    """Bytes for people: 150 MB, 12 GB."""
    return f"{n / 1e9:.3g} GB" if n >= 1e9 else f"{n / 1e6:.3g} MB"


def check_portrait_size(body: Body, theta0: float, n_orbits: int, t_end: float, ode_t_ends: Sequence[float] = ()
                        ) -> float:
    """The estimated θ-maxima of a portrait of ``n_orbits`` map orbits over t_end and direct runs over ``ode_t_ends``
    (t_end/T_θ(0) each), or a ValueError naming t_end and the memory and CSV size they would take unless at most
    ``MAX_PORTRAIT_MAXIMA``."""
    from rocknroller.analysis.slow.work import map_maxima

    per_time = float(map_maxima(body, [theta0], 1.0)[0])  # maxima per time unit, 1/T_θ(0)
    n = per_time * (n_orbits * float(t_end) + float(sum(ode_t_ends)))
    if n > MAX_PORTRAIT_MAXIMA:
        most = (MAX_PORTRAIT_MAXIMA / per_time - float(sum(ode_t_ends))) / n_orbits
        raise ValueError(
            f"t_end must be at most {max(most, 0.0):.3g} for a portrait of {n_orbits} orbits (got t_end={t_end!r}): "
            f"it would keep about {n:.2g} theta-maxima, {_size(n * BYTES_PER_MAXIMUM)} of memory and a "
            f"{_size(n * CSV_BYTES_PER_ROW)} CSV, more than MAX_PORTRAIT_MAXIMA = {MAX_PORTRAIT_MAXIMA:.0e} "
            f"({_size(MAX_PORTRAIT_MAXIMA * BYTES_PER_MAXIMUM)}, a {_size(MAX_PORTRAIT_MAXIMA * CSV_BYTES_PER_ROW)} "
            "CSV); give a shorter t_end or fewer starts")
    return n
