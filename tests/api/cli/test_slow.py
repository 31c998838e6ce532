"""``rocknroller slow``: JSON keys, --check against the ODE, warnings and errors outside the valid regime."""

from __future__ import annotations

import json
import math
import warnings

import numpy as np
import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow import prediction as av
from rocknroller.analysis.slow.map import table as slow_table
from rocknroller.analysis.slow.dynamics.pendulum import pendulum_constants
from rocknroller.cli import main


@pytest.fixture(scope="module")
def fresh_cache(tmp_path_factory):
    """An empty cache directory (shared by this module): the command must build its tables itself."""
    path = tmp_path_factory.mktemp("cache")
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("ROCKNROLLER_CACHE", str(path))
        mp.setattr(slow_table, "_TABLES", {})
        yield path


def test_json_and_check(fresh_cache, capsys):
    """The first-order map in a fresh cache (the tests here use --order 1 so that each builds only the first-order
    tables; test_slow_order_option covers the default, order 2)."""
    assert main(["slow", "--order", "1", "--eps", "1e-3", "--psi0", "3pi/8", "--t-end", "400", "--json", "--check"]) == 0
    out = json.loads(capsys.readouterr().out)
    for key in ("slow_period", "QR_extent", "QJ_extent", "Phi", "pendulum", "ode", "rel_error"):
        assert key in out
    for key in ("slow_period", "QR_extent", "QJ_extent", "Phi", "kappa", "eps_period_doubling"):
        assert key in out["pendulum"]
    # first-order map at eps = 1e-3: relative errors O(eps) (docs/averaging.md)
    for q in ("slow_period", "QR_extent", "Phi"):
        assert abs(out["rel_error"][q]) < 5e-3, (q, out["rel_error"][q])
    assert out["rocks_per_region"] == out["ode"]["rocks_per_region"]
    assert out["warnings"] == []
    # the tables were built and cached
    assert list((fresh_cache / "averaging").glob("slowmap-*.npz"))


def test_plain_output_and_plot(fresh_cache, tmp_path, capsys):
    assert main(["slow", "--order", "1", "--t-end", "200", "--plot", str(tmp_path / "fig")]) == 0
    captured = capsys.readouterr()
    assert "slow_period" in captured.out and "period doubling" in captured.out
    for ext in ("png", "pdf"):
        f = tmp_path / "fig" / f"slow_orbit.{ext}"
        assert f.exists() and f.stat().st_size > 1000


def test_outside_valid_regime(fresh_cache, capsys):
    assert main(["slow", "--eps=-1e-3"]) == 2
    assert "eps" in capsys.readouterr().err
    assert main(["slow", "--theta0", "1.2pi"]) == 2
    assert "theta0" in capsys.readouterr().err
    assert main(["slow", "--theta0", "0.9pi", "--cached-only"]) == 2
    assert "no averaging tables" in capsys.readouterr().err
    assert main(["slow", "--order", "1", "--eps", "1.1e-2", "--t-end", "100", "--json"]) == 0
    captured = capsys.readouterr()
    eps_pd = pendulum_constants(Body.paper(1.1e-2), 0.95 * math.pi).eps_period_doubling
    assert "K = eps*kappa" in captured.err and f"eps < {eps_pd:.4g} " in captured.err
    assert json.loads(captured.out)["warnings"]


# ----------------------------------------------------------------------------- limits and validity (issue 10)
def _strict_json(text: str):
    """json.loads that refuses NaN and Infinity (not JSON)."""
    def refuse(name):
        raise ValueError(f"not JSON: {name}")

    return json.loads(text, parse_constant=refuse)


def test_t_end_limit_is_checked_up_front(fresh_cache, capsys):
    """t_end is refused before any table is built or loaded (it used to run until memory ran out)."""
    assert main(["slow", "--t-end", "1e300", "--theta0", "0.8pi", "--cached-only"]) == 2
    err = capsys.readouterr().err
    assert "--t-end" in err and "(0, " in err and "1e+06" in err and "no averaging tables" not in err
    assert main(["slow", "--t-end", "nan"]) == 2 and "--t-end" in capsys.readouterr().err
    # the API: the same check, naming t_end, before building (build=False would otherwise raise "no tables")
    limit = av.max_t_end(Body.paper(1e-3), 0.8 * math.pi)
    assert limit == pytest.approx(0.5 * av.MAX_MAXIMA * pendulum_constants(Body.paper(0.0), 0.8 * math.pi).T0,
                                  rel=1e-9)
    for t_end in (1e300, 1.0001 * limit, math.inf, math.nan, 0.0, -1.0):
        with pytest.raises(ValueError, match=r"^t_end must be a finite number in \(0, "):
            av.predict_slow_motion(Body.paper(1e-3), 0.8 * math.pi, math.pi / 4, t_end, build=False)


