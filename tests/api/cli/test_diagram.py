"""`rocknroller diagram` and rocknroller.papers.plotting: files, plotted data from the library, bad input (issue 4)."""

from __future__ import annotations

import json

import numpy as np
import pytest
import roundoff as ro

from rocknroller.analysis.criticality import lines as C
from rocknroller.analysis.criticality import starts
from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.invariants import V_phi
from rocknroller.cli import main
from rocknroller.papers.plotting import region_diagram

BODY = Body.paper()


def _line(ax, gid):
    (line,) = [ln for ln in ax.get_lines() if ln.get_gid() == gid]
    return np.asarray(line.get_xdata(), float), np.asarray(line.get_ydata(), float)


@pytest.mark.parametrize("body", [BODY, Body(a=0.2, I1=0.3, I2=0.3, I3=0.5, g=9.81)])
def test_plotted_data_come_from_the_library(body):
    """Line data equal Q_J,0^crit and Q_J,π^crit exactly; each representative point lies in its region and its
    panel plots V_φ (rocknroller.analysis.model.invariants) at that point."""
    import matplotlib.pyplot as plt

    fig, data = region_diagram(body, QR_max=2.0)
    ax = data.axes["main"]
    x0, y0 = _line(ax, "QJ0crit")
    xpi, ypi = _line(ax, "QJpicrit")
    assert x0.min() == -2.0 and x0.max() == 2.0
    # exact: the plotted data are these functions' values on the same inputs
    np.testing.assert_array_equal(y0, C.QJ_crit_0(x0, body))
    np.testing.assert_array_equal(ypi, C.QJ_crit_pi(xpi, body))
    np.testing.assert_array_equal(data.QJ0_line, C.QJ_crit_0(data.QR_line, body))
    assert set(data.representatives) == set(C.REGIONS)
    for lab, (qr, qj) in data.representatives.items():
        assert C.region(qr, qj, body) == lab
        theta, v = (np.asarray(a, float) for a in data.axes[lab].get_lines()[0].get_data())
        np.testing.assert_array_equal(v, V_phi(theta, QR=qr, QJ=qj, body=body))
    plt.close(fig)


def test_representatives_keep_clear_of_lines():
    """The representative points (and their labels) sit away from both lines (>= 10 % of the axes)."""
    import matplotlib.pyplot as plt

    fig, data = region_diagram(BODY)
    x0, x1, y0, y1 = data.window
    for qr, qj in data.representatives.values():
        u, v = (qr - x0) / (x1 - x0), (qj - y0) / (y1 - y0)
        for fn in (C.QJ_crit_0, C.QJ_crit_pi):
            q = np.linspace(x0, x1, 2001)
            lu, lv = (q - x0) / (x1 - x0), (fn(q, BODY) - y0) / (y1 - y0)
            assert np.hypot(lu - u, lv - v).min() > 0.1
    plt.close(fig)


