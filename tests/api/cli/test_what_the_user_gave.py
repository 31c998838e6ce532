"""Numbers and notes as the user gave them: no round-off noise or NumPy reprs in reprs, messages and CSV headers,
budgets and ε that never read as 0, warnings in the command line's one-line format, and notes that say what the
start is."""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.numerics.cache import CacheWarning
from rocknroller.cli import main
from rocknroller.cli import cite as cite_command
from rocknroller.cli.options import parse_angle
from rocknroller.numerics.budget import check_work, format_seconds
from rocknroller.papers.output import angle_text

#: Round-off noise of the paper's defaults (I1 = (1 - 5a/2) I3, eps from I2) and NumPy scalar reprs.
NOISE = ("0.35000000000000003", "0.004999999999999", "np.float64", "array(")


def _header(path: Path) -> str:
    return "\n".join(line for line in path.read_text().splitlines() if line.startswith("#"))


def test_body_repr_and_description_have_no_round_off_noise():
    for eps in (0.0, 0.005, 1e-3, 0.004, 0.0123):
        body = Body.paper(eps)
        text = f"{body!r} {body.describe()}"
        assert not any(n in text for n in NOISE), text
        assert eval(repr(body), {"Body": Body}) == body  # exact, not rounded
    assert repr(Body.paper(0.005)) == "Body.paper(epsilon=0.005)"
    other = Body(a=0.1, I1=0.3, I2=0.31, I3=0.4, g=9.8)
    assert eval(repr(other), {"Body": Body}) == other


@pytest.mark.parametrize("text", ["0.93pi", "0.95pi", "pi/4", "0.1", "2.9", "-0.5pi", "0.999pi"])
def test_angles_are_echoed_as_given(text):
    """θ0 given as 0.93pi was echoed as 2.92168."""
    shown = angle_text(parse_angle(text))
    assert parse_angle(shown) == parse_angle(text)
    assert shown == {"pi/4": "0.25pi"}.get(text, text)


def test_tiny_budget_is_not_zero_seconds():
    """--budget 1e-300 said "would take about 0 s ... over the budget of 0 s"."""
    assert format_seconds(1e-300) == "1e-300 s" and format_seconds(0.0029) == "0.0029 s"
    with pytest.raises(ValueError) as err:
        check_work(0.0029, "this run", 1e-300)
    assert "about 0.0029 s" in str(err.value) and "budget of 1e-300 s" in str(err.value)
    assert " 0 s" not in str(err.value)


def test_eps_too_small_to_resolve_is_refused_as_given(tmp_path, capsys):
    """portrait --eps 1e-300 reported `got eps=0.0`: I2 = (1 + 1e-300) I1 is I1, the symmetric body."""
    with pytest.raises(ValueError, match=r"epsilon=1e-300"):
        Body.paper(1e-300)
    assert main(["portrait", "--eps", "1e-300", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "--eps=1e-300" in err and "eps=0.0" not in err


def test_warnings_in_one_line(monkeypatch, capsys):
    """Cache warnings reached the user in Python's two-line form (file:line: CacheWarning: ..., then the source line)
    in atlas --method ode, portrait and slow: every command now prints them as its errors, in one line."""
    def run(args):
        warnings.warn("the cached averaging table x is not used (checksum); it is rebuilt", CacheWarning)
        return 0

    monkeypatch.setattr(cite_command, "run", run)
    with warnings.catch_warnings():
        warnings.simplefilter("always")
        assert main(["cite"]) == 0
    err = capsys.readouterr().err
    assert err == "rocknroller cite: warning: the cached averaging table x is not used (checksum); it is rebuilt\n"


def test_portrait_header_shows_what_was_given(tmp_path, capsys):
    """The portrait CSV header held np.float64(137.2...), I1=0.35000000000000003 and theta0 2.921681167838508."""
    assert main(["portrait", "--theta0", "0.93pi", "--Theta", "0.5:1:2", "--p", "0:0.01:2", "--t-end", "200",
                 "--quiet", "--out", str(tmp_path)]) == 0
    capsys.readouterr()
    header = _header(tmp_path / "portrait.csv")
    assert not any(n in header for n in NOISE), header
    assert "theta0 0.93pi" in header and "epsilon=0.005" in header


def test_slow_echoes_theta0_and_eps(tmp_path, capsys):
    assert main(["slow", "--theta0", "0.93pi", "--psi0", "0.1", "--eps", "0.005", "--t-end", "300", "--quiet",
                 "--csv", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "theta0=0.93pi" in out and "2.92168" not in out
    assert "eps = 4/kappa = " in out and "to first order" in out  # the period doubling of the table is K = 4
    header = _header(tmp_path / "slow_maxima.csv")
    assert not any(n in header for n in NOISE), header
    assert "eps=0.005;" in header and "theta0=0.93pi;" in header


def test_statistics_note_of_a_release_below_the_release_tables(capsys):
    """slow --theta0 0.5pi (a release from rest, run on the region tables) said "not a release from rest"."""
    assert main(["slow", "--theta0", "0.5pi", "--t-end", "100", "--quiet", "--json"]) == 0
    note = json.loads(capsys.readouterr().out)["statistics_note"]
    assert "not a release from rest" not in note and "a release from rest off the release tables" in note
