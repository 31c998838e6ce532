"""The figure of a precession table of Routh's sphere: the rocking period and the precession angles Δφ, Δψ over the
(Q_R, Q_J) plane, one panel each with its labelled colour bar.  It is the figure of
:meth:`rocknroller.analysis.routh.quadrature.Precession.plot` and of ``rocknroller table --plot``.

Points that fill a grid Q_R × Q_J once each (the command's table, or a ``numpy.meshgrid``) are drawn as cells about
their values (:func:`cell_edges`), any other points as dots.  The period is in time units; the angles, per period, in
units of π on a colour scale symmetric about 0 (white: no precession; the sign is the sense of the motion).  Points
without a rocking motion (no motion, steady rolling, or unresolved: the masked entries, or the empty cells of the
table) are left blank.  Without a figure a new pyplot figure is opened (on whatever backend the user has chosen);
matplotlib is imported only when a figure is drawn.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["PERIODS", "cell_edges", "precession_figure"]

#: The period the angles are given per, by its name in the table (``--per``), as the figure writes it.
PERIODS = {"T_theta": "$T_\\theta$", "tau": "$\\tau$"}


def cell_edges(x: ArrayLike) -> NDArray[np.float64]:
    """The edges of the cells about sorted grid values: the midpoints, and the ends as far beyond the first and last
    values as the midpoints next to them; a single value gets a cell of ±1 % of it (±0.01 about 0 or a small value).

    Parameters
    ----------
    x : array_like
        Increasing grid values (one at least).

    Returns
    -------
    ndarray
        ``x.size + 1`` edges (for ``pcolormesh(..., shading="flat")``).

    Examples
    --------
    >>> from rocknroller.analysis.routh.precession_plots import cell_edges
    >>> print(cell_edges([0.0, 1.0, 3.0]), cell_edges([2.0]))
    [-0.5  0.5  2.   4. ] [1.98 2.02]
    """
    x = np.atleast_1d(np.asarray(x, float))
    if x.size == 1:
        h = 0.01 * max(abs(x[0]), 1.0)
        return np.array([x[0] - h, x[0] + h])
    mid = 0.5 * (x[1:] + x[:-1])
    return np.concatenate([[2 * x[0] - mid[0]], mid, [2 * x[-1] - mid[-1]]])


def _floats(a: Any) -> np.ma.MaskedArray:
    """Flat floats, masked where missing (None, masked or not finite); mpmath numbers are converted."""
    m: np.ma.MaskedArray = np.ma.ravel(np.ma.asarray(a, dtype=object))
    missing = np.ma.getmaskarray(m)
    return np.ma.masked_invalid(np.array([np.nan if k or v is None else float(v) for v, k in zip(m.data, missing)]))


def _grid(x: NDArray[np.float64], y: NDArray[np.float64]) -> tuple[NDArray, NDArray, NDArray, NDArray] | None:
    """The distinct Q_R and Q_J and each point's column and row, if the points fill that grid once each; else None."""
    xs, ix = np.unique(x, return_inverse=True)
    ys, iy = np.unique(y, return_inverse=True)
    if xs.size * ys.size != x.size or np.unique(iy * xs.size + ix).size != x.size:
        return None
    return xs, ys, ix, iy


