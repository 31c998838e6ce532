"""``rocknroller atlas``'s files: the figure written is ``Atlas.plot()``'s (one function draws both), as PNG and
PDF."""

from __future__ import annotations

import math

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from rocknroller.analysis.model.body import Body  # noqa: E402
from rocknroller.analysis.slow.atlas import atlas_from_rest  # noqa: E402
from rocknroller.papers import atlas_plots  # noqa: E402


def _looks(fig):
    """Per titled panel: its axis labels, and its heat map's colour-bar label and colour limits."""
    out = {}
    for ax in fig.axes:
        if ax.get_title():
            mesh = next(iter(ax.collections))
            out[ax.get_title()] = (ax.get_xlabel(), ax.get_ylabel(), mesh.colorbar.ax.get_ylabel(), mesh.get_clim())
    return out


def test_the_command_writes_the_figure_of_atlas_plot(tmp_path, monkeypatch):
    """The command's atlas.png/.pdf and ``Atlas.plot()`` show the same panels: titles, axis and colour-bar labels, and
    colour limits (the API's quick look had code names, unlabelled colour bars and an auto-scaled MEGNO)."""
    atlas = atlas_from_rest(Body.paper(1e-3), [0.9 * math.pi, 0.95 * math.pi], np.array([0.1, 0.25]) * math.pi,
                            300.0, progress=False)
    written = []
    real = atlas_plots.save_figure
    monkeypatch.setattr(atlas_plots, "save_figure", lambda fig, *a, **k: written.append(fig) or real(fig, *a, **k))
    paths = atlas_plots.plot_atlas(atlas, tmp_path, "atlas")
    assert [p.name for p in paths] == ["atlas.png", "atlas.pdf"] and all(p.stat().st_size > 0 for p in paths)
    (fig,) = written
    assert _looks(fig) == _looks(atlas.plot()) and len(_looks(fig)) == len(atlas.observables)
    plt.close("all")
