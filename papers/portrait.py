"""Phase portrait of the slow motion: the averaged map's orbits from a grid of starts, in the (Θ, p) plane of the
standard map and in the (Q_R, Q_J) plane over the critical lines, with the direct ODE's θ-maxima of chosen starts
overlaid (``rocknroller portrait``).

The plane.  Near pure rocking the slow map is Chirikov's standard map p' = p + K sin Θ, Θ' = Θ + p' with
K = ε κ and p = ∇W(0)·Q (docs/averaging.md, "Closed forms"; :mod:`rocknroller.analysis.slow.dynamics.pendulum`).  A start
(Θ, p) of the grid is the maximum of θ with Θ = 2ψ and Q = (p / ∇W(0)·e) e on the kick direction e = C0/|C0| of
the release tables of (body, θ0) (:class:`rocknroller.analysis.slow.map.chart.SlowMapTable`: Q = (p/κ) C0, the pendulum's
line), with the energy E = U(θ0) of the release from rest at θ0; every orbit is plotted at its maxima as
(Θ mod 2π, ∇W(0)·Q) and as (Q_R, Q_J).  The releases from rest at θ0 are the line p = 0 (Q = 0, the origin of the
(Q_R, Q_J) plane), drawn in both panels.  For κ > 0 the stable rocking (ψ = π/2) is Θ = π, the unstable Θ = 0.

The map runs on the release tables (:class:`rocknroller.analysis.slow.map.maps.SlowMap`, order 1 or 2); an
orbit that leaves the tables is cut where it leaves and listed in ``SlowPortrait.left``.  The ODE's starts are the
same maxima (:func:`rocknroller.analysis.slow.map.family.maximum_state`), run by
:func:`rocknroller.numerics.ensembles.ensemble.run_ensemble`.

Colour.  Each orbit is coloured by one value (:func:`portrait_values`): the values passed in; else, by default, the
orbit's MEGNO (``SlowPortrait.chaos``: the map's tangent vector carried along the orbit,
``SlowMap.run(..., tangent=True)``, and :func:`rocknroller.analysis.slow.dynamics.chaos.map_indicators`, the indicators
``predict_slow_motion`` gives a release, over the same span, max(t_end, ``SPAN_ROCKS`` rocks): a release on the line
p = 0 gets the verdict and MEGNO of ``rocknroller slow`` to the bit, whatever t_end), on a colour scale clipped to [0, ``MEGNO_CLIP``] = [0, 5] (regular ≈ 2, a
stable periodic orbit 0, chaotic above 3, marked on the colour bar), grey where an orbit has fewer than
:data:`~rocknroller.numerics.megno.MIN_SAMPLES` maxima (it left the tables early); with ``chaos=False``, or for other
``orbits`` given (:func:`orbit_values`: their ``chaos.megno`` where every one carries it), as those say, else the
orbit's index in the grid.
"""

from __future__ import annotations

import math
import sys
import warnings
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import Body, as_float
from rocknroller.analysis.slow import prediction as av
from rocknroller.analysis.slow.dynamics.chaos import PROBE_ROCKS, MapChaos, indicator_span, map_indicators
from rocknroller.analysis.slow.map.compiled_map import SlowSeries, centre_period
from rocknroller.analysis.slow.map.family import maximum_state, rest_energy
from rocknroller.analysis.slow.map.limits import default_order
from rocknroller.analysis.slow.map.maps import SlowMap
from rocknroller.analysis.slow.map.tables_at_once import release_tables
from rocknroller.numerics.budget import WORK_BUDGET_SECONDS, check_work
from rocknroller.numerics.megno import MEGNO_CHAOTIC, MEGNO_CLIP, MIN_SAMPLES
from rocknroller.papers.output import new_figure
from rocknroller.papers.plotting import draw_critical_lines, scaled_axis
from rocknroller.papers.portrait_limits import (BYTES_PER_MAXIMUM, CSV_BYTES_PER_ROW, MAX_ODE_STARTS,  # re-exported
                                                MAX_PORTRAIT_MAXIMA, MAX_PORTRAIT_ORBITS, _check_grid,
                                                check_portrait_size, portrait_seconds)