def precession_figure(QR: ArrayLike, QJ: ArrayLike, period: ArrayLike, delta_phi: ArrayLike, delta_psi: ArrayLike, *,
                      per: str = "T_theta", fig: Any = None, title: str | None = None) -> Any:
    """Draw a precession table over the (Q_R, Q_J) plane: the period, Δφ and Δψ per period, three panels with colour
    bars (module docstring).

    Parameters
    ----------
    QR, QJ : array_like
        The points (any shape; flattened together with the values).
    period, delta_phi, delta_psi : array_like
        At each point: the period (T_θ, or τ = 2 T_θ) and the full increments of φ and ψ per that period, masked or
        None where there is no rocking motion (mpmath numbers are converted to floats).
    per : {"T_theta", "tau"}
        The period the values are given per (the table's ``--per``).
    fig : matplotlib.figure.Figure, optional
        The figure to draw on (a new pyplot figure with a constrained layout without one).
    title : str, optional
        The figure's title (default: "precession of Routh's sphere"); a line under it counts the blank points.

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    ValueError
        ``per`` not one of ``PERIODS``, or arrays of different sizes.

    Examples
    --------
    >>> import math
    >>> import numpy as np
    >>> from matplotlib.figure import Figure
    >>> import rocknroller as rr
    >>> from rocknroller.analysis.routh.precession_plots import precession_figure
    >>> QR, QJ = np.meshgrid(np.linspace(-0.01, 0.01, 5), np.linspace(-0.004, 0.004, 3))
    >>> p, _ = rr.precession_from_turning_point(0.95 * math.pi, QR, QJ, rr.Body.paper())
    >>> fig = precession_figure(QR, QJ, p.T_theta, p.delta_phi, p.delta_psi, fig=Figure(figsize=(13, 4)))
    >>> print([ax.get_title() for ax in fig.axes[:3]])
    ['rocking period $T_\\\\theta$', 'precession $\\\\Delta\\\\phi$ per $T_\\\\theta$', 'spin $\\\\Delta\\\\psi$ per $T_\\\\theta$']
    >>> print(fig.axes[3].get_ylabel(), fig.axes[4].get_ylabel())
    $T_\\theta$ (time units) $\\Delta\\phi/\\pi$ (rad / $\\pi$)
    """
    if per not in PERIODS:
        raise ValueError(f"per must be one of {list(PERIODS)}, got per={per!r}")
    x, y = _floats(QR).filled(np.nan), _floats(QJ).filled(np.nan)
    values = [_floats(v) for v in (period, delta_phi, delta_psi)]
    if any(v.size != x.size for v in (y, *values)):
        sizes = [x.size, y.size] + [v.size for v in values]
        raise ValueError(f"QR, QJ, period, delta_phi and delta_psi must have one size, got sizes {sizes}")
    if fig is None:
        import matplotlib.pyplot as plt

        fig = plt.figure(figsize=(13, 4), layout="constrained")
    sym = PERIODS[per]
    panels = ((f"rocking period {sym}", 1.0, "viridis", f"{sym} (time units)"),
              (f"precession $\\Delta\\phi$ per {sym}", math.pi, "RdBu_r", "$\\Delta\\phi/\\pi$ (rad / $\\pi$)"),
              (f"spin $\\Delta\\psi$ per {sym}", math.pi, "RdBu_r", "$\\Delta\\psi/\\pi$ (rad / $\\pi$)"))
    grid = _grid(x, y)
    for ax, v, (name, unit, cmap, label) in zip(fig.subplots(1, 3), values, panels):
        v = v / unit
        top = float(np.ma.max(np.abs(v))) if v.count() else 1.0
        lim = {} if unit == 1.0 else {"vmin": -top, "vmax": top}  # the angles: symmetric about 0
        if grid is None:
            ok = ~np.ma.getmaskarray(v)
            art = ax.scatter(x[ok], y[ok], c=v.compressed(), s=25, cmap=cmap, **lim)
        else:
            xs, ys, ix, iy = grid
            z = np.ma.masked_all((ys.size, xs.size))
            z[iy, ix] = v
            art = ax.pcolormesh(cell_edges(xs), cell_edges(ys), z, shading="flat", cmap=cmap, **lim)
        fig.colorbar(art, ax=ax, label=label)
        ax.set_title(name, fontsize=10)
        ax.set_xlabel("$Q_R$")
        ax.set_ylabel("$Q_J$")
        ax.ticklabel_format(style="sci", scilimits=(-2, 2))
    blank = int(np.count_nonzero(np.ma.getmaskarray(values[0])))
    note = f"\n{blank} of {x.size} points without a rocking motion (blank)" if blank else ""
    fig.suptitle((title or "precession of Routh's sphere") + note, fontsize=10)
    return fig
