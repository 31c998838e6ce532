"""Quick looks of the slow motion's result types: the ``plot()`` of
:class:`~rocknroller.analysis.slow.prediction_result.SlowPrediction`,
:class:`~rocknroller.analysis.slow.ensemble_statistics.EnsembleStatistics`,
:class:`~rocknroller.analysis.slow.ensemble_statistics.EnsembleComparison`,
:class:`~rocknroller.analysis.slow.dynamics.periodic_orbits.PeriodicOrbit`,
:class:`~rocknroller.analysis.slow.dynamics.periodic_orbits.Branch` (the atlas's:
:mod:`rocknroller.analysis.slow.dynamics.atlas_figure`).

Each function draws on the axes (or figure) it is given; without one it opens a pyplot figure with a constrained
layout (for interactive use, on whatever backend the user has chosen: the package never calls ``matplotlib.use``).
They take a result by its attributes, so that this module imports none of the modules that call it.  The figures for
papers (the paper's starts, colour bars, CSV): :mod:`rocknroller.papers`.
"""

from __future__ import annotations

import math
from typing import Any, Mapping, Sequence

import numpy as np

from rocknroller.analysis.criticality.drawing import draw_critical_lines

__all__ = ["plot_prediction", "plot_statistics", "plot_comparison", "plot_periodic_orbit", "plot_branch"]


def _axes(ax: Any, figsize: tuple[float, float]) -> Any:
    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(figsize=figsize, layout="constrained")
    return ax


def _panels(fig: Any, n: int, width: float = 3.2, height: float = 2.6) -> tuple[Any, list[Any]]:
    """``n`` axes in rows of at most four on ``fig`` (a new pyplot figure without one); the unused ones hidden."""
    cols = min(n, 4)
    rows = -(-n // cols)
    if fig is None:
        import matplotlib.pyplot as plt

        fig = plt.figure(figsize=(width * cols, height * rows), layout="constrained")
    axes = np.atleast_1d(fig.subplots(rows, cols)).ravel()
    for ax in axes[n:]:
        ax.set_visible(False)
    return fig, list(axes[:n])


def _prediction_title(pred: Any) -> str:
    """The body, ε, the start and the map's order, as the figure's title."""
    start = "released from rest" if pred.start is None else "started with velocity"
    head = (f"slow motion by the averaged map of order {pred.order}: ε = {pred.eps:.3g}, {start} at "
            f"θ0 = {pred.theta0 / math.pi:.4g}π, ψ0 = {pred.psi0 / math.pi:.4g}π")
    return head if pred.body is None else f"{head}\nbody {pred.body.with_epsilon(pred.eps).describe()}"


def plot_prediction(pred: Any, fig: Any = None, *, horizon: float | None = None, ode: Any = None) -> Any:
    """Draw a :class:`SlowPrediction`: its (Q_R, Q_J) at the θ-maxima over the critical lines of its ``body`` (paper
    eqs. QJcrit_pi, QJcrit_0; none without one), the axes keeping the samples' range, and ψ mod π at the maxima
    against t with the predictability horizon; titled with the body, ε, the start and the map's order.

    Parameters
    ----------
    pred : SlowPrediction
        The prediction (read by its attributes).
    fig : matplotlib.figure.Figure, optional
        The figure to draw on (a new pyplot figure with a constrained layout without one).
    horizon : float, optional
        The predictability horizon: before t_end, a line at it and the span past it shaded (the map's points there
        are statistical only); after t_end, named in the legend; None: no horizon.
    ode : optional
        The direct ODE's θ-maxima from the same start (``QR``, ``QJ``, ``t``, ``Theta``: ``check_prediction(...).ode``),
        drawn beside the map's as open red circles.

    Returns
    -------
    matplotlib.figure.Figure
        Its axes: the (Q_R, Q_J) panel, then the ψ panel.

    Examples
    --------
    >>> import math
    >>> from matplotlib.figure import Figure
    >>> import rocknroller as rr
    >>> from rocknroller.analysis.slow.dynamics.result_plots import plot_prediction
    >>> pred = rr.predict_slow_motion(rr.Body.paper(1e-3), 0.95 * math.pi, math.pi / 4, 200.0, order=1)
    >>> fig = plot_prediction(pred, Figure(figsize=(11, 4.2), layout="constrained"), horizon=150.0)
    >>> print([line.get_label() for line in fig.axes[1].get_lines()])
    ['averaged map', 'predictability horizon t = 150']
    """
    if fig is None:
        import matplotlib.pyplot as plt

        fig = plt.figure(figsize=(11, 4.2), layout="constrained")
    ax_q, ax_t = fig.subplots(1, 2)
    series = pred.series
    if ode is not None:
        ax_q.plot(ode.QR, ode.QJ, "o", ms=5, mfc="none", color="tab:red", label="direct ODE (maxima)")
        ax_t.plot(ode.t, np.mod(0.5 * ode.Theta, np.pi), "o", ms=4, mfc="none", color="tab:red", label="direct ODE")
    ax_q.plot(series.QR, series.QJ, ".", ms=3, color="k", label="averaged map (maxima)")
    if pred.body is not None and series.QR.size:
        xlim, ylim = ax_q.get_xlim(), ax_q.get_ylim()
        draw_critical_lines(ax_q, pred.body, *xlim)
        ax_q.set_xlim(xlim)
        ax_q.set_ylim(ylim)
    ax_q.set_xlabel("$Q_R$ at the maxima of $\\theta$")
    ax_q.set_ylabel("$Q_J$ at the maxima of $\\theta$")
    ax_q.ticklabel_format(style="sci", scilimits=(-2, 2))
    ax_q.legend(fontsize=7, loc="best")
    ax_t.plot(series.t, series.psi_mod_pi, ".", ms=3, color="k", label="averaged map")
    if horizon is not None and horizon < pred.t_end:
        ax_t.axvline(horizon, color="tab:purple", lw=1.2, label=f"predictability horizon t = {horizon:.4g}")
        ax_t.axvspan(horizon, pred.t_end, color="tab:purple", alpha=0.08, lw=0, label="past it: statistical only")
        ax_t.set_xlim(0.0, pred.t_end)
    elif horizon is not None:  # named in the legend, beyond the axis
        ax_t.plot([], [], " ", label=f"predictability horizon t = {horizon:.4g} (after t_end)")
    ax_t.set_xlabel("t (time units)")
    ax_t.set_ylabel("$\\psi$ mod $\\pi$ at the maxima (rad)")
    ax_t.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.0, 1.0))
    fig.suptitle(_prediction_title(pred), fontsize=9)
    return fig