if TYPE_CHECKING:
    import pandas

__all__ = ["N_P_DEFAULT", "SlowPortrait", "orbit_values", "portrait_values",
           "theta0_of_energy", "slow_portrait", "plot_portrait"]

@dataclass(frozen=True)
class SlowPortrait:
    """The slow map's orbits from a grid of starts in the (Θ, p) plane, and the ODE's maxima from chosen starts.

    Attributes
    ----------
    body : the asymmetric body (ε = body.epsilon).
    theta0, E : the release angle of the tables and its energy U(θ0) (every orbit's).
    t_end, order : time span of every orbit, the map's order.
    K : ε κ, the standard-map parameter.
    grad_W : ∇W(0) in (Q_R, Q_J), so that p = grad_W·Q.
    e : the kick direction (unit vector in (Q_R, Q_J)) along which the grid's Q lie.
    Theta0, p0 : the grid's starts, one per orbit.
    orbits : the map's samples at the θ-maxima of each orbit (t ≤ t_end, or until it left the tables).
    left : indices of the orbits that left the tables before t_end.
    ode_starts : the (Θ, p) of the direct runs.
    ode : the direct runs' θ-maxima (``TurningPoints``), one per ODE start.
    probes : for each orbit with indicators, its run over the horizon probe's window and its (Q_R, Q_J) extents over
        the indicators' span (what ``predict_slow_motion`` measures the horizon from); ``rock_time``: T_θ(0) of the
        tables, whose ``PROBE_ROCKS`` times is that window.
    chaos : the map's chaos indicators of each orbit (None for an orbit of fewer than ``MIN_SAMPLES`` maxima); empty
        for a portrait made with ``chaos=False``.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> portrait = rr.slow_portrait(rr.Body.paper(epsilon=5e-3), 0.95 * math.pi, [0.5, 1.5], [0.0], 200.0)
    >>> print(portrait.Theta0.tolist(), portrait.p0.tolist(), portrait.left)
    [0.5, 1.5] [0.0, 0.0] ()
    """

    body: Body
    theta0: float
    E: float
    t_end: float
    order: int
    K: float
    grad_W: NDArray[np.float64]
    e: NDArray[np.float64]
    Theta0: NDArray[np.float64]
    p0: NDArray[np.float64]
    orbits: tuple[SlowSeries, ...] = field(repr=False)
    left: tuple[int, ...] = ()
    ode_starts: tuple[tuple[float, float], ...] = ()
    ode: tuple[Any, ...] = field(default=(), repr=False)
    chaos: tuple[MapChaos | None, ...] = field(default=(), repr=False)
    probes: tuple[tuple[SlowSeries, tuple[float, float]] | None, ...] = field(default=(), repr=False, compare=False)
    rock_time: float = math.nan

    @property
    def megno(self) -> NDArray[np.float64]:
        """Each orbit's MEGNO, NaN where it has none (fewer than ``MIN_SAMPLES`` maxima).

        Raises
        ------
        ValueError
            A portrait made with ``chaos=False``.
        """
        if len(self.chaos) != len(self.orbits):
            raise ValueError("this portrait has no chaos indicators: make it with slow_portrait(..., chaos=True)")
        return np.array([math.nan if c is None else c.megno for c in self.chaos], dtype=float)

    def p(self, QR: ArrayLike, QJ: ArrayLike) -> NDArray[np.float64]:
        """p = ∇W(0)·Q of samples (Q_R, Q_J)."""
        return self.grad_W[0] * np.asarray(QR, float) + self.grad_W[1] * np.asarray(QJ, float)

    def to_dataframe(self) -> "pandas.DataFrame":
        """One row per θ-maximum of the map's orbits, then of the ODE's runs: source (``"map"`` or ``"ode"``), orbit
        index, its start (Θ0, p0), its MEGNO (missing where not measured, and for the ODE), t, Θ mod 2π, p, Q_R, Q_J
        (the columns of :func:`~rocknroller.papers.portrait_output.write_portrait`'s CSV; needs pandas)."""
        from rocknroller.analysis.model.frames import dataframe

        megno = self.megno if len(self.chaos) == len(self.orbits) else np.full(len(self.orbits), np.nan)
        runs = [("map", k, th, p0, m, s.t, s.Theta, s.QR, s.QJ)
                for k, (s, th, p0, m) in enumerate(zip(self.orbits, self.Theta0, self.p0, megno))]
        runs += [("ode", k, th, p0, np.nan, m.t, 2.0 * m.psi, m.QR, m.QJ)
                 for k, (m, (th, p0)) in enumerate(zip(self.ode, self.ode_starts))]
        n = [len(r[5]) for r in runs]
        cols: dict[str, Any] = {name: np.repeat(np.array([r[i] for r in runs], dtype=object if i == 0 else None), n)
                                for i, name in enumerate(("source", "orbit", "Theta0", "p0", "megno"))}
        t, Th, QR, QJ = (np.concatenate([r[i] for r in runs]) for i in (5, 6, 7, 8))
        cols.update(megno=np.ma.masked_invalid(cols["megno"]), t=t, Theta=np.mod(Th, 2.0 * math.pi),
                    p=self.p(QR, QJ), QR=QR, QJ=QJ)
        return dataframe(cols)

    def plot(self, values: ArrayLike | None = None, **kwargs: Any) -> Any:
        """The portrait's figure (:func:`plot_portrait`, with its ``values``, ``cmap`` and ``orbits``); returns it."""
        return plot_portrait(self, values, **kwargs)


