"""`rocknroller table`: CSV layout and header, agreement with the library, points without motion, bad input."""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest
import roundoff as ro

from rocknroller.analysis.criticality.lines import region
from rocknroller.analysis.model.body import Body
from rocknroller.analysis.routh.quadrature import precession, precession_from_turning_point
from rocknroller.cli import main
from rocknroller.cli.table import COLUMNS, parse_grid

EXPECTED_COLUMNS = ["Q_R", "Q_J", "E", "theta_N", "theta_X", "T_theta", "tau", "delta_phi", "delta_psi",
                    "visible_phi", "region", "status"]


def _read(path):
    lines = path.read_text().splitlines()
    header = [ln for ln in lines if ln.startswith("#")]
    rows = list(csv.DictReader(ln for ln in lines if not ln.startswith("#")))
    names = next(csv.reader([ln for ln in lines if not ln.startswith("#")][0:1]))
    return header, names, rows


def test_parse_grid():
    assert np.array_equal(parse_grid("-0.01:0.01:3", "--QR"), [-0.01, 0.0, 0.01])
    assert np.array_equal(parse_grid("0.5", "--QJ"), [0.5])
    for bad in ("1:2", "0:1:0", "0:1:2.5", "a:b:3", "0:inf:3", "1:2:3:4"):
        with pytest.raises(ValueError, match="--QR must be"):
            parse_grid(bad, "--QR")