def test_t_end_and_n_steps_limits_of_the_map(fresh_cache):
    table = av.load_or_build_table(Body.paper(0.0), 0.95 * math.pi)
    T0 = pendulum_constants(Body.paper(0.0), 0.95 * math.pi).T0
    with pytest.raises(ValueError, match="t_end must be"):
        av.iterate_slow_map(table, 1e-3, 0.5, 1e300)
    with pytest.raises(ValueError, match="n_steps must be an integer in"):
        av.iterate_slow_map(table, 1e-3, 0.5, 100.0, n_steps=av.MAX_MAXIMA + 1)
    # with n_steps the run is bounded by it, whatever t_end
    assert av.iterate_slow_map(table, 1e-3, 0.5, 1e300, n_steps=5).t.size == 5
    # at the limit the run is accepted; it produces fewer maxima than the bound (T_theta >= 0.7 T_theta(0))
    s = av.iterate_slow_map(table, 1e-3, 0.5, 0.5 * av.MAX_MAXIMA * T0 * 0.999 / 50)
    assert s.t.size <= av.MAX_MAXIMA / 50


def test_theta0_outside_supported_range_is_refused(fresh_cache, capsys):
    for theta0 in ("0.9999pi", "1.2pi", "-0.5pi", "0"):
        assert main(["slow", f"--theta0={theta0}", "--t-end", "100"]) == 2
        err = capsys.readouterr().err
        assert "error: --theta0 must lie in (0, 0.999pi] for a release from rest" in err, (theta0, err)
        assert "Traceback" not in err and "numpy" not in err
    # releases below the release tables' range are served by the region tables of their energy
    for theta0 in ("0.7pi", "0.5pi", "0.1"):
        assert main(["slow", f"--theta0={theta0}", "--t-end", "100", "--cached-only"]) == 2
        assert "no averaging tables for E=" in capsys.readouterr().err
    lo, hi = av.THETA0_RANGE
    assert (lo, hi) == (0.75 * math.pi, 0.999 * math.pi)
    for theta0 in (0.7 * math.pi, math.nextafter(lo, 0.0), math.nextafter(hi, 4.0), math.nan):
        for call in (lambda th: av.build_table(Body.paper(0.0), th, nu=8, nv=4),
                     lambda th: av.load_or_build_table(Body.paper(0.0), th, build=False)):
            with pytest.raises(ValueError, match=r"^theta0 must lie in \[0.75pi, 0.999pi\]"):
                call(theta0)
    for theta0 in (math.nextafter(hi, 4.0), math.nan, -0.1, 0.0):
        with pytest.raises(ValueError, match=r"^theta0 must lie in \(0, 0.999pi\] for a release from rest"):
            av.predict_slow_motion(Body.paper(1e-3), theta0, 0.5, 100.0, build=False)
    with pytest.raises(ValueError, match="no averaging tables for E="):
        av.predict_slow_motion(Body.paper(1e-3), 0.7 * math.pi, 0.5, 100.0, build=False)


def test_help_states_limits(capsys):
    with pytest.raises(SystemExit):
        main(["slow", "--help"])
    out = " ".join(capsys.readouterr().out.split())
    assert "[0.75pi, 0.999pi]" in out and "at most 1e+06 maxima" in out and "null" in out


