"""Quick looks of the slow motion's result types: the ``plot()`` of
:class:`~rocknroller.analysis.slow.prediction_result.SlowPrediction`,
:class:`~rocknroller.analysis.slow.ensemble_statistics.EnsembleStatistics`,
:class:`~rocknroller.analysis.slow.ensemble_statistics.EnsembleComparison`,
:class:`~rocknroller.analysis.slow.dynamics.periodic_orbits.PeriodicOrbit`,
:class:`~rocknroller.analysis.slow.dynamics.periodic_orbits.Branch` and :class:`~rocknroller.analysis.slow.atlas.Atlas`.

Each function draws on the axes (or figure) it is given; without one it opens a pyplot figure with a constrained
layout (for interactive use, on whatever backend the user has chosen: the package never calls ``matplotlib.use``).
They take a result by its attributes, so that this module imports none of the modules that call it.  The figures for
papers (the paper's starts, colour bars, CSV): :mod:`rocknroller.papers`.
"""

from __future__ import annotations

import math
from typing import Any, Sequence

import numpy as np

from rocknroller.analysis.criticality.drawing import draw_critical_lines

__all__ = ["plot_prediction", "plot_statistics", "plot_comparison", "plot_periodic_orbit", "plot_branch",
           "line_axis", "plot_atlas_panels"]


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


def plot_prediction(pred: Any, ax: Any = None) -> Any:
    """A :class:`SlowPrediction`'s (Q_R, Q_J) at the θ-maxima over the critical lines (paper eqs. QJcrit_pi,
    QJcrit_0) of its ``body`` (none without one); the axes keep the samples' range."""
    ax = _axes(ax, (5.5, 4.2))
    QR, QJ = pred.series.QR, pred.series.QJ
    ax.plot(QR, QJ, ".", ms=3, color="k", label="averaged map (maxima)")
    if pred.body is not None and QR.size:
        xlim, ylim = ax.get_xlim(), ax.get_ylim()
        draw_critical_lines(ax, pred.body, *xlim)
        ax.set_xlim(xlim)
        ax.set_ylim(ylim)
    ax.set_xlabel("$Q_R$")
    ax.set_ylabel("$Q_J$")
    ax.ticklabel_format(style="sci", scilimits=(-2, 2))
    ax.legend(fontsize=7, loc="best")
    return ax


def _histogram(ax: Any, samples: Sequence[Any], labels: Sequence[str], colours: Sequence[str]) -> None:
    """Histograms of one statistic of one or two ensembles on shared bins (one bin for a constant), at most four
    x ticks (in units of a power of ten where small or large) so that their labels stay apart."""
    from matplotlib.ticker import MaxNLocator

    lo = min(float(np.min(x)) for x in samples)
    hi = max(float(np.max(x)) for x in samples)
    half = 0.05 * max(abs(lo), 1.0)  # a constant: one narrow bin about it
    bins = np.linspace(lo, hi, 21) if hi > lo else np.array([lo - half, lo + half])
    for x, label, colour in zip(samples, labels, colours):
        ax.hist(x, bins=bins, histtype="step", color=colour, lw=1.3, label=label)
    ax.xaxis.set_major_locator(MaxNLocator(4))
    ax.ticklabel_format(axis="x", style="sci", scilimits=(-2, 3), useOffset=False)


def plot_statistics(ens: Any, fig: Any = None) -> Any:
    """Histograms of an :class:`EnsembleStatistics`' statistics over its members, one panel each, the mean in the
    title.  Returns the figure."""
    names = list(ens.values)
    fig, axes = _panels(fig, len(names))
    label = f"{ens.method}" + (f" (order {ens.order})" if ens.order else "")
    for ax, name in zip(axes, names):
        _histogram(ax, [ens.values[name]], [label], ["k"])
        ax.set_title(f"{name}: mean {ens.mean(name):.3g}", fontsize=8)
        ax.set_ylabel("members", fontsize=8)
        ax.tick_params(labelsize=7)
    axes[0].legend(fontsize=7)
    fig.suptitle(f"{ens.ball.describe()}; t_end = {ens.t_end:g}, eps = {ens.eps:g}", fontsize=9)
    return fig


def plot_comparison(cmp: Any, fig: Any = None) -> Any:
    """Both ensembles of an :class:`EnsembleComparison` as histograms on shared bins, one panel per statistic, titled
    with the KS p-value, the difference of the means in standard errors and the verdict.  Returns the figure."""
    fig, axes = _panels(fig, len(cmp.statistics))
    labels = [f"a: {cmp.a.method}", f"b: {cmp.b.method}"]
    for ax, s in zip(axes, cmp.statistics):
        _histogram(ax, [cmp.a.values[s.name], cmp.b.values[s.name]], labels, ["k", "tab:red"])
        verdict = "consistent" if s.consistent else "NOT consistent"
        ax.set_title(f"{s.name}\nKS p = {s.ks_pvalue:.2g}, {s.n_se:.2g} SE: {verdict}", fontsize=8)
        ax.set_ylabel("members", fontsize=8)
        ax.tick_params(labelsize=7)
    axes[0].legend(fontsize=7)
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


def line_axis(atlas: Any) -> str | None:
    """``"cols"`` or ``"rows"`` for an atlas of one row or one column (drawn as lines along the other), else None."""
    if atlas.rows.size == 1 and atlas.cols.size > 1:
        return "cols"
    if atlas.cols.size == 1 and atlas.rows.size > 1:
        return "rows"
    return None


def plot_atlas_panels(atlas: Any, fig: Any = None) -> Any:
    """One panel per observable of an :class:`Atlas`: lines along the grid for an atlas of one row or one column,
    else heat maps over its plane (angles in units of π, masked points blank).  Returns the figure."""
    fig, axes = _panels(fig, len(atlas.observables), width=3.6, height=3.0)
    along = line_axis(atlas)
    scale = {name: math.pi if name in ("theta0", "psi0") else 1.0 for name in (atlas.row_name, atlas.col_name)}
    unit = {name: "/π" if scale[name] != 1.0 else "" for name in scale}
    x_name = atlas.row_name if along == "rows" else atlas.col_name
    for ax, name in zip(axes, atlas.observables):
        values = atlas.values[name]
        if along is not None:
            x = (atlas.rows if along == "rows" else atlas.cols) / scale[x_name]
            ax.plot(x, np.ma.ravel(values).filled(np.nan), ".-", ms=4, lw=1)
        else:
            mesh = ax.pcolormesh(atlas.cols / scale[atlas.col_name], atlas.rows / scale[atlas.row_name], values,
                                 shading="nearest")
            fig.colorbar(mesh, ax=ax)
            ax.set_ylabel(atlas.row_name + unit[atlas.row_name], fontsize=8)
        ax.set_xlabel(x_name + unit[x_name], fontsize=8)
        ax.set_title(name, fontsize=9)
        ax.tick_params(labelsize=7)
    fixed = ""
    if along is not None:
        f_name = atlas.col_name if along == "rows" else atlas.row_name
        f_value = (atlas.cols if along == "rows" else atlas.rows)[0] / scale[f_name]
        fixed = f", {f_name} = {f_value:.6g}" + ("π" if scale[f_name] != 1.0 else "")
    fig.suptitle(f"atlas ({atlas.method}): eps = {atlas.eps:g}, t_end = {atlas.t_end:g}{fixed}", fontsize=9)
    return fig