def test_theta0_grid_matches_library(tmp_path, capsys):
    out = tmp_path / "t.csv"
    assert main(["table", "--QR", "-0.01:0.01:5", "--QJ", "-0.004:0.004:3", "--out", str(out), "--json",
                 "--quiet"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["n_points"] == 15 and summary["status_counts"] == {"ok": 15}
    header, names, rows = _read(out)
    assert names == EXPECTED_COLUMNS == list(COLUMNS)
    body = Body.paper()
    assert any(body.describe() in ln for ln in header)
    assert any(ln.startswith(f"# theta0: {0.95 * np.pi!r}") for ln in header)
    QR = np.array([float(r["Q_R"]) for r in rows])
    QJ = np.array([float(r["Q_J"]) for r in rows])
    pr, upper = precession_from_turning_point(0.95 * np.pi, QR, QJ, body)
    assert np.all(upper)
    for name, ref in (("T_theta", pr.T_theta), ("tau", pr.tau), ("delta_phi", pr.delta_phi),
                      ("delta_psi", pr.delta_psi), ("visible_phi", pr.visible_phi), ("theta_N", pr.theta_N),
                      ("E", pr.E)):
        assert np.array_equal([float(r[name]) for r in rows], ref), name  # written with repr: exact
    assert all(float(r["theta_X"]) == 0.95 * np.pi for r in rows)
    assert [r["region"] for r in rows] == [str(v) for v in region(QR, QJ, body)]


def test_energy_grid_keeps_points_without_motion(tmp_path, capsys):
    out = tmp_path / "e.csv"
    assert main(["table", "--E", "0:2:5", "--QR", "0.01", "--QJ", "-0.01:0.01:4", "--out", str(out),
                 "--quiet"]) == 0
    text = out.read_text()
    assert "nan" not in text.lower()
    header, names, rows = _read(out)
    assert len(rows) == 20  # nothing dropped
    E = np.array([float(r["E"]) for r in rows])
    no_motion = [r for r in rows if r["status"] == "no_motion"]
    assert no_motion and all(r[c] == "" for r in no_motion for c in EXPECTED_COLUMNS[3:10])
    ok = [r for r in rows if r["status"] == "ok"]
    assert ok and all(r[c] != "" for r in ok for c in EXPECTED_COLUMNS[3:10])
    pr = precession(E, [float(r["Q_R"]) for r in rows], [float(r["Q_J"]) for r in rows], Body.paper())
    assert [r["status"] for r in rows] == ["ok" if s == 0 else "no_motion" for s in pr.status]
    assert any("status no_motion:" in ln for ln in header)
    assert "no_motion=" in capsys.readouterr().out


def test_per_tau_and_mpmath_backend(tmp_path, capsys):
    base, tau, mp = tmp_path / "b.csv", tmp_path / "t.csv", tmp_path / "m.csv"
    args = ["table", "--QR", "0.01", "--QJ", "0.002:0.003:2", "--theta0", "0.9pi", "--quiet"]
    assert main(args + ["--out", str(base)]) == 0
    assert main(args + ["--out", str(tau), "--per", "tau"]) == 0
    assert main(args + ["--out", str(mp), "--dps", "25"]) == 0
    _, _, rb = _read(base)
    _, _, rt = _read(tau)
    header, _, rm = _read(mp)
    from quadrature_bounds import _bound_at, _root_error

    from rocknroller.analysis.routh.turning_points import solve_turning_points

    QJs = [float(r["Q_J"]) for r in rb]
    pr, _ = precession_from_turning_point(0.9 * np.pi, 0.01, np.array(QJs), Body.paper())
    for i, (b, t, m) in enumerate(zip(rb, rt, rm)):
        assert float(t["delta_phi"]) == 2 * float(b["delta_phi"])  # exact: ×2 of the same value
        assert float(t["tau"]) == float(b["tau"])  # exact: the same column, written the same way
        assert len(m["T_theta"].replace(".", "").lstrip("0")) >= 24  # 25 significant digits written
        # the double quadrature's bound (tests/analysis/routh/test_quadrature.py: quadrature_bound), the mpmath value to 1e-25;
        # θ_N from its end variable x: half x's relative rounding (``_root_error``) + the atan, √ (γ_4); × 4
        E, QR, QJ = float(b["E"]), float(b["Q_R"]), float(b["Q_J"])
        bT, bA = _bound_at(E, QR, QJ, pr.n_nodes[i])
        tp = solve_turning_points(np.array([E]), np.array([QR]), np.array([QJ]), Body.paper())
        bounds = {"T_theta": bT * float(b["T_theta"]), "delta_phi": bA, "delta_psi": bA,
                  "theta_N": 4 * (0.5 * _root_error(tp, 0, "N") + ro.gamma(4)) * float(b["theta_N"])}
        for c, bound in bounds.items():
            ro.assert_within(float(m[c]) - float(b[c]), bound + 1e-25 * max(abs(float(m[c])), 1.0), c, float(m[c]))
    assert any("mpmath dps=25" in ln for ln in header)


@pytest.mark.parametrize("argv,message", [
    (["--QR", "1:2"], "--QR must be a number or a grid"),
    (["--QJ", "0:1:0"], "--QJ must be a number or a grid"),
    (["--theta0", "pi"], "--theta0 must lie in the open interval"),
    (["--theta0", "2.0", "--E", "1"], "either --theta0"),
    (["--eps", "1e-3"], "symmetric body"),
    (["--dps", "3"], "--dps must be"),
])
def test_bad_input_message_and_status_2(argv, message, tmp_path, capsys):
    assert main(["table", "--quiet", "--out", str(tmp_path / "x.csv")] + argv) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err


@pytest.mark.parametrize("argv, fragment", [
    (["--QR", "0:0.01:100000", "--QJ", "0:0.01:100000"], "over the limit 500000"),
    (["--QR", "0:0.01:1000000000"], "COUNT must be at most 500000"),
    (["--QR", "0:0.01:3000", "--QJ", "0:1:3", "--dps", "20"], "over the limit 2000 with --dps"),
    (["--rtol", "0"], "--rtol must lie in [1e-14, 0.001]"),
    (["--rtol", "1e-17"], "--rtol must lie in [1e-14, 0.001]"),
])
def test_sizes_are_refused_before_computing(argv, fragment, tmp_path, capsys):
    out = tmp_path / "t.csv"
    assert main(["table", *argv, "--out", str(out), "--quiet"]) == 2
    assert fragment in capsys.readouterr().err and not out.exists()


def test_existing_output_is_not_overwritten(tmp_path, capsys):
    out = tmp_path / "t.csv"
    out.write_text("keep")
    assert main(["table", "--QR", "0.01", "--QJ", "0", "--out", str(out), "--quiet"]) == 2
    assert "--force" in capsys.readouterr().err and out.read_text() == "keep"
    assert main(["table", "--QR", "0.01", "--QJ", "0", "--out", str(out), "--quiet", "--force"]) == 0
    assert out.read_text().splitlines()[1].startswith("# rocknroller table")
    assert main(["table", "--out", str(tmp_path), "--quiet"]) == 2
    assert "is a directory" in capsys.readouterr().err


def test_plot_writes_the_figure_of_precession_plot(tmp_path, capsys, monkeypatch):
    """``--plot DIR``: precession_table.png and .pdf, the figure of ``Precession.plot()`` (one function draws both:
    the same titles, axis and colour-bar labels and values, the grid's cells), per ``--per``; one energy only."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    from rocknroller.papers import output

    figures = []
    real = output.save_figure
    monkeypatch.setattr(output, "save_figure", lambda fig, *a, **k: figures.append(fig) or real(fig, *a, **k))
    out, figs = tmp_path / "t.csv", tmp_path / "figs"
    assert main(["table", "--QR", "-0.01:0.01:5", "--QJ", "-0.004:0.004:3", "--out", str(out), "--plot", str(figs),
                 "--json", "--quiet"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["figures"] == [str(figs / "precession_table.png"), str(figs / "precession_table.pdf")]
    assert all((figs / name).stat().st_size > 0 for name in ("precession_table.png", "precession_table.pdf"))
    (fig,) = figures
    QR, QJ = np.meshgrid(np.linspace(-0.01, 0.01, 5), np.linspace(-0.004, 0.004, 3))
    pr, _ = precession_from_turning_point(0.95 * np.pi, QR, QJ, Body.paper())
    api = pr.plot(Figure())

    def looks(f):
        return [(ax.get_title(), ax.get_xlabel(), ax.get_ylabel(), ax.collections[0].colorbar.ax.get_ylabel(),
                 ax.collections[0].get_array().tolist()) for ax in f.axes if ax.get_title()]

    assert looks(fig) == looks(api) and len(looks(fig)) == 3
    assert "theta_X = theta0 = 0.95pi" in fig.get_suptitle() and Body.paper().describe() in fig.get_suptitle()
    assert main(["table", "--QR", "0.01", "--QJ", "0", "--per", "tau", "--out", str(tmp_path / "tau.csv"),
                 "--plot", str(tmp_path / "tau"), "--quiet"]) == 0
    assert [ax.get_title() for ax in figures[-1].axes][0] == "rocking period $\\tau$"
    assert main(["table", "--E", "0.5:1:2", "--QR", "0.01", "--QJ", "0", "--out", str(tmp_path / "e.csv"),
                 "--plot", str(tmp_path / "e"), "--quiet"]) == 2
    assert "--plot draws the (Q_R, Q_J) plane at one energy" in capsys.readouterr().err
