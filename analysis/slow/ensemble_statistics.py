"""Statistics of the slow motion where it is chaotic: distributions over a small ball of starts, by the averaged map and
by the direct ODE, and their comparison by a stated two-sample test.

Where the slow motion is chaotic a prediction holds point by point only up to a horizon of a few Lyapunov times; past
it what the theory can predict is statistical.  This module takes a release from rest at (θ0, ψ0), an ensemble of
starts in a stated ball about it (:class:`StartBall`: ψ0 ± δ, uniform, seeded; θ0 and rest fixed), and gives per member,
over the stated time span [0, t_end] (:func:`member_statistics`):

* ``fraction_I`` … ``fraction_IV``: the fraction of its rocks (θ-maxima) in each critical region I–IV;
* ``full_reversals``, ``visible_reversals``: the reversals per 1000 time units, crossings of Q_J,0^crit (full-angle)
  and of Q_J,π^crit (visible-angle) between consecutive θ-maxima;
* ``QR_extent``, ``QJ_extent``: max − min of Q_R and Q_J at the maxima.

The regions and crossings are the package's own (:func:`rocknroller.analysis.slow.prediction_result.critical_regions`, paper
§criticality and §Recession; the counts per 1000 time units :func:`rocknroller.analysis.slow.atlas.reversal_counts`,
as in the recession atlas), applied to the θ-maxima of either method alike.  The map's ensemble runs
:func:`rocknroller.analysis.slow.prediction.predict_slow_motion` per member (:func:`map_ensemble`), the direct ODE's
:func:`rocknroller.numerics.ensembles.ensemble.run_ensemble` (:func:`ode_ensemble`: in process, threads or a dask cluster).

The test (:func:`compare_ensembles`).  For each statistic the two samples x (map, n members) and y (ODE, m members)
are called *consistent* if either

* the two-sample Kolmogorov–Smirnov test (``scipy.stats.ks_2samp``, two-sided) gives p > α = ``KS_ALPHA`` = 0.01, or
* the means differ by at most ``N_STANDARD_ERRORS`` = 3 standard errors of their difference,
  |x̄ − ȳ| ≤ 3 √(s_x²/n + s_y²/m) (sample variances, ddof = 1).

The second clause is there for the discrete statistics (reversal counts are integers per member, region fractions
multiples of 1/rocks), whose ties make the KS test's p-value conservative but whose many equal values can still
reject on a small shift of the whole distribution; a statistic constant across both ensembles is consistent only if
the two constants are equal.  Members started in one ball are not independent draws of the invariant measure: they
share the motion up to the ball's own horizon, so the test compares the two methods' distributions for this ball and
this time span, the quantity a user asks for, not an ergodic average.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, ClassVar, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.criticality.lines import REGIONS
from rocknroller.analysis.model.body import Body, as_float
from rocknroller.analysis.model.diagnostics import span
from rocknroller.analysis.model.equations import EulerState
from rocknroller.analysis.slow import prediction as av
from rocknroller.analysis.slow.atlas import reversal_counts
from rocknroller.analysis.slow.work import check_map_work
from rocknroller.numerics.budget import WORK_BUDGET_SECONDS

if TYPE_CHECKING:
    import pandas

__all__ = ["STATISTICS", "STATISTIC_UNITS", "DISTRIBUTION_STATISTICS", "KS_ALPHA", "N_STANDARD_ERRORS", "MAX_MEMBERS", "StartBall", "member_statistics",
           "EnsembleStatistics", "map_ensemble", "ode_ensemble", "StatisticComparison", "EnsembleComparison",
           "compare_ensembles"]

#: The statistics of one member, in this order: region fractions, reversals per 1000 time units, extents.
STATISTICS = tuple(f"fraction_{r}" for r in REGIONS) + ("full_reversals", "visible_reversals", "QR_extent",
                                                       "QJ_extent")
#: The unit of each statistic that has one (``rocknroller slow`` prints it beside the value); the region fractions are
#: fractions of the rocks, the extents in the units of Q_R and Q_J.
STATISTIC_UNITS = {"full_reversals": "per 1000 time units", "visible_reversals": "per 1000 time units"}
#: The statistics whose distributions the map and the ODE must give consistently (region fractions and reversal
#: counts); the extents are compared too, and reported beside them.
DISTRIBUTION_STATISTICS = STATISTICS[:6]
#: Significance level of the two-sample KS test: p above it is consistent.
KS_ALPHA = 0.01
#: Means within this many standard errors of their difference are consistent.
N_STANDARD_ERRORS = 3.0
#: Most members of one ensemble (the ODE's cost is checked against its budget besides; the map's is ~1 ms a member
#: per 1000 time units).
MAX_MEMBERS = 10_000


@dataclass(frozen=True)
class StartBall:
    """An ensemble of releases from rest: θ0 fixed, ψ0 drawn uniformly from [ψ0 − δ, ψ0 + δ] with a seeded generator.

    Parameters
    ----------
    theta0 : float
        Release tilt, 0 < θ0 ≤ 0.999π (as :func:`rocknroller.analysis.slow.prediction.predict_slow_motion` takes it).
    psi0 : float
        Centre of the ball in ψ0 (finite).
    delta : float
        Half-width of the ball, 0 < δ ≤ π/2.
    members : int
        Number of starts, 2 ≤ members ≤ ``MAX_MEMBERS``.
    seed : int
        Seed of ``numpy.random.default_rng`` (≥ 0): the same ball gives the same starts.

    Raises
    ------
    ValueError
        Naming the parameter and its range.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> ball = rr.StartBall(theta0=0.95 * math.pi, psi0=math.pi / 4, delta=0.01, members=4, seed=1)
    >>> psi0 = ball.psi0_values()
    >>> print(psi0.size, bool(abs(psi0 - math.pi / 4).max() <= 0.01))
    4 True
    """

    theta0: float
    psi0: float
    delta: float
    members: int
    seed: int = 0

    def __post_init__(self) -> None:
        object.__setattr__(self, "theta0", av.check_release_theta0(self.theta0))
        psi0, delta = as_float("psi0", self.psi0), as_float("delta", self.delta)
        if not math.isfinite(psi0):
            raise ValueError(f"psi0 must be finite, got psi0={self.psi0!r}")
        if not 0.0 < delta <= 0.5 * math.pi:
            raise ValueError(f"delta must be a half-width in (0, pi/2], got delta={self.delta!r}")
        for name, value, lo, hi in (("members", self.members, 2, MAX_MEMBERS), ("seed", self.seed, 0, 2**63 - 1)):
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not lo <= value <= hi:
                raise ValueError(f"{name} must be a whole number in [{lo}, {hi}], got {name}={value!r}")
        object.__setattr__(self, "psi0", psi0)
        object.__setattr__(self, "delta", delta)
        object.__setattr__(self, "members", int(self.members))
        object.__setattr__(self, "seed", int(self.seed))

    def psi0_values(self) -> NDArray[np.float64]:
        """The members' ψ0, uniform on [ψ0 − δ, ψ0 + δ] (``numpy.random.default_rng(seed)``)."""
        return np.random.default_rng(self.seed).uniform(self.psi0 - self.delta, self.psi0 + self.delta, self.members)

    def describe(self) -> str:
        """One line: θ0, ψ0 ± δ, members and seed."""
        return (f"theta0 = {self.theta0 / math.pi:.6g} pi, psi0 = {self.psi0:.6g} +- {self.delta:.3g} (uniform), "
                f"{self.members} members, seed {self.seed}")


