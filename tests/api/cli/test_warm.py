"""``rocknroller warm`` (``api/cli/warm.py``) and the note on stderr while an integrator compiles
(``rocknroller.numerics.cache.compiling``)."""

from __future__ import annotations

import threading

import pytest

from rocknroller.cli import main, warm
from rocknroller.numerics import cache
from rocknroller.numerics.ensembles import lanes

#: What the fake lane measurement reports (the real one runs the batch integrator for seconds).
FAKE_CHOICE = lanes.LaneChoice({4: 8.03, 8: 7.07}, 4, 8, True)


@pytest.fixture(autouse=True)
def fake_lanes(monkeypatch):
    """warm's lane measurement, faked: the tests here are about the integrators and what warm prints."""
    monkeypatch.setattr(lanes, "measure_lanes", lambda: FAKE_CHOICE)


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
    assert [line.split(":")[0] for line in out] == [what for what, _ in fake] + ["ensembles' lanes, measured side by side"]
    assert out[-1].endswith("run_ensemble uses 8 lanes")


def test_warm_lists_the_integrators_of_every_compile_site():
    """One entry per compiled integrator: direct (2 precisions), ensembles (at each lane count run_ensemble may use:
    4, 8 and heyoka's recommendation), chaos, the same for the general loaded sphere, tables of order 1 and 2 and of
    the three harmonics."""
    from rocknroller.numerics.ensembles.batch import batch_width

    widths = {*lanes.LANE_CANDIDATES, batch_width()}
    names = [what for what, _ in warm.integrators()]
    assert len(names) == len(set(names)) == 8 + 2 * len(widths)
    assert sum("general loaded sphere" in n for n in names) == 2 + len(widths)
    assert {f"ensembles' batch integrator ({w} lanes)" for w in widths} <= set(names)
    assert any("order 2" in n for n in names) and any("chaos" in n for n in names)
    assert any("harmonics" in n for n in names)


def test_a_compilation_is_announced_once_on_stderr(monkeypatch, capsys):
    announced = _announcements(monkeypatch)
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


class _FakeCache:
    """heyoka's disk cache as warm sees it: enabled or not, and a size that a compilation grows."""

    def __init__(self, enabled: bool) -> None:
        self.enabled, self.size = enabled, 100

    def compile(self) -> None:
        self.size += 10


def _fake(monkeypatch, enabled: bool, warn: str | None = None) -> _FakeCache:
    import warnings

    import heyoka as hy

    from rocknroller.numerics import backends

    disk = _FakeCache(enabled)
    monkeypatch.setattr(hy.llvm_state, "get_diskcache_enabled", lambda: disk.enabled)
    monkeypatch.setattr(hy.llvm_state, "get_diskcache_size", lambda: disk.size)
    monkeypatch.setattr(backends, "check_diskcache",
                        lambda: warnings.warn(warn, cache.CacheWarning) if warn else None)
    monkeypatch.setattr(warm, "integrators", lambda: [("new one", disk.compile), ("old one", lambda: None)])
    return disk


def test_warm_says_which_integrators_it_compiled_and_which_it_loaded(monkeypatch, capsys):
    _fake(monkeypatch, enabled=True)
    assert main(["warm"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith("new one: compiled and cached in ")
    assert out[1].startswith("old one: loaded from heyoka's disk cache in ")
    assert out[2] == f"ensembles' lanes, measured side by side: {FAKE_CHOICE.describe()}"


def test_warm_fails_saying_why_when_nothing_can_be_cached(monkeypatch, capsys):
    """With a read-only or corrupt HEYOKA_CACHE_DIR warm compiled for a minute, printed "ready" and exited 0."""
    _fake(monkeypatch, enabled=False, warn="the cache directory /x cannot be used (read-only)")
    assert main(["warm"]) == 1
    captured = capsys.readouterr()
    assert all(": compiled, not cached in " in line for line in captured.out.splitlines()[:-1])
    assert "nothing was cached" in captured.err and "/x cannot be used (read-only)" in captured.err


def test_warm_does_not_tell_the_user_to_run_warm(monkeypatch, capsys):
    announced = _announcements(monkeypatch)
    with cache.warming(), cache.compiling("the test integrator", 12.0):
        assert announced.wait(10.0)
    err = capsys.readouterr().err
    assert "compiling the test integrator" in err and "rocknroller warm" not in err


def _announcements(monkeypatch) -> threading.Event:
    """The compile note at once (COMPILE_NOTE_AFTER = 0), and an event set when anything is printed."""
    monkeypatch.setattr(cache, "COMPILE_NOTE_AFTER", 0.0)
    announced = threading.Event()
    real_print = print

    def spy(*args, **kwargs):
        real_print(*args, **kwargs)
        announced.set()

    monkeypatch.setattr("builtins.print", spy)
    return announced


def test_warm_tables_builds_the_tables_over_energy_and_says_so(monkeypatch, capsys):
    """``warm --tables``: after the integrators, the tables over energy of the body given (built here by a stand-in),
    one line naming the range, the body, what was done and the errors the build measured."""
    from types import SimpleNamespace

    from rocknroller.analysis.slow.map import tables_at_once as ta

    asked = []

    def fake_load(body, workers=1, progress=None):
        asked.append((body.a, workers, progress))
        return SimpleNamespace(theta0_lo=0.75 * 3.141592653589793, theta0_hi=0.999 * 3.141592653589793,
                               first_error=1.7e-7, second_error=1.4e-3)

    monkeypatch.setattr(warm, "integrators", lambda: [])
    monkeypatch.setattr(ta, "energy_tables_cached", lambda body: False)
    monkeypatch.setattr(ta, "load_energy_tables", fake_load)
    assert main(["warm", "--tables", "--a", "0.06", "--processes", "1", "--quiet"]) == 0
    line = capsys.readouterr().out.splitlines()[-1]
    assert asked == [(0.06, 1, False)]
    assert line.startswith("tables over energy, theta0 in [0.75pi, 0.999pi], a=0.06")
    assert "built and cached in" in line and "1.7e-07 (first order), 1.4e-03 (k2)" in line


def test_warm_tables_refuses_a_bad_body_before_any_work(monkeypatch, capsys):
    monkeypatch.setattr(warm, "integrators", lambda: [("must not run", lambda: pytest.fail("an integrator ran"))])
    assert main(["warm", "--tables", "--a", "1.5"]) == 2
    assert "a" in capsys.readouterr().err
