"""Shared by the work-budget tests (portrait, atlas, bifurcation): no table in the process's memory, a stand-in for
the work that must not start before the budget is checked, and a cache folder that says which tables are cached."""

from __future__ import annotations

import os
from typing import Any, Callable, Iterable

import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.map.table import _table_location  # the one place tests read a table's file name


@pytest.fixture(autouse=True)
def no_tables_in_memory(monkeypatch):
    """No table in this process's memory either: each test's cache folder says which are cached."""
    from rocknroller.analysis.slow.map import table as slow_table
    from rocknroller.numerics.cache import MemoryCache

    monkeypatch.setattr(slow_table, "_TABLES", MemoryCache(slow_table.TABLE_CACHE_BYTES))


def no_work(*args: Any, **kwargs: Any) -> None:
    """Put in place of a builder or a run: fails the test if the work starts."""
    raise AssertionError("work started before the budget was checked")


def mark_cached(folder: os.PathLike[str] | str, monkeypatch: pytest.MonkeyPatch, body: Body,
                tables: Iterable[tuple[Callable[..., Any], float]]) -> None:
    """Point ROCKNROLLER_CACHE at ``folder`` holding an empty file for each (builder, θ0): ``is_cached`` looks no
    further than the file."""
    monkeypatch.setenv("ROCKNROLLER_CACHE", str(folder))
    for builder, where in tables:
        path = _table_location(builder, body, where, {})[2]
        os.makedirs(os.path.dirname(path), exist_ok=True)
        open(path, "wb").close()
