"""Property-based fuzzing of the public API and of every CLI subcommand (issue 10, acceptance).

Each property feeds wide inputs (zeros, signed zeros, subnormals, 1e±300, NaN, inf, negative values, and realistic
ranges) and asserts one of two outcomes: a ``ValueError`` whose message names the offending parameter, or finite
results that pass their invariant checks.  Never another exception, a NaN or inf in a result, or a hang: every call
runs under a wall-clock alarm (:func:`bounded`).  The CLI properties call ``rocknroller.cli.main(argv)`` and accept
exit status 0 or 2 (1 only where ``--strict`` asks for it), never a traceback.

Budgets: ``max_examples`` per property and the alarm below keep the module at about a minute.
"""

from __future__ import annotations

import contextlib
import json
import math
import signal
import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rocknroller.analysis.criticality import lines as crit
from rocknroller.analysis.criticality import starts, theta_z
from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState
from rocknroller.analysis.routh.quadrature import precession, precession_from_turning_point
from rocknroller.analysis.routh.reduction import F
from rocknroller.analysis.routh.turning_points import solve_turning_points
from rocknroller.cli import main
from rocknroller.numerics.integrate import AccuracyWarning, simulate

#: Longest any single call may take before the fuzz test calls it a hang (seconds of wall time).
CALL_LIMIT = 60.0
FUZZ = settings(max_examples=40, deadline=None, derandomize=True, database=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
FEW = settings(FUZZ, max_examples=15)

NASTY = [0.0, -0.0, 5e-324, 2.2250738585072014e-308, 1e-300, 1e-12, 1.0, -1.0, 1e12, 1e300, -1e300,
         1.7976931348623157e308, math.inf, -math.inf, math.nan]


def numbers(lo: float, hi: float) -> st.SearchStrategy[float]:
    """Realistic values in [lo, hi], the special values of ``NASTY``, and any float at all."""
    return st.one_of(st.floats(lo, hi), st.sampled_from(NASTY), st.floats(allow_nan=True, allow_infinity=True))


@contextlib.contextmanager
def bounded(seconds: float = CALL_LIMIT):
    """Fail (TimeoutError) if the block runs longer than ``seconds``: a hang is a defect."""
    def alarm(signum, frame):  # pragma: no cover - only on a hang
        raise TimeoutError(f"call did not return within {seconds} s")

    previous = signal.signal(signal.SIGALRM, alarm)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0.0)
        signal.signal(signal.SIGALRM, previous)


def names_a_parameter(err: ValueError, *names: str) -> None:
    """The error message names one of ``names`` (the parameters the call was given)."""
    text = str(err)
    assert any(n in text for n in names), f"{text!r} names none of {names}"


def all_finite(*values) -> bool:
    """Every number in ``values`` (arrays, masked arrays' unmasked data, scalars) is finite."""
    for v in values:
        if v is None:
            continue
        if np.ma.isMaskedArray(v):
            v = v.compressed()
        arr = np.asarray(v, dtype=float)
        if not np.all(np.isfinite(arr)):
            return False
    return True


BODY = Body.paper(0.0)
BODY_EPS = Body.paper(1e-3)


# ----------------------------------------------------------------------------- Body
@FUZZ
@given(a=numbers(0.0, 0.9), I1=numbers(0.01, 2.0), I2=numbers(0.01, 2.0), I3=numbers(0.01, 2.0), g=numbers(0.1, 20.0))
def test_body(a, I1, I2, I3, g):
    try:
        with bounded():
            body = Body(a=a, I1=I1, I2=I2, I3=I3, g=g)
    except ValueError as err:
        names_a_parameter(err, "a", "I1", "I2", "I3", "g")
        return
    assert all_finite(body.a, body.I1, body.I2, body.I3, body.g, body.epsilon)
    assert 0 <= body.a < 1 and 0 < body.I1 <= body.I2 < body.I3 <= body.I1 + body.I2 and body.g > 0
    assert body.epsilon >= 0


