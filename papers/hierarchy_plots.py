"""The hierarchy of loaded spheres as a figure (paper fig. 1, with Borisov and Mamaev's table beside it): the members
and the conditions that lead from one to the next, and for each member and quantity the drift measured along the
direct ODE, marked with the sympy verdict.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from rocknroller.analysis.hierarchy.conservation import QUANTITIES
from rocknroller.analysis.hierarchy.table import MemberRow
from rocknroller.papers.output import new_figure

__all__ = ["hierarchy_figure"]

#: Where each member sits in the left panel (paper fig. 1) and the arrows between them, with their conditions.
_PLACES = {"Chaplygin's top": (0.5, 0.88), "rock'n'roller": (0.25, 0.5), "Chaplygin's ball": (0.78, 0.5),
           "Routh's sphere": (0.25, 0.12)}
_ARROWS = (("Chaplygin's top", "rock'n'roller", "c on a\nprincipal axis"),
           ("Chaplygin's top", "Chaplygin's ball", "c = 0"),
           ("rock'n'roller", "Routh's sphere", "I1 = I2"))


def _symbol(name: str) -> str:
    q = next(q for q in QUANTITIES if q.name == name)
    return q.symbol + (" (g=0)" if q.without_gravity else "")


def hierarchy_figure(rows: tuple[MemberRow, ...]) -> Any:
    """The figure of :func:`~rocknroller.analysis.hierarchy.table.hierarchy_table`'s rows: left, the family tree
    with each member's proved integrals and invariant measure; right, log10 of each quantity's measured drift
    (colour, fixed scale −16 to 0) with the sympy verdict in the cell (✓ conserved, ✗ not; a cell whose measurement
    disagrees with its proof is outlined in red).  Returns the matplotlib figure.

    Examples
    --------
    >>> from rocknroller.analysis.hierarchy.table import hierarchy_table
    >>> from rocknroller.papers.hierarchy_plots import hierarchy_figure
    >>> fig = hierarchy_figure(hierarchy_table(t_end=20.0))
    >>> print([ax.get_title() for ax in fig.axes][:2])
    ['The loaded spheres (paper fig. 1)', 'Drift along the direct ODE, with the sympy verdict']
    """
    fig = new_figure(figsize=(12.0, 5.2))
    tree, grid = fig.add_axes((0.01, 0.08, 0.33, 0.83)), fig.add_axes((0.47, 0.25, 0.42, 0.63))
    by_member = {row.member: row for row in rows}
    tree.set_axis_off()
    tree.set_title("The loaded spheres (paper fig. 1)")
    tree.set_xlim(0, 1)
    tree.set_ylim(0, 1)
    for start, end, condition in _ARROWS:
        (x0, y0), (x1, y1) = _PLACES[start], _PLACES[end]
        tree.annotate("", xy=(x1, y1 + 0.09), xytext=(x0, y0 - 0.09), arrowprops=dict(arrowstyle="->", lw=1.2))
        tree.text(0.5 * (x0 + x1) + 0.02, 0.5 * (y0 + y1), condition, fontsize=8, style="italic", va="center")
    for member, (x, y) in _PLACES.items():
        row = by_member[member]
        integrals = ", ".join(_symbol(n) for n in row.integrals)
        measure = "measure: yes" if row.measure.density_exists else "measure ρ(γ): none"
        tree.text(x, y, f"{member}\n{integrals}\n{measure}", ha="center", va="center", fontsize=8,
                  bbox=dict(boxstyle="round", fc="white", ec="0.3"))
    names = [q.name for q in QUANTITIES]
    values = np.full((len(rows), len(names)), np.nan)
    for i, row in enumerate(rows):
        for j, name in enumerate(names):
            if name in row.entries:
                values[i, j] = math.log10(max(row.entries[name].drift.drift, 1e-17))
    image = grid.imshow(values, cmap="viridis", vmin=-16.0, vmax=0.0, aspect="auto")
    for i, row in enumerate(rows):
        for j, name in enumerate(names):
            entry = row.entries.get(name)
            if entry is None:
                grid.text(j, i, "n/a", ha="center", va="center", fontsize=8, color="0.4")
                continue
            mark = "✓" if entry.proof.conserved else "✗"
            grid.text(j, i, f"{mark}\n{entry.drift.drift:.0e}", ha="center", va="center", fontsize=8,
                      color="white" if values[i, j] < -6 else "black")
            if not entry.agrees:
                grid.add_patch(_outline(j, i))
    grid.set_xticks(range(len(names)), [_symbol(n) for n in names], rotation=30, ha="right")
    grid.set_yticks(range(len(rows)), [row.member for row in rows])
    grid.set_title("Drift along the direct ODE, with the sympy verdict")
    bar = fig.colorbar(image, cax=fig.add_axes((0.91, 0.25, 0.015, 0.63)))
    bar.set_label(r"$\log_{10}$ max$_t|Q(t)-Q(0)|\,/\,|Q|$")
    t_end = rows[0].entries["energy"].drift.t_end
    fig.text(0.36, 0.03, f"✓ proved conserved by sympy, ✗ proved not (exact witness). Drift over {t_end:g} time units "
             f"of heyoka at tolerance u from θ0 = 0.6π, ω = (0.7, −0.5, 1.3);\nround-off bound of each run "
             f"{rows[0].entries['energy'].drift.bound:.0e}; Q_R is proved through Q_R², its drift measured on Q_R.",
             fontsize=8, va="bottom")
    return fig


def _outline(j: int, i: int) -> Any:
    from matplotlib.patches import Rectangle

    return Rectangle((j - 0.5, i - 0.5), 1.0, 1.0, fill=False, ec="red", lw=2.0)