#: The statistics of an ensemble in words (the region fractions: ``fraction_I`` ... ``fraction_IV``).
_STATISTIC_WORDS = {"full_reversals": "full-angle reversals", "visible_reversals": "visible-angle reversals",
                    "QR_extent": "$Q_R$ extent (max - min)", "QJ_extent": "$Q_J$ extent (max - min)"}


def _statistic_words(name: str) -> str:
    region = name.removeprefix("fraction_")
    return f"fraction of the rocks in region {region}" if region != name else _STATISTIC_WORDS[name]


def _histogram(ax: Any, name: str, samples: Sequence[Any], labels: Sequence[str], colours: Sequence[str],
               units: Mapping[str, str]) -> None:
    """Histograms of one statistic of one or two ensembles on shared bins, the x axis labelled in words with the
    statistic's unit (``units``: ``STATISTIC_UNITS``).  A region fraction on the fixed range [0, 1]; a constant as
    one narrow bin in a window ten times as wide; a statistic that is 0 for every member not drawn, but said so.  At
    most four x ticks (in units of a power of ten where small or large) so that their labels stay apart."""
    from matplotlib.ticker import MaxNLocator

    unit = units.get(name)
    ax.set_xlabel(_statistic_words(name) + (f" ({unit})" if unit else ""), fontsize=8)
    ax.set_ylabel("members", fontsize=8)
    ax.tick_params(labelsize=7)
    lo = min(float(np.min(x)) for x in samples)
    hi = max(float(np.max(x)) for x in samples)
    if lo == hi == 0.0:
        ax.text(0.5, 0.5, "none: 0 for every member", transform=ax.transAxes, ha="center", va="center", fontsize=8,
                color="0.3")
        return
    if name.startswith("fraction_"):
        bins = np.linspace(0.0, 1.0, 21)
        ax.set_xlim(0.0, 1.0)
    elif hi > lo:
        bins = np.linspace(lo, hi, 21)
    else:
        half = 0.05 * max(abs(lo), 1.0)
        bins = np.array([lo - half, lo + half])
        ax.set_xlim(lo - 10.0 * half, lo + 10.0 * half)
    for x, label, colour in zip(samples, labels, colours):
        ax.hist(x, bins=bins, histtype="step", color=colour, lw=1.3, label=label)
    ax.xaxis.set_major_locator(MaxNLocator(4))
    ax.ticklabel_format(axis="x", style="sci", scilimits=(-2, 3), useOffset=False)


def _legend(axes: Sequence[Any]) -> None:
    """The ensembles' legend, on the first panel with a histogram."""
    drawn = [ax for ax in axes if ax.patches]
    if drawn:
        drawn[0].legend(fontsize=7)