# ----------------------------------------------------------------------------- initial state
@FUZZ
@given(theta=numbers(0.0, math.pi), rates=st.tuples(numbers(-1, 1), numbers(-1, 1), numbers(-1, 1)),
       angles=st.tuples(numbers(-10, 10), numbers(-10, 10)))
def test_initial_state(theta, rates, angles):
    try:
        with bounded():
            state = EulerState(theta, angles[0], angles[1], *rates)
            y = state.to_body_state()
    except ValueError as err:
        names_a_parameter(err, "theta", "phi", "psi", "theta_dot", "phi_dot", "psi_dot")
        return
    assert all_finite(state.theta, state.phi, state.psi, state.theta_dot, state.phi_dot, state.psi_dot, y)


@FUZZ
@given(theta=numbers(1e-3, math.pi - 1e-3), omega=st.tuples(numbers(-1, 1), numbers(-1, 1), numbers(-1, 1)))
def test_state_from_omega(theta, omega):
    try:
        with bounded():
            state = EulerState.from_omega(theta, 0.0, 0.3, omega)
    except ValueError as err:
        names_a_parameter(err, "theta", "omega")
        return
    assert all_finite(state.theta, state.phi_dot, state.psi_dot, state.theta_dot)


# ----------------------------------------------------------------------------- simulate
@FEW
@given(theta=numbers(1e-6, math.pi - 1e-6), rates=st.tuples(numbers(-0.5, 0.5), numbers(-0.5, 0.5)),
       t_end=numbers(0.5, 20.0), eps=st.sampled_from([0.0, 1e-3, 0.05]), samples=st.booleans())
def test_simulate(theta, rates, t_end, eps, samples):
    body = Body.paper(eps)
    try:
        with bounded(), warnings.catch_warnings():
            warnings.simplefilter("error", AccuracyWarning)  # a run that misses its tolerance is a finding
            state = EulerState(theta, 0.0, 0.4, 0.0, *rates)
            run = simulate(body, state, t_end, samples=samples)
    except ValueError as err:
        names_a_parameter(err, "theta", "phi_dot", "psi_dot", "rates", "t_end", "motion")
        return
    assert run.energy_rel_error <= run.energy_tolerance
    for tp in (run.maxima, run.minima):
        assert all_finite(tp.t, tp.theta, tp.phi, tp.psi, tp.QR, tp.QJ)
        assert np.all(np.diff(tp.t) > 0) and np.all((tp.t > 0) & (tp.t <= t_end))
        assert np.all((tp.theta >= 0) & (tp.theta <= math.pi))
    if samples:
        assert all_finite(run.t, run.theta, run.phi, run.psi, run.QR, run.QJ, run.E)
        # at a maximum θ is not exceeded by the neighbouring samples (a turning point, not a threshold)
        for t_max, th_max in zip(run.maxima.t, run.maxima.theta):
            near = np.abs(run.t - t_max) < 0.05
            assert np.all(run.theta[near] <= th_max + 1e-9)


@FUZZ
@given(t_end=numbers(1.0, 50.0), dt=numbers(1e-3, 1.0))
def test_simulate_sizes(t_end, dt):
    """Sizes that scale the work are checked before any work (limits named in the message)."""
    state = EulerState(0.95 * math.pi, 0.0, 0.4)
    try:
        with bounded():
            run = simulate(BODY_EPS, state, t_end, dt=dt)
    except ValueError as err:
        names_a_parameter(err, "t_end", "dt")
        return
    assert run.t.size >= 2 and all_finite(run.t, run.theta)


