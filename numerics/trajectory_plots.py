"""Plots of a direct-ODE trajectory: contact track, φ at the θ-maxima, the (Q_R, Q_J) orbit, and the running MEGNO of
a run's chaos indicators.

Each function draws on the axes it is given; without one it opens a pyplot figure (for interactive use,
on whatever backend the user has chosen: the package never calls ``matplotlib.use``).  They are the quick look of
:meth:`rocknroller.numerics.trajectory.Trajectory.plot` and take a run by its attributes (``maxima``, ``minima``
and, for a sampled :class:`~rocknroller.numerics.trajectory.Trajectory`, ``QR``, ``QJ``, ``X``, ``Y``), so that
this module imports nothing from the one that calls it (a :class:`~rocknroller.numerics.ensembles.ensemble.RunSummary` has the
θ-maxima only, and is drawn with them)."""

from __future__ import annotations

import math
from typing import Any

__all__ = ["plot_contact_track", "plot_phi_at_maxima", "plot_invariant_orbit", "plot_megno"]


def _pyplot():
    """pyplot, imported only when a function is called without axes (so importing this module never
    resolves a backend)."""
    import matplotlib.pyplot as plt

    return plt


def plot_contact_track(traj: Any, ax=None, label: str | None = None):
    """Contact point (X, Y) with a circle at the start (paper figs. 5, 6)."""
    if ax is None:
        _, ax = _pyplot().subplots(figsize=(4.5, 4.5))
    ax.plot(traj.X, traj.Y, lw=0.6, label=label)
    ax.plot(traj.X[:1], traj.Y[:1], "o", mfc="none", color="k", ms=6)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("X (radii)")
    ax.set_ylabel("Y (radii)")
    return ax


def plot_phi_at_maxima(traj: Any, ax=None, label: str | None = None):
    """Full azimuth φ at the θ-maxima against time (paper fig. 5, right panels)."""
    if ax is None:
        _, ax = _pyplot().subplots(figsize=(5, 3.5))
    ax.plot(traj.maxima.t, traj.maxima.phi / math.pi, ".", ms=3, label=label)
    ax.set_xlabel("t (time units)")
    ax.set_ylabel(r"$\phi$ at $\theta$-maxima ($\pi$ rad)")
    return ax


def plot_invariant_orbit(traj: Any, ax=None, turning_points: bool = True):
    """(Q_R(t), Q_J(t)) with dots at the θ-maxima (red) and θ-minima (blue; a run that kept the maxima only: those)
    (paper figs. 7-10)."""
    if ax is None:
        _, ax = _pyplot().subplots(figsize=(5, 4))
    if hasattr(traj, "QR"):  # a TurningPointRun has only the turning points
        ax.plot(traj.QR, traj.QJ, color="k", lw=0.5, label=r"$(Q_R(t), Q_J(t))$")
    if turning_points:
        ax.plot(traj.maxima.QR, traj.maxima.QJ, ".", color="tab:red", ms=4, label=r"$\theta$-maxima")
        if hasattr(traj, "minima"):
            ax.plot(traj.minima.QR, traj.minima.QJ, ".", color="tab:blue", ms=4, label=r"$\theta$-minima")
    ax.set_xlabel(r"$Q_R$")
    ax.set_ylabel(r"$Q_J$")
    ax.ticklabel_format(style="sci", scilimits=(-2, 2))
    return ax


def plot_megno(indicators: Any, ax=None):
    """The running MEGNO ⟨Y⟩ at the θ-maxima against t (a :class:`~rocknroller.numerics.megno.ChaosIndicators`), with
    the line ⟨Y⟩ = ``MEGNO_CHAOTIC`` (above: chaotic) and the verdict in the legend."""
    from rocknroller.numerics.megno import MEGNO_CHAOTIC

    if ax is None:
        _, ax = _pyplot().subplots(figsize=(5, 3.5), layout="constrained")
    verdict = "regular" if indicators.regular else "chaotic"
    ax.plot(indicators.t, indicators.mean_megno, color="k", lw=1,
            label=rf"MEGNO $\langle Y\rangle$ (final {indicators.megno:.3g}: {verdict})")
    ax.axhline(MEGNO_CHAOTIC, color="tab:red", ls="--", lw=1, label=f"{MEGNO_CHAOTIC:g}: chaotic above")
    ax.set_xlabel("t (time units)")
    ax.set_ylabel(r"MEGNO $\langle Y\rangle$ at the $\theta$-maxima")
    ax.legend(fontsize=8, loc="best")
    return ax