def orbit_values(orbits: Sequence[Any], values: ArrayLike | None = None) -> tuple[NDArray[np.float64], str]:
    """One colour value per orbit and its label: ``values`` if given (finite, one per orbit); else the MEGNO of every
    orbit if each has ``chaos.megno`` (``getattr(orbit, "chaos", None)``); else the orbits' indices.

    Raises
    ------
    ValueError
        ``values`` of another length than ``orbits``, or not finite.
    """
    if values is not None:
        v = np.asarray(values, float)
        if v.shape != (len(orbits),) or not np.all(np.isfinite(v)):
            raise ValueError(f"values must be {len(orbits)} finite numbers, one per orbit, got shape {v.shape}")
        return v, "value"
    megno = [getattr(getattr(o, "chaos", None), "megno", None) for o in orbits]
    if orbits and all(m is not None for m in megno):
        return np.array(megno, dtype=float), "MEGNO"
    return np.arange(len(orbits), dtype=float), "orbit index"


def portrait_values(portrait: SlowPortrait, values: ArrayLike | None = None,
                    orbits: Sequence[Any] | None = None) -> tuple[NDArray[np.float64], str]:
    """One colour value per orbit of ``portrait`` and its label: ``values`` if given, else :func:`orbit_values` of
    ``orbits`` if given; else the orbits' MEGNO (``SlowPortrait.megno``, NaN where not measured; label
    ``"MEGNO"``) if the portrait has its indicators; else the orbits' indices.

    Raises
    ------
    ValueError
        ``values`` or ``orbits`` of another length than the portrait's orbits, or ``values`` not finite.
    """
    n = len(portrait.orbits)
    if orbits is not None and len(orbits) != n:
        raise ValueError(f"orbits must be {n} objects, one per orbit of the portrait, got {len(orbits)}")
    if values is not None or orbits is not None or len(portrait.chaos) != n:
        return orbit_values(portrait.orbits if orbits is None else orbits, values)
    return portrait.megno, "MEGNO"


def theta0_of_energy(body: Body, E: float) -> float:
    """The release angle θ0 in ``THETA0_RANGE`` whose energy from rest U(θ0) is E (Brent's method on
    :func:`rocknroller.analysis.slow.map.family.rest_energy`).

    Raises
    ------
    ValueError
        If E is not the energy of a release in ``THETA0_RANGE`` (naming the range of E).
    """
    from scipy.optimize import brentq

    sym = body.symmetric()
    lo, hi = av.THETA0_RANGE
    E_lo, E_hi = rest_energy(sym, lo), rest_energy(sym, hi)
    E = as_float("E", E)
    if not E_lo <= E <= E_hi:
        raise ValueError(f"E must be the energy of a release from rest in THETA0_RANGE = [0.75pi, 0.999pi], "
                         f"[{E_lo:.6g}, {E_hi:.6g}] for this body, got E={E!r}")
    return float(brentq(lambda th: rest_energy(sym, th) - E, lo, hi, xtol=1e-15, rtol=8.9e-16))


