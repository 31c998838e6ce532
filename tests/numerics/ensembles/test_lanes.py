"""The ensembles' default lane count (numerics/ensembles/lanes.py): heyoka's recommendation unless a width measured
on this machine is faster by more than the margin; the record is a checked plain-array file, and a bad one is
refused with a CacheWarning, never used."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState
from rocknroller.numerics import cache
from rocknroller.numerics.ensembles import ensemble, lanes
from rocknroller.numerics.ensembles.batch import batch_width


@pytest.fixture
def empty_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("ROCKNROLLER_CACHE", str(tmp_path))
    return tmp_path


def test_the_faster_width_wins_only_beyond_the_margin():
    """On the AVX-512 machine whose heyoka recommends 4, 8 lanes measured 7.07 against 8.03 ms: 8; within the
    margin the recommendation stays (the AVX2 machine's equal widths)."""
    assert lanes.choose_lanes(4, {4: 8.03, 8: 7.07}) == 8
    below = 1.0 - lanes.LANE_MARGIN
    assert lanes.choose_lanes(4, {4: 1.0, 8: math.nextafter(below, 0.0)}) == 8
    assert lanes.choose_lanes(4, {4: 1.0, 8: below}) == 4
    assert lanes.choose_lanes(8, {4: 5.0, 8: 5.0}) == 8
    with pytest.raises(ValueError, match="recommended"):
        lanes.choose_lanes(16, {4: 1.0, 8: 1.0})


def test_without_a_record_the_default_is_heyokas_width(empty_cache):
    assert lanes.default_lanes() == batch_width()


def _fake_timer(seconds: dict[int, float]):
    """A clock on which each width's ensemble takes ``seconds[w]``: measure_lanes reads it before and after each
    width, in increasing width, round after round."""
    widths = sorted({*lanes.LANE_CANDIDATES, batch_width()})
    readings, now = [], 0.0
    for _ in range(3):
        for w in widths:
            readings += [now, now + seconds[w]]
            now += seconds[w]
    calls = iter(readings)
    return lambda: next(calls)


def test_a_measured_faster_width_becomes_the_default_of_run_ensemble(empty_cache, monkeypatch):
    widths = sorted({*lanes.LANE_CANDIDATES, batch_width()})
    other = next(w for w in lanes.LANE_CANDIDATES if w != batch_width())
    seconds = {w: (1.0 if w == other else 2.0) for w in widths}
    choice = lanes.measure_lanes(2, 5.0, timer=_fake_timer(seconds))
    assert choice.chosen == other and choice.saved and choice.recommended == batch_width()
    assert lanes.default_lanes() == other
    used = []
    monkeypatch.setattr(ensemble, "run_jobs", lambda jobs, n: used.append(n) or [None] * len(jobs))
    ensemble.run_ensemble([ensemble.Job(Body.paper(1e-3), EulerState(2.9, 0.0, 0.3, 0.0, 0.0, 0.0), 5.0)],
                          progress=False)
    assert used == [other]


def test_a_slower_width_leaves_the_recommendation(empty_cache):
    widths = sorted({*lanes.LANE_CANDIDATES, batch_width()})
    seconds = {w: (1.0 if w == batch_width() else 1.02) for w in widths}
    assert lanes.measure_lanes(2, 5.0, timer=_fake_timer(seconds)).chosen == batch_width() == lanes.default_lanes()


def test_a_bad_record_is_refused_not_used(empty_cache):
    path = empty_cache / f"lanes-{lanes.machine_key()}.npz"
    cache.save_arrays(path, path.stem, {"widths": np.array([4.0, 8.0]), "cpu_seconds": np.array([1.0, 1.0]),
                                        "chosen": np.array(3.5)})
    with pytest.warns(cache.CacheWarning, match="not a lane count"):
        assert lanes.default_lanes() == batch_width()
    path.write_bytes(b"not a zip file")
    with pytest.warns(cache.CacheWarning, match="ignoring the lane record"):
        assert lanes.default_lanes() == batch_width()


@pytest.mark.parametrize("kwargs, match", [({"jobs": 0}, "jobs"), ({"jobs": True}, "jobs"),
                                           ({"jobs": 10**6}, "jobs"), ({"t_end": -1.0}, "t_end"),
                                           ({"t_end": math.inf}, "t_end"), ({"t_end": "5"}, "t_end")])
def test_measure_lanes_checks_its_sizes_first(kwargs, match):
    with pytest.raises(ValueError, match=match):
        lanes.measure_lanes(**kwargs, save=False)