def member_statistics(body: Body, t: ArrayLike, QR: ArrayLike, QJ: ArrayLike, t_end: float) -> dict[str, float]:
    """The ``STATISTICS`` of one member from its θ-maxima (t, Q_R, Q_J) within [0, t_end] (module docstring).

    Raises
    ------
    ValueError
        If there is no maximum, the arrays differ in length, or t_end is not a finite number > 0 at or after the
        last maximum.
    """
    t, QR, QJ = (np.asarray(v, float) for v in (t, QR, QJ))
    t_end = as_float("t_end", t_end)
    if t.ndim != 1 or t.size == 0 or QR.shape != t.shape or QJ.shape != t.shape:
        raise ValueError(f"t, QR, QJ must be 1-d arrays of one length >= 1 (the theta-maxima), got shapes {t.shape}, "
                         f"{QR.shape}, {QJ.shape}")
    if not (math.isfinite(t_end) and t_end > 0.0 and t_end >= t[-1]):
        raise ValueError(f"t_end must be a finite number > 0, at or after the last maximum (t = {t[-1]:.6g}), "
                         f"got t_end={t_end!r}")
    _, runs, crossings = av.critical_regions(QR, QJ, t, body)
    rocks = av.rocks_per_region(runs)
    full, visible = reversal_counts(crossings, t_end)
    out = {f"fraction_{r}": rocks.get(r, 0) / t.size for r in REGIONS}
    out.update(full_reversals=full, visible_reversals=visible, QR_extent=span(QR), QJ_extent=span(QJ))
    return out