def _bar(total: int, progress: bool | None, desc: str) -> Any:
    from tqdm import tqdm

    enabled = sys.stderr.isatty() if progress is None else progress
    return tqdm(total=total, desc=desc, unit="orbit", disable=not enabled, leave=False, file=sys.stderr)


#: Default number of p values of the grid when none are given (:func:`slow_portrait`).
N_P_DEFAULT = 9


def slow_portrait(body: Body, theta0: float, Theta: ArrayLike, p: ArrayLike | None = None, t_end: float = 2000.0, *,
                  order: int | None = None, ode_starts: Sequence[tuple[float, float]] = (), ode_t_end: float | None = None,
                  build: bool = True, progress: bool | None = None,
                  budget: float | None = WORK_BUDGET_SECONDS, chaos: bool = True) -> SlowPortrait:
    """The slow map's orbits from the grid Θ × p at (body, θ0, ε = body.epsilon), and the direct ODE's θ-maxima
    from ``ode_starts`` (module docstring).

    Parameters
    ----------
    body : Body
        The asymmetric body, ε > 0.
    theta0 : float
        Release angle of the tables, in ``THETA0_RANGE`` = [0.75π, 0.999π] (the energy of every orbit is U(θ0);
        :func:`theta0_of_energy` gives θ0 from an energy).
    Theta, p : array_like
        The grid's values of Θ = 2ψ, in [−2π, 2π], and of p = ∇W(0)·Q, |p| within the tables (their half-length
        along the kick direction, |∇W(0)·e| U); one orbit per pair, at most ``MAX_PORTRAIT_ORBITS``.  p None:
        ``N_P_DEFAULT`` values evenly over ±1.5 times the half-width 2√K of the standard map's main resonance
        (within 0.9 of the tables' half-length).
    t_end : float
        Time span of each orbit (checked as ``iterate_slow_map`` checks it, and with the grid against
        ``MAX_PORTRAIT_MAXIMA``).
    order : {1, 2}, optional
        The map's order (2 builds or loads the second-order tables of (body, θ0)); default
        :func:`~rocknroller.analysis.slow.map.limits.default_order`, 2, as every entry's.
    ode_starts : sequence of (Θ, p)
        Starts run by the direct ODE over ``ode_t_end`` (default ``t_end``), at most ``MAX_ODE_STARTS``.
    build : bool
        Build the tables if they are not cached (else ValueError).
    progress : bool or None
        tqdm bars over the grid and the direct runs on stderr (None: only if stderr is a terminal).
    budget : float or None
        CPU seconds the portrait may take (None: no limit), estimated before any work
        (:func:`~rocknroller.papers.portrait_limits.portrait_seconds`: the tables not cached, the orbits with their
        tangent vectors, the direct runs); over it a ``WorkBudgetError`` (a ValueError) naming the estimate.
    chaos : bool
        Carry the map's tangent vector along each orbit and give it its chaos indicators (``SlowPortrait.chaos``,
        the colour of the orbits by default; ~1.5-1.8x the map's own cost, the orbits the same to the bit).

    Raises
    ------
    ValueError
        Naming the parameter: ε ≤ 0, θ0 out of range, a grid value out of range or too many orbits, a bad order,
        or more θ-maxima than ``MAX_PORTRAIT_MAXIMA`` in all (:func:`check_portrait_size`: memory and CSV size,
        before any table is built or orbit run); ``WorkBudgetError`` for an estimated cost over ``budget``, before any
        work.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> portrait = rr.slow_portrait(rr.Body.paper(epsilon=5e-3), 0.95 * math.pi, [0.5, 1.5], [0.0], 200.0)
    >>> print(len(portrait.orbits), f"K = {portrait.K:.4f}")
    2 K = 2.1311
    """
    if not isinstance(chaos, bool):
        raise ValueError(f"chaos must be True or False, got chaos={chaos!r}")
    eps = body.epsilon
    if not eps > 0.0:
        raise ValueError(f"eps must be > 0 for a portrait of the slow motion (at eps = 0 there is none), got "
                         f"eps={eps!r}")
    order = default_order(theta0) if order is None else order
    if order not in (1, 2) or isinstance(order, bool):
        raise ValueError(f"order must be 1 or 2, got order={order!r}")
    theta0 = av.check_map_theta0(theta0)
    Th = _check_grid("Theta", Theta, -2.0 * math.pi, 2.0 * math.pi)
    n_p = N_P_DEFAULT if p is None else np.atleast_1d(np.asarray(p, float)).size
    if Th.size * n_p > MAX_PORTRAIT_ORBITS:
        raise ValueError(f"the grid has {Th.size * n_p} starts (Theta x p), at most MAX_PORTRAIT_ORBITS = "
                         f"{MAX_PORTRAIT_ORBITS}")
    if not 0.0 < as_float("t_end", t_end) < math.inf:
        raise ValueError(f"t_end must be a finite number > 0, got t_end={t_end!r}")
    ode_span = t_end if ode_t_end is None else as_float("ode_t_end", ode_t_end)
    if not 0.0 < ode_span < math.inf:
        raise ValueError(f"ode_t_end must be a finite number > 0 (or None: t_end), got ode_t_end={ode_t_end!r}")
    check_portrait_size(body, theta0, Th.size * n_p, t_end, [ode_span] * len(ode_starts))
    seconds, what = portrait_seconds(body, theta0, Th.size * n_p, t_end, order=order, chaos=chaos,
                                     ode_t_ends=[ode_span] * len(ode_starts))
    check_work(seconds, what, budget)
    table = release_tables(body, theta0, 1, build=build, progress=progress)[0]  # the chart slow's tables use
    gu, gv = table.gradient("W", (0.0, 0.0))
    grad_W = gu * table.e + gv * table.n
    e = np.asarray(table.e, float)
    p_max = abs(float(grad_W @ e)) * table.U
    if p is None:
        p = np.linspace(-1.0, 1.0, N_P_DEFAULT) * min(3.0 * math.sqrt(eps * abs(table.kappa)), 0.9 * p_max)
    pp = _check_grid("p", p, -p_max, p_max)
    n = Th.size * pp.size
    pairs = [tuple(map(float, s)) for s in ode_starts]
    if len(pairs) > MAX_ODE_STARTS or any(len(s) != 2 for s in pairs):
        raise ValueError(f"ode_starts must be at most MAX_ODE_STARTS = {MAX_ODE_STARTS} pairs (Theta, p), "
                         f"got {ode_starts!r}")
    starts = [(s[0], s[1]) for s in pairs]
    for s_Th, s_p in starts:
        _check_grid("ode_starts Theta", s_Th, -2.0 * math.pi, 2.0 * math.pi)
        _check_grid("ode_starts p", s_p, -p_max, p_max)
    slow_map = SlowMap(body, theta0, eps, order, build=build)
    T, P = (g.ravel() for g in np.meshgrid(Th, pp, indexing="ij"))
    along = float(grad_W @ e)
    from rocknroller.numerics.ensembles.ensemble import Job, run_ensemble

    jobs = []  # made (and checked: t_end, the run's limits) before any work
    for s_Th, s_p in starts:
        QR, QJ = (s_p / along) * e
        state = maximum_state(body.symmetric(), eps, table.E0, QR, QJ, 0.5 * s_Th)[2]
        jobs.append(Job(body, state, t_end if ode_t_end is None else ode_t_end))
    orbits, left, indicators, probes = [], [], [], []
    rock_time = centre_period(table)
    span, window = indicator_span(t_end, rock_time), PROBE_ROCKS * rock_time
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", av.AveragingValidityWarning)  # K > 4 is stated in the portrait's title
        with _bar(n, progress, "portrait") as bar:
            for k, (th, pk) in enumerate(zip(T, P)):
                x = np.array([*((pk / along) * e), th])
                run = _indicator_run(slow_map, x, span) if chaos else None  # over the span slow measures over
                if run is not None:
                    s = run.until(t_end)
                else:
                    try:
                        s = slow_map.run(x, t_end, tangent=chaos)
                    except av.AveragingRangeError:
                        s = _until_left(slow_map, x, t_end, chaos)
                        left.append(k)
                    run = s
                orbits.append(s)
                if chaos:
                    indicators.append(None if run.log_growth is None else map_indicators(run.t, run.log_growth))
                    probes.append((run.until(window), (float(np.ptp(run.QR)), float(np.ptp(run.QJ))))
                                  if run.t.size else None)
                bar.update(1)
    ode = [] if not jobs else [r.maxima for r in run_ensemble(jobs, progress=progress, budget=budget)]
    return SlowPortrait(body=body, theta0=theta0, E=float(table.E0), t_end=float(t_end), order=order,
                        K=eps * table.kappa, grad_W=np.asarray(grad_W, float), e=e, Theta0=T, p0=P,
                        orbits=tuple(orbits), left=tuple(left), ode_starts=tuple(starts), ode=tuple(ode),
                        chaos=tuple(indicators), probes=tuple(probes), rock_time=rock_time)


