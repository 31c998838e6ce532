"""Work whose progress bar is hidden (stderr not a terminal) still says what it is doing (numerics/parallel.py): a
13.6-s table build printed nothing into a log."""

from __future__ import annotations

import time

from rocknroller.numerics import parallel


def _slow(x: int) -> int:
    time.sleep(0.05)
    return x


def test_hidden_progress_is_noted_in_one_line_and_its_end(monkeypatch, capsys):
    monkeypatch.setattr(parallel, "QUIET_NOTE_AFTER", 0.0)
    assert parallel.map_blocks(_slow, [(1,), (2,)], [1, 1], desc="test tables", unit="node", progress=None) == [1, 2]
    err = capsys.readouterr().err.splitlines()
    assert err[0] == "rocknroller: test tables: 2 nodes (no progress bar: stderr is not a terminal) ..."
    assert err[-1].startswith("rocknroller: test tables: done in ") and len(err) == 2


def test_quick_or_silenced_work_says_nothing(monkeypatch, capsys):
    assert parallel.map_blocks(_slow, [(1,)], [1], desc="test tables", progress=None) == [1]  # under 2 s
    monkeypatch.setattr(parallel, "QUIET_NOTE_AFTER", 0.0)
    assert parallel.map_blocks(_slow, [(1,)], [1], desc="test tables", progress=False) == [1]
    assert capsys.readouterr().err == ""
