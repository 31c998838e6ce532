"""Figures of a recession atlas (:class:`rocknroller.analysis.slow.atlas.Atlas`): one panel per observable, heat maps
over its plane of starts (ψ0, θ0) or (φ̇0, ψ̇0) with the paper's starts marked (and, over the rates, the starts on
the critical lines drawn), or lines along the grid for an atlas of one row or one column; and the map's errors at the
points the direct ODE confirmed (:class:`rocknroller.analysis.slow.atlas_check.AtlasCheck`).  An atlas with its chaos
layer gets two more panels: the map's MEGNO on the fixed scale [0, :data:`rocknroller.numerics.megno.MEGNO_CLIP`]
(larger values clipped to the top colour, the line MEGNO = 3 between regular and chaotic drawn) and its Lyapunov
exponent.

Each panel is titled in words (:data:`TITLES`), its colour bar (or, for a line, its y axis) labelled with the
observable's unit (:data:`UNIT_LABELS`), its axes with the initial values (:data:`AXIS_LABELS`, angles in units of
π).  These are the figures of :meth:`Atlas.plot` and of ``rocknroller atlas`` (``atlas.png``, ``atlas_check.png``):
the functions take a result by its attributes, so that this module imports none of the modules that call it; without
a figure they open a pyplot figure (on whatever backend the user has chosen).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from rocknroller.analysis.criticality.starts import PSI0, THETA0, paper_rate_starts
from rocknroller.analysis.model.body import Body
from rocknroller.analysis.routh.precession_plots import cell_edges
from rocknroller.numerics.megno import MEGNO_CHAOTIC, MEGNO_CLIP

__all__ = ["PAPER_RELEASES", "TITLES", "UNIT_LABELS", "AXIS_LABELS", "atlas_figsize", "atlas_figure",
           "atlas_check_figure"]

#: The paper's releases from rest (θ0, ψ0) (§numerics: figs. 6 and 7, θ0 = 0.95π; the four ψ0 of its slow runs).
PAPER_RELEASES = tuple((0.95 * math.pi, psi) for psi in (math.pi / 8, math.pi / 4, 3 * math.pi / 8, 3.9 * math.pi / 8))
#: Panel titles.
TITLES = {"slow_period": "slow period of $\\Theta = 2\\psi$", "Phi": "azimuth span $\\Phi$",
          "QR_extent": "$Q_R$ extent", "QJ_extent": "$Q_J$ extent",
          "full_reversals": "full-angle reversals", "visible_reversals": "visible-angle reversals",
          "megno": f"map's MEGNO (clipped at {MEGNO_CLIP:g}; > {MEGNO_CHAOTIC:g}: chaotic)",
          "lyapunov": "map's Lyapunov exponent"}
#: The label of each observable's colour bar (or y axis), with its unit.
UNIT_LABELS = {"slow_period": "slow period (time units)", "Phi": "$\\Phi$ (rad)", "QR_extent": "max - min of $Q_R$",
               "QJ_extent": "max - min of $Q_J$", "full_reversals": "per 1000 time units",
               "visible_reversals": "per 1000 time units", "megno": "MEGNO $\\langle Y\\rangle$",
               "lyapunov": "$\\lambda$ (per unit time)"}
#: Axis labels of the initial values (angles in units of π).
AXIS_LABELS = {"theta0": "$\\theta_0/\\pi$", "psi0": "$\\psi_0/\\pi$", "phi_dot0": "$\\dot\\phi_0$",
               "psi_dot0": "$\\dot\\psi_0$"}


def _scale(name: str) -> float:
    return math.pi if name in ("theta0", "psi0") else 1.0


def _line_axis(atlas: Any) -> str | None:
    """``"cols"`` or ``"rows"`` for an atlas of one row or one column (drawn as lines along the other), else None."""
    if atlas.rows.size == 1 and atlas.cols.size > 1:
        return "cols"
    if atlas.cols.size == 1 and atlas.rows.size > 1:
        return "rows"
    return None


def _new_figure(fig: Any, figsize: tuple[float, float]) -> Any:
    if fig is None:
        import matplotlib.pyplot as plt

        fig = plt.figure(figsize=figsize, layout="constrained")
    return fig


def _paper_points(atlas: Any) -> list[tuple[float, float]]:
    """The paper's starts inside the atlas's window, as (column, row) values."""
    if atlas.plane == "release":
        pts = [(p0, t0) for t0, p0 in PAPER_RELEASES]
    else:
        if not np.allclose(atlas.at, (THETA0, PSI0), rtol=0.0, atol=1e-12):
            return []
        pts = list(paper_rate_starts().values())
    c, r = atlas.cols, atlas.rows
    return [(x, y) for x, y in pts if c.min() <= x <= c.max() and r.min() <= y <= r.max()]


def _decorate(ax: Any, atlas: Any, body: Body | None) -> None:
    """Axis labels, the paper's starts (white stars), and over a plane of rates the starts on the two critical lines
    (the lines' styles of paper fig. 4)."""
    xs, ys = _scale(atlas.col_name), _scale(atlas.row_name)
    for x, y in _paper_points(atlas):
        ax.plot(x / xs, y / ys, marker="*", ms=9, mfc="white", mec="k", ls="none")
    if atlas.plane == "rates" and body is not None:
        from rocknroller.analysis.criticality.drawing import LINE_STYLE
        from rocknroller.analysis.criticality.lines import QJ_crit
        from rocknroller.analysis.routh.reduction import invariants_from_euler

        pd = np.linspace(atlas.cols.min(), atlas.cols.max(), 201)
        sd = np.linspace(atlas.rows.min(), atlas.rows.max(), 201)
        PD, SD = np.meshgrid(pd, sd)
        _, QR, QJ = invariants_from_euler(body, atlas.at[0], 0.0, PD, SD, atlas.at[1])
        for line in ("pi", "0"):
            style = LINE_STYLE[line]
            ax.contour(PD, SD, QJ - QJ_crit(line, QR, body.symmetric()), levels=[0.0], colors=style["color"],
                       linewidths=style["lw"], linestyles=style["ls"])
    ax.set_xlabel(AXIS_LABELS[atlas.col_name])
    ax.set_ylabel(AXIS_LABELS[atlas.row_name])


def _fixed_value(atlas: Any, along: str) -> str:
    """The value held fixed along a line atlas, as a title: ``θ0 = 0.95π``."""
    name = atlas.row_name if along == "cols" else atlas.col_name
    value = (atlas.rows if along == "cols" else atlas.cols)[0] / _scale(name)
    symbol = AXIS_LABELS[name].replace("/\\pi", "")
    return f"{symbol} = {value:.6g}" + ("π" if _scale(name) != 1.0 else "")


def _plot_line(ax: Any, atlas: Any, name: str, along: str) -> None:
    """One observable of a one-row (one-column) atlas against the column (row) values: the masked points left out;
    MEGNO clipped at ``MEGNO_CLIP`` (clipped points as triangles at the top) with the line MEGNO = 3; the paper's
    starts on the line as dotted verticals."""
    x_name = atlas.col_name if along == "cols" else atlas.row_name
    x = (atlas.cols if along == "cols" else atlas.rows) / _scale(x_name)
    y = np.ma.ravel(atlas.values[name])
    if name == "megno":
        over = np.ma.filled(y > MEGNO_CLIP, False)
        ax.plot(x, np.ma.minimum(y, MEGNO_CLIP).filled(np.nan), ".-", color="tab:purple", ms=4, lw=1)
        ax.plot(x[over], np.full(over.sum(), MEGNO_CLIP), "^", color="tab:purple", ms=6,
                label=f"above {MEGNO_CLIP:g} (clipped)")
        ax.axhline(MEGNO_CHAOTIC, color="k", ls="--", lw=0.8, label=f"MEGNO = {MEGNO_CHAOTIC:g}")
        ax.set_ylim(0.0, 1.08 * MEGNO_CLIP)
    else:
        ax.plot(x, y.filled(np.nan), ".-", color="tab:blue", ms=4, lw=1)
    for k, (px, py) in enumerate(_paper_points(atlas)):
        ax.axvline((px if along == "cols" else py) / _scale(x_name), color="0.5", ls=":", lw=1,
                   label="the paper's starts" if k == 0 else None)
    ax.margins(x=0.03)
    ax.set_xlabel(AXIS_LABELS[x_name])
    ax.set_ylabel(UNIT_LABELS[name])


def atlas_figsize(atlas: Any) -> tuple[float, float]:
    """The size in inches of :func:`atlas_figure`'s figure: two rows of panels, one per observable.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> from rocknroller.analysis.slow.dynamics.atlas_figure import atlas_figsize
    >>> print(atlas_figsize(SimpleNamespace(observables=("slow_period", "Phi", "megno", "lyapunov"))))
    (8.666666666666666, 7.5)
    """
    return 13 * ((len(atlas.observables) + 1) // 2) / 3, 7.5


def atlas_figure(atlas: Any, fig: Any = None, title: str | None = None, body: Body | None = None) -> Any:
    """Draw an atlas: one panel per observable (``Atlas.observables``: six, and the two of its chaos layer), titled
    with :data:`TITLES`.

    A plane of starts is drawn as heat maps over it, each with its colour bar labelled with :data:`UNIT_LABELS`
    (MEGNO on the fixed scale [0, ``MEGNO_CLIP``], the contour MEGNO = 3 drawn), the paper's starts starred (and over
    a plane of rates, given the ``body``, the critical lines: red solid Q_J,π^crit, blue dashed Q_J,0^crit); an atlas
    of one row (one θ0, or one ψ̇0) or one column as lines along the values it has, the fixed one in the title and
    the paper's starts on the line dotted.

    Parameters
    ----------
    atlas : Atlas
        The atlas (read by its attributes).
    fig : matplotlib.figure.Figure, optional
        The figure to draw on (of :func:`atlas_figsize`, with a constrained layout); a new pyplot figure without one.
    title : str, optional
        The figure's title (default: the method, ε and t_end of the atlas).
    body : Body, optional
        The body, whose critical lines are drawn over a plane of rates.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> import math
    >>> from matplotlib.figure import Figure
    >>> import rocknroller as rr
    >>> from rocknroller.analysis.slow.dynamics.atlas_figure import atlas_figsize, atlas_figure
    >>> atlas = rr.atlas_from_rest(rr.Body.paper(1e-3), [0.9 * math.pi, 0.95 * math.pi], [0.3, 0.8], 200.0)
    >>> fig = atlas_figure(atlas, Figure(figsize=atlas_figsize(atlas), layout="constrained"))
    >>> megno = fig.axes[6]
    >>> print(megno.get_title(), megno.collections[0].get_clim())
    map's MEGNO (clipped at 5; > 3: chaotic) (0.0, 5.0)
    """
    names = atlas.observables
    fig = _new_figure(fig, atlas_figsize(atlas))
    axes = fig.subplots(2, (len(names) + 1) // 2).ravel()
    along = _line_axis(atlas)
    xe, ye = cell_edges(atlas.cols / _scale(atlas.col_name)), cell_edges(atlas.rows / _scale(atlas.row_name))
    for ax, name in zip(axes, names):
        ax.set_title(TITLES[name], fontsize=10)
        if along is not None:
            _plot_line(ax, atlas, name, along)
            if name == "megno" or (ax is axes[0] and ax.get_legend_handles_labels()[0]):
                ax.legend(fontsize=7, loc="best")
            continue
        if name == "megno":
            mesh = ax.pcolormesh(xe, ye, atlas.values[name], shading="flat", cmap="plasma", vmin=0.0, vmax=MEGNO_CLIP)
            bar = fig.colorbar(mesh, ax=ax, extend="max", label=UNIT_LABELS[name])
            bar.ax.axhline(MEGNO_CHAOTIC, color="w", lw=1.5)
            if atlas.rows.size > 1 and atlas.cols.size > 1 and np.ma.count(atlas.values[name]) > 0:
                ax.contour(atlas.cols / _scale(atlas.col_name), atlas.rows / _scale(atlas.row_name),
                           atlas.values[name], levels=[MEGNO_CHAOTIC], colors="w", linewidths=1.0)
        else:
            mesh = ax.pcolormesh(xe, ye, atlas.values[name], shading="flat", cmap="viridis")
            fig.colorbar(mesh, ax=ax, label=UNIT_LABELS[name])
        _decorate(ax, atlas, body)
        ax.set_xlim(xe[0], xe[-1])
        ax.set_ylim(ye[0], ye[-1])
    for ax in axes[len(names):]:
        ax.set_visible(False)
    title = title or f"atlas ({atlas.method}): eps = {atlas.eps:g}, t_end = {atlas.t_end:g}"
    fig.suptitle(title if along is None else f"{title}; {_fixed_value(atlas, along)}", fontsize=10)
    return fig


def atlas_check_figure(atlas: Any, check: Any, title: str, fig: Any = None) -> Any:
    """Draw where the direct ODE confirmed a map-made atlas: over a plane, the confirmed points coloured by their
    largest |map/ODE - 1| of the slow period, Φ and the extents (log scale), the points whose reversal counts differ
    (red ring) and, with the chaos layer, those whose regular/chaotic verdict differs (black square); for an atlas of
    one row or one column, that error against the values it has (log scale) with those points as vertical lines.

    Parameters
    ----------
    atlas : Atlas
        The atlas.
    check : AtlasCheck
        Its check by the direct ODE (:func:`rocknroller.analysis.slow.atlas_check.confirm_atlas`).
    title : str
        The figure's title.
    fig : matplotlib.figure.Figure, optional
        The figure to draw on (a new pyplot figure without one).

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> import math
    >>> from matplotlib.figure import Figure
    >>> import rocknroller as rr
    >>> from rocknroller.analysis.slow.dynamics.atlas_figure import atlas_check_figure
    >>> body = rr.Body.paper(1e-3)
    >>> atlas = rr.atlas_from_rest(body, [0.95 * math.pi], [0.3, 0.5, 0.8], 200.0)
    >>> check = rr.confirm_atlas(atlas, body, every=2, progress=False)
    >>> ax = atlas_check_figure(atlas, check, "check", Figure(layout="constrained")).axes[0]
    >>> print(ax.get_yscale(), ax.get_xlabel())
    log $\\psi_0/\\pi$
    """
    from matplotlib.colors import LogNorm

    fig = _new_figure(fig, (6.5, 5.0))
    ax = fig.subplots()
    cont = [np.ma.abs(check.rel_error[n]) for n in ("slow_period", "Phi", "QR_extent", "QJ_extent")]
    worst = np.ma.max(np.ma.vstack(cont), axis=0).filled(np.nan)
    xs, ys = _scale(atlas.col_name), _scale(atlas.row_name)
    x, y = atlas.cols[check.index[:, 1]] / xs, atlas.rows[check.index[:, 0]] / ys
    along = _line_axis(atlas)
    if along == "rows":
        x, xs = y, ys
    ok = np.isfinite(worst) & (worst > 0)
    diff = (np.ma.abs(check.rel_error["full_reversals"])
            + np.ma.abs(check.rel_error["visible_reversals"])).filled(0) > 0
    differs = ~check.verdict_agrees.filled(True) if "megno" in check.ode else np.zeros_like(diff)
    error_label = "largest |map/ODE - 1| (slow period, $\\Phi$, extents)"
    if along is not None:
        ax.semilogy(x[ok], worst[ok], "o", color="k", ms=5, label=error_label)
        for k, xv in enumerate(x[diff]):
            ax.axvline(xv, color="tab:red", ls=":", lw=1.2, label="reversal counts differ" if k == 0 else None)
        for k, xv in enumerate(x[differs]):
            ax.axvline(xv, color="k", ls="--", lw=1.0, label="regular/chaotic verdict differs" if k == 0 else None)
        ax.margins(x=0.03)
        ax.set_xlabel(AXIS_LABELS[atlas.row_name if along == "rows" else atlas.col_name])
        ax.set_ylabel("largest |map/ODE - 1|")
        ax.legend(fontsize=8, loc="best")
        ax.set_title(f"{title}; {_fixed_value(atlas, along)}", fontsize=9)
        return fig
    if ok.any():
        sc = ax.scatter(x[ok], y[ok], c=worst[ok], cmap="magma_r", s=40, norm=LogNorm(vmin=max(worst[ok].min(), 1e-12),
                                                                                     vmax=max(worst[ok].max(), 1e-11)))
        fig.colorbar(sc, ax=ax, label=error_label)
    ax.plot(x[diff], y[diff], "o", ms=12, mfc="none", mec="tab:red", label="reversal counts differ")
    if differs.any():
        ax.plot(x[differs], y[differs], "s", ms=15, mfc="none", mec="k", label="regular/chaotic verdict differs")
    ax.set_xlim(*cell_edges(atlas.cols / xs)[[0, -1]])
    ax.set_ylim(*cell_edges(atlas.rows / ys)[[0, -1]])
    _decorate(ax, atlas, None)
    if (diff | differs).any():
        ax.legend(fontsize=8, loc="best")
    ax.set_title(title, fontsize=9)
    return fig