@dataclass(frozen=True)
class EnsembleStatistics:
    """The ``STATISTICS`` of every member of an ensemble, by one method.

    Attributes
    ----------
    method : ``"map"`` (the averaged map, of ``order``) or ``"ode"`` (the direct ODE).
    eps : the body's ε.
    ball : the starts.
    t_end : time span of every member.
    values : dict
        For each of ``STATISTICS`` an array of one value per member (in the order of ``ball.psi0_values()``, without
        the members in ``left``).
    rocks : number of θ-maxima of each member within t_end.
    order : the map's order in ε (None for the ODE).
    warnings : the distinct validity warnings of the map's predictions (e.g. K = ε κ > 4).
    left : the ψ0 of the map's members whose slow orbit left the tables before t_end (counted, not in ``values``).

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> ball = rr.StartBall(theta0=0.95 * math.pi, psi0=math.pi / 4, delta=0.1, members=4)
    >>> stats = rr.map_ensemble(body, ball, 200.0, order=1)
    >>> print(stats.order, sorted(stats.values)[:3])
    1 ['QJ_extent', 'QR_extent', 'fraction_I']
    """

    method: str
    eps: float
    ball: StartBall
    t_end: float
    values: dict[str, NDArray[np.float64]] = field(repr=False)
    rocks: NDArray[np.int64] = field(repr=False)
    order: int | None = None
    warnings: tuple[str, ...] = ()
    left: tuple[float, ...] = ()
    units: ClassVar[dict[str, str]] = STATISTIC_UNITS  #: the statistics' units (``STATISTIC_UNITS``), for the figures

    def mean(self, name: str) -> float:
        """Mean of one statistic over the members."""
        return float(np.mean(self._values(name)))

    def standard_error(self, name: str) -> float:
        """Standard error of that mean, s/√n (sample standard deviation, ddof = 1)."""
        x = self._values(name)
        return float(np.std(x, ddof=1) / math.sqrt(x.size))

    def _values(self, name: str) -> NDArray[np.float64]:
        if name not in self.values:
            raise ValueError(f"name must be one of {STATISTICS}, got name={name!r}")
        return self.values[name]

    def to_dataframe(self) -> "pandas.DataFrame":
        """One row per member: its ψ0 (``ball.psi0_values()``), its rocks within t_end and its ``STATISTICS``
        (needs pandas)."""
        from rocknroller.analysis.model.frames import dataframe

        return dataframe({"psi0": self.ball.psi0_values(), "rocks": self.rocks, **self.values})

    def plot(self, fig: Any = None) -> Any:
        """The figure of the statistics over the members (histograms, one panel each, the x axes labelled with
        :attr:`units`) on ``fig``, a new pyplot figure without one (:func:`~.result_plots.plot_statistics`).

        Examples
        --------
        >>> import math, matplotlib.figure, rocknroller as rr
        >>> ens = rr.map_ensemble(rr.Body.paper(1e-3), rr.StartBall(0.95 * math.pi, 0.8, 0.1, 4), 200.0, order=1)
        >>> print(ens.plot(matplotlib.figure.Figure(figsize=(13, 5.2))).axes[4].get_xlabel())
        full-angle reversals (per 1000 time units)
        """
        from rocknroller.analysis.slow.dynamics.result_plots import plot_statistics

        return plot_statistics(self, fig)