# ----------------------------------------------------------------------------- reduction and precession
@FUZZ
@given(E=numbers(-1, 5), QR=numbers(-0.5, 0.5), QJ=numbers(-0.5, 0.5))
def test_turning_points_and_F(E, QR, QJ):
    try:
        with bounded():
            tp = solve_turning_points(E, QR, QJ, BODY)
    except ValueError as err:
        names_a_parameter(err, "E", "QR", "QJ")
        return
    ok = np.asarray(tp.status) == 0
    assert all_finite(tp.theta_N, tp.theta_X, tp.U_min, tp.theta_min)
    if ok:
        tN, tX = float(tp.theta_N), float(tp.theta_X)
        assert 0 <= tN <= tX <= math.pi  # Q_R = Q_J = 0 above 2ga rolls over both poles: 0 and pi
        mid = np.linspace(tN, tX, 9)[1:-1]
        if tX - tN > 1e-6:
            assert np.all(F(mid, E, QR, QJ, BODY) >= -1e-9 * max(1.0, abs(E)))


@FEW
@given(E=numbers(0.0, 2.0), QR=numbers(-0.2, 0.2), QJ=numbers(-0.2, 0.2))
def test_precession(E, QR, QJ):
    try:
        with bounded():
            pr = precession(E, QR, QJ, BODY)
    except ValueError as err:
        names_a_parameter(err, "E", "QR", "QJ", "motion", "steady", "rtol")
        return
    assert all_finite(pr.T_theta, pr.tau, pr.delta_phi, pr.delta_psi, pr.visible_phi, pr.visible_half_phi,
                      pr.theta_N, pr.theta_X)
    assert float(pr.T_theta) > 0 and float(pr.tau) == pytest.approx(2 * float(pr.T_theta), rel=1e-15)
    assert -math.pi < float(pr.visible_phi) <= math.pi and -math.pi / 2 < float(pr.visible_half_phi) <= math.pi / 2


@FEW
@given(theta0=numbers(0.0, math.pi), QR=numbers(-0.2, 0.2), QJ=numbers(-0.2, 0.2), max_nodes=st.integers(-5, 10**9))
def test_precession_from_turning_point(theta0, QR, QJ, max_nodes):
    try:
        with bounded():
            pr, upper = precession_from_turning_point(np.array([theta0, 0.9 * math.pi]), QR, QJ, BODY,
                                                      max_nodes=max_nodes)
    except ValueError as err:
        names_a_parameter(err, "theta0", "QR", "QJ", "max_nodes")
        return
    assert all_finite(pr.T_theta, pr.delta_phi, pr.delta_psi, pr.theta_N, pr.theta_X)
    assert np.all(np.ma.compressed(pr.T_theta) > 0)


# ----------------------------------------------------------------------------- criticality
@FUZZ
@given(QR=numbers(-1, 1), QJ=numbers(-1, 1))
def test_critical_values_and_regions(QR, QJ):
    try:
        with bounded():
            q0, qpi = crit.QJ_crit_0(QR, BODY), crit.QJ_crit_pi(QR, BODY)
            reg = crit.region(QR, QJ, BODY)
    except ValueError as err:
        names_a_parameter(err, "QR", "QJ")
        return
    assert all_finite(q0, qpi)
    assert str(reg) in {*crit.REGIONS, crit.ON_LINE_0, crit.ON_LINE_PI, crit.ON_BOTH}
    if QR > 0:
        assert float(q0) > 0 > float(qpi)


@FUZZ
@given(QR=numbers(-1, 1), QJ=numbers(-1, 1))
def test_cos_theta_z_and_delta(QR, QJ):
    try:
        with bounded():
            c = theta_z.cos_theta_z(QR, QJ, BODY)
            d = theta_z.delta_of(QR, QJ, BODY)
    except ValueError as err:
        names_a_parameter(err, "QR", "QJ")
        return
    assert all_finite(c, d)
    assert np.all(np.abs(np.ma.compressed(np.ma.asarray(c))) <= 1.0)


@FUZZ
@given(delta=numbers(0.0, 0.1), terms=st.integers(-1, 4))
def test_theta_z_expansion(delta, terms):
    try:
        with bounded():
            th = theta_z.theta_z_expansion(delta, BODY, terms=terms)
    except ValueError as err:
        names_a_parameter(err, "delta", "terms")
        return
    assert all_finite(th) and np.all(np.asarray(th) <= math.pi)