def plot_statistics(ens: Any, fig: Any = None) -> Any:
    """Histograms of an :class:`EnsembleStatistics`' statistics over its members, one panel each titled in words with
    the mean, the x axes labelled with the units (``ens.units``), the region fractions on [0, 1], a statistic that is
    0 for every member not drawn but noted.  Returns the figure."""
    names = list(ens.values)
    fig, axes = _panels(fig, len(names))
    label = f"{ens.method}" + (f" (order {ens.order})" if ens.order else "")
    for ax, name in zip(axes, names):
        _histogram(ax, name, [ens.values[name]], [label], ["k"], ens.units)
        ax.set_title(f"{_statistic_words(name)}: mean {ens.mean(name):.3g}", fontsize=8)
    _legend(axes)
    fig.suptitle(f"{ens.ball.describe()}; t_end = {ens.t_end:g}, eps = {ens.eps:g}", fontsize=9)
    return fig


def plot_comparison(cmp: Any, fig: Any = None) -> Any:
    """Both ensembles of an :class:`EnsembleComparison` as histograms on shared bins (drawn as
    :func:`plot_statistics` draws one), one panel per statistic, titled with the KS p-value, the difference of the
    means in standard errors and the verdict.  Returns the figure."""
    fig, axes = _panels(fig, len(cmp.statistics))
    labels = [f"a: {cmp.a.method}", f"b: {cmp.b.method}"]
    for ax, s in zip(axes, cmp.statistics):
        _histogram(ax, s.name, [cmp.a.values[s.name], cmp.b.values[s.name]], labels, ["k", "tab:red"], cmp.a.units)
        verdict = "consistent" if s.consistent else "NOT consistent"
        ax.set_title(f"{_statistic_words(s.name)}\nKS p = {s.ks_pvalue:.2g}, {s.n_se:.2g} SE: {verdict}", fontsize=8)
    _legend(axes)
    fig.suptitle(f"{cmp.a.ball.describe()}; KS level {cmp.alpha:g}, {cmp.n_se_limit:g} SE", fontsize=9)
    return fig


def plot_periodic_orbit(orbit: Any, ax: Any = None) -> Any:
    """A :class:`PeriodicOrbit`'s points in the (Q_R, Q_J) plane (filled: stable, open: unstable)."""
    ax = _axes(ax, (5.0, 4.0))
    state = "stable" if orbit.stable else "unstable"
    ax.plot(orbit.Q[:, 0], orbit.Q[:, 1], "o", color="C0", mfc="C0" if orbit.stable else "none",
            label=f"period {orbit.period}, {orbit.map} map, eps = {orbit.eps:.4g}: {state} (R = {orbit.residue:.3g})")
    ax.set_xlabel("$Q_R$")
    ax.set_ylabel("$Q_J$")
    ax.ticklabel_format(style="sci", scilimits=(-2, 2))
    ax.legend(fontsize=7, loc="best")
    return ax


def _segments(x: np.ndarray, y: np.ndarray, stable: np.ndarray) -> list[tuple[np.ndarray, np.ndarray, bool]]:
    """Runs of equal stability, each closed with the next point so that the line is continuous."""
    out, start = [], 0
    for i in range(1, len(x) + 1):
        if i == len(x) or stable[i] != stable[start]:
            end = min(i + 1, len(x))
            out.append((x[start:end], y[start:end], bool(stable[start])))
            start = i
    return out


#: What :func:`plot_branch` draws against ε: the kick phase of each point, or Greene's residue.
BRANCH_KINDS = ("kick_phase", "residue")


def plot_branch(branch: Any, ax: Any = None, kind: str = "kick_phase", *, x_scale: float = 1.0,
                color: str = "C0", label: str | None = None) -> Any:
    """A :class:`Branch` against ε / ``x_scale``: its kick phase ϑ (one line per point of the orbit) or Greene's
    residue R, solid where stable, dashed where not; ``label`` on its first line."""
    if kind not in BRANCH_KINDS:
        raise ValueError(f"kind must be one of {list(BRANCH_KINDS)}, got kind={kind!r}")
    ax = _axes(ax, (5.0, 3.5))
    x = branch.eps / x_scale
    ys = branch.kick_phase.T if kind == "kick_phase" else branch.residue[None, :]
    for y in ys:
        for xs, yy, st in _segments(x, y, branch.stable):
            ax.plot(xs, yy, color=color, ls="-" if st else "--", lw=1.4, label=label)
            label = None
    if kind == "residue":
        ax.set_ylabel("Greene's residue R")
    else:
        ax.set_ylabel(r"kick phase $\vartheta = \Theta + W(Q)/2$")
    ax.set_xlabel(r"$\varepsilon$" if x_scale == 1.0 else rf"$\varepsilon$ / {x_scale:.6g}")
    return ax