def _collect(method: str, body: Body, ball: StartBall, t_end: float, members: list[dict[str, float]],
             rocks: list[int], order: int | None = None, caught: tuple[str, ...] = ()) -> EnsembleStatistics:
    values = {name: np.array([m[name] for m in members]) for name in STATISTICS}
    return EnsembleStatistics(method=method, eps=body.epsilon, ball=ball, t_end=float(t_end), values=values,
                              rocks=np.array(rocks, dtype=np.int64), order=order, warnings=caught)


def map_ensemble(body: Body, ball: StartBall, t_end: float, *, order: int | None = None,
                 progress: bool | None = None, budget: float | None = WORK_BUDGET_SECONDS) -> EnsembleStatistics:
    """The ensemble's statistics by the averaged map (:func:`rocknroller.analysis.slow.prediction.predict_slow_motion`
    per member, on one table).

    Parameters
    ----------
    body : Body
    ball : StartBall
    t_end : float
        Time span of each member (checked as ``predict_slow_motion`` checks it).
    order : {1, 2}, optional
        The map's order; default that of ``predict_slow_motion`` (:func:`rocknroller.analysis.slow.prediction.default_order`).
    progress : bool or None
        A tqdm bar for a table built here (as ``predict_slow_motion``'s).
    budget : float or None
        CPU seconds the members' runs may take together (:mod:`rocknroller.numerics.budget`; None: no limit),
        estimated before any work (:func:`rocknroller.analysis.slow.work.check_map_work`).

    Returns
    -------
    EnsembleStatistics
        Its ``warnings`` hold the predictions' distinct :class:`AveragingValidityWarning` messages, each also issued
        once here; its ``left`` the ψ0 of the members whose slow orbit left the tables (their statistics are left out,
        the other members' kept).

    Raises
    ------
    AveragingRangeError
        If fewer than two members stay on the tables (no standard deviation).
    WorkBudgetError
        A ValueError: the estimated work exceeds ``budget`` (before any run).

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> ball = rr.StartBall(theta0=0.95 * math.pi, psi0=math.pi / 4, delta=0.1, members=4)
    >>> stats = rr.map_ensemble(body, ball, 200.0, order=1)
    >>> print(stats.method, stats.values["QR_extent"].shape, stats.rocks)
    map (4,) [15 15 15 15]
    """
    if not isinstance(ball, StartBall):
        raise ValueError(f"ball must be a StartBall, got {type(ball).__name__}")
    if order is None:
        order = av.default_order(ball.theta0)
    if order not in (1, 2) or isinstance(order, bool):
        raise ValueError(f"order must be 1 or 2, got order={order!r}")
    check_map_work(body, [ball.theta0], ball.members, t_end, order,
                   f"an ensemble of {ball.members} map runs of {float(t_end):g} time units each", budget)
    members, rocks = [], []
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", av.AveragingValidityWarning)
        left = []
        for psi0 in ball.psi0_values():
            try:
                pred = av.predict_slow_motion(body, ball.theta0, float(psi0), t_end, order=order, progress=progress,
                                              indicators=False)  # the statistics need the orbit only
            except av.AveragingRangeError:
                left.append(float(psi0))
                continue
            s = pred.series
            members.append(member_statistics(body, s.t, s.QR, s.QJ, t_end))
            rocks.append(s.t.size)
    distinct = tuple(dict.fromkeys(str(w.message) for w in caught if issubclass(w.category,
                                                                               av.AveragingValidityWarning)))
    for message in distinct:
        warnings.warn(message, av.AveragingValidityWarning, stacklevel=2)
    if len(members) < 2:
        raise av.AveragingRangeError(f"{len(left)} of the {ball.members} members' slow orbits left the tables before "
                                     f"t_end={t_end!r} ({ball.describe()}): fewer than two remain for statistics")
    return replace(_collect("map", body, ball, t_end, members, rocks, order=order, caught=distinct), left=tuple(left))


