"""``rocknroller animate``: the body rolling in 3-D beside its (Q_R, Q_J) over the critical lines, as a GIF or MP4."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from rocknroller.cli.options import (add_body_options, add_critical_line_options, add_force_option,
                                     add_initial_state_options, body_from_args, critical_line_state, output_path,
                                     prepare_output_file, start_with_default_rates)
from rocknroller.papers.lynch_bustamante import fig5_symmetry_breaking as fig5


def register(sub: argparse._SubParsersAction) -> None:
    """Add the ``animate`` subcommand and its ``--help`` to ``sub``."""
    from rocknroller.papers.animation import ANIMATION_HINT, FPS_RANGE, MAX_FRAMES

    eps = fig5.EPSILONS[1]
    p = sub.add_parser(
        "animate",
        help="animate a direct-ODE run: the rolling body and its (Q_R, Q_J) over the critical lines (GIF/MP4)",
        description="Integrate the direct ODE from the simulate options (default: the paper's figure-5 start; the "
        "fig. 8 reversal start is --critical-line pi --psi-dot0 0.002 --psi0 pi/4) and write an animation: the unit sphere "
        "rolling on the plane with its band, two meridians and pole (spin visible), its mass centre, the contact "
        "track so far, and beside it (Q_R, Q_J) at the maxima of theta over the critical lines. GIF with pillow; "
        f"MP4 with the ffmpeg of imageio-ffmpeg ({ANIMATION_HINT}). At most {MAX_FRAMES} "
        f"frames; fps in [{FPS_RANGE[0]}, {FPS_RANGE[1]}].",
    )
    add_body_options(p, eps_default=eps)
    add_initial_state_options(p, rates_note="with none of --theta-dot0/--phi-dot0/--psi-dot0/--omega given (and no "
                              "--critical-line), the figure-5 omega = (0, 0.001, -0.001)")
    add_critical_line_options(p.add_argument_group("start on a critical line"))
    p.add_argument("--t-end", type=float, default=200.0, help="time span shown (default 200)")
    p.add_argument("--fps", type=int, default=15, help="frames per second (default 15)")
    p.add_argument("--duration", type=float, default=10.0, help="length of the animation in seconds (default 10)")
    p.add_argument("--out", type=output_path, default=Path("rocknroller.gif"), metavar="FILE",
                   help="the .gif or .mp4 to write (default rocknroller.gif; not overwritten without --force)")
    add_force_option(p)
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Run ``rocknroller animate`` with the parsed ``args``; returns the exit status."""
    from rocknroller.numerics.integrate import check_run, simulate
    from rocknroller.papers.animation import animate, frame_times

    body = body_from_args(args)
    initial, _ = critical_line_state(args, body)
    if args.critical_line is None:
        initial = start_with_default_rates(args, initial)
    if args.out.suffix.lower() not in (".gif", ".mp4"):
        raise ValueError(f"--out must name a .gif or an .mp4 file, got {str(args.out)!r}")
    # the body, the start and --t-end as simulate checks them, before the frame times are spread over [0, t_end]
    # (a grid of two samples: the frames' spacing is checked with the run)
    check_run(body, initial, args.t_end, dt=args.t_end)
    times = frame_times(args.t_end, args.fps, args.duration)  # checked before the run
    prepare_output_file(args.out, "--out", args.force)
    traj = simulate(body, initial, args.t_end, dt=float(times[1] - times[0]), progress=None if not args.quiet else False)
    path = animate(traj, args.out, fps=args.fps, duration=args.duration, progress=None if not args.quiet else False,
                   title=f"eps={body.epsilon:.3g}")
    print(f"wrote {path} ({len(times)} frames, t = 0 to {args.t_end:g})", file=sys.stderr)
    return 0
