"""The files of a recession atlas (:mod:`rocknroller.analysis.slow.atlas`) that ``rocknroller atlas`` writes: the
atlas's figure and the figure of its check by the direct ODE, each as PNG and PDF.  The figures are drawn by
:mod:`rocknroller.analysis.slow.dynamics.atlas_figure`, the same functions as :meth:`Atlas.plot`'s (titles in words,
colour bars labelled with units, MEGNO on the fixed scale [0, :data:`rocknroller.numerics.megno.MEGNO_CLIP`]), on
figures outside pyplot (:func:`rocknroller.papers.output.new_figure`)."""

from __future__ import annotations

from pathlib import Path

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.atlas import Atlas
from rocknroller.analysis.slow.atlas_check import AtlasCheck
from rocknroller.analysis.slow.dynamics.atlas_figure import atlas_check_figure, atlas_figsize, atlas_figure
from rocknroller.papers.output import new_figure, save_figure

__all__ = ["plot_atlas", "plot_atlas_check"]


def plot_atlas(atlas: Atlas, out: Path, title: str, body: Body | None = None) -> list[Path]:
    """Write the atlas's figure (:func:`rocknroller.analysis.slow.dynamics.atlas_figure.atlas_figure`, the critical
    lines of ``body`` over a plane of rates) as ``out/atlas.png`` and ``out/atlas.pdf``; returns both paths."""
    fig = new_figure(figsize=atlas_figsize(atlas), layout="constrained")
    return save_figure(atlas_figure(atlas, fig, title, body), out, "atlas")


def plot_atlas_check(atlas: Atlas, check: AtlasCheck, out: Path, title: str) -> list[Path]:
    """Write where the direct ODE confirmed the map, the map's largest error at each confirmed point and the points
    whose reversal counts or regular/chaotic verdicts differ
    (:func:`~rocknroller.analysis.slow.dynamics.atlas_figure.atlas_check_figure`), as ``out/atlas_check.png`` and
    ``out/atlas_check.pdf``; returns both paths."""
    fig = new_figure(figsize=(6.5, 5.0), layout="constrained")
    return save_figure(atlas_check_figure(atlas, check, title, fig), out, "atlas_check")
