"""``rocknroller warm`` (``api/cli/warm.py``) and the note on stderr while an integrator compiles
(``rocknroller.numerics.cache.compiling``)."""

from __future__ import annotations

import threading

import pytest

from rocknroller.cli import main, warm
from rocknroller.numerics import cache


def test_warm_has_help_naming_the_disk_cache(capsys):
    with pytest.raises(SystemExit) as stop:
        main(["warm", "--help"])
    assert stop.value.code == 0
    text = " ".join(capsys.readouterr().out.split())
    assert "heyoka's disk cache" in text and "HEYOKA_CACHE_DIR" in text


def test_warm_builds_every_integrator_once_and_reports_each(monkeypatch, capsys):
    built = []
    fake = [(f"integrator {k}", (lambda k=k: built.append(k))) for k in range(3)]
    monkeypatch.setattr(warm, "integrators", lambda: fake)
    assert main(["warm"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert built == [0, 1, 2]
    assert [line.split(":")[0] for line in out] == [what for what, _ in fake]


def test_warm_lists_the_integrators_of_every_compile_site():
    """One entry per compiled integrator: direct (2 precisions), ensembles, chaos, the same three for the general
    loaded sphere, tables of order 1 and 2 and of the three harmonics."""
    names = [what for what, _ in warm.integrators()]
    assert len(names) == len(set(names)) == 10
    assert sum("general loaded sphere" in n for n in names) == 3
    assert any("order 2" in n for n in names) and any("chaos" in n for n in names)
    assert any("harmonics" in n for n in names)


def test_a_compilation_is_announced_once_on_stderr(monkeypatch, capsys):
    monkeypatch.setattr(cache, "COMPILE_NOTE_AFTER", 0.0)
    announced = threading.Event()
    real_print = print

    def spy(*args, **kwargs):
        real_print(*args, **kwargs)
        announced.set()

    monkeypatch.setattr("builtins.print", spy)
    with cache.compiling("the test integrator", 12.0):
        assert announced.wait(10.0)  # the build is still running: the note comes
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1
    assert "compiling the test integrator" in err[0] and "~12 s" in err[0] and "rocknroller warm" in err[0]


def test_a_build_from_the_disk_cache_says_nothing(monkeypatch, capsys):
    monkeypatch.setattr(cache, "COMPILE_NOTE_AFTER", 3600.0)
    with cache.compiling("the test integrator", 12.0):
        pass
    assert capsys.readouterr().err == ""
