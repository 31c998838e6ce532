"""Figures of a recession atlas (:mod:`rocknroller.analysis.atlas`): heat maps over (ψ0, θ0), the paper's starts
marked, and the map's errors at the points the direct ODE confirmed."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from rocknroller.analysis.atlas import ATLAS_OBSERVABLES, Atlas, AtlasCheck
from rocknroller.papers.output import new_figure, save_figure

__all__ = ["PAPER_RELEASES", "LABELS", "plot_atlas", "plot_atlas_check"]

#: The paper's releases from rest (θ0, ψ0) (§numerics: figs. 6 and 7, θ0 = 0.95π; the four ψ0 of its slow runs).
PAPER_RELEASES = tuple((0.95 * math.pi, psi) for psi in (math.pi / 8, math.pi / 4, 3 * math.pi / 8, 3.9 * math.pi / 8))
#: Panel titles.
LABELS = {"slow_period": "slow period of $\\Theta = 2\\psi$", "Phi": "azimuth span $\\Phi$ (rad)",
          "QR_extent": "$Q_R$ extent", "QJ_extent": "$Q_J$ extent",
          "full_reversals": "full-angle reversals / 1000 t.u.", "visible_reversals": "visible reversals / 1000 t.u."}


def _edges(x: np.ndarray) -> np.ndarray:
    """Cell edges around grid values (midpoints; a single value gets a cell of ±1 % or ±0.01)."""
    if x.size == 1:
        h = 0.01 * max(abs(x[0]), 1.0)
        return np.array([x[0] - h, x[0] + h])
    mid = 0.5 * (x[1:] + x[:-1])
    return np.concatenate([[2 * x[0] - mid[0]], mid, [2 * x[-1] - mid[-1]]])


def _mark_paper(ax: Any, atlas: Atlas) -> None:
    th, ps = atlas.theta0, atlas.psi0
    for t0, p0 in PAPER_RELEASES:
        if th.min() <= t0 <= th.max() and ps.min() <= p0 <= ps.max():
            ax.plot(p0 / math.pi, t0 / math.pi, marker="*", ms=9, mfc="white", mec="k", ls="none")


def plot_atlas(atlas: Atlas, out: Path, title: str) -> list[Path]:
    """Six heat maps of ``ATLAS_OBSERVABLES`` over (ψ0/π, θ0/π), the paper's releases starred; PNG and PDF."""
    fig = new_figure(figsize=(13, 7.5))
    axes = fig.subplots(2, 3).ravel()
    xe, ye = _edges(atlas.psi0 / math.pi), _edges(atlas.theta0 / math.pi)
    for ax, name in zip(axes, ATLAS_OBSERVABLES):
        mesh = ax.pcolormesh(xe, ye, atlas.values[name], shading="flat", cmap="viridis")
        fig.colorbar(mesh, ax=ax)
        _mark_paper(ax, atlas)
        ax.set_title(LABELS[name], fontsize=10)
        ax.set_xlabel("$\\psi_0/\\pi$")
        ax.set_ylabel("$\\theta_0/\\pi$")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return save_figure(fig, out, "atlas")


def plot_atlas_check(atlas: Atlas, check: AtlasCheck, out: Path, title: str) -> list[Path]:
    """Where the direct ODE confirmed the map: the largest |relative error| of the slow period, Φ and the extents
    at each confirmed point (colour, log scale), and the points whose reversal counts differ (red ring)."""
    from matplotlib.colors import LogNorm

    fig = new_figure(figsize=(6.5, 5))
    ax = fig.subplots()
    cont = [np.ma.abs(check.rel_error[n]) for n in ("slow_period", "Phi", "QR_extent", "QJ_extent")]
    worst = np.ma.max(np.ma.vstack(cont), axis=0).filled(np.nan)
    x, y = atlas.psi0[check.index[:, 1]] / math.pi, atlas.theta0[check.index[:, 0]] / math.pi
    ok = np.isfinite(worst) & (worst > 0)
    if ok.any():
        sc = ax.scatter(x[ok], y[ok], c=worst[ok], cmap="magma_r", s=40, norm=LogNorm(vmin=max(worst[ok].min(), 1e-12),
                                                                                     vmax=max(worst[ok].max(), 1e-11)))
        fig.colorbar(sc, ax=ax, label="largest |map/ODE - 1| (slow period, $\\Phi$, extents)")
    diff = (np.ma.abs(check.rel_error["full_reversals"]) + np.ma.abs(check.rel_error["visible_reversals"])).filled(0) > 0
    ax.plot(x[diff], y[diff], "o", ms=12, mfc="none", mec="tab:red", label="reversal counts differ")
    ax.set_xlim(*_edges(atlas.psi0 / math.pi)[[0, -1]])
    ax.set_ylim(*_edges(atlas.theta0 / math.pi)[[0, -1]])
    _mark_paper(ax, atlas)
    ax.set_xlabel("$\\psi_0/\\pi$")
    ax.set_ylabel("$\\theta_0/\\pi$")
    if diff.any():
        ax.legend(fontsize=8, loc="best")
    ax.set_title(title, fontsize=9)
    fig.tight_layout()
    return save_figure(fig, out, "atlas_check")
