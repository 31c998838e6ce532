"""`rocknroller portrait`: --help for every option, a small run's files and JSON, bad input."""

from __future__ import annotations

import json

import numpy as np
import pytest

from rocknroller.cli import build_parser, main

OPTIONS = ("--theta0", "--E", "--Theta", "--p", "--t-end", "--order", "--ode-start", "--ode-t-end", "--values",
           "--out", "--force", "--budget", "--cached-only", "--json", "--quiet", "--eps")


def test_help_documents_every_option(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["portrait", "--help"])
    assert exc.value.code == 0
    text = capsys.readouterr().out
    for option in OPTIONS:
        assert option in text, option
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command").choices["portrait"]
    for action in sub._actions:
        assert action.help, action.option_strings  # no option without a help text


def test_small_run_writes_the_figure_and_the_csv(tmp_path, capsys):
    out = tmp_path / "p"
    values = tmp_path / "values.txt"
    np.savetxt(values, [0.5, 2.0, 3.0, 9.0])
    argv = ["portrait", "--Theta", "0.5:2.5:2", "--p", "-1:1:2", "--t-end", "150", "--ode-start", "0.2,0",
            "--values", str(values), "--out", str(out), "--json", "--quiet"]
    assert main(argv) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["n_orbits"] == 4 and summary["n_ode"] == 1 and summary["order"] == 2  # slow's default
    assert sorted(p.rsplit("/", 1)[1] for p in summary["files"]) == ["portrait.csv", "portrait.pdf", "portrait.png",
                                                                    "portrait_orbits.csv"]
    assert "# value: value;" in (out / "portrait.csv").read_text()
    assert main(argv) == 2  # the files exist: not overwritten without --force
    assert "--force" in capsys.readouterr().err


def test_default_colour_is_the_megno(tmp_path, capsys):
    """Without --values the orbits are coloured by their MEGNO (ε = 5e-3, θ0 = 0.95π: Θ = 0.1 on p = 0, ψ0 = 0.05, in
    the separatrix's chaotic layer; Θ = 3.0 near the stable rocking, regular), counted in the JSON and the text."""
    argv = ["portrait", "--Theta", "0.1:3.0:2", "--p", "0", "--t-end", "1000", "--out", str(tmp_path / "p"), "--quiet"]
    assert main([*argv, "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["n_megno"] == 2 and summary["n_chaotic"] == 1 and summary["megno_range"][1] > 3.0
    assert "# value: MEGNO of the map's orbit" in (tmp_path / "p" / "portrait.csv").read_text()
    assert main([*argv, "--force"]) == 0
    assert "1 of the 2 orbits with a MEGNO are chaotic" in capsys.readouterr().out


@pytest.mark.parametrize("extra, match", [
    (["--theta0", "0.5pi"], "theta0"),
    (["--theta0", "0.95pi", "--E", "0.98"], "either --theta0 or --E"),
    (["--E", "100"], "E must be the energy"),
    (["--ode-start", "1"], "--ode-start must be THETA,P"),
    (["--Theta", "0:1:x"], "--Theta must be a value or a grid"),
    (["--eps", "0"], "eps must be > 0"),
])
def test_bad_input_exits_2_with_one_line(tmp_path, capsys, extra, match):
    assert main(["portrait", "--t-end", "100", "--out", str(tmp_path / "o"), "--quiet", *extra]) == 2
    err = capsys.readouterr().err
    assert match in err and "Traceback" not in err
