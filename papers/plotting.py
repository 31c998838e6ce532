"""Plotting helpers for the critical-line diagrams (paper figs. 4, 7–10), shared by ``rocknroller diagram`` and
the figure scripts in ``papers/lynch_bustamante``.  No physics here: every number comes from
:mod:`rocknroller.analysis.criticality.lines` and :mod:`rocknroller.analysis.model.invariants`.

Layout of :func:`region_diagram`: the (Q_R, Q_J) plane in the centre with the critical lines Q_J = Q_J,π^crit
(red, solid) and Q_J = Q_J,0^crit (blue, dashed), one marked representative point per region, and the graph of
V_φ(θ) at each representative point in a panel on the side where that region lies (II above, IV below, III left,
I right), so that no inset covers a line, a label or the orbit.  The lines' styles and drawing
(:mod:`rocknroller.analysis.criticality.drawing`) are re-exported here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from numpy.typing import NDArray

from rocknroller.analysis.criticality import lines as crit
from rocknroller.analysis.criticality import theta_z
from rocknroller.analysis.criticality.drawing import LINE_STYLE, critical_line_data, draw_critical_lines
from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.invariants import V_phi
from rocknroller.analysis.routh.reduction import Q_RANGE
from rocknroller.papers.output import new_figure

if TYPE_CHECKING:  # pragma: no cover
    from rocknroller.numerics.trajectory import Trajectory

__all__ = ["LINE_STYLE", "DiagramData", "critical_line_data", "draw_critical_lines", "free_spots",
           "plot_V_phi", "region_diagram", "scaled_axis"]

#: Where each region's V_φ panel sits around the central axes (row, column of a 3×3 grid).
_PANEL_CELL = {"II": (0, 1), "IV": (2, 1), "III": (1, 0), "I": (1, 2)}
_NUMERAL_FONT: dict[str, Any] = dict(fontsize=12, fontweight="bold")


@dataclass
class DiagramData:
    """What :func:`region_diagram` drew (for tests and CSV output).

    Examples
    --------
    >>> import rocknroller as rr
    >>> fig, data = rr.region_diagram(rr.Body.paper(), QR_max=0.01)
    >>> for name, (QR, QJ) in sorted(data.representatives.items()):
    ...     print(name, rr.region(QR, QJ, rr.Body.paper()))
    ...
    I I
    II II
    III III
    IV IV
    """

    QR_line: NDArray[np.float64]
    QJ0_line: NDArray[np.float64]
    QJpi_line: NDArray[np.float64]
    window: tuple[float, float, float, float]
    representatives: dict[str, tuple[float, float]] = field(default_factory=dict)
    axes: dict[str, object] = field(default_factory=dict)


def _to_axes(QR, QJ, window):
    x0, x1, y0, y1 = window
    return (np.asarray(QR) - x0) / (x1 - x0), (np.asarray(QJ) - y0) / (y1 - y0)


def _from_axes(u, v, window):
    x0, x1, y0, y1 = window
    return x0 + np.asarray(u) * (x1 - x0), y0 + np.asarray(v) * (y1 - y0)


def free_spots(body: Body, window: tuple[float, float, float, float],
               obstacles: NDArray[np.float64] | None = None, margin: float = 0.1,
               n: int = 41) -> dict[str, tuple[float, float, float]]:
    """For each region visible in ``window``, the grid point farthest (in axes-fraction units) from both
    critical lines, the frame and the ``obstacles`` (axes-fraction points, shape (2, m)).

    Returns ``{region: (Q_R, Q_J, clearance)}``.
    """
    u = np.linspace(margin, 1 - margin, n)
    U, Vv = np.meshgrid(u, u)
    QR, QJ = _from_axes(U, Vv, window)
    reg = np.asarray(crit.region(QR, QJ, body, tol=0.0))
    clearance = np.minimum(np.minimum(U, 1 - U), np.minimum(Vv, 1 - Vv))
    line_QR = np.linspace(window[0], window[1], 400)
    for fn in (crit.QJ_crit_0, crit.QJ_crit_pi):
        lu, lv = _to_axes(line_QR, fn(line_QR, body), window)
        keep = (lv > -0.5) & (lv < 1.5)
        if np.any(keep):
            d = np.hypot(U[..., None] - lu[keep], Vv[..., None] - lv[keep]).min(axis=-1)
            clearance = np.minimum(clearance, d)
    if obstacles is not None and obstacles.size:
        ou, ov = obstacles
        for i in range(0, ou.size, 500):
            d = np.hypot(U[..., None] - ou[i:i + 500], Vv[..., None] - ov[i:i + 500]).min(axis=-1)
            clearance = np.minimum(clearance, d)
    out = {}
    for lab in crit.REGIONS:
        m = reg == lab
        if np.any(m):
            k = np.argmax(np.where(m, clearance, -np.inf))
            out[lab] = (float(QR.flat[k]), float(QJ.flat[k]), float(clearance.flat[k]))
    return out


def plot_V_phi(ax, body: Body, QR: float, QJ: float, region: str) -> None:
    """V_φ(θ; Q_J, Q_R) on (0, π) (paper eq. phidotCJQR) with its zero θ_z (I, III) or extremum θ_e (II, IV)."""
    theta = np.linspace(1e-3, math.pi - 1e-3, 1200)
    v = V_phi(theta, QR=QR, QJ=QJ, body=body)
    core = v[(theta > 0.35) & (theta < math.pi - 0.35)]
    lo, hi = min(core.min(), 0.0), max(core.max(), 0.0)
    pad = 1.2 * (hi - lo) if hi > lo else 1.0
    ax.plot(theta, v, color="k", lw=1.2)
    ax.axhline(0.0, color="0.6", lw=0.6)
    if region in ("I", "III"):
        tz = float(theta_z.theta_z(QR, QJ, body))
        ax.axvline(tz, color="0.3", ls=":", lw=1)
        ax.annotate(r"$\theta_z$", (tz, 0), xytext=(4, 4), textcoords="offset points", fontsize=8)
    else:
        te = float(theta_z.theta_e(QR, QJ, body))
        ax.axvline(te, color="0.3", ls=":", lw=1)
        ax.annotate(r"$\theta_e$", (te, float(V_phi(te, QR=QR, QJ=QJ, body=body))), xytext=(4, 4 if region == "IV" else -12),
                    textcoords="offset points", fontsize=8)
    ax.set_xlim(0, math.pi)
    ax.set_ylim(lo - 0.25 * pad, hi + 0.25 * pad)
    ax.set_xticks([0, math.pi / 2, math.pi], ["0", r"$\pi/2$", r"$\pi$"])
    ax.tick_params(labelsize=7)
    ax.yaxis.get_offset_text().set_fontsize(7)
    ax.ticklabel_format(axis="y", style="sci", scilimits=(-2, 3))
    ax.set_xlabel(r"$\theta$", fontsize=8, labelpad=1)
    ax.set_ylabel(r"$\dot\phi=V_\phi(\theta)$", fontsize=8, labelpad=1)
    ax.set_title(f"Region {region}:  $(Q_R, Q_J)$ = ({QR:.3g}, {QJ:.3g})", fontsize=8)


def _window(body: Body, QR_max: float, traj: "Trajectory | None") -> tuple[float, float, float, float]:
    if traj is None:
        k = max(abs(float(crit.QJ_crit_0(1.0, body))), abs(float(crit.QJ_crit_pi(1.0, body))))
        return (-QR_max, QR_max, -1.3 * k * QR_max, 1.3 * k * QR_max)
    x0, x1 = float(np.min(traj.QR)), float(np.max(traj.QR))
    y0, y1 = float(np.min(traj.QJ)), float(np.max(traj.QJ))
    wx = max(x1 - x0, 1e-3 * max(abs(x0), abs(x1), 1e-12))
    wy = max(y1 - y0, 1e-3 * max(abs(y0), abs(y1), 1e-12))
    return (x0 - 0.35 * wx, x1 + 0.35 * wx, y0 - 0.35 * wy, y1 + 0.35 * wy)


#: Half-widths of the Q_R window the diagram draws: Q_RANGE (reduction) with a margin of 1e3 below (the window's
#: sample points fall to ~1e-3 of it about 0) and 10 above (the window reaches 1.7 QR_max).
_QR_MAX_RANGE = (1e3 * Q_RANGE[0], Q_RANGE[1] / 10.0)


#: Height of the orbit layout's legend strip (inches), below the orbit's axis label.
_LEGEND_INCHES = 0.75


def region_diagram(body: Body, QR_max: float = 1.0, traj: "Trajectory | None" = None,
                   title: str | None = None) -> tuple[Figure, DiagramData]:
    """The four-region diagram (paper fig. 4), optionally with a trajectory's (Q_R(t), Q_J(t)) orbit
    and its turning points (paper figs. 7–10: θ-maxima red, θ-minima blue).

    Parameters
    ----------
    body : Body
    QR_max : float
        Half-width of the Q_R window without a trajectory (Q_J spans 1.3× the steeper line).
    traj : rocknroller.numerics.trajectory.Trajectory, optional
        Zooms to the orbit (with 35 % margins) and overlays it.

    Returns
    -------
    (figure, DiagramData)

    Examples
    --------
    >>> import rocknroller as rr
    >>> fig, data = rr.region_diagram(rr.Body.paper(), QR_max=0.01)
    >>> print(type(fig).__name__, sorted(data.representatives))
    Figure ['I', 'II', 'III', 'IV']
    """
    lo, hi = _QR_MAX_RANGE
    if not lo <= QR_max <= hi:  # also NaN
        raise ValueError(f"QR_max must lie in [{lo:g}, {hi:g}] (the window, 1.7 QR_max either side of 0, and its sample "
                         f"points must stay within the critical lines' range of Q, reduction.Q_RANGE = {Q_RANGE}), got "
                         f"QR_max={QR_max!r}")
    window = _window(body, QR_max, traj)
    obstacles = None
    if traj is not None:
        idx = np.linspace(0, traj.QR.size - 1, min(traj.QR.size, 4000)).astype(int)
        obstacles = np.array(_to_axes(traj.QR[idx], traj.QJ[idx], window))
    spots = free_spots(body, window, obstacles)
    if traj is None:  # cross layout: each region's panel on the side where the region lies
        fig = new_figure(figsize=(8.0, 7.2))
        gs = fig.add_gridspec(3, 3, width_ratios=[1, 1.45, 1], height_ratios=[1, 1.45, 1], wspace=0.42, hspace=0.6)
        ax = fig.add_subplot(gs[1, 1])
        cells = {lab: gs[_PANEL_CELL[lab]] for lab in spots}
    else:  # orbit layout: large orbit panel, the visible regions' panels stacked on the right
        n = max(len(spots), 2)
        height = 2.1 * n + 1.6 + _LEGEND_INCHES
        fig = new_figure(figsize=(8.0, height))
        gs = fig.add_gridspec(n, 3, width_ratios=[1, 1, 0.9], wspace=0.5, hspace=0.75, top=1 - 0.85 / height,
                              bottom=(0.6 + _LEGEND_INCHES) / height)
        ax = fig.add_subplot(gs[:, :2])
        order = [lab for lab in ("II", "I", "III", "IV") if lab in spots]
        cells = {lab: gs[i, 2] for i, lab in enumerate(order)}
    lines = draw_critical_lines(ax, body, window[0], window[1])
    if traj is not None:
        from rocknroller.numerics.trajectory_plots import plot_invariant_orbit

        plot_invariant_orbit(traj, ax=ax)
    ax.set_xlim(window[0], window[1])
    ax.set_ylim(window[2], window[3])
    ax.axhline(0, color="0.85", lw=0.5, zorder=0)
    ax.axvline(0, color="0.85", lw=0.5, zorder=0)
    scaled_axis(ax.xaxis, r"Routh's quantity $Q_R$", window[:2])
    scaled_axis(ax.yaxis, r"Jellett's quantity $Q_J$", window[2:])
    data = DiagramData(QR_line=lines["QR"], QJ0_line=lines["QJ0"], QJpi_line=lines["QJpi"], window=window)
    data.axes["main"] = ax
    for lab, (qr, qj, _) in spots.items():
        ax.plot([qr], [qj], "o", color="tab:green", ms=5, zorder=5)
        ax.annotate(lab, (qr, qj), xytext=(5, 4), textcoords="offset points", color="darkgreen", **_NUMERAL_FONT)
        data.representatives[lab] = (qr, qj)
        inset = fig.add_subplot(cells[lab])
        plot_V_phi(inset, body, qr, qj, lab)
        data.axes[lab] = inset
    handles, labels = ax.get_legend_handles_labels()
    handles.append(Line2D([], [], marker="o", ls="", color="tab:green"))
    labels.append(r"representative point (its $V_\phi(\theta)$ in the side panel)")
    if traj is None:
        legend_ax = fig.add_subplot(gs[0, 0])
        legend_ax.axis("off")
        legend_ax.legend(handles, [_wrap(s) for s in labels], loc="upper left", fontsize=7.5, frameon=False,
                         borderaxespad=0)
    else:
        # below the orbit's axis label, inside the figure: a plain savefig keeps it (it fell below the figure)
        box = ax.get_position()
        fig.legend(handles, labels, loc="lower center", bbox_to_anchor=(0.5 * (box.x0 + box.x1), 0.1 / height),
                   ncol=2, fontsize=7.5, frameon=False)
    fig.suptitle(title or (f"Critical regions I–IV: a={body.a:g}, I1={body.I1:.4g}, I3={body.I3:.4g}"
                           + (f", eps={body.epsilon:.3g}" if not body.is_symmetric else "")), fontsize=10,
                 y=1 - 0.25 / fig.get_figheight())
    return fig, data


def scaled_axis(axis, label: str, lim: tuple[float, float]) -> None:
    """Tick labels in units of 10^p with the power in the axis label (no offset text to collide with labels)."""
    from matplotlib.ticker import FuncFormatter, ScalarFormatter

    big = max(abs(lim[0]), abs(lim[1]))
    p = int(math.floor(math.log10(big))) if big > 0 else 0
    if -1 <= p <= 2:
        axis.set_label_text(label)
        axis.set_major_formatter(ScalarFormatter(useOffset=False))
        axis.get_major_formatter().set_scientific(False)
        return
    scale = 10.0**p
    axis.set_major_formatter(FuncFormatter(lambda v, _: f"{v / scale:g}"))
    axis.set_label_text(f"{label}  ($\\times 10^{{{p}}}$)")


def _wrap(text: str, width: int = 34) -> str:
    """Break a legend entry at a space before ``width`` characters (outside TeX math)."""
    if len(text) <= width or "(" not in text:
        return text
    head, tail = text.split(" (", 1)
    return head + "\n(" + tail