def test_eps_zero_is_pure_rocking(fresh_cache, capsys):
    """eps = 0: Routh's sphere from rest rocks in a plane with Q = 0 exactly, on both critical lines: no region
    runs or crossings (they used to be printed from round-off), Phi = 0, undefined quantities null."""
    assert main(["slow", "--eps", "0", "--t-end", "200", "--json"]) == 0
    out = _strict_json(capsys.readouterr().out)
    assert out["pure_rocking"] is True
    assert out["region_runs"] == [] and out["crossings"] == [] and out["rocks_per_region"] == {}
    assert out["slow_period"] is None and out["line_slope"] is None and out["pendulum"]["slow_period"] is None
    assert out["QR_extent"] == out["QJ_extent"] == out["Phi"] == 0.0 and out["n_maxima"] == 15
    assert main(["slow", "--eps", "0", "--t-end", "200"]) == 0
    text = capsys.readouterr().out
    assert "pure rocking" in text and "both critical lines" in text and "rocks per critical region" not in text
    pred = av.predict_slow_motion(Body.paper(0.0), 0.95 * math.pi, 0.3, 200.0)
    assert pred.pure_rocking and pred.region_runs == [] and pred.crossings == [] and pred.rocks_per_region == {}
    assert set(pred.regions) == {"origin"} and pred.slow_period is None and pred.line_slope is None
    assert not pred.series.QR.any() and not pred.series.QJ.any() and pred.Phi == 0.0
    assert not av.predict_slow_motion(Body.paper(1e-3), 0.95 * math.pi, 0.3, 200.0, order=1).pure_rocking


@pytest.mark.parametrize("argv", [
    [],                                      # the default run
    ["--eps", "0"],                          # pure rocking
    ["--t-end", "10"],                       # shorter than one rock: no maxima
    ["--t-end", "20"],                       # one maximum: no line, no period
    ["--psi0", "0"],                         # the unstable equilibrium of the closed form
    ["--eps", "1.1e-2", "--t-end", "100"],   # K > 4: a warning
    ["--eps", "0", "--t-end", "100", "--check"],
])
def test_json_is_strict_without_the_guard(fresh_cache, capsys, monkeypatch, argv):
    """--json passes json.loads(parse_constant=raise), and no NaN or inf reaches the last guard: undefined
    quantities are null because they are None, not because a NaN was replaced."""
    from rocknroller.cli import options

    guard = options.finite_or_none

    def strict(x):
        if isinstance(x, float):
            assert math.isfinite(x), x
        if isinstance(x, dict):
            [strict(v) for v in x.values()]
        if isinstance(x, (list, tuple)):
            [strict(v) for v in x]
        return guard(x)

    monkeypatch.setattr(options, "finite_or_none", strict)
    assert main(["slow", "--json", "--order", "1", *argv]) == 0
    out = _strict_json(capsys.readouterr().out)
    if argv[:2] == ["--t-end", "20"]:
        assert out["n_maxima"] == 1 and out["line_slope"] is None and out["slow_period"] is None
    assert av.line_slope([0.1], [0.2]) is None and av.line_slope([0.1, 0.1], [0.2, 0.2]) is None


@pytest.mark.parametrize("argv, flag", [
    (["--eps", "0.5"], "--eps"),
    (["--eps", "inf"], "--eps"),
    (["--eps=-1e-3"], "--eps"),
    (["--polar-cap", "0.5", "--eps", "0.9"], "--eps"),
    (["--I2", "0.5"], "--I2"),
    (["--I2", "0.3"], "--I2"),
    (["--a", "0.9"], "--a"),
    (["--g", "-1"], "--g"),
    (["--I2", "0.36", "--eps", "1e-3"], "--I2"),
    (["--polar-cap", "0.999"], "--eps"),  # the default eps 1e-3 is too large for this body
    (["--theta0", "abc"], "--theta0"),
    (["--theta0", "0.9999pi"], "--theta0"),
    (["--psi0", "nan"], "--psi0"),
    (["--t-end", "-5"], "--t-end"),
])
def test_errors_name_the_option_given(fresh_cache, capsys, argv, flag):
    assert main(["slow", "--cached-only", *argv]) == 2
    err = capsys.readouterr().err
    assert flag in err, err
    assert "Traceback" not in err