@FEW
@given(theta0=numbers(0.5, math.pi - 0.01), psi0=numbers(-4, 4), line=st.sampled_from(["pi", "0", "x"]),
       QR=st.one_of(st.none(), numbers(-0.1, 0.1)), psi_dot0=st.one_of(st.none(), numbers(-0.5, 0.5)),
       offset=numbers(-1e-3, 1e-3))
def test_critical_start(theta0, psi0, line, QR, psi_dot0, offset):
    try:
        with bounded():
            cs = starts.critical_start(BODY_EPS, theta0, psi0, line, QR=QR, psi_dot0=psi_dot0, offset=offset)
    except ValueError as err:
        names_a_parameter(err, "theta0", "psi0", "line", "QR", "psi_dot0", "offset")
        return
    assert all_finite(cs.phi_dot0, cs.psi_dot0, cs.omega, cs.QR, cs.QJ, cs.offset)
    target = crit.QJ_crit(line, cs.QR, BODY_EPS) + cs.offset
    assert np.all(np.abs(cs.QJ - target) <= 1e-12 * np.maximum(1.0, np.abs(cs.QJ)))


# ----------------------------------------------------------------------------- the CLI
TEXT = st.one_of(st.sampled_from(["0", "-0", "1e300", "-1e300", "1e-300", "nan", "inf", "-inf", "abc", "", "pi",
                                  "-0.5pi", "0.95pi", "pi/4", "3", "-1", "0.001", "1e-8"]),
                 st.floats(-5, 5).map(repr))


def run_cli(argv: list[str], capsys) -> tuple[int, str, str]:
    """Exit status, stdout and stderr of ``rocknroller argv``; argparse's exits are statuses too."""
    try:
        with bounded():
            code = main(argv)
    except SystemExit as exc:
        code = exc.code if isinstance(exc.code, int) else 2
    out, err = capsys.readouterr()
    assert "Traceback" not in err
    return code, out, err


def check_exit(code: int, argv: list[str], out: str) -> None:
    allowed = {0, 2} | ({1} if "--strict" in argv else set())
    assert code in allowed, (code, argv)
    if code == 0 and "--json" in argv:
        json.loads(out, parse_constant=lambda c: pytest.fail(f"{c} in JSON output of {argv}"))


@pytest.fixture(scope="module")
def outputs(tmp_path_factory):
    """A new output directory per example, under pytest's temporary tree (cleaned by pytest)."""
    return lambda: str(tmp_path_factory.mktemp("cli"))


@FEW
@given(opts=st.dictionaries(st.sampled_from(["--theta0", "--psi0", "--phi0", "--theta-dot0", "--phi-dot0",
                                             "--psi-dot0", "--eps", "--t-end", "--dt", "--a", "--I3", "--g"]),
                            TEXT, max_size=4),
       json_out=st.booleans(), strict=st.booleans(), tp_only=st.booleans())
def test_cli_simulate(opts, json_out, strict, tp_only, capsys, outputs):
    opts["--t-end"] = _short(opts.get("--t-end", "5"))
    argv = ["simulate", "--out", outputs(), "--quiet"] + [x for kv in opts.items() for x in kv]
    argv += ["--json"] * json_out + ["--strict"] * strict + ["--turning-points-only"] * tp_only
    code, out, _ = run_cli(argv, capsys)
    check_exit(code, argv, out)


def _short(text: str) -> str:
    """The CLI fuzz keeps runs short: a t_end between 50 and 1e6 time units (long, but allowed) becomes 5; every
    other value, refused ones included, is kept."""
    try:
        value = float(text.replace("pi", "")) if text not in ("pi",) else math.pi
    except ValueError:
        return text
    return "5" if 50 < value < 1e6 else text


@FEW
@given(qr=TEXT, qj=TEXT, theta0=TEXT, per=st.sampled_from(["T_theta", "tau", "bad"]), json_out=st.booleans(),
       grid=st.booleans())
