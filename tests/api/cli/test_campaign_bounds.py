"""Memory, work and outputs bounded before any work: the fault campaign's reproducers end in one line (exit 2), with
nothing written or overwritten (portrait --values and its size, two runs into one --out, the work budget of the map
run many times and of the exact-map solves)."""

from __future__ import annotations

import os
import pathlib
import threading

import numpy as np
import pytest

from rocknroller.cli import main
from rocknroller.cli.options import WRITING_MARKER, prepare_output_dir, prepare_output_file, release_outputs


def one_line_error(capsys, *words: str) -> str:
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("rocknroller "), err
    for w in words:
        assert w in err, (w, err)
    return err


# ----------------------------------------------------------------------------- portrait --values
@pytest.mark.parametrize("make", ["device", "directory", "large", "missing"])
def test_values_must_be_a_small_regular_file(tmp_path, capsys, make):
    path = {"device": pathlib.Path("/dev/zero"), "directory": tmp_path, "large": tmp_path / "v.txt",
            "missing": tmp_path / "none.txt"}[make]
    if make == "large":
        path.write_text("1.0\n" * 300_000)  # 1.2 MB
    out = tmp_path / "p"
    assert main(["portrait", "--values", str(path), "--out", str(out)]) == 2
    one_line_error(capsys, "--values must be a regular file of at most 1,000,000 bytes")
    assert not out.exists()


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
def test_values_from_a_fifo_is_refused_without_waiting(tmp_path, capsys):
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    codes = []
    worker = threading.Thread(target=lambda: codes.append(main(["portrait", "--values", str(fifo), "--out",
                                                                str(tmp_path / "p")])), daemon=True)
    worker.start()
    worker.join(60.0)
    if worker.is_alive():  # it waits for a writer: give it an empty one so that the thread ends, and fail
        os.close(os.open(fifo, os.O_WRONLY | os.O_NONBLOCK))
        worker.join(60.0)
        pytest.fail("--values FIFO waited for a writer")
    assert codes == [2]
    one_line_error(capsys, "--values", "not a regular file")


def test_values_of_another_count_than_the_grid_are_refused_before_any_work(tmp_path, capsys):
    values = tmp_path / "v.txt"
    np.savetxt(values, [1.0, 2.0, 3.0])
    assert main(["portrait", "--Theta", "0.5:2.5:2", "--p", "-1:1:2", "--values", str(values), "--out",
                 str(tmp_path / "p")]) == 2
    one_line_error(capsys, "--values must hold 4 finite numbers", "got 3 numbers")
    assert not (tmp_path / "p").exists()


# ----------------------------------------------------------------------------- portrait size
def test_a_portrait_too_large_for_memory_is_refused_with_its_estimate(tmp_path, capsys):
    """180 orbits of 6e6 time units: ~8e7 maxima (the campaign: 5.5 GB and a MemoryError after 155 s)."""
    out = tmp_path / "p"
    assert main(["portrait", "--Theta", "0.1:6:20", "--p", "-0.05:0.05:9", "--t-end", "6e6", "--out", str(out)]) == 2
    err = one_line_error(capsys, "--t-end must be at most", "180 orbits", "8.1e+07 theta-maxima", "GB of memory",
                         "GB CSV")
    assert "MAX_PORTRAIT_MAXIMA" not in err  # the command line shows the limit's value
    assert not out.exists()


# ----------------------------------------------------------------------------- --out
def test_the_second_of_two_racing_runs_refuses(tmp_path, monkeypatch):
    """Both runs pass the "already exists" check (the second checks before the first has created anything: here
    the check is made blind); the files are created exclusively, so the second still refuses and removes nothing of
    the first's."""
    out = tmp_path / "same"
    names = ["a.csv", "b.png"]
    prepare_output_dir(out, "--out", False, names)  # the first run
    (out / "a.csv").write_text("first run\n")
    real_exists = pathlib.Path.exists
    monkeypatch.setattr(pathlib.Path, "exists", lambda self: False if self.parent == out else real_exists(self))
    with pytest.raises(ValueError, match=r"--out: .* already holds a\.csv \(another run may be writing it\); "
                                         "pass --force"):
        prepare_output_dir(out, "--out", False, names)
    with pytest.raises(ValueError, match="already exists; pass --force"):
        prepare_output_file(out / "a.csv", "--out", False)
    monkeypatch.undo()
    assert (out / "a.csv").read_text() == "first run\n" and (out / "b.png").exists()
    release_outputs()  # the first run ends: its unwritten reservation goes, its written file stays
    assert sorted(p.name for p in out.iterdir()) == ["a.csv"]