@pytest.mark.slow
@pytest.mark.parametrize("frac, K", [(0.75, None), (0.999, 0.4)])
def test_map_at_the_ends_of_the_theta0_range(frac, K):
    """The ends of THETA0_RANGE: the tables build (interpolation error < 1e-7) and the map agrees with the
    direct ODE to < 5e-3 at eps = 1e-3 (0.75pi; K = 0.018) or K = 0.4 (0.999pi, eps = 3.8e-7); docs/averaging.md."""
    from rocknroller.papers.averaging_check import ode_slow_summary, relative_errors

    theta0 = frac * math.pi
    table = av.build_table(Body.paper(0.0), theta0)
    assert table.interp_error < 1e-7
    eps = 1e-3 if K is None else K / table.kappa
    pred = av.predict_slow_motion(Body.paper(eps), theta0, math.pi / 4, 1000.0, table=table, order=1)
    ref = ode_slow_summary(Body.paper(eps), theta0, math.pi / 4, 1000.0)
    errs = relative_errors(pred, ref)
    for q in ("slow_period", "QR_extent", "Phi"):
        assert abs(errs[q]) < 5e-3, (q, errs)
    assert [r[:2] for r in pred.region_runs] == [r[:2] for r in ref.region_runs]


def test_plot_directory_is_checked_before_computing(tmp_path, capsys):
    (tmp_path / "slow_orbit.png").write_bytes(b"keep")
    assert main(["slow", "--plot", str(tmp_path)]) == 2
    assert "--force" in capsys.readouterr().err and (tmp_path / "slow_orbit.png").read_bytes() == b"keep"
    blocker = tmp_path / "file"
    blocker.write_text("")
    assert main(["slow", "--plot", str(blocker / "sub")]) == 2
    assert "cannot write" in capsys.readouterr().err


# ----------------------------------------------------------------------------- starts with velocity
#: Coarse region tables (16 × 8 nodes, ~2 s): these tests check the command's plumbing, not the map's accuracy
#: (tests/analysis/slow/map/test_region.py compares the default tables with the direct ODE); the command says they are coarse.
COARSE = ["--nodes", "16", "8", "--processes", "1"]


def test_start_with_velocity(fresh_cache, tmp_path, capsys):
    argv = ["slow", "--eps", "1e-3", "--theta0", "0.6pi", "--psi0", "0.3", "--phi-dot0", "0.05", "--t-end", "200",
            "--json", "--check", "--plot", str(tmp_path / "fig"), *COARSE]
    assert main(argv) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["start"]["phi_dot"] == 0.05 and out["pendulum"] is None
    assert out["n_maxima"] > 10
    assert any("interpolate the map's coefficients only" in w for w in out["warnings"])  # coarse tables: said so
    assert out["rocks_per_region"] == out["ode"]["rocks_per_region"]
    assert (tmp_path / "fig" / "slow_orbit.png").stat().st_size > 1000
    # the map from the first maximum carries its indicators and horizon too
    assert out["chaos"]["megno"] > 0.0 and out["horizon"]["t"] > out["first_maximum"]["t"]


def test_start_on_a_critical_line(fresh_cache, capsys):
    """The paper's fig. 8 start (on Q_J,pi^crit, psi_dot0 = 0.002) through the command."""
    assert main(["slow", "--critical-line", "pi", "--psi-dot0", "0.002", "--t-end", "100", "--json", *COARSE]) == 0
    out = json.loads(capsys.readouterr().out)
    # the start is built from omega (EulerState.from_omega): its rates carry the conversion's few roundings
    assert out["start"]["psi_dot"] == pytest.approx(0.002, rel=1e-14)
    assert abs(out["start"]["theta_dot"]) < 1e-18
    assert out["first_maximum"]["t"] == 0.0  # a turning-point start at which theta falls: its own first maximum
    assert out["chart"] == "band"  # the energy of a release from 0.95pi: the band about Q_J,pi^crit


def test_chart_option(fresh_cache, capsys):
    argv = ["slow", "--theta0", "0.6pi", "--phi-dot0", "0.05", "--t-end", "50", "--json", *COARSE]
    assert main(argv + ["--chart", "band"]) == 0
    assert json.loads(capsys.readouterr().out)["chart"] == "band"
    assert main(argv) == 0
    assert json.loads(capsys.readouterr().out)["chart"] == "spindle"  # auto below the energy of a release from 0.65pi
    with pytest.raises(SystemExit) as exc:  # argparse's choices
        main(argv + ["--chart", "pi"])
    assert exc.value.code == 2 and "--chart" in capsys.readouterr().err