def _indicator_run(slow_map: SlowMap, x: NDArray[np.float64], span: float) -> SlowSeries | None:
    """The orbit with its tangent vector over the chaos indicators' span (``indicator_span``, as
    ``predict_slow_motion`` runs a release: the same run, so the same verdict and MEGNO to the bit), or None where it
    leaves the tables before the span's end (then, as there, the indicators are those of the run over t_end)."""
    try:
        return slow_map.run(x, span, tangent=True)
    except av.AveragingRangeError:
        return None


def _until_left(slow_map: SlowMap, x: NDArray[np.float64], t_end: float, tangent: bool) -> SlowSeries:
    """The orbit up to its last maximum inside the tables: the longest n_steps that does not leave them (bisection on
    the number of steps; the map is deterministic, so a prefix is the same orbit), with its tangent vector if
    ``tangent`` (log_growth None for an empty orbit)."""
    lo, hi = 0, 1
    while True:  # grow until it leaves
        try:
            slow_map.run(x, t_end, n_steps=hi)
        except av.AveragingRangeError:
            break
        lo, hi = hi, 2 * hi
    while hi - lo > 1:
        mid = (lo + hi) // 2
        try:
            slow_map.run(x, t_end, n_steps=mid)
            lo = mid
        except av.AveragingRangeError:
            hi = mid
    if lo == 0:
        empty = np.empty(0)
        return SlowSeries(t=empty, QR=empty.copy(), QJ=empty.copy(), Theta=empty.copy(), phi=empty.copy())
    return slow_map.run(x, t_end, n_steps=lo, tangent=tangent)


