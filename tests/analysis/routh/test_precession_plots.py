"""The precession table's figure, ``Precession.plot()``'s and ``rocknroller table --plot``'s: T_θ, Δφ and Δψ over the
(Q_R, Q_J) plane with labelled axes and colour bars, the angles on a scale symmetric about 0, points without motion
blank."""

from __future__ import annotations

import math

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.collections import PathCollection, QuadMesh  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from figure_checks import draw, inside  # noqa: E402
from rocknroller.analysis.model.body import Body  # noqa: E402
from rocknroller.analysis.routh.precession_plots import cell_edges, precession_figure  # noqa: E402
from rocknroller.analysis.routh.quadrature import precession, precession_from_turning_point  # noqa: E402

TITLES = ["rocking period $T_\\theta$", "precession $\\Delta\\phi$ per $T_\\theta$",
          "spin $\\Delta\\psi$ per $T_\\theta$"]
BAR_LABELS = ["$T_\\theta$ (time units)", "$\\Delta\\phi/\\pi$ (rad / $\\pi$)", "$\\Delta\\psi/\\pi$ (rad / $\\pi$)"]


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def _panels(fig):
    """The three panels (their colour bars follow them in ``fig.axes``) and each one's drawn collection."""
    axes = [ax for ax in fig.axes if ax.get_title()]
    return axes, [ax.collections[0] for ax in axes]


def test_precession_plot_draws_the_grid_with_labelled_colour_bars(tmp_path):
    """A meshgrid of (Q_R, Q_J) at θ_X = 0.95π: three heat maps, cell k of each the value at (Q_R[k], Q_J[k]), the
    axes and colour bars labelled with units, the angles in units of π on limits symmetric about 0."""
    QR, QJ = np.meshgrid(np.linspace(-0.01, 0.01, 6), np.linspace(-0.004, 0.004, 4))
    p, _ = precession_from_turning_point(0.95 * math.pi, QR, QJ, Body.paper())
    fig = p.plot()
    fig.savefig(tmp_path / "table.png")
    axes, meshes = _panels(fig)
    assert [ax.get_title() for ax in axes] == TITLES
    assert all(isinstance(m, QuadMesh) for m in meshes)
    assert [m.colorbar.ax.get_ylabel() for m in meshes] == BAR_LABELS
    assert all(ax.get_xlabel() == "$Q_R$" and ax.get_ylabel() == "$Q_J$" for ax in axes)
    for mesh, values, unit in zip(meshes, (p.T_theta, p.delta_phi, p.delta_psi), (1.0, math.pi, math.pi)):
        np.testing.assert_array_equal(mesh.get_array().reshape(QR.shape), values / unit)  # rows: Q_J, columns: Q_R
    for mesh, values in zip(meshes[1:], (p.delta_phi, p.delta_psi)):
        top = float(np.max(np.abs(values))) / math.pi
        assert mesh.get_clim() == pytest.approx((-top, top), rel=1e-15)
    np.testing.assert_array_equal(mesh.get_coordinates()[0, :, 0], cell_edges(QR[0]))
    renderer = draw(fig)
    assert all(inside(fig, t, renderer) for ax in axes for t in (ax.title, ax.xaxis.label, ax.yaxis.label))


def test_points_without_motion_are_blank_and_other_points_are_dots():
    """An energy below min U at some points: those cells masked (blank), counted in the title; points off a grid
    (here two) drawn as coloured dots."""
    QR, QJ = np.meshgrid([0.01, 0.02], np.linspace(-0.01, 0.01, 3))
    E = np.where(QR < 0.015, 0.0, 1.0)  # E = 0 is below min U here: no motion at Q_R = 0.01
    p = precession(E, QR, QJ, Body.paper())
    blank = np.ma.getmaskarray(p.T_theta)
    assert blank.any() and not blank.all()
    fig = precession_figure(QR, QJ, p.T_theta, p.delta_phi, p.delta_psi, fig=Figure())
    _, meshes = _panels(fig)
    np.testing.assert_array_equal(np.ma.getmaskarray(meshes[0].get_array()).reshape(QR.shape), blank)
    assert f"{int(blank.sum())} of {QR.size} points without a rocking motion" in fig.get_suptitle()
    q, _ = precession_from_turning_point(0.95 * math.pi, [0.01, 0.02], [-0.002, 0.0], Body.paper())
    axes, dots = _panels(q.plot(Figure()))
    assert all(isinstance(d, PathCollection) for d in dots)
    np.testing.assert_array_equal(dots[1].get_offsets(), [[0.01, -0.002], [0.02, 0.0]])
    np.testing.assert_array_equal(dots[1].get_array(), q.delta_phi / math.pi)


def test_per_tau_labels_and_bad_input():
    fig = precession_figure([0.01], [0.0], [26.0], [1.0], [2.0], per="tau", fig=Figure(), title="one point")
    axes, _ = _panels(fig)
    assert axes[0].get_title() == "rocking period $\\tau$" and fig.get_suptitle() == "one point"
    with pytest.raises(ValueError, match="per must be one of"):
        precession_figure([0.01], [0.0], [26.0], [1.0], [2.0], per="T")
    with pytest.raises(ValueError, match="one size"):
        precession_figure([0.01, 0.02], [0.0], [26.0], [1.0], [2.0])
