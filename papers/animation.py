"""Animations of a direct-ODE run: the body rolling in 3-D beside its (Q_R, Q_J) point over the critical lines.

The body is the unit sphere (radius 1, the package's length unit) touching the plane z = 0 at the contact point
(X, Y); its geometric centre is at height 1 and its mass centre a below it along the symmetry axis k (paper §2:
θ = 0, k up, is the stable rest).  Three body-fixed great circles are drawn, the band ⟂ k (red) and two meridians
through the pole k (grey), so that spin and precession are visible; the pole, the mass centre and the contact track
so far are marked; beside it, (Q_R, Q_J) at the maxima of θ with the latest one in red, over the critical lines.
The body's orientation is Υ(θ, φ, ψ) (``analysis.model.kinematics.space_axes_in_body``: a body
vector v has space components Υ v).  Frames are evenly spaced in time; the Euler angles and the contact point are
interpolated linearly between the run's samples (its output grid is the frames' times, so the interpolation only
matters at the turning points the grid also holds).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from rocknroller.analysis.model.body import as_float
from rocknroller.analysis.model.kinematics import space_axes_in_body
from rocknroller.numerics.trajectory import Trajectory

__all__ = ["MAX_FRAMES", "FPS_RANGE", "FrameGeometry", "frame_times", "frame_geometry", "animate", "ANIMATION_HINT"]

#: Most frames of one animation (each ~50–100 ms to draw and ~20 kB in a GIF).
MAX_FRAMES = 3000
#: Allowed frame rates.
FPS_RANGE = (1, 60)
#: How to install the MP4 encoder.
ANIMATION_HINT = ('python -m pip install -e ".[animation]" in a clone of the repository '
                  "(imageio-ffmpeg ships an ffmpeg binary)")
_CIRCLE = np.linspace(0.0, 2.0 * np.pi, 73)


def frame_times(t_end: float, fps: int, duration: float) -> NDArray[np.float64]:
    """The times of round(fps · duration) frames spread evenly over [0, t_end].

    Raises
    ------
    ValueError
        t_end not a finite number > 0, fps outside ``FPS_RANGE``, duration not > 0, fewer than 2 or more than
        ``MAX_FRAMES`` frames, naming them.
    """
    t_end = as_float("t_end", t_end)
    if not (np.isfinite(t_end) and t_end > 0.0):  # linspace to inf gave a RuntimeWarning and NaN frame times
        raise ValueError(f"t_end must be a finite number > 0, got t_end={t_end!r}")
    lo, hi = FPS_RANGE
    if int(fps) != fps or not lo <= fps <= hi:
        raise ValueError(f"fps must be an integer in [{lo}, {hi}], got fps={fps!r}")
    if not (np.isfinite(duration) and duration > 0.0):
        raise ValueError(f"duration must be a finite number of seconds > 0, got duration={duration!r}")
    n = int(round(fps * duration))
    if not 2 <= n <= MAX_FRAMES:
        raise ValueError(f"fps * duration must give 2 to {MAX_FRAMES} frames (MAX_FRAMES), got {n} "
                         f"(fps={fps!r}, duration={duration!r})")
    return np.linspace(0.0, float(t_end), n)


@dataclass(frozen=True)
class FrameGeometry:
    """What one frame draws, in space coordinates (z up, the plane z = 0).

    Attributes
    ----------
    t : time.
    theta : the tilt θ of k from the upward vertical.
    centre, pole, mass_centre : the geometric centre, the pole (centre + k) and the mass centre (centre − a k).
    k : the symmetry axis in space.
    band, meridians : ndarray
        (3, M) and two (3, M) arrays: points of the body-fixed great circles.
    track : ndarray
        (2, N): the contact points so far.
    """

    t: float
    theta: float
    centre: NDArray[np.float64]
    pole: NDArray[np.float64]
    mass_centre: NDArray[np.float64]
    k: NDArray[np.float64]
    band: NDArray[np.float64]
    meridians: tuple[NDArray[np.float64], NDArray[np.float64]]
    track: NDArray[np.float64]


def frame_geometry(traj: Trajectory, t: float) -> FrameGeometry:
    """The geometry of the frame at time ``t`` (module docstring)."""
    th, ph, ps, X, Y = (float(np.interp(t, traj.t, v)) for v in (traj.theta, traj.phi, traj.psi, traj.X, traj.Y))
    R = space_axes_in_body(th, ph, ps)  # rows: space axes in body components; space = R @ body
    centre = np.array([X, Y, 1.0])
    k = R[:, 2]
    c, s = np.cos(_CIRCLE), np.sin(_CIRCLE)
    band = centre[:, None] + R @ np.array([c, s, np.zeros_like(c)])
    meridians = (centre[:, None] + R @ np.array([c, np.zeros_like(c), s]),
                 centre[:, None] + R @ np.array([np.zeros_like(c), c, s]))
    upto = traj.t <= t
    track = np.array([np.append(traj.X[upto], X), np.append(traj.Y[upto], Y)])
    return FrameGeometry(t=float(t), theta=th, centre=centre, pole=centre + k, mass_centre=centre - traj.paper_body.a * k,
                         k=k, band=band, meridians=meridians, track=track)


def animate(traj: Trajectory, path: str | Path, *, fps: int = 15, duration: float = 10.0, title: str = "",
            progress: bool | None = None, dpi: int = 80) -> Path:
    """Write the animation of ``traj`` to ``path`` (.gif with pillow, .mp4 with ffmpeg); returns the path.

    Raises
    ------
    ValueError
        A suffix other than .gif or .mp4, an .mp4 without an ffmpeg (``ANIMATION_HINT``), or frame options out of
        range (:func:`frame_times`).
    """
    from matplotlib import animation, rc_context
    from tqdm.auto import tqdm

    from rocknroller.papers.output import PRODUCER, new_figure
    from rocknroller.papers.plotting import draw_critical_lines

    path = Path(path)
    if path.suffix.lower() not in (".gif", ".mp4"):
        raise ValueError(f"the animation must be a .gif or an .mp4 file, got {str(path)!r}")
    times = frame_times(float(traj.t[-1]), fps, duration)
    ffmpeg: str | None = None  # the ffmpeg binary of an .mp4 (rcParams["animation.ffmpeg_path"])
    if path.suffix.lower() == ".mp4":
        try:
            import imageio_ffmpeg
        except ImportError:
            raise ValueError(f"an .mp4 needs an ffmpeg: {ANIMATION_HINT}; or write a .gif") from None
        ffmpeg = imageio_ffmpeg.get_ffmpeg_exe()
    fig = new_figure(figsize=(10, 4.8))
    ax3 = fig.add_subplot(1, 2, 1, projection="3d")
    axq = fig.add_subplot(1, 2, 2)
    span = max(np.ptp(traj.X), np.ptp(traj.Y), 2.5)
    mx, my = 0.5 * (traj.X.max() + traj.X.min()), 0.5 * (traj.Y.max() + traj.Y.min())
    ax3.set(xlim=(mx - span / 2, mx + span / 2), ylim=(my - span / 2, my + span / 2), zlim=(0, 2),
            xlabel="X", ylabel="Y", zlabel="z")
    ax3.set_box_aspect((span, span, 2))  # equal scales: the sphere looks round
    band, = ax3.plot([], [], [], color="tab:red", lw=2)
    merid = [ax3.plot([], [], [], color="0.35", lw=1.0)[0] for _ in range(2)]
    axis, = ax3.plot([], [], [], color="k", lw=1)
    pole, = ax3.plot([], [], [], "o", color="tab:blue", ms=5)
    mass, = ax3.plot([], [], [], "o", color="k", ms=4)
    track, = ax3.plot([], [], [], color="tab:green", lw=1)
    lo, hi = float(traj.QR.min()), float(traj.QR.max())
    pad = 0.15 * max(hi - lo, 1e-12)
    axq.plot(traj.maxima.QR, traj.maxima.QJ, ".", color="0.6", ms=3, label="at the maxima of theta")
    ylim = axq.get_ylim()
    draw_critical_lines(axq, traj.paper_body, lo - pad, hi + pad)
    axq.set(ylim=ylim, xlabel="$Q_R$", ylabel="$Q_J$")
    axq.ticklabel_format(style="sci", scilimits=(-2, 2))
    point, = axq.plot([], [], "o", color="tab:red", ms=6)
    axq.legend(fontsize=7, loc="upper right")
    fig.subplots_adjust(wspace=0.35)
    label = fig.suptitle("")

    def draw(i: int) -> list[Any]:
        g = frame_geometry(traj, times[i])
        band.set_data_3d(*g.band)
        for line, m in zip(merid, g.meridians):
            line.set_data_3d(*m)
        axis.set_data_3d(*np.array([g.centre - g.k, g.pole]).T)
        pole.set_data_3d(*g.pole[:, None])
        mass.set_data_3d(*g.mass_centre[:, None])
        track.set_data_3d(g.track[0], g.track[1], np.zeros(g.track.shape[1]))
        last = int(np.searchsorted(traj.maxima.t, g.t, side="right")) - 1  # the latest maximum: the slow point
        point.set_data([traj.maxima.QR[last] if last >= 0 else traj.QR[0]],
                       [traj.maxima.QJ[last] if last >= 0 else traj.QJ[0]])
        label.set_text(f"{title}  t = {g.t:7.2f}   theta = {g.theta / np.pi:.4f} pi")
        return [band, *merid, axis, pole, mass, track, point, label]

    anim = animation.FuncAnimation(fig, draw, frames=len(times), blit=False)
    writer = (animation.PillowWriter(fps=fps, metadata={"comment": PRODUCER}) if path.suffix.lower() == ".gif"
              else animation.FFMpegWriter(fps=fps, metadata={"comment": PRODUCER}))
    path.parent.mkdir(parents=True, exist_ok=True)
    with (rc_context({} if ffmpeg is None else {"animation.ffmpeg_path": ffmpeg}),
          tqdm(total=len(times), desc="frames", unit="frame",
               disable=None if progress is None else not progress) as bar):
        anim.save(str(path), writer=writer, dpi=dpi, progress_callback=lambda i, n: bar.update(1))
    return path