def plot_portrait(portrait: SlowPortrait, values: ArrayLike | None = None, *, cmap: str = "viridis",
                  orbits: Sequence[Any] | None = None) -> Any:
    """Draw the portrait: (Θ mod 2π, p) on the left, (Q_R, Q_J) over the critical lines on the right; the map's
    orbits as dots coloured by :func:`portrait_values` (by default their MEGNO, clipped to [0, ``MEGNO_CLIP``], grey
    where not measured), the release line p = 0 (and its point Q = 0), and the ODE's maxima as black crosses.  The
    dots are drawn in the order of their values, the grey ones first: higher values over lower, so that the chaotic
    orbits (MEGNO > 3) are not hidden under the regular ones where their maxima share the (Q_R, Q_J) line.  The
    (Q_R, Q_J) axes are labelled in units of a power of ten (:func:`rocknroller.papers.plotting.scaled_axis`) with at
    most six ticks, so their labels stay apart.  Returns the figure."""
    import matplotlib
    from matplotlib import colors
    from matplotlib.ticker import MaxNLocator

    vals, label = portrait_values(portrait, values, orbits)
    megno = label == "MEGNO"
    cm = matplotlib.colormaps[cmap]
    if megno:
        norm = colors.Normalize(vmin=0.0, vmax=MEGNO_CLIP)
        cm = cm.with_extremes(bad="0.75")
    else:
        norm = colors.Normalize(vmin=float(vals.min()), vmax=float(vals.max()) if vals.max() > vals.min()
                                else float(vals.min()) + 1.0)
    fig = new_figure(figsize=(11, 4.6), layout="constrained")
    ax_p, ax_q = fig.subplots(1, 2)
    c = np.concatenate([np.full(s.t.size, v) for s, v in zip(portrait.orbits, vals)] + [np.empty(0)])
    QR, QJ, Th = (np.concatenate([getattr(s, k) for s in portrait.orbits] + [np.empty(0)])
                  for k in ("QR", "QJ", "Theta"))
    order = np.argsort(np.where(np.isnan(c), -np.inf, c), kind="stable")  # the highest values drawn last, on top
    c, QR, QJ, Th = c[order], QR[order], QJ[order], Th[order]
    dots = dict(c=c, s=0.6, cmap=cm, norm=norm, linewidths=0, rasterized=True)
    ax_p.scatter(np.mod(Th, 2.0 * math.pi), portrait.p(QR, QJ), **dots)
    ax_q.scatter(QR, QJ, **dots)
    for k, m in enumerate(portrait.ode):
        kw = dict(marker="x", s=6, color="k", linewidths=0.6, label="direct ODE (maxima)" if k == 0 else None)
        ax_p.scatter(np.mod(2.0 * m.psi, 2.0 * math.pi), portrait.p(m.QR, m.QJ), **kw)
        ax_q.scatter(m.QR, m.QJ, **kw)
    ax_p.axhline(0.0, color="tab:orange", ls=":", lw=1.2, label="release from rest (p = 0)")
    ax_p.set_xlim(0.0, 2.0 * math.pi)
    ax_p.set_xlabel(r"$\Theta = 2\psi$ mod $2\pi$")
    ax_p.set_ylabel(r"$p = \nabla W(0)\cdot Q$")
    ax_p.legend(fontsize=7, loc="upper right")
    QR_all = np.concatenate([QR] + [m.QR for m in portrait.ode] + [np.zeros(1)])
    QJ_all = np.concatenate([QJ] + [m.QJ for m in portrait.ode] + [np.zeros(1)])
    pad = 0.05 * max(float(np.ptp(QR_all)), 1e-12)
    draw_critical_lines(ax_q, portrait.body, float(QR_all.min()) - pad, float(QR_all.max()) + pad)
    ax_q.plot([0.0], [0.0], "o", color="tab:orange", ms=4, label="release from rest (Q = 0)")
    qj_pad = 0.05 * max(float(np.ptp(QJ_all)), 1e-12)
    ax_q.set_ylim(float(QJ_all.min()) - qj_pad, float(QJ_all.max()) + qj_pad)
    ax_q.xaxis.set_major_locator(MaxNLocator(nbins=6))
    scaled_axis(ax_q.xaxis, "$Q_R$", ax_q.get_xlim())
    scaled_axis(ax_q.yaxis, "$Q_J$", ax_q.get_ylim())
    ax_q.legend(fontsize=7, loc="upper left")
    from matplotlib.cm import ScalarMappable

    sm = ScalarMappable(norm=norm, cmap=cm)
    if megno:
        bar = fig.colorbar(sm, ax=[ax_p, ax_q], label=f"MEGNO (clipped at {MEGNO_CLIP:g}; > {MEGNO_CHAOTIC:g} "
                           f"chaotic; grey: < {MIN_SAMPLES} maxima)", shrink=0.9, aspect=30, extend="max")
        bar.ax.axhline(MEGNO_CHAOTIC, color="w", lw=1.5)
    else:
        fig.colorbar(sm, ax=[ax_p, ax_q], label=label, shrink=0.9, aspect=30)
    fig.suptitle(rf"slow map (order {portrait.order}) at $\varepsilon$ = {portrait.body.epsilon:.4g}, "
                 rf"$\theta_0$ = {portrait.theta0 / math.pi:.4g}$\pi$, K = $\varepsilon\kappa$ = {portrait.K:.3g}, "
                 f"t_end = {portrait.t_end:g}", fontsize=10)
    return fig
