"""The critical lines drawn on a (Q_R, Q_J) axes, in the styles of paper fig. 4, for the quick looks of the result
types (``SlowPrediction.plot`` and the others) and the figures of :mod:`rocknroller.papers`.  Only matplotlib's axes
methods are called (no pyplot, no backend); the numbers come from :mod:`rocknroller.analysis.criticality.lines`."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from rocknroller.analysis.criticality import lines as crit
from rocknroller.analysis.model.body import Body

__all__ = ["LINE_STYLE", "critical_line_data", "draw_critical_lines"]

#: Paper fig. 4 conventions: Q_J,π^crit red solid, Q_J,0^crit blue dashed.
LINE_STYLE = {
    "pi": dict(color="tab:red", ls="-", lw=1.4, label=r"$Q_J=Q_{J,\pi}^{\mathrm{crit}}$ (visible-angle reversal)"),
    "0": dict(color="tab:blue", ls="--", lw=1.4, label=r"$Q_J=Q_{J,0}^{\mathrm{crit}}$ (full-angle reversal)"),
}


def critical_line_data(body: Body, QR_min: float, QR_max: float, n: int = 201) -> dict[str, NDArray[np.float64]]:
    """Q_R samples and Q_J,0^crit, Q_J,π^crit on them (paper eqs. QJcrit_0, QJcrit_pi)."""
    QR = np.linspace(QR_min, QR_max, n)
    return {"QR": QR, "QJ0": crit.QJ_crit_0(QR, body), "QJpi": crit.QJ_crit_pi(QR, body)}


def draw_critical_lines(ax: Any, body: Body, QR_min: float, QR_max: float) -> dict[str, NDArray[np.float64]]:
    """Draw both critical lines over [QR_min, QR_max]; the Line2D objects get gid "QJ0crit" / "QJpicrit"."""
    d = critical_line_data(body, QR_min, QR_max)
    ax.plot(d["QR"], d["QJpi"], gid="QJpicrit", **LINE_STYLE["pi"])
    ax.plot(d["QR"], d["QJ0"], gid="QJ0crit", **LINE_STYLE["0"])
    return d