def ode_ensemble(body: Body, ball: StartBall, t_end: float, *, scheduler: str | None = None,
                 workers: int | None = None, threads: int | None = None, progress: bool | None = None,
                 budget: float | None = WORK_BUDGET_SECONDS) -> EnsembleStatistics:
    """The ensemble's statistics by the direct ODE (:func:`rocknroller.numerics.ensembles.ensemble.run_ensemble`: ``scheduler``,
    ``workers``, ``threads``, ``progress`` and ``budget`` as there; the summaries are the same bit for bit whichever
    way they run).

    Raises
    ------
    ValueError
        A bad ``t_end`` (each member's :class:`rocknroller.numerics.ensembles.ensemble.Job` checks it), a run over ``budget``,
        or a member without any θ-maximum within t_end.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> ball = rr.StartBall(theta0=0.95 * math.pi, psi0=math.pi / 4, delta=0.1, members=4)
    >>> stats = rr.ode_ensemble(body, ball, 200.0)
    >>> print(stats.method, stats.values["QR_extent"].shape, stats.rocks)
    ode (4,) [15 15 15 15]
    """
    from rocknroller.numerics.ensembles.ensemble import Job, run_ensemble

    if not isinstance(ball, StartBall):
        raise ValueError(f"ball must be a StartBall, got {type(ball).__name__}")
    jobs = [Job(body, EulerState(ball.theta0, 0.0, float(psi0)), t_end) for psi0 in ball.psi0_values()]
    runs = run_ensemble(jobs, scheduler=scheduler, workers=workers, threads=threads, progress=progress,
                        budget=budget)
    members = [member_statistics(body, r.maxima.t, r.maxima.QR, r.maxima.QJ, t_end) for r in runs]
    return _collect("ode", body, ball, t_end, members, [r.n_maxima for r in runs])


@dataclass(frozen=True)
class StatisticComparison:
    """One statistic of two ensembles under the stated test (module docstring).

    Attributes
    ----------
    name : one of ``STATISTICS``.
    mean_a, se_a, mean_b, se_b : means and their standard errors.
    ks_statistic, ks_pvalue : the two-sample KS statistic and its two-sided p-value.
    n_se : |mean_a − mean_b| in standard errors of the difference (inf if that is 0 and the means differ, 0 if they
        are equal).
    consistent : ``ks_pvalue > alpha`` or ``n_se <= n_se_limit`` of the comparison.
    """

    name: str
    mean_a: float
    se_a: float
    mean_b: float
    se_b: float
    ks_statistic: float
    ks_pvalue: float
    n_se: float
    consistent: bool


@dataclass(frozen=True)
class EnsembleComparison:
    """Two ensembles of one ball compared statistic by statistic (:func:`compare_ensembles`).

    Attributes
    ----------
    a, b : the ensembles (``a`` usually the map's, ``b`` the ODE's).
    alpha, n_se_limit : the test's KS level and its limit in standard errors.
    statistics : one :class:`StatisticComparison` per name of ``STATISTICS``.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> ball = rr.StartBall(theta0=0.95 * math.pi, psi0=math.pi / 4, delta=0.1, members=8)
    >>> cmp = rr.compare_ensembles(rr.map_ensemble(body, ball, 200.0, order=1), rr.ode_ensemble(body, ball, 200.0))
    >>> print(cmp.a.method, cmp.b.method, [s.name for s in cmp.statistics][-2:])
    map ode ['QR_extent', 'QJ_extent']
    """

    a: EnsembleStatistics = field(repr=False)
    b: EnsembleStatistics = field(repr=False)
    alpha: float
    n_se_limit: float
    statistics: tuple[StatisticComparison, ...]

    @property
    def consistent(self) -> bool:
        """True if every statistic is consistent."""
        return all(s.consistent for s in self.statistics)

    def consistent_on(self, names: Sequence[str]) -> bool:
        """True if each statistic of ``names`` (e.g. ``DISTRIBUTION_STATISTICS``) is consistent."""
        return all(self[name].consistent for name in names)

    def __getitem__(self, name: str) -> StatisticComparison:
        for s in self.statistics:
            if s.name == name:
                return s
        raise ValueError(f"name must be one of {STATISTICS}, got name={name!r}")

    def to_dataframe(self) -> "pandas.DataFrame":
        """One row per statistic: the fields of its :class:`StatisticComparison` (needs pandas)."""
        from dataclasses import fields

        from rocknroller.analysis.model.frames import dataframe

        return dataframe({f.name: [getattr(s, f.name) for s in self.statistics]
                          for f in fields(StatisticComparison)})

    def plot(self, fig: Any = None) -> Any:
        """Both ensembles' histograms on shared bins, one panel per statistic titled with its test's outcome, on
        ``fig`` (a new pyplot figure without one; :func:`rocknroller.analysis.slow.dynamics.result_plots.plot_comparison`).
        Returns the figure."""
        from rocknroller.analysis.slow.dynamics.result_plots import plot_comparison

        return plot_comparison(self, fig)