def test_cli_table(qr, qj, theta0, per, json_out, grid, capsys, outputs):
    qr_arg = f"{qr}:0.01:3" if grid else qr
    argv = ["table", "--QR", qr_arg, "--QJ", qj, "--theta0", theta0, "--per", per, "--out",
            str(Path(outputs()) / "t.csv"), "--quiet"] + ["--json"] * json_out
    code, out, _ = run_cli(argv, capsys)
    check_exit(code, argv, out)


@FEW
@given(qr_max=TEXT, eps=TEXT, simulate_it=st.booleans(), t_end=st.sampled_from(["10", "1e300", "-1", "nan"]),
       line=st.sampled_from(["pi", "0", "x"]))
def test_cli_diagram(qr_max, eps, simulate_it, t_end, line, capsys, outputs):
    argv = ["diagram", "--QR-max", qr_max, "--eps", eps, "--out", outputs()]
    if simulate_it:
        argv += ["--simulate", "--t-end", t_end, "--critical-line", line, "--psi-dot0", "0.002"]
    code, out, _ = run_cli(argv, capsys)
    check_exit(code, argv, out)


@FEW
@given(theta0=TEXT, psi0=TEXT, eps=TEXT, t_end=TEXT, json_out=st.booleans())
def test_cli_slow(theta0, psi0, eps, t_end, json_out, capsys):
    # --cached-only: a start without cached tables is a clean error, never an 8 s build per example
    argv = ["slow", "--theta0", theta0, "--psi0", psi0, "--eps", eps, "--t-end", t_end, "--cached-only"]
    argv += ["--json"] * json_out
    code, out, _ = run_cli(argv, capsys)
    check_exit(code, argv, out)


@FEW
@given(opts=st.lists(st.sampled_from(["--theta0", "--psi0", "--phi-dot0", "--omega", "--t-end", "--fps"]), max_size=3),
       values=st.lists(TEXT, min_size=3, max_size=3), duration=st.sampled_from(["1", "0", "-1", "nan", "abc"]))
def test_cli_animate(opts, values, duration, capsys, outputs):
    # --duration of at most 1 s: at most 60 frames (fps ≤ 60), a few seconds to draw
    argv = ["animate", "--duration", duration, "--out", f"{outputs()}/a.gif", "--quiet"]
    for opt, val in zip(opts, values):
        argv += [opt, val] + ([val, val] if opt == "--omega" else [])
    code, out, _ = run_cli(argv, capsys)
    check_exit(code, argv, out)


@FEW
@given(theta0=TEXT, psi0=TEXT, t_end=TEXT, every=TEXT, json_out=st.booleans())
def test_cli_atlas(theta0, psi0, t_end, every, json_out, capsys, outputs):
    # --cached-only: a grid without cached tables is a clean error, never a build per example
    argv = ["atlas", "--theta0", theta0, "--psi0", psi0, "--t-end", t_end, "--confirm-every", every, "--out",
            outputs(), "--cached-only", "--quiet"] + ["--json"] * json_out
    code, out, _ = run_cli(argv, capsys)
    check_exit(code, argv, out)


@FEW
@given(only=st.lists(st.sampled_from(["table_polar_cap", "table_small_amplitude", "nope", ""]), min_size=1,
                     max_size=2), listing=st.booleans())
def test_cli_reproduce(only, listing, capsys, outputs):
    argv = ["reproduce", "--out", outputs(), "--quiet", "--only", *only] + ["--list"] * listing
    code, out, _ = run_cli(argv, capsys)
    check_exit(code, argv, out)


@FEW
@given(command=st.one_of(st.none(), st.sampled_from(["simulate", "slow", "nope"])), extra=st.lists(TEXT, max_size=2))
def test_cli_cite_help_and_garbage(command, extra, capsys):
    for argv in (["cite"] + ([command] if command else []), ["--version"], ["nope", *extra], [*extra]):
        code, out, _ = run_cli(argv, capsys)
        check_exit(code, argv, out)


def test_cli_verify(capsys):
    """verify has no inputs to fuzz: it runs clean (exit 0; 1 would be a failed check, also no traceback)."""
    code, _, _ = run_cli(["verify"], capsys)
    assert code == 0
