"""`rocknroller verify`: the table passes, --json emits it, and a failing check gives status 1."""

from __future__ import annotations

import json

from rocknroller.cli import main
from rocknroller.papers import verification


def test_verify_passes_and_emits_json(capsys):
    assert main(["verify", "--json", "--quiet"]) == 0
    rows = json.loads(capsys.readouterr().out)
    assert rows and all(r["passed"] for r in rows)
    assert {"group", "name", "reference", "error", "tolerance", "passed"} <= set(rows[0])


def test_failure_gives_status_1(monkeypatch, capsys):
    def failing():
        return [verification.Check("demo", "deliberately failing", "nothing", 1.0, 0.5)]

    monkeypatch.setattr(verification, "CHECKS", (failing,))
    assert main(["verify", "--quiet"]) == 1
    assert "FAIL" in capsys.readouterr().out


def test_nan_error_fails():
    assert not verification.Check("g", "n", "r", float("nan"), 1.0).passed
