"""``rocknroller animate`` and ``numerics.animation``: frames, the drawn geometry, files and bad options."""

from __future__ import annotations

import builtins
import math
import warnings

import numpy as np
import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState
from rocknroller.cli import main
from rocknroller.numerics.integrate import simulate
from rocknroller.papers import animation as an

BODY = Body.paper(1e-3)
THETA0 = 0.7 * math.pi


@pytest.fixture(scope="module")
def run():
    return simulate(BODY, EulerState.from_omega(THETA0, 0.3, 0.2, (0.0, 0.01, 0.05)), 20.0, dt=0.5)


def test_first_frame_shows_the_initial_tilt(run):
    """Frame 0 is t = 0: the drawn axis k makes the angle θ0 with the vertical, to the rounding of the few operations
    of Υ (~1e-15; 1e-13 leaves a margin of ~100), and the body's points sit where the geometry says."""
    g = an.frame_geometry(run, 0.0)
    assert g.t == 0.0 and g.theta == THETA0
    assert math.atan2(math.hypot(g.k[0], g.k[1]), g.k[2]) == pytest.approx(THETA0, abs=1e-13)
    assert np.linalg.norm(g.k) == pytest.approx(1.0, abs=1e-15)
    assert np.allclose(g.mass_centre, g.centre - BODY.a * g.k, rtol=0, atol=1e-15)
    assert g.centre[2] == 1.0 and np.array_equal(g.centre[:2], [run.X[0], run.Y[0]])
    assert np.max(np.abs((g.band - g.centre[:, None]).T @ g.k)) < 1e-15 * 8  # the band is the great circle ⟂ k
    assert np.allclose(np.linalg.norm(g.band - g.centre[:, None], axis=0), 1.0, rtol=0, atol=1e-15 * 8)


def test_frame_times_are_checked():
    assert an.frame_times(10.0, 5, 2.0).tolist() == np.linspace(0, 10, 10).tolist()
    for kw, name in (({"fps": 0}, "fps"), ({"fps": 61}, "fps"), ({"duration": 0.0}, "duration"),
                     ({"duration": math.inf}, "duration"), ({"fps": 60, "duration": 60.0}, "MAX_FRAMES")):
        with pytest.raises(ValueError, match=name):
            an.frame_times(10.0, **{"fps": 5, "duration": 2.0, **kw})
    for t_end in (math.inf, math.nan, 0.0, -1.0, 10**400):  # linspace to inf warned and gave NaN frame times
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            with pytest.raises(ValueError, match="t_end"):
                an.frame_times(t_end, 5, 2.0)


def test_gif_has_the_frames(run, tmp_path):
    from PIL import Image

    path = an.animate(run, tmp_path / "a.gif", fps=4, duration=2.0, progress=False, dpi=40)
    with Image.open(path) as im:
        assert im.n_frames == 8


def test_mp4_needs_an_encoder(run, tmp_path, monkeypatch):
    real_import = builtins.__import__

    def no_ffmpeg(name, *args, **kw):
        if name == "imageio_ffmpeg":
            raise ImportError(name)
        return real_import(name, *args, **kw)

    monkeypatch.setattr(builtins, "__import__", no_ffmpeg)
    with pytest.raises(ValueError, match=r"pip install -e \"\.\[animation\]\" in a clone"):
        an.animate(run, tmp_path / "a.mp4", fps=4, duration=1.0, progress=False)
    with pytest.raises(ValueError, match=".gif or an .mp4"):
        an.animate(run, tmp_path / "a.avi", fps=4, duration=1.0, progress=False)


def test_animate_command(tmp_path, capsys):
    from PIL import Image

    out = tmp_path / "run.gif"
    argv = ["animate", "--theta0", "0.8pi", "--phi-dot0", "0.1", "--t-end", "10", "--fps", "3", "--duration", "2",
            "--out", str(out), "--quiet"]
    assert main(argv) == 0
    with Image.open(out) as im:
        assert im.n_frames == 6
    assert main(argv) == 2 and "--force" in capsys.readouterr().err  # not overwritten unasked
    assert main([*argv[:-3], "--out", str(tmp_path / "run.avi"), "--quiet"]) == 2
    assert "--out must name a .gif or an .mp4" in capsys.readouterr().err
    assert main(["animate", "--fps", "0", "--out", str(tmp_path / "b.gif"), "--quiet"]) == 2
    assert "--fps" in capsys.readouterr().err
    # the default start takes the figure-5 omega, which needs 0 < theta0 < pi: said so, as simulate says it
    assert main(["animate", "--theta0", "0", "--out", str(tmp_path / "c.gif"), "--quiet"]) == 2
    assert "0 < theta0 < pi when no rates are given" in capsys.readouterr().err