def _compare_one(name: str, x: NDArray[np.float64], y: NDArray[np.float64], alpha: float,
                 n_se_limit: float) -> StatisticComparison:
    from scipy.stats import ks_2samp

    ks = ks_2samp(x, y)
    se_x, se_y = (float(np.std(v, ddof=1) / math.sqrt(v.size)) for v in (x, y))
    diff, se = abs(float(np.mean(x) - np.mean(y))), math.hypot(se_x, se_y)
    n_se = diff / se if se > 0.0 else (0.0 if diff == 0.0 else math.inf)
    p = float(ks.pvalue)
    return StatisticComparison(name=name, mean_a=float(np.mean(x)), se_a=se_x, mean_b=float(np.mean(y)), se_b=se_y,
                               ks_statistic=float(ks.statistic), ks_pvalue=p, n_se=n_se,
                               consistent=bool(p > alpha or n_se <= n_se_limit))


def compare_ensembles(a: EnsembleStatistics, b: EnsembleStatistics, *, alpha: float = KS_ALPHA,
                      n_se_limit: float = N_STANDARD_ERRORS) -> EnsembleComparison:
    """Apply the stated test (module docstring) to every statistic of two ensembles of one ball and time span.

    Parameters
    ----------
    a, b : EnsembleStatistics
        Of the same ball, t_end and ε (typically :func:`map_ensemble` and :func:`ode_ensemble`).
    alpha : float
        KS level, 0 < α < 1 (default ``KS_ALPHA`` = 0.01).
    n_se_limit : float
        Means within this many standard errors are consistent, > 0 (default ``N_STANDARD_ERRORS`` = 3).

    Raises
    ------
    ValueError
        Ensembles of different balls, spans or ε, or α, n_se_limit out of range.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> ball = rr.StartBall(theta0=0.95 * math.pi, psi0=math.pi / 4, delta=0.1, members=8)
    >>> cmp = rr.compare_ensembles(rr.map_ensemble(body, ball, 200.0, order=1), rr.ode_ensemble(body, ball, 200.0))
    >>> print(cmp.consistent)
    True
    """
    for name, ens in (("a", a), ("b", b)):
        if not isinstance(ens, EnsembleStatistics):
            raise ValueError(f"{name} must be an EnsembleStatistics, got {type(ens).__name__}")
    if (a.ball, a.t_end, a.eps) != (b.ball, b.t_end, b.eps):
        raise ValueError(f"the ensembles must share ball, t_end and eps: a has ({a.ball}, t_end={a.t_end}, "
                         f"eps={a.eps}), b has ({b.ball}, t_end={b.t_end}, eps={b.eps})")
    alpha, n_se_limit = as_float("alpha", alpha), as_float("n_se_limit", n_se_limit)
    if not 0.0 < alpha < 1.0:
        raise ValueError(f"alpha must be a level in (0, 1), got alpha={alpha!r}")
    if not (0.0 < n_se_limit < math.inf):
        raise ValueError(f"n_se_limit must be a finite number > 0, got n_se_limit={n_se_limit!r}")
    stats = tuple(_compare_one(name, a.values[name], b.values[name], alpha, n_se_limit) for name in STATISTICS)
    return EnsembleComparison(a=a, b=b, alpha=alpha, n_se_limit=n_se_limit, statistics=stats)