def test_a_run_into_any_file_marks_its_folder(tmp_path):
    """A command that writes any file (reproduce: names None) reserves a marker; a second run then refuses, and the
    marker goes when the first ends."""
    out = tmp_path / "r"
    prepare_output_dir(out, "--out", False)
    assert (out / WRITING_MARKER).exists()
    with pytest.raises(ValueError, match=f"already holds {WRITING_MARKER}"):
        prepare_output_dir(out, "--out", False)
    (out / "index.md").write_text("x")
    release_outputs()
    assert sorted(p.name for p in out.iterdir()) == ["index.md"]


def test_a_refused_run_leaves_nothing_behind(tmp_path, capsys):
    """A run refused after its outputs were reserved (here by its budget) removes the empty reservations and the
    folder it created; in an existing folder it leaves what was there."""
    argv = ["bifurcation", "--budget", "1", "--out"]
    assert main([*argv, str(tmp_path / "new" / "deeper")]) == 2
    one_line_error(capsys, "--budget SECONDS")
    assert not (tmp_path / "new").exists()
    (tmp_path / "old").mkdir()
    (tmp_path / "old" / "notes.txt").write_text("mine")
    assert main([*argv, str(tmp_path / "old")]) == 2
    assert sorted(p.name for p in (tmp_path / "old").iterdir()) == ["notes.txt"]


def test_two_runs_into_one_folder_one_after_the_other(tmp_path, capsys):
    out = tmp_path / "same"
    assert main(["simulate", "--t-end", "20", "--turning-points-only", "--out", str(out), "--quiet"]) == 0
    before = (out / "turning_points.csv").read_bytes()
    capsys.readouterr()
    assert main(["simulate", "--t-end", "30", "--turning-points-only", "--out", str(out), "--quiet"]) == 2
    one_line_error(capsys, "already holds", "--force")
    assert (out / "turning_points.csv").read_bytes() == before


# ----------------------------------------------------------------------------- the work budget
@pytest.mark.parametrize("argv, words", [
    (["slow", "--order", "1", "--statistics", "10000", "--t-end", "6.6e6"],
     ["--statistics 10000 (10000 map runs of 6.6e+06 time units each)", "h of CPU", "--budget SECONDS"]),
    (["atlas", "--theta0", "0.95pi", "--psi0", "0:3:2000", "--t-end", "6e6", "--confirm-every", "0"],
     ["the atlas's 2000 points", "2000 map runs", "--budget SECONDS"]),
    (["atlas", "--theta0", "0.95pi", "--psi0", "0:3:250000", "--t-end", "6e6", "--confirm-every", "0"],
     ["the atlas's 250000 points", "days of CPU"]),
    (["bifurcation", "--exact-at", *(f"{0.5 + 0.005 * k:g}" for k in range(200))],
     ["--exact-at takes at most 16 values", "got 200"]),
    (["bifurcation", *(a for k in range(40) for a in ("--theta0", f"{0.8 + 0.004 * k:g}pi"))],
     ["--theta0 may be given at most 8 times", "got 40"]),
    (["bifurcation", "--budget", "10"], ["a bifurcation diagram at 2 theta0", "over the budget of 10 s"]),
])
def test_the_campaign_s_long_calls_are_refused(tmp_path, capsys, argv, words):
    out = tmp_path / "out"
    option = "--csv" if argv[0] == "slow" else "--out"
    assert main([*argv, option, str(out)]) == 2
    one_line_error(capsys, *words)
    assert not out.exists()


def test_the_bifurcation_api_checks_its_counts_and_budget(tmp_path):
    import math

    from rocknroller.analysis.model.body import Body
    from rocknroller.numerics.budget import WorkBudgetError
    from rocknroller.papers.bifurcation import (MAX_DIAGRAM_THETA0, MAX_EXACT_FRACTIONS, bifurcation_data,
                                                bifurcation_diagram, bifurcation_seconds)

    body, th = Body.paper(), 0.95 * math.pi
    with pytest.raises(ValueError, match="exact_fractions must be at most MAX_EXACT_FRACTIONS = 16 values"):
        bifurcation_data(body, th, exact_fractions=[1.0] * (MAX_EXACT_FRACTIONS + 1))
    with pytest.raises(ValueError, match="theta0s must be 1 to MAX_DIAGRAM_THETA0 = 8 release angles"):
        bifurcation_diagram(body, tmp_path, [th] * (MAX_DIAGRAM_THETA0 + 1))
    with pytest.raises(WorkBudgetError, match="over the budget of 1 s"):
        bifurcation_data(body, th, budget=1.0)
    assert bifurcation_seconds(body, [th, th], 111, [0.9, 1.2]) == pytest.approx(
        2 * bifurcation_seconds(body, [th], 111, [0.9, 1.2]), rel=1e-12)
    assert not any(tmp_path.iterdir())
