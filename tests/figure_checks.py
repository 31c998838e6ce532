"""Checks of drawn figures by their artists' window extents (in display pixels, after a draw on the Agg canvas): an
artist inside the figure, two artists that do not overlap."""

from __future__ import annotations

from typing import Any

from matplotlib.backends.backend_agg import FigureCanvasAgg


def draw(fig: Any) -> Any:
    """Draw ``fig`` on an Agg canvas; returns the renderer (extents are measured on it)."""
    FigureCanvasAgg(fig).draw()
    return fig.canvas.get_renderer()


def inside(fig: Any, artist: Any, renderer: Any = None) -> bool:
    """True if the artist's window extent lies within the figure's (a plain ``savefig`` keeps it whole); the figure
    is drawn first unless the ``renderer`` of a draw is given."""
    e, box = artist.get_window_extent(renderer or draw(fig)), fig.bbox
    return box.x0 <= e.x0 and box.y0 <= e.y0 and e.x1 <= box.x1 and e.y1 <= box.y1


def legends(fig: Any) -> list[Any]:
    """The figure's legends: those of its axes and its own."""
    return [ax.get_legend() for ax in fig.axes if ax.get_legend() is not None] + list(fig.legends)


def legend_texts(fig: Any) -> list[str]:
    """The entries of every legend of ``fig``."""
    return [t.get_text() for leg in legends(fig) for t in leg.get_texts()]


def overlapping(fig: Any, artists: list[Any], renderer: Any = None) -> list[tuple[str, str]]:
    """Pairs of the (visible, non-empty) artists whose window extents intersect, by their text (drawn first unless
    the ``renderer`` of a draw is given)."""
    renderer = renderer or draw(fig)
    shown = [a for a in artists if a.get_visible() and (not hasattr(a, "get_text") or a.get_text())]
    boxes = [(a, a.get_window_extent(renderer)) for a in shown]
    out = []
    for i, (a, ea) in enumerate(boxes):
        for b, eb in boxes[i + 1:]:
            if ea.x0 < eb.x1 and eb.x0 < ea.x1 and ea.y0 < eb.y1 and eb.y0 < ea.y1:
                out.append((getattr(a, "get_text", str)(), getattr(b, "get_text", str)()))
    return out


def tick_labels(axis: Any) -> list[Any]:
    """The major tick labels of ``axis`` (``ax.xaxis``) that are drawn: those of ticks within its view interval."""
    lo, hi = sorted(axis.get_view_interval())
    return [t.label1 for t in axis.get_major_ticks() if lo <= t.get_loc() <= hi and t.label1.get_visible()]