def test_start_options_are_checked(fresh_cache, capsys):
    assert main(["slow", "--QR", "0.1"]) == 2
    assert "--QR needs --critical-line" in capsys.readouterr().err
    assert main(["slow", "--phi-dot0", "0.05", "--processes", "0", "--nodes", "16", "8"]) == 2
    assert "--processes must be" in capsys.readouterr().err
    assert main(["slow", "--phi-dot0", "0.05", "--nodes", "16", "7"]) == 2
    assert "--nodes" in capsys.readouterr().err


def test_slow_period_doubling_option(capsys):
    """--period-doubling adds the exact one-step map's ε_pd (what rr.period_doubling computes) beside 4/κ; a start
    with velocity is refused, naming the option."""
    from rocknroller.analysis.slow.dynamics.period_doubling import period_doubling

    assert main(["slow", "--theta0", "0.95pi", "--order", "1", "--period-doubling", "--json"]) == 0
    got = json.loads(capsys.readouterr().out)["period_doubling"]
    ref = period_doubling(Body.paper(1e-3), 0.95 * math.pi)
    assert got["eps_exact"] == ref.eps_exact and got["eps_first_order"] == ref.eps_first_order
    assert main(["slow", "--theta0", "0.95pi", "--order", "1", "--period-doubling"]) == 0
    assert "exact one-step map: period doubling at eps = " in capsys.readouterr().out
    assert main(["slow", "--theta0", "0.5pi", "--phi-dot0", "0.1", "--period-doubling"]) == 2
    assert "--period-doubling applies to releases from rest" in capsys.readouterr().err



@pytest.mark.parametrize("argv, named", [(["--offset", "0.01"], "--offset"), (["--QR", "0.01"], "--QR")])
def test_a_release_refuses_the_options_of_a_start_on_a_line(argv, named, capsys):
    """A release from rest read neither --offset nor --QR: --offset was silently ignored (the prediction ran)."""
    assert main(["slow", "--t-end", "100", "--json", *argv]) == 2
    assert f"{named} needs --critical-line" in capsys.readouterr().err


@pytest.mark.parametrize("extra", [["--nodes", "16", "8"], ["--chart", "band"]])
def test_region_table_options_are_refused_for_a_release(extra, capsys):
    """Issue 25, item 25: ``slow --nodes`` and ``--chart`` with a release from rest (which uses the release tables)
    were silently ignored, while similar options are refused; now refused before any work, naming them."""
    assert main(["slow", "--theta0", "0.95pi", "--cached-only", *extra]) == 2
    err = capsys.readouterr().err
    assert "--nodes and --chart set the region tables" in err and "leave them out" in err


def test_chaos_and_horizon_in_text_json_and_csv(fresh_cache, tmp_path, capsys):
    """Issue 23, item 6: the chaotic release of the issue's table (ε = 1e-2, ψ0 = 0.1, θ0 = 0.95π) is called chaotic,
    with MEGNO, λ per unit time and per rock and the horizon equal to the API's (the same tables and map), and a t_end
    past the horizon is labelled as such in the text, the JSON and the CSV (each maximum past it: beyond_horizon)."""
    import csv

    argv = ["slow", "--order", "1", "--eps", "1e-2", "--psi0", "0.1", "--t-end", "3000"]
    assert main([*argv, "--json", "--csv", str(tmp_path / "out")]) == 0
    out = json.loads(capsys.readouterr().out)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", av.AveragingValidityWarning)  # K = 4.26 > 4: the case
        api = av.predict_slow_motion(Body.paper(1e-2), 0.95 * math.pi, 0.1, 3000.0, order=1)
    assert out["chaos"] == {"verdict": "chaotic", "regular": False, "megno": api.chaos.megno,
                            "lyapunov": api.chaos.lyapunov, "lyapunov_per_rock": api.chaos.lyapunov_per_rock,
                            "lyapunov_time": 1.0 / api.chaos.lyapunov, "span": api.chaos.span,
                            "criterion": api.chaos.criterion}
    assert out["chaos"]["megno"] > 3.0 and out["chaos"]["span"] > 3000.0  # over ~1000 rocks, whatever t_end
    assert out["horizon"]["t"] == api.horizon() < 3000.0 and out["horizon"]["fraction"] == 0.1
    assert out["horizon"]["method"] == api.horizon_estimate().method
    assert out["beyond_horizon"] is True
    assert "statistical only" in out["horizon"]["statistical_only"]
    path = tmp_path / "out" / "slow_maxima.csv"
    lines = path.read_text().splitlines()
    head = [line for line in lines if line.startswith("#")]
    assert any("CHAOTIC" in line for line in head) and any("statistical only" in line for line in head)
    assert any("over the span t <= " in line and "lambda*span" in line for line in head)
    rows = list(csv.DictReader(line for line in lines if not line.startswith("#")))
    assert len(rows) == out["n_maxima"]
    for row in rows:
        assert row["beyond_horizon"] == ("true" if float(row["t"]) > out["horizon"]["t"] else "false")
    assert {row["beyond_horizon"] for row in rows} == {"true", "false"}
    assert main(argv) == 0
    text = capsys.readouterr().out
    assert "order/chaos over the span" in text and "CHAOTIC" in text and "per rock" in text
    # the horizon to the two digits its probe resolves (six were printed for an extrapolation 4500x past its probe)
    from rocknroller.cli.slow_chaos import two_digits

    assert f"predictions past t = {two_digits(out['horizon']['t'])} are statistical only" in text
    assert two_digits(248.132) == "250" and two_digits(1956950.0) == "2e+06"