def test_cli_writes_png_and_pdf(tmp_path, capsys):
    assert main(["diagram", "--out", str(tmp_path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    for name in ("regions.png", "regions.pdf"):
        assert (tmp_path / name).stat().st_size > 10_000, name
    assert (tmp_path / "regions.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert (tmp_path / "regions.pdf").read_bytes()[:5] == b"%PDF-"
    assert set(out["representatives"]) == set(C.REGIONS)


def test_cli_simulate_on_critical_line(tmp_path, capsys):
    """--simulate with a start on Q_J,π^crit (paper fig. 8 method): orbit file written, start on the line."""
    assert main(["diagram", "--simulate", "--t-end", "40", "--critical-line", "pi", "--QR", "0.003",
                 "--out", str(tmp_path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    for name in ("regions_orbit.png", "regions_orbit.pdf"):
        assert (tmp_path / name).stat().st_size > 10_000, name
    assert out["region0"] == C.ON_LINE_PI
    # the same run through the library (the CLI's defaults: ε = 1e-3, θ0 = 0.95π, ψ0 = π/4): identical numbers
    from rocknroller.analysis.model.equations import EulerState
    from rocknroller.analysis.model.invariants import routh
    from rocknroller.numerics.integrate import simulate

    body = Body.paper(1e-3)
    start = starts.critical_start(body, 0.95 * np.pi, np.pi / 4, "pi", QR=0.003)
    traj = simulate(body, EulerState.from_omega(0.95 * np.pi, 0.0, np.pi / 4, start.omega), 40.0)
    assert (out["QR0"], out["energy_rel_error"]) == (float(traj.QR[0]), traj.energy_rel_error)  # same computation
    # Q_R of the start: ω3 = ρ(θ0) Q_R built from sin/cos of θ0, Q_R recomputed as ω3/ρ from γ; each ≤ 25 rounded
    # operations on positive terms (ρ⁻² = I3 + s² + (I3/I1) f²), carried by κ_R = Σ|yᵢ ∂Q_R/∂yᵢ|; × 4 (margin)
    y0 = traj.states[:1, 0:6]
    kappa_R = float(ro.relative_condition(lambda Z: routh(body, Z[:, 0:3].T, Z[:, 3:6].T), y0)[0])
    ro.assert_within(out["QR0"] - 0.003, 4 * 2 * ro.gamma(25) * kappa_R, "QR0", 0.003)
    # energy: heyoka at ε over traj.n_steps steps, amplified by c_E (``roundoff.energy_condition``), × 4
    c_E = ro.energy_condition(body)
    bound = 4 * (ro.integration_bound(traj.n_steps, traj.tolerance, c_E) + 2 * ro.gamma(25) * c_E)
    ro.assert_within(out["energy_rel_error"], bound, "energy", 1.0)


def test_cli_simulate_plain_initial_state(tmp_path, capsys):
    """Same initial-state options as `simulate` (paper fig. 7: released from rest at ψ0 = π/4)."""
    assert main(["diagram", "--simulate", "--t-end", "30", "--theta0", "0.95pi", "--psi0", "pi/4",
                 "--out", str(tmp_path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["initial"]["psi0"] == pytest.approx(np.pi / 4)
    assert (tmp_path / "regions_orbit.png").stat().st_size > 10_000


def test_window_range_ends_are_drawn():
    """The ends of the allowed half-widths draw (the range is not stricter than the critical lines need)."""
    import matplotlib.pyplot as plt

    from rocknroller.papers.plotting import _QR_MAX_RANGE

    for qr_max in _QR_MAX_RANGE:
        fig, data = region_diagram(BODY, QR_max=qr_max)
        assert np.all(np.isfinite(data.QJ0_line)) and np.all(np.isfinite(data.QJpi_line))
        plt.close(fig)


@pytest.mark.parametrize("argv, message", [
    (["diagram", "--QR", "0.1"], "--critical-line, --QR and --offset need --simulate"),
    (["diagram", "--QR-max", "0"], "--QR-max must lie in [1e-147, 1e+79]"),
    (["diagram", "--QR-max", "1e308"], "--QR-max must lie in [1e-147, 1e+79]"),  # was an overflow to QR=inf inside
    (["diagram", "--QR-max", "1e-160"], "--QR-max must lie in [1e-147, 1e+79]"),
    (["diagram", "--simulate", "--critical-line", "pi", "--QR", "0.1", "--phi-dot0", "0.2"], "do not give"),
    (["diagram", "--simulate", "--critical-line", "pi", "--QR", "0.1", "--theta0", "pi"], "theta0 must lie"),
])
def test_cli_bad_input(argv, message, tmp_path, capsys):
    assert main(argv + ["--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err


def test_a_start_on_a_critical_line_is_said_to_be_on_it(tmp_path, capsys):
    """The start placed on Q_J,pi^crit printed "in on QJpicrit"."""
    assert main(["diagram", "--simulate", "--critical-line", "pi", "--psi-dot0", "0.002", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert " on QJpicrit;" in out and "in on" not in out
