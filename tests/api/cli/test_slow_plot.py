"""``rocknroller slow --plot``: the figure marks the predictability horizon (issue 32, item 12)."""

from __future__ import annotations

import json

import pytest

from figure_checks import inside, legend_texts
from rocknroller.cli import main
from rocknroller.papers import output


def test_plot_marks_the_horizon(tmp_path, capsys, monkeypatch):
    """ε = 5e-3, ψ0 = 0.05 (chaotic, horizon ≈ 184 t.u.) over 400 t.u.: the ψ-panel has a vertical line at the
    horizon the JSON reports, a shaded span from it to t_end, both in its legend; the (Q_R, Q_J) panel has both
    critical lines; every axis label lies inside the figure."""
    figures = []
    real = output.save_figure
    monkeypatch.setattr(output, "save_figure", lambda fig, *a, **k: figures.append(fig) or real(fig, *a, **k))
    argv = ["slow", "--order", "1", "--eps", "5e-3", "--psi0", "0.05", "--t-end", "400", "--json"]
    assert main([*argv, "--plot", str(tmp_path / "fig")]) == 0
    t_h = json.loads(capsys.readouterr().out)["horizon"]["t"]
    assert 0.0 < t_h < 400.0
    (fig,) = figures
    ax_q, ax_t = fig.axes[:2]
    assert {line.get_gid() for line in ax_q.get_lines()} >= {"QJ0crit", "QJpicrit"}
    marks = [line for line in ax_t.get_lines() if list(line.get_xdata()) == [t_h, t_h]]
    assert len(marks) == 1 and "horizon" in marks[0].get_label()
    (span,) = ax_t.patches
    x0, x1 = span.get_x(), span.get_x() + span.get_width()
    assert (x0, x1) == pytest.approx((t_h, 400.0), rel=1e-12)
    texts = legend_texts(fig)
    assert any("horizon" in t for t in texts) and any("statistical only" in t for t in texts)
    assert all(inside(fig, ax.xaxis.label) and inside(fig, ax.yaxis.label) for ax in (ax_q, ax_t))
    fig.savefig(tmp_path / "slow_orbit.png")


def test_a_horizon_after_t_end_is_named_in_the_legend(tmp_path, capsys, monkeypatch):
    """The command's default release over 200 t.u. (regular, horizon ≈ 2000 t.u.): no line or span inside the axis,
    the horizon named in the legend as after t_end."""
    figures = []
    real = output.save_figure
    monkeypatch.setattr(output, "save_figure", lambda fig, *a, **k: figures.append(fig) or real(fig, *a, **k))
    assert main(["slow", "--order", "1", "--t-end", "200", "--json", "--plot", str(tmp_path / "fig")]) == 0
    t_h = json.loads(capsys.readouterr().out)["horizon"]["t"]
    assert t_h > 200.0
    (fig,) = figures
    ax_t = fig.axes[1]
    assert not ax_t.patches and all(len(line.get_xdata()) != 2 for line in ax_t.get_lines())  # no axvline
    assert f"predictability horizon t = {t_h:.4g} (after t_end)" in legend_texts(fig)