@pytest.mark.parametrize("method, lower", [("measured", False), ("linear", True), ("exponential", True)])
def test_an_extrapolated_horizon_is_a_lower_bound_to_two_digits(method, lower):
    """--psi0 0.05 --eps 3e-3 printed t = 1.95695e+06, a linear extrapolation 4500x past a 435-unit probe, to six
    digits: two digits, and '>=' with the extrapolation's measured caution where it was extrapolated."""
    from rocknroller.cli.slow_chaos import chaos_lines

    h = {"t": 1956950.0, "method": method, "fraction": 0.1, "probe_t": 435.0, "probe_error": 0.015, "rate": 5e-8,
         "lower_bound": lower}
    line = chaos_lines({"chaos": None, "chaos_note": "-", "horizon": h, "beyond_horizon": False})[1]
    assert ("t >= 2e+06" if lower else "t = 2e+06") in line and "1.95695" not in line
    assert ("fell short of the true one by about 2x" in line) is lower


def test_a_slope_at_round_off_is_no_rate():
    """A slope of 3.2e-21 per unit time (0.96pi, eps 5.2e-3, psi0 1.1) made a finite horizon: it is unresolved."""
    from rocknroller.analysis.slow.dynamics.chaos import horizon_from_errors

    t = np.linspace(0.0, 500.0, 101)
    flat = np.full_like(t, 0.011) + 3.2e-21 * t
    assert horizon_from_errors(t, flat, "linear").method == "unresolved"
    grows = 0.011 + 1e-6 * t
    assert horizon_from_errors(t, grows, "linear").method == "linear"


