"""`rocknroller simulate`: JSON summary, output files, and bad input (message, no traceback, status 2)."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import pytest
import roundoff as ro

from rocknroller.analysis.model.body import Body
from rocknroller.cli import main
from rocknroller.cli.options import parse_angle
from rocknroller.numerics.integrate import MAX_SAMPLES
from rocknroller.papers.output import PRODUCER


def test_parse_angle():
    assert parse_angle("0.95pi") == pytest.approx(0.95 * math.pi)
    assert parse_angle("pi/4") == pytest.approx(math.pi / 4)
    assert parse_angle("3pi/8") == pytest.approx(3 * math.pi / 8)
    assert parse_angle("-0.5*pi") == pytest.approx(-0.5 * math.pi)
    assert parse_angle("-pi/4") == pytest.approx(-math.pi / 4) and parse_angle("+pi") == pytest.approx(math.pi)
    assert parse_angle("-1e-3") == -1e-3
    assert parse_angle("2.9") == 2.9
    for bad in ("", "pie", "1/0pi", "pi/0", "abc", "-", "--pi", "1e400"):
        with pytest.raises(ValueError, match="angle"):
            parse_angle(bad)


def test_json_summary(capsys):
    assert main(["simulate", "--t-end", "50", "--json", "--quiet"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out) == {"rocknroller_version", "energy_rel_error", "energy_tolerance", "n_maxima", "n_minima", "Phi", "t_end", "n_steps",
                        "warnings"}
    assert out["t_end"] == 50 and out["n_maxima"] >= 3
    # heyoka at ε: n_steps × ε × c_E (``roundoff.energy_condition``, the paper body with the default ε = 1e-3)
    # plus two evaluations of E (25 rounded operations each), × 4 (margin of the first-order analysis)
    c_E = ro.energy_condition(Body.paper(1e-3))
    bound = 4 * (ro.integration_bound(out["n_steps"], 2 * ro.u, c_E) + 2 * ro.gamma(25) * c_E)
    ro.assert_within(out["energy_rel_error"], bound, "energy", 1.0)
    assert out["warnings"] == [] and out["energy_rel_error"] <= out["energy_tolerance"]


def test_tol_sets_the_integrators_tolerance(capsys):
    """--tol 1e-11: the figure-5 run's turning points, at DOP853's best energy error (≈ 2.4e-13, 100× the default's),
    within the energy bound at that tolerance."""
    assert main(["simulate", "--t-end", "1500", "--turning-points-only", "--json", "--quiet", "--tol", "1e-11"]) == 0
    loose = json.loads(capsys.readouterr().out)
    assert main(["simulate", "--t-end", "1500", "--turning-points-only", "--json", "--quiet"]) == 0
    default = json.loads(capsys.readouterr().out)
    assert (loose["n_maxima"], loose["n_minima"]) == (default["n_maxima"], default["n_minima"]) == (113, 114)
    assert 10 * default["energy_rel_error"] < loose["energy_rel_error"] <= loose["energy_tolerance"]
    assert loose["energy_tolerance"] > 1e4 * default["energy_tolerance"] and not loose["warnings"]


def test_outputs_written(tmp_path, capsys):
    assert main(["simulate", "--t-end", "30", "--quiet", "--out", str(tmp_path), "--eps", "0.01",
                 "--theta0", "0.9pi", "--psi0", "pi/4"]) == 0
    for name in ("samples.csv", "turning_points.csv", "contact_track.png", "contact_track.pdf",
                 "phi_at_maxima.png", "phi_at_maxima.pdf", "QR_QJ_orbit.png", "QR_QJ_orbit.pdf"):
        assert (tmp_path / name).stat().st_size > 0, name
    head = (tmp_path / "samples.csv").read_text().splitlines()[:5]
    assert head[0] == f"# {PRODUCER}" and head[1].startswith("# rocknroller simulate") and "epsilon=0.01" in head[2]


@pytest.mark.parametrize(
    "argv, fragment",
    [
        (["--a", "1.2"], "--a must satisfy 0 <= a < 1"),
        (["--I1", "-1"], "--I1 must be > 0"),
        (["--I1", "0.1", "--I2", "0.1"], "triangle inequality"),
        (["--eps", "0.01", "--I2", "0.36"], "either --I2 or --eps"),
        (["--theta0", "4", "--theta-dot0", "1"], "0 <= theta0 <= pi"),
        (["--t-end", "-1"], "--t-end must be"),
        (["--theta0", "nan"], "angle"),
        (["--theta0", "0"], "0 < theta0 < pi when no rates are given (the start then takes the figure-5 omega"),
        (["--tol", "1e-3"], "--tol must be a number in [2.220446049250313e-16, 1e-06]"),
        (["--tol", "nan"], "--tol must be a number in"),
        (["--tol", "1e-11", "--method", "scipy"], "--tol is heyoka's tolerance (--method heyoka)"),
    ],
)
def test_bad_input_exits_2_without_traceback(argv, fragment):
    proc = subprocess.run([sys.executable, "-m", "rocknroller.cli", "simulate", "--quiet", *argv],
                          capture_output=True, text=True)
    assert proc.returncode == 2
    assert fragment in proc.stderr and "Traceback" not in proc.stderr


def test_every_command_has_help():
    from rocknroller.cli import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    assert "simulate" in sub.choices
    for name, p in sub.choices.items():
        assert p.format_help().strip(), name


def _json(capsys) -> dict:
    def refuse(name):
        raise AssertionError(f"non-standard JSON constant {name}")

    return json.loads(capsys.readouterr().out, parse_constant=refuse)


def test_explicit_zero_rates_start_from_rest(capsys):
    """--theta-dot0 0 --phi-dot0 0 --psi-dot0 0 is a start from rest (it used to run the figure-5 ω)."""
    from rocknroller.analysis.model.body import Body
    from rocknroller.analysis.model.equations import EulerState
    from rocknroller.numerics.integrate import simulate

    argv = ["simulate", "--t-end", "50", "--json", "--quiet", "--psi0", "pi/4"]
    assert main(argv + ["--theta-dot0", "0", "--phi-dot0", "0", "--psi-dot0", "0"]) == 0
    rest = _json(capsys)
    ref = simulate(Body.paper(1e-3), EulerState(0.95 * math.pi, psi=math.pi / 4), 50.0)
    assert rest["Phi"] == ref.Phi and rest["n_maxima"] == len(ref.maxima)
    assert main(argv) == 0  # no rate given: the figure-5 ω
    fig5 = _json(capsys)
    assert fig5["Phi"] != rest["Phi"]


def test_help_states_the_defaults_that_apply(capsys):
    with pytest.raises(SystemExit):
        main(["simulate", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "(default 0.001)" in text  # eps of simulate
    assert "figure-5 omega = (0, 0.001, -0.001)" in text and "rates default to 0" in text


@pytest.mark.parametrize("values", [["--phi0", "-0.5pi"], ["--psi0", "-pi/4"], ["--omega", "0", "-1e-3", "1e-3"]])
def test_negative_values_parse_like_the_equals_form(values, capsys):
    argv = ["simulate", "--t-end", "20", "--json", "--quiet"]
    assert main(argv + values) == 0
    spaced = _json(capsys)
    joined = [f"{values[0]}={values[1]}"] + values[2:] if len(values) == 2 else values
    assert main(argv + joined) == 0
    assert _json(capsys) == spaced


def test_outputs_are_checked_before_computing_and_never_overwritten(tmp_path, capsys, monkeypatch):
    import rocknroller.numerics.integrate

    def no_run(*args, **kwargs):
        raise AssertionError("simulate must not run before the output directory is checked")

    blocker = tmp_path / "file"
    blocker.write_text("x")
    monkeypatch.setattr(rocknroller.numerics.integrate, "simulate", no_run)
    for out, fragment in ((blocker, "not a directory"), (blocker / "sub", "cannot write")):
        assert main(["simulate", "--quiet", "--out", str(out)]) == 2
        assert fragment in capsys.readouterr().err
    monkeypatch.undo()
    out = tmp_path / "run"
    assert main(["simulate", "--t-end", "10", "--quiet", "--out", str(out)]) == 0
    before = (out / "samples.csv").read_bytes()
    monkeypatch.setattr(rocknroller.numerics.integrate, "simulate", no_run)
    assert main(["simulate", "--t-end", "20", "--quiet", "--out", str(out)]) == 2
    assert "--force" in capsys.readouterr().err and (out / "samples.csv").read_bytes() == before
    monkeypatch.undo()
    assert main(["simulate", "--t-end", "20", "--quiet", "--out", str(out), "--force"]) == 0
    assert (out / "samples.csv").read_bytes() != before


def test_turning_points_only_streams_the_csv(tmp_path, capsys):
    """--turning-points-only writes the same turning points as the full run (maxima then minima per stretch)."""
    import csv

    full, tp = tmp_path / "full", tmp_path / "tp"
    common = ["simulate", "--t-end", "300", "--quiet", "--eps", "0.01"]
    assert main(common + ["--out", str(full)]) == 0
    capsys.readouterr()
    assert main(common + ["--out", str(tp), "--turning-points-only", "--json"]) == 0
    summary = _json(capsys)

    def rows(path):
        with path.open() as fh:
            return sorted(tuple(r) for r in csv.reader(line for line in fh if not line.startswith("#")))[:-1]

    assert rows(full / "turning_points.csv") == rows(tp / "turning_points.csv")
    assert summary["n_maxima"] + summary["n_minima"] == len(rows(tp / "turning_points.csv"))
    assert not (tp / "samples.csv").exists() and (tp / "QR_QJ_orbit.png").stat().st_size > 0


@pytest.mark.parametrize(
    "argv, fragment",
    [
        (["--t-end", "1e300"], "--t-end=1e+300 is too long"),
        (["--dt", "1e-8"], f"over the limit {MAX_SAMPLES}"),
        (["--I3", "1e-300"], "--I3 must lie in"),
        (["--I3", "1e300"], "--I3 must lie in"),
        (["--g", "1e300"], "--g must be 0 or lie in"),
        (["--phi-dot0", "1e300"], "--phi-dot0 must satisfy |phi_dot| <= 1e+150"),
        (["--omega", "1e300", "0", "0"], "--omega must be three finite numbers"),
        (["--phi-dot0", "1e100"], "rates are too large"),
        (["--omega", "1e100", "0", "0"], "rates are too large"),
        (["--theta0", "0", "--omega", "0", "0", "0"], "--theta0"),
        (["--theta0", "0", "--theta-dot0", "0"], "no motion"),
        # issue 25, item 20: E underflows to 0 without gravity (a ZeroDivisionError traceback)
        (["--a", "0", "--I1", "0.35", "--psi-dot0", "1e-200"], "no motion to resolve"),
        # issue 25, item 21: a release within THETA_MIN of the pole (spurious turning points)
        (["--theta0", "1e-14", "--theta-dot0", "0"], "--theta0=1e-14: the start's energy keeps its tilt within"),
    ],
)
def test_extreme_input_is_refused_quickly(argv, fragment, capsys):
    assert main(["simulate", "--quiet", *argv]) == 2
    err = capsys.readouterr().err
    assert fragment in err and "Traceback" not in err


def test_strict_energy_check(capsys, monkeypatch):
    """Without --strict a run that misses its energy tolerance warns (exit 0, listed in the JSON); with it, exit 1.
    The bound is made impossibly tight to exercise the check."""
    monkeypatch.setattr("rocknroller.numerics.run_limits.ENERGY_SLACK", 1e-30)
    assert main(["simulate", "--t-end", "20", "--quiet", "--json"]) == 0
    captured = capsys.readouterr()
    assert "energy error" in captured.err and json.loads(captured.out)["warnings"]
    assert main(["simulate", "--t-end", "20", "--quiet", "--strict"]) == 1
    assert "check failed" in capsys.readouterr().err


def test_json_stays_json_when_heyoka_cannot_use_its_cache(tmp_path):
    """Issue 25, item 22: with HEYOKA_CACHE_DIR a file (or a cache.db that is not a database) heyoka logged
    `[warning]` lines on stdout ahead of the JSON.  The package now switches that cache off: stdout is the JSON alone
    and no heyoka log line is printed."""
    import os

    blocker = tmp_path / "afile"
    blocker.write_text("not a directory")
    env = {**os.environ, "HEYOKA_CACHE_DIR": str(blocker)}
    proc = subprocess.run([sys.executable, "-m", "rocknroller.cli", "simulate", "--t-end", "50", "--json", "--quiet"],
                          env=env, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    assert json.loads(proc.stdout)["n_maxima"] >= 1
    assert "[warning]" not in proc.stdout + proc.stderr and "Traceback" not in proc.stderr
    # the package says it once, in its own words, on stderr (simulate recorded it and printed only AccuracyWarnings)
    said = [line for line in proc.stderr.splitlines() if line.startswith("rocknroller simulate: warning:")]
    assert len(said) == 1 and "cache" in said[0], proc.stderr


_RELEASE = ["--eps", "0.01", "--theta0", "0.95pi", "--theta-dot0", "0", "--phi-dot0", "0", "--psi-dot0", "0"]


def test_chaos_option_prints_and_writes_the_indicators(tmp_path, capsys):
    """--chaos: the direct motion's MEGNO and λ (those of rr.direct_chaos_indicators, to the bit) in the JSON and in
    chaos.csv (one row per θ-maximum); the chaotic release of issue 23 (ψ0 = 0.1) is called chaotic."""
    import csv

    from rocknroller.analysis.model.body import Body
    from rocknroller.analysis.model.equations import EulerState
    from rocknroller.numerics.variational import direct_chaos_indicators

    argv = ["simulate", "--t-end", "1300", "--quiet", "--psi0", "0.1", *_RELEASE, "--turning-points-only", "--chaos"]
    assert main(argv + ["--json", "--out", str(tmp_path)]) == 0
    chaos = _json(capsys)["chaos"]
    ref = direct_chaos_indicators(Body.paper(1e-2), EulerState(0.95 * math.pi, 0.0, 0.1), 1300.0).indicators
    assert chaos["megno"] == ref.megno and chaos["lyapunov"] == ref.lyapunov
    assert chaos["lyapunov_per_rock"] == ref.lyapunov_per_rock and chaos["n_maxima"] == len(ref.t)
    assert chaos["regular"] is False and chaos["megno"] > chaos["megno_threshold"] == 3.0
    text = (tmp_path / "chaos.csv").read_text().splitlines()
    assert text[0] == f"# {PRODUCER}" and any("MEGNO=" in line for line in text if line.startswith("#"))
    rows = list(csv.DictReader(line for line in text if not line.startswith("#")))
    assert len(rows) == len(ref.t) and float(rows[-1]["mean_megno"]) == ref.megno
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert "chaos: MEGNO=" in out and "chaotic (MEGNO > 3)" in out


def test_chaos_option_regular_release_and_too_short_run(capsys):
    argv = ["simulate", "--quiet", "--psi0", "pi/4", *_RELEASE, "--turning-points-only", "--chaos"]
    assert main(argv + ["--t-end", "600"]) == 0
    assert "regular (MEGNO <= 3)" in capsys.readouterr().out
    assert main(argv + ["--t-end", "50"]) == 2
    err = capsys.readouterr().err
    assert "--t-end=50.0: the indicators need at least 8 samples" in err and "Traceback" not in err


def test_chaos_option_has_help(capsys):
    with pytest.raises(SystemExit):
        main(["simulate", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "--chaos" in text and "MEGNO" in text and "Lyapunov exponent per unit time and per rock" in text


def test_offset_runs_a_chaplygin_top_and_leaves_out_the_papers_quantities(tmp_path, capsys):
    out = tmp_path / "top"
    assert main(["simulate", "--offset", "0.03", "-0.02", "-0.05", "--I1", "0.37", "--I2", "0.35", "--theta0", "0.9pi",
                 "--omega", "0", "0", "0", "--t-end", "30", "--out", str(out), "--json", "--quiet"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["n_maxima"] >= 3 and summary["energy_rel_error"] < 1e-13
    names = {p.name for p in out.iterdir()}
    assert "QR_QJ_orbit.png" not in names and {"samples.csv", "turning_points.csv", "contact_track.png"} <= names
    header = [line for line in (out / "samples.csv").read_text().splitlines() if not line.startswith("#")][0]
    assert header.split(",") == ["t", "theta", "phi", "psi", "w1", "w2", "w3", "E", "X", "Y"]
    assert "Chaplygin's top: c=(0.03, -0.02, -0.05)" in (out / "turning_points.csv").read_text()


@pytest.mark.parametrize("argv, message", [
    (["--offset", "0", "0", "0", "--a", "0.1"], "--offset places the mass centre: do not combine it with --a"),
    (["--offset", "0.9", "0.9", "0"], "offset must satisfy |c| < 1"),
    (["--offset", "0", "0", "-0.05", "--I1", "0.1", "--I2", "0.1"], "triangle inequality"),
    (["--tilt-axis", "2"], "--tilt-axis needs --offset"),
])
def test_bad_offsets_are_refused_in_one_line(argv, message, capsys):
    assert main(["simulate", "--t-end", "1", "--quiet", *argv]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err


def test_the_tolerance_bound_help_shows_is_accepted(capsys):
    """--help showed the machine epsilon as 2.22e-16, below it, so the bound as shown was refused: it is shown to all
    its digits, and that text is accepted."""
    from cli_help import help_texts

    text = " ".join(help_texts()["simulate"].split())
    shown = text.split("heyoka's tolerance, in [", 1)[1].split(",", 1)[0]
    assert main(["simulate", "--tol", shown, "--t-end", "5", "--quiet", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["n_maxima"] >= 0
