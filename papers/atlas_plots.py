"""Figures of a recession atlas (:mod:`rocknroller.analysis.slow.atlas`): heat maps over (ψ0, θ0) or (φ̇0, ψ̇0), the
paper's starts marked (and, over the rates, the starts on the critical lines drawn), and the map's errors at the
points the direct ODE confirmed.  An atlas with its chaos layer gets two more panels: the map's MEGNO (colours
clipped to [0, :data:`rocknroller.papers.plotting.MEGNO_CLIP`], the line MEGNO = 3 between regular and chaotic
drawn) and its Lyapunov exponent."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from rocknroller.analysis.criticality.starts import PSI0, THETA0, paper_rate_starts
from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.atlas import Atlas
from rocknroller.analysis.slow.atlas_check import AtlasCheck
from rocknroller.analysis.slow.dynamics.result_plots import line_axis
from rocknroller.numerics.megno import MEGNO_CHAOTIC
from rocknroller.papers.output import new_figure, save_figure
from rocknroller.papers.plotting import MEGNO_CLIP

__all__ = ["PAPER_RELEASES", "LABELS", "AXIS_LABELS", "atlas_figure", "atlas_check_figure", "plot_atlas",
           "plot_atlas_check"]

#: The paper's releases from rest (θ0, ψ0) (§numerics: figs. 6 and 7, θ0 = 0.95π; the four ψ0 of its slow runs).
PAPER_RELEASES = tuple((0.95 * math.pi, psi) for psi in (math.pi / 8, math.pi / 4, 3 * math.pi / 8, 3.9 * math.pi / 8))
#: Panel titles.
LABELS = {"slow_period": "slow period of $\\Theta = 2\\psi$", "Phi": "azimuth span $\\Phi$ (rad)",
          "QR_extent": "$Q_R$ extent", "QJ_extent": "$Q_J$ extent",
          "full_reversals": "full-angle reversals / 1000 t.u.", "visible_reversals": "visible reversals / 1000 t.u.",
          "megno": f"map's MEGNO (clipped at {MEGNO_CLIP:g}; > {MEGNO_CHAOTIC:g}: chaotic)",
          "lyapunov": "map's Lyapunov exponent (per unit time)"}
#: Axis labels of the initial values (angles in units of π).
AXIS_LABELS = {"theta0": "$\\theta_0/\\pi$", "psi0": "$\\psi_0/\\pi$", "phi_dot0": "$\\dot\\phi_0$",
               "psi_dot0": "$\\dot\\psi_0$"}


def _scale(name: str) -> float:
    return math.pi if name in ("theta0", "psi0") else 1.0


def _edges(x: np.ndarray) -> np.ndarray:
    """Cell edges around grid values (midpoints; a single value gets a cell of ±1 % or ±0.01)."""
    if x.size == 1:
        h = 0.01 * max(abs(x[0]), 1.0)
        return np.array([x[0] - h, x[0] + h])
    mid = 0.5 * (x[1:] + x[:-1])
    return np.concatenate([[2 * x[0] - mid[0]], mid, [2 * x[-1] - mid[-1]]])


def _paper_points(atlas: Atlas) -> list[tuple[float, float]]:
    """The paper's starts inside the atlas's window, as (column, row) values."""
    if atlas.plane == "release":
        pts = [(p0, t0) for t0, p0 in PAPER_RELEASES]
    else:
        assert atlas.at is not None
        if not np.allclose(atlas.at, (THETA0, PSI0), rtol=0.0, atol=1e-12):
            return []
        pts = list(paper_rate_starts().values())
    c, r = atlas.cols, atlas.rows
    return [(x, y) for x, y in pts if c.min() <= x <= c.max() and r.min() <= y <= r.max()]


def _decorate(ax: Any, atlas: Atlas, body: Body | None) -> None:
    """Axis labels, the paper's starts (white stars), and over a plane of rates the starts on the two critical lines
    (the lines' styles of paper fig. 4)."""
    xs, ys = _scale(atlas.col_name), _scale(atlas.row_name)
    for x, y in _paper_points(atlas):
        ax.plot(x / xs, y / ys, marker="*", ms=9, mfc="white", mec="k", ls="none")
    if atlas.plane == "rates" and body is not None:
        from rocknroller.analysis.criticality.lines import QJ_crit
        from rocknroller.analysis.routh.reduction import invariants_from_euler
        from rocknroller.papers.plotting import LINE_STYLE

        assert atlas.at is not None
        pd = np.linspace(atlas.cols.min(), atlas.cols.max(), 201)
        sd = np.linspace(atlas.rows.min(), atlas.rows.max(), 201)
        PD, SD = np.meshgrid(pd, sd)
        _, QR, QJ = invariants_from_euler(body, atlas.at[0], 0.0, PD, SD, atlas.at[1])
        for line in ("pi", "0"):
            style = {k: v for k, v in LINE_STYLE[line].items() if k in ("color", "lw")}
            ax.contour(PD, SD, QJ - QJ_crit(line, QR, body.symmetric()), levels=[0.0], colors=style["color"],
                       linewidths=style["lw"], linestyles=LINE_STYLE[line]["ls"])
    ax.set_xlabel(AXIS_LABELS[atlas.col_name])
    ax.set_ylabel(AXIS_LABELS[atlas.row_name])


def _fixed_value(atlas: Atlas, along: str) -> str:
    """The value held fixed along a line atlas, as a title: ``θ0 = 0.95π``."""
    name = atlas.row_name if along == "cols" else atlas.col_name
    value = (atlas.rows if along == "cols" else atlas.cols)[0] / _scale(name)
    symbol = AXIS_LABELS[name].replace("/\\pi", "")
    return f"{symbol} = {value:.6g}" + ("π" if _scale(name) != 1.0 else "")


def _plot_line(ax: Any, atlas: Atlas, name: str, along: str) -> None:
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


def atlas_figure(atlas: Atlas, title: str, body: Body | None = None) -> Any:
    """The figure of :func:`plot_atlas`: one panel per observable (``Atlas.observables``: six, and the two of its
    chaos layer).  A plane of starts is drawn as heat maps over it, the paper's starts starred (and over a plane of
    rates, given the ``body``, the critical lines: red solid Q_J,π^crit, blue dashed Q_J,0^crit); an atlas of one row
    (one θ0, or one ψ̇0) or one column as lines along the values it has, the fixed one in the title and the paper's
    starts on the line dotted.  Returns the figure."""
    names = atlas.observables
    n_cols = (len(names) + 1) // 2
    along = line_axis(atlas)
    fig = new_figure(figsize=(13 * n_cols / 3, 7.5))
    axes = fig.subplots(2, n_cols).ravel()
    xe, ye = _edges(atlas.cols / _scale(atlas.col_name)), _edges(atlas.rows / _scale(atlas.row_name))
    for ax, name in zip(axes, names):
        ax.set_title(LABELS[name], fontsize=10)
        if along is not None:
            _plot_line(ax, atlas, name, along)
            if name == "megno" or (ax is axes[0] and ax.get_legend_handles_labels()[0]):
                ax.legend(fontsize=7, loc="best")
            continue
        if name == "megno":
            mesh = ax.pcolormesh(xe, ye, atlas.values[name], shading="flat", cmap="plasma", vmin=0.0, vmax=MEGNO_CLIP)
            bar = fig.colorbar(mesh, ax=ax, extend="max")
            bar.ax.axhline(MEGNO_CHAOTIC, color="w", lw=1.5)
            if atlas.rows.size > 1 and atlas.cols.size > 1 and np.ma.count(atlas.values[name]) > 0:
                ax.contour(atlas.cols / _scale(atlas.col_name), atlas.rows / _scale(atlas.row_name),
                           atlas.values[name], levels=[MEGNO_CHAOTIC], colors="w", linewidths=1.0)
        else:
            mesh = ax.pcolormesh(xe, ye, atlas.values[name], shading="flat", cmap="viridis")
            fig.colorbar(mesh, ax=ax)
        _decorate(ax, atlas, body)
        ax.set_xlim(xe[0], xe[-1])
        ax.set_ylim(ye[0], ye[-1])
    for ax in axes[len(names):]:
        ax.set_visible(False)
    fig.suptitle(title if along is None else f"{title}; {_fixed_value(atlas, along)}", fontsize=10)
    fig.tight_layout()
    return fig


def plot_atlas(atlas: Atlas, out: Path, title: str, body: Body | None = None) -> list[Path]:
    """Write the atlas's figure (:func:`atlas_figure`) as PNG and PDF."""
    return save_figure(atlas_figure(atlas, title, body), out, "atlas")


def atlas_check_figure(atlas: Atlas, check: AtlasCheck, title: str) -> Any:
    """The figure of :func:`plot_atlas_check`: over a plane, the confirmed points coloured by their largest error; for
    an atlas of one row or one column, that error against the values it has (log scale) with the points that differ
    as vertical lines.  Returns the figure."""
    from matplotlib.colors import LogNorm

    fig = new_figure(figsize=(6.5, 5))
    ax = fig.subplots()
    cont = [np.ma.abs(check.rel_error[n]) for n in ("slow_period", "Phi", "QR_extent", "QJ_extent")]
    worst = np.ma.max(np.ma.vstack(cont), axis=0).filled(np.nan)
    xs, ys = _scale(atlas.col_name), _scale(atlas.row_name)
    x, y = atlas.cols[check.index[:, 1]] / xs, atlas.rows[check.index[:, 0]] / ys
    along = line_axis(atlas)
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
        fig.tight_layout()
        return fig
    if ok.any():
        sc = ax.scatter(x[ok], y[ok], c=worst[ok], cmap="magma_r", s=40, norm=LogNorm(vmin=max(worst[ok].min(), 1e-12),
                                                                                     vmax=max(worst[ok].max(), 1e-11)))
        fig.colorbar(sc, ax=ax, label=error_label)
    ax.plot(x[diff], y[diff], "o", ms=12, mfc="none", mec="tab:red", label="reversal counts differ")
    if differs.any():
        ax.plot(x[differs], y[differs], "s", ms=15, mfc="none", mec="k", label="regular/chaotic verdict differs")
    ax.set_xlim(*_edges(atlas.cols / xs)[[0, -1]])
    ax.set_ylim(*_edges(atlas.rows / ys)[[0, -1]])
    _decorate(ax, atlas, None)
    if (diff | differs).any():
        ax.legend(fontsize=8, loc="best")
    ax.set_title(title, fontsize=9)
    fig.tight_layout()
    return fig


def plot_atlas_check(atlas: Atlas, check: AtlasCheck, out: Path, title: str) -> list[Path]:
    """Where the direct ODE confirmed the map: the largest |relative error| of the slow period, Φ and the extents
    at each confirmed point (colour, log scale; along the line for an atlas of one row or column), the points whose
    reversal counts differ (red ring, or dotted line) and, with the chaos layer, those where the map's regular/chaotic
    verdict differs from the ODE's (black square, or dashed line) (:func:`atlas_check_figure`); PNG and PDF."""
    return save_figure(atlas_check_figure(atlas, check, title), out, "atlas_check")
