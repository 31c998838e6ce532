"""The check of a map-made atlas (:class:`rocknroller.analysis.slow.atlas.Atlas`) by the direct ODE: a sample of its
points (and any the caller names) run as an ensemble (:func:`rocknroller.numerics.ensembles.ensemble.run_ensemble`), with
the map's relative errors there, and the map's chaos layer against the direct motion's indicators over the same span
(:func:`confirm_atlas`, :class:`AtlasCheck`; the atlas module's docstring, "Order and chaos").
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState
from rocknroller.analysis.slow.atlas import ATLAS_OBSERVABLES, CHAOS_OBSERVABLES, Atlas, _ode_values
from rocknroller.numerics.budget import WORK_BUDGET_SECONDS, check_work
from rocknroller.numerics.megno import MEGNO_CHAOTIC

__all__ = ["chaos_span", "AtlasCheck", "confirm_atlas", "confirm_seconds"]


@dataclass(frozen=True)
class AtlasCheck:
    """The direct ODE at some points of an atlas, and the map's relative errors there.

    Attributes
    ----------
    index : ndarray of int
        (N, 2): the (row, column) of each point.
    ode : dict, for each of the atlas's observables (``Atlas.observables``), the ODE's values (masked where
        undefined); ``megno`` and ``lyapunov`` are those of the direct motion's variational run over the same span
        (:func:`rocknroller.numerics.variational.direct_chaos_indicators`), masked where the map has none.
    rel_error : dict, the map's value / the ODE's − 1 (masked where either is undefined or the ODE's is 0);
        for the reversal counts, MEGNO and the Lyapunov exponent, the difference map − ODE instead (a regular
        orbit's MEGNO is ≈ 2 and its finite-time exponent ≈ 0 by either method: a ratio would measure noise).
    map : dict, the atlas's own values at those points, for the same names as ``ode``.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> atlas = rr.atlas_from_rest(body, [0.95 * math.pi], [0.3, 0.8], 200.0)
    >>> check = rr.confirm_atlas(atlas, body, every=1, chaos=False)
    >>> print(check.index.tolist(), sorted(check.ode) == sorted(check.map))
    [[0, 0], [0, 1]] True
    """

    index: NDArray[np.int64]
    ode: dict[str, np.ma.MaskedArray] = field(repr=False)
    rel_error: dict[str, np.ma.MaskedArray] = field(repr=False)
    map: dict[str, np.ma.MaskedArray] = field(default_factory=dict, repr=False)

    @property
    def verdict_agrees(self) -> np.ma.MaskedArray:
        """At each confirmed point, whether the map and the ODE give the same verdict, regular (MEGNO ≤
        ``MEGNO_CHAOTIC``) or chaotic; masked where either has no MEGNO.

        Raises
        ------
        ValueError
            A check without the chaos layer.
        """
        if "megno" not in self.ode:
            raise ValueError("this check has no chaos layer (the atlas was made with chaos=False, or confirm_atlas "
                             "was called with chaos=False)")
        return (self.map["megno"] <= MEGNO_CHAOTIC) == (self.ode["megno"] <= MEGNO_CHAOTIC)

    @property
    def verdict_agreement(self) -> float | None:
        """The fraction of the points with both MEGNOs at which the verdicts agree (None: no such point)."""
        agrees = self.verdict_agrees
        n = int(np.ma.count(agrees))
        return None if n == 0 else float(np.ma.sum(agrees)) / n


def _chosen(n_t: int, n_p: int, every: int | None, points: Sequence[tuple[int, int]]) -> list[int]:
    """The flat indices (row-major) of the points confirmed: 1 in ``every`` and ``points``; a ValueError naming
    ``every`` or ``points`` where they are not as :func:`confirm_atlas` states."""
    if every is not None and (int(every) != every or every < 1):
        raise ValueError(f"every must be an integer >= 1 or None, got every={every!r}")
    chosen = [] if every is None else list(range(0, n_t * n_p, int(every)))
    for i, j in points:
        if not (0 <= i < n_t and 0 <= j < n_p):
            raise ValueError(f"points must lie on the {n_t} x {n_p} grid, got {(i, j)!r}")
        chosen.append(int(i) * n_p + int(j))
    return sorted(set(chosen))


def confirm_seconds(body: Body, theta0: ArrayLike, psi0: ArrayLike, t_end: float, *, every: int | None = 50,
                    points: Sequence[tuple[int, int]] = (), chaos: bool = True) -> tuple[float, str]:
    """The estimated CPU seconds of :func:`confirm_atlas` on a release atlas over the grid ``theta0`` × ``psi0``
    (before the atlas is made: the points it confirms follow from the grid), and a phrase saying what they count: a
    direct run over t_end at each confirmed point (Λ t_end radians at ``HEYOKA_SECONDS_PER_RADIAN``, and
    ``DIRECT_RUN_SECONDS`` a run) and, with ``chaos``, a variational run there over the indicators' span
    (:func:`chaos_span`; ``VARIATIONAL_SECONDS_PER_RADIAN``; counted at every confirmed point, where the map's layer
    may be masked).

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> plain, _ = confirm_seconds(body, [0.95 * math.pi], [0.3, 0.8], 1000.0, every=1, chaos=False)
    >>> both, what = confirm_seconds(body, [0.95 * math.pi], [0.3, 0.8], 1000.0, every=1)
    >>> print(both > plain, "|", what.split(" and ")[0])
    True | the confirmation of 2 points (direct runs over t_end = 1000
    """
    from rocknroller.numerics.budget import DIRECT_RUN_SECONDS, HEYOKA_SECONDS_PER_RADIAN
    from rocknroller.numerics.run_limits import rate_bound
    from rocknroller.numerics.variational import VARIATIONAL_SECONDS_PER_RADIAN

    th, ps = np.atleast_1d(np.asarray(theta0, float)), np.atleast_1d(np.asarray(psi0, float))
    flat = _chosen(th.size, ps.size, every, points)
    rates = {}  # Λ of a release depends on θ0 alone (its energy)
    for f in flat:
        t0 = float(th[f // ps.size])
        if t0 not in rates:
            rates[t0] = rate_bound(body, EulerState(t0).to_body_state())
    radians = sum(rates[float(th[f // ps.size])] for f in flat) * float(t_end)
    spans = {t0: chaos_span(body, t0, t_end) for t0 in rates} if chaos else {}
    variational = sum(rates[float(th[f // ps.size])] * spans[float(th[f // ps.size])] for f in flat) if chaos else 0.0
    seconds = radians * HEYOKA_SECONDS_PER_RADIAN + variational * VARIATIONAL_SECONDS_PER_RADIAN \
        + len(flat) * DIRECT_RUN_SECONDS * (2 if chaos else 1)
    extra = " and variational runs over the span of the indicators" if chaos else ""
    return seconds, (f"the confirmation of {len(flat)} points (direct runs over t_end = {float(t_end):g}{extra}, "
                     "one of each a point)")


def chaos_span(body: Body, theta0: float, t_end: float) -> float:
    """The span of the chaos indicators of the release from rest at θ0 (the map's and the direct motion's alike):
    ``predict_slow_motion``'s, max(t_end, 1000 rocks) with T_θ(0) of the release by quadrature
    (:func:`~rocknroller.analysis.slow.dynamics.chaos.indicator_span`).

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> print(round(chaos_span(rr.Body.paper(1e-3), 0.95 * math.pi, 1000.0)))  # 1000 rocks of 13.26 time units
    13261
    """
    from rocknroller.analysis.slow.dynamics.chaos import indicator_span
    from rocknroller.analysis.slow.work import rocking_period

    return indicator_span(t_end, rocking_period(body, theta0))


def _ode_chaos(body: Body, states: Sequence[EulerState], spans: Sequence[float],
              threads: int | None) -> NDArray[np.float64]:
    """(MEGNO, λ) of the direct motion from each state over [0, its span], shape (2, len(states)): one variational run
    each (:func:`rocknroller.numerics.variational.direct_chaos_indicators`), on ``threads`` threads of this process
    (each run is the same whichever thread makes it)."""
    from concurrent.futures import ThreadPoolExecutor

    from rocknroller.numerics.variational import direct_chaos_indicators

    def one(state: EulerState, span: float) -> tuple[float, float]:
        ind = direct_chaos_indicators(body, state, span, budget=None).indicators
        return ind.megno, ind.lyapunov

    with ThreadPoolExecutor(max_workers=max(1, threads or 1)) as pool:
        found = list(pool.map(one, states, spans))
    return np.array(found, dtype=float).reshape(-1, 2).T


def confirm_atlas(atlas: Atlas, body: Body, *, every: int | None = 50, points: Sequence[tuple[int, int]] = (),
                  scheduler: str | None = None, workers: int | None = None, threads: int | None = None,
                  progress: bool | None = None, budget: float | None = WORK_BUDGET_SECONDS,
                  chaos: bool | None = None) -> AtlasCheck:
    """Run the direct ODE at 1 point in ``every`` (row-major, starting at the first; None: none) and at ``points``
    (row, column) of a map-made atlas, as an ensemble (:func:`rocknroller.numerics.ensembles.ensemble.run_ensemble`; where it
    runs does not change the numbers); ``budget``: the CPU seconds the direct and the variational runs may take
    together (:func:`confirm_seconds`, estimated before any run; None: no limit).

    ``chaos`` (None: whether the atlas has its chaos layer) also confirms the map's MEGNO and λ there by the direct
    motion's (:func:`rocknroller.numerics.variational.direct_chaos_indicators` over the map's span, :func:`chaos_span`, at the points
    where the map has them; on ``threads`` threads of this process whatever ``scheduler`` and ``workers`` say: the
    variational runs do not go through ``run_ensemble``); :attr:`AtlasCheck.verdict_agrees` compares the verdicts.

    Raises
    ------
    ValueError
        An atlas made by the ODE (there is nothing to confirm), ``every`` not an integer ≥ 1, a point outside the
        grid, ``chaos=True`` for an atlas without the chaos layer, or the ensemble's own limits, naming them.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> atlas = rr.atlas_from_rest(body, [0.95 * math.pi], [0.3, 0.8], 200.0)
    >>> check = rr.confirm_atlas(atlas, body, every=None, points=[(0, 1)], chaos=False)
    >>> print(abs(check.rel_error["Phi"][0]) < 0.01)
    True
    """
    if atlas.method != "map":
        raise ValueError(f"atlas.method must be 'map' to be confirmed by the ODE, got {atlas.method!r} (an atlas made "
                         "by the ODE is its own confirmation)")
    has_chaos = "megno" in atlas.values
    if chaos is None:
        chaos = has_chaos
    elif not isinstance(chaos, bool) or (chaos and not has_chaos):
        raise ValueError(f"chaos must be None, False, or True for an atlas with its chaos layer (atlas_from_rest's "
                         f"chaos=True), got chaos={chaos!r} for an atlas {'with' if has_chaos else 'without'} it")
    n_t, n_p = atlas.rows.size, atlas.cols.size
    flat = _chosen(n_t, n_p, every, points)
    if not flat:
        raise ValueError("nothing to confirm: give every or points")
    index = np.array([divmod(f, n_p) for f in flat], dtype=np.int64).reshape(-1, 2)
    states = [atlas.state(i, j) for i, j in index]
    names = ATLAS_OBSERVABLES + (CHAOS_OBSERVABLES if chaos else ())
    have = ~np.ma.getmaskarray(atlas.values["megno"][index[:, 0], index[:, 1]]) if chaos else np.zeros(0, bool)
    chaos_states = [s for s, h in zip(states, have) if h]
    check_work(*confirm_seconds(body, atlas.rows, atlas.cols, atlas.t_end, every=every, points=points,
                                chaos=bool(chaos_states)), budget)  # before any run
    out, mask = _ode_values(body, states, atlas.t_end, scheduler, workers, threads, progress, budget)
    ode = {name: np.ma.MaskedArray(out[k], mask[k]) for k, name in enumerate(ATLAS_OBSERVABLES)}
    if chaos:
        found = np.zeros((len(CHAOS_OBSERVABLES), len(states)))
        if chaos_states:
            spans = [chaos_span(body, s.theta, atlas.t_end) for s in chaos_states]
            found[:, have] = _ode_chaos(body, chaos_states, spans, threads)
        ode.update({name: np.ma.MaskedArray(found[k], ~have) for k, name in enumerate(CHAOS_OBSERVABLES)})
    rel: dict[str, np.ma.MaskedArray] = {}
    own = {name: atlas.values[name][index[:, 0], index[:, 1]] for name in names}
    for name, mv in own.items():
        if name.endswith("reversals") or name in CHAOS_OBSERVABLES:
            rel[name] = mv - ode[name]
        else:
            with np.errstate(divide="ignore", invalid="ignore"):
                rel[name] = np.ma.masked_invalid(mv / np.ma.masked_equal(ode[name], 0.0) - 1.0)
    return AtlasCheck(index=index, ode=ode, rel_error=rel, map=own)
