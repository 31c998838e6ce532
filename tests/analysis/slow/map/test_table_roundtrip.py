"""Every kind of averaging table is read back from the disk cache in a new process's place: built once into an empty
cache directory, dropped from memory, and loaded from its file without calling its builder, bit for bit.

The kinds: the first-order release table, the region tables on both charts (spindle and band), and the second-order
tables on a release table's chart and on a region table's.  The grids are the smallest the builders accept (the
cache does not depend on them); the second-order builders take their chart from a first-order table of the same
kind, here such a small one (instead of the default grid's, minutes to build), so each case takes seconds.
"""

from __future__ import annotations

import functools
import math
import warnings

import numpy as np
import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.map import region, second_order, table
from rocknroller.analysis.slow.map.family import rest_energy
from rocknroller.analysis.slow.map.limits import AveragingValidityWarning
from rocknroller.numerics import cache

BODY = Body.paper(1e-3)
SYM = BODY.symmetric()
THETA0 = 0.9 * math.pi
#: A region table's energy on each chart: a release from 0.6π (spindle) and from 0.9π (band).
E_SPINDLE, E_BAND = rest_energy(SYM, 0.6 * math.pi), rest_energy(SYM, 0.9 * math.pi)
SMALL = {"nu": 4, "nv": 4}  # check_grid's least
SMALL_K2 = {"nu": 8, "nv": 2}  # _build_k2's least


def _small_first(body: Body, where: float, kind: str, **run) -> table.SlowMapTable:
    """The first-order table whose chart a second-order table uses, on the smallest grid (``run``: progress,
    workers)."""
    if kind == "release":
        return table.load_or_build_table(body, where, **SMALL, **run)
    return region.load_or_build_region_table(body, where, axis="spindle", **SMALL, **run)


#: kind: (module, name of the builder its loader calls, the loader's call)
KINDS = {
    "release": (table, "build_table", lambda: table.load_or_build_table(SYM, THETA0, **SMALL)),
    "region spindle": (region, "build_region_table",
                       lambda: region.load_or_build_region_table(SYM, E_SPINDLE, axis="spindle", **SMALL)),
    "region band": (region, "build_region_table",
                    lambda: region.load_or_build_region_table(SYM, E_BAND, axis="band", **SMALL)),
    "second-order release": (second_order, "build_second_order_table",
                             lambda: second_order.load_or_build_second_order_table(BODY, THETA0, **SMALL_K2)),
    "second-order region": (second_order, "build_second_order_region_table",
                            lambda: second_order.load_or_build_second_order_region_table(BODY, E_SPINDLE, **SMALL_K2)),
}


@pytest.mark.parametrize("kind", list(KINDS))
def test_every_table_is_read_back_from_disk(kind, tmp_path, monkeypatch):
    module, name, load = KINDS[kind]
    monkeypatch.setenv("ROCKNROLLER_CACHE", str(tmp_path))
    monkeypatch.setattr(table, "_TABLES", cache.MemoryCache(table.TABLE_CACHE_BYTES))
    monkeypatch.setattr(second_order, "_first_table", _small_first)
    builder, calls = getattr(module, name), []

    @functools.wraps(builder)  # the loader reads the builder's name and keyword options from it
    def counted(*args, **kw):
        calls.append(args)
        return builder(*args, **kw)

    monkeypatch.setattr(module, name, counted)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AveragingValidityWarning)  # small grids interpolate coarsely
        built = load()
    assert len(calls) == 1
    files = {p.name for p in (tmp_path / "averaging").glob("slowmap-*.npz")}
    assert files  # it was written

    monkeypatch.setattr(table, "_TABLES", cache.MemoryCache(table.TABLE_CACHE_BYTES))  # a new process's memory
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a refused file would say so with a CacheWarning
        loaded = load()
    assert len(calls) == 1, "the table was rebuilt instead of read from the disk cache"
    assert {p.name for p in (tmp_path / "averaging").glob("slowmap-*.npz")} == files
    assert type(loaded) is type(built)
    for field in built.__dataclass_fields__:  # bit for bit, NaN included
        a, b = (np.asarray(getattr(t, field), np.float64) for t in (built, loaded))
        assert a.shape == b.shape and a.tobytes() == b.tobytes(), field