def test_regular_release_within_its_horizon(fresh_cache, capsys):
    """ε = 1e-3, ψ0 = π/4 (regular): MEGNO ≤ 3 over the span of ~1000 rocks (1.46 at order 1; it tends to 2
    slowly), and t_end = 1000 lies within the horizon: nothing is labelled."""
    assert main(["slow", "--order", "1", "--t-end", "1000", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["chaos"]["regular"] is True and 0.0 < out["chaos"]["megno"] <= 3.0
    assert out["horizon"]["t"] > 1000.0 and out["beyond_horizon"] is False
    assert out["horizon"]["statistical_only"] is None
    assert main(["slow", "--order", "1", "--t-end", "1000"]) == 0
    text = capsys.readouterr().out
    assert "regular (MEGNO" in text and "statistical only" not in text


def test_no_indicators_said_so(fresh_cache, capsys):
    """ε = 0 (pure rocking): no indicators, no horizon, and the reason (null in JSON, never NaN); a run of fewer than
    8 maxima has its indicators all the same, over their span."""
    assert main(["slow", "--eps", "0", "--t-end", "300", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["chaos"] is None and out["horizon"] is None and out["beyond_horizon"] is None
    assert "pure rocking" in out["chaos_note"] and "eps = 0" in out["horizon_note"]
    assert main(["slow", "--order", "1", "--t-end", "60", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["n_maxima"] < 8 and out["chaos"]["verdict"] == "regular" and out["chaos"]["span"] > 60.0
    assert main(["slow", "--eps", "0", "--t-end", "300"]) == 0
    assert "predictability horizon: not defined" in capsys.readouterr().out


def test_csv_directory_is_checked_before_computing(tmp_path, capsys):
    (tmp_path / "slow_maxima.csv").write_text("keep")
    assert main(["slow", "--csv", str(tmp_path)]) == 2
    assert "--csv" in capsys.readouterr().err and (tmp_path / "slow_maxima.csv").read_text() == "keep"


def test_statistics_beside_the_past_horizon_numbers(fresh_cache, tmp_path, capsys):
    """Issue 23, item 6: past the horizon of the chaotic release (ε = 1e-2, ψ0 = 0.1) the statistical prediction
    stands beside the point prediction, by default the map's ensemble of AUTO_MEMBERS releases within ±1e-3 in ψ0:
    its means, standard deviations and standard errors are map_ensemble's of that ball, and the point values
    member_statistics' of the API's prediction, in the JSON, the text, slow_statistics.csv and the maxima's header."""
    import csv

    import numpy as np

    from rocknroller.analysis.slow.ensemble_statistics import (STATISTIC_UNITS, STATISTICS, StartBall, map_ensemble,
                                                               member_statistics)
    from rocknroller.cli.slow_statistics import AUTO_MEMBERS

    body, argv = Body.paper(1e-2), ["slow", "--order", "1", "--eps", "1e-2", "--psi0", "0.1", "--t-end", "3000"]
    assert main([*argv, "--json", "--csv", str(tmp_path / "out")]) == 0
    out = json.loads(capsys.readouterr().out)
    st = out["statistics"]
    assert out["beyond_horizon"] is True and st["members"] == AUTO_MEMBERS and st["delta"] == 1e-3
    assert st["label"] == f"statistical (map ensemble of {AUTO_MEMBERS} starts within +-0.001 in psi0)"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", av.AveragingValidityWarning)  # K = 4.26 > 4: the case
        ens = map_ensemble(body, StartBall(0.95 * math.pi, 0.1, 1e-3, AUTO_MEMBERS, seed=0), 3000.0, order=1)
        api = av.predict_slow_motion(body, 0.95 * math.pi, 0.1, 3000.0, order=1)
    point = member_statistics(body, api.series.t, api.series.QR, api.series.QJ, 3000.0)
    assert list(st["values"]) == list(STATISTICS)
    for name, v in st["values"].items():
        assert v == {"point": point[name], "mean": ens.mean(name), "std": float(np.std(ens.values[name], ddof=1)),
                     "standard_error": ens.standard_error(name), "unit": STATISTIC_UNITS.get(name, "")}, name
    # the reversals are counted per 1000 time units, and say so (the text and the JSON did not)
    assert st["values"]["full_reversals"]["unit"] == "per 1000 time units"
    assert st["values"]["QR_extent"]["std"] > 0.0  # the members differ: the ball is resolved past the horizon
    rows = list(csv.DictReader(ln for ln in (tmp_path / "out" / "slow_statistics.csv").read_text().splitlines()
                               if not ln.startswith("#")))
    assert [r["statistic"] for r in rows] == list(STATISTICS)
    for r in rows:
        assert float(r["mean"]) == st["values"][r["statistic"]]["mean"]
        assert float(r["point"]) == st["values"][r["statistic"]]["point"]
        assert r["unit"] == STATISTIC_UNITS.get(r["statistic"], "")
    head = [ln for ln in (tmp_path / "out" / "slow_maxima.csv").read_text().splitlines() if ln.startswith("#")]
    assert any(st["label"] in ln for ln in head) and any("fraction_I " in ln for ln in head)
    assert main([*argv, "--statistics", "4", "--statistics-delta", "0.01", "--statistics-seed", "3"]) == 0
    text = capsys.readouterr().out
    assert "statistical (map ensemble of 4 starts within +-0.01 in psi0)" in text and "seed 3" in text
    assert "point prediction (past the horizon)" in text and "ensemble mean +- std" in text
    assert all(line.endswith("per 1000 time units") for line in text.splitlines() if "_reversals " in line)
    assert main([*argv, "--statistics", "0", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["statistics"] is None and "--statistics 0" in out["statistics_note"]


def test_no_statistics_within_the_horizon_unless_asked(fresh_cache, capsys):
    """A regular release within its horizon gets none by default (and says why); asked for, it gets them."""
    assert main(["slow", "--order", "1", "--t-end", "1000", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["beyond_horizon"] is False and out["statistics"] is None
    assert "within the predictability horizon" in out["statistics_note"]
    assert main(["slow", "--order", "1", "--t-end", "1000", "--json", "--statistics", "3"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["statistics"]["members"] == 3 and out["statistics"]["order"] == 1


@pytest.mark.parametrize("extra, named", [
    (["--statistics", "1"], "--statistics must be 0 (none) or a number of members in [2, 10000]"),
    (["--statistics", "-2"], "--statistics must be"),
    (["--statistics", "100000"], "--statistics must be"),
    (["--statistics-delta", "0"], "--statistics-delta must be a half-width in (0, pi/2]"),
    (["--statistics-delta", "2"], "--statistics-delta must be"),
    (["--statistics-seed", "-1"], "--statistics-seed must be >= 0"),
    (["--statistics", "4", "--psi-dot0", "0.1"], "--statistics applies to releases from rest"),
])
def test_bad_statistics_options_are_refused(extra, named, capsys):
    assert main(["slow", "--cached-only", *extra]) == 2
    assert named in capsys.readouterr().err


def test_json_shows_eps_as_given(capsys):
    """--eps 1e-2 was reported as "eps": 0.010000000000000007, the rounding of (I2 - I1)/I1."""
    assert main(["slow", "--order", "1", "--eps", "1e-2", "--psi0", "3pi/8", "--t-end", "200", "--json",
                 "--statistics", "0"]) == 0
    assert json.loads(capsys.readouterr().out)["eps"] == 0.01


@pytest.mark.parametrize("psi0, rocking", [("0", True), ("pi/2", True), ("pi", True), ("-0.0", True),
                                           ("1e-300", True), ("0.3", False)])
def test_pure_rocking_has_one_meaning(psi0, rocking, capsys):
    """--psi0 0 gave "pure_rocking": false beside "periodic_orbit": {"kind": "pure rocking"}: the flag meant eps = 0.
    Now pure_rocking says the release rocks in a vertical plane, and routh_sphere says eps = 0."""
    assert main(["slow", "--order", "1", "--psi0", psi0, "--t-end", "300", "--json", "--statistics", "0"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["pure_rocking"] is rocking and out["routh_sphere"] is False
    assert (out["periodic_orbit"] is not None and out["periodic_orbit"]["kind"] == "pure rocking") is rocking


def test_the_kappa_line_and_the_closed_forms_period_at_the_rocking_axes(capsys):
    """At --psi0 0 the kappa line was missing (the closed form does not apply on the separatrix, the constants do);
    at --psi0 pi/2 the closed form's slow period stood beside the map's n/a with no word on what it is."""
    from rocknroller.analysis.slow.dynamics.pendulum import pendulum_constants

    kappa = f"kappa = {pendulum_constants(Body.paper(1e-3), 0.95 * math.pi).kappa:.6g};"
    assert main(["slow", "--order", "1", "--psi0", "0", "--t-end", "300", "--statistics", "0"]) == 0
    assert kappa in capsys.readouterr().out
    assert main(["slow", "--order", "1", "--psi0", "pi/2", "--t-end", "300", "--statistics", "0"]) == 0
    text = capsys.readouterr().out
    assert kappa in text and "small librations about this pure rocking" in text
    assert main(["slow", "--order", "1", "--psi0", "0.3", "--t-end", "300", "--statistics", "0"]) == 0
    assert "small librations" not in capsys.readouterr().out


def test_a_run_with_no_maximum_reports_undefined_extents_and_no_statistics(capsys):
    """slow --t-end 1 --statistics 4 failed with "t, QR, QJ must be 1-d arrays..."; with zero maxima the extents were
    printed as 0.0 instead of null."""
    assert main(["slow", "--order", "1", "--t-end", "1", "--statistics", "4", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["n_maxima"] == 0 and out["statistics"] is None and "before the first" in out["statistics_note"]
    for part in (out, out["pendulum"]):
        assert part["QR_extent"] is None and part["QJ_extent"] is None and part["Phi"] is None
