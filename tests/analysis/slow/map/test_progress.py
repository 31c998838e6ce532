"""Progress on long work (issue 25, item 6): a table build names what it builds and shows a tqdm bar on stderr with
the time left; ``progress=`` means the same everywhere (True, False, or None: only if stderr is a terminal), and
``predict_slow_motion`` and ``rocknroller slow`` pass it to every build they start (the release path passed none:
343 s of a cold ``slow --check`` with nothing on stderr)."""

from __future__ import annotations

import inspect
import math

import pytest

import rocknroller as rr
from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState
from rocknroller.analysis.slow import prediction as av
from rocknroller.analysis.slow.map import region, second_order
from rocknroller.cli import main

SYM = Body.paper()
#: The coarse grids here (to keep builds short) interpolate poorly, and say so.
pytestmark = pytest.mark.filterwarnings("ignore::rocknroller.analysis.slow.map.limits.AveragingValidityWarning")


class Stop(Exception):
    """Raised by a stand-in builder once it has recorded how it was called."""


def test_release_table_build_names_itself_on_stderr(capsys):
    av.build_table(SYM, 0.95 * math.pi, nu=8, nv=4, progress=True)
    err = capsys.readouterr().err
    assert "release tables, theta0=0.95pi" in err and "32/32" in err and "node" in err
    av.build_table(SYM, 0.95 * math.pi, nu=8, nv=4, progress=False)
    assert capsys.readouterr().err == ""


def test_region_table_build_names_itself_on_stderr(capsys):
    E = av.rest_energy(SYM, 0.5 * math.pi)
    region.build_region_table(SYM, E, nu=8, nv=4, progress=True)
    err = capsys.readouterr().err
    assert f"region tables, E={E:.6g}" in err and "32/32" in err


def test_progress_means_the_same_everywhere():
    """Every public function that takes ``progress`` types it ``bool | None``; builds and sweeps default to None (a
    bar on a terminal); ``simulate`` (one run, called in loops by the package itself) to False."""
    from rocknroller.analysis.slow.map.region import build_region_table
    from rocknroller.analysis.slow.map.second_order import build_second_order_region_table, build_second_order_table

    builds = [rr.run_ensemble, rr.predict_slow_motion, rr.atlas_from_rest, rr.atlas_of_rates, rr.confirm_atlas,
              av.build_table, build_region_table, build_second_order_table, build_second_order_region_table]
    for fn in builds + [rr.simulate]:
        p = inspect.signature(fn).parameters["progress"]
        assert p.annotation == "bool | None", fn.__name__
        assert p.default is (False if fn is rr.simulate else None), fn.__name__


@pytest.mark.parametrize("order", [1, 2])
def test_predict_passes_progress_to_the_release_builds(monkeypatch, order):
    seen = []

    def record(*args, **kwargs):
        seen.append(kwargs.get("progress", "missing"))
        raise Stop

    if order == 1:
        from rocknroller.analysis.slow.map import tables_at_once as ta

        monkeypatch.setattr(ta, "energy_tables_cached", lambda body: False)  # the per-θ0 build is the one observed
        monkeypatch.setattr(ta, "load_or_build_table", record)
    else:
        monkeypatch.setattr(second_order, "load_or_build_second_order_table", record)
    with pytest.raises(Stop):
        av.predict_slow_motion(Body.paper(1e-3), 0.95 * math.pi, 0.5, order=order, progress=True,
                               table=None if order == 1 else av.build_table(SYM, 0.95 * math.pi, nu=8, nv=4))
    assert seen == [True]


def test_predict_passes_progress_to_the_region_build(monkeypatch, tmp_path):
    seen = []
    real = region.load_or_build_region_table

    def record(*args, **kwargs):
        if kwargs.get("build") is False:
            return real(*args, **kwargs)  # the cache lookup: TableNotCachedError
        seen.append(kwargs.get("progress", "missing"))
        raise Stop

    monkeypatch.setattr(region, "load_or_build_region_table", record)
    monkeypatch.setenv("ROCKNROLLER_CACHE", str(tmp_path))  # an empty disk cache: the lookup misses
    start = EulerState(0.3 * math.pi, 0.0, 0.4, 0.0, 0.05, 0.0)
    with pytest.raises(Stop):
        av.predict_slow_motion(Body.paper(1e-3), start, progress=False)
    assert seen == [False]


@pytest.mark.parametrize("extra, expected", [([], None), (["--quiet"], False)])
def test_slow_release_path_shows_progress_like_every_command(monkeypatch, extra, expected):
    """``rocknroller slow`` from rest: its table builds get the bar every command shows (on a terminal unless
    --quiet), as the start-with-velocity path already did."""
    seen = []

    def record(*args, **kwargs):
        seen.append((kwargs.get("progress", "missing"), kwargs.get("workers", "missing")))
        raise Stop

    from rocknroller.analysis.slow.map import tables_at_once as ta

    monkeypatch.setattr(ta, "energy_tables_cached", lambda body: False)  # the per-θ0 build is the one observed
    monkeypatch.setattr(ta, "load_or_build_table", record)
    with pytest.raises(Stop):
        main(["slow", "--theta0", "0.95pi", "--eps", "1e-3", "--processes", "1", *extra])
    assert seen == [(expected, 1)]
