"""Command-line options shared by the subcommands: the body, the initial state, angles like ``0.95pi``."""

from __future__ import annotations

import argparse
import math
import re

from analysis.body import PAPER_A, PAPER_G, PAPER_I3, Body, paper_I1
from numerics.equations import EulerState

__all__ = [
    "parse_angle",
    "add_body_options",
    "body_from_args",
    "add_initial_state_options",
    "initial_state_from_args",
]

_ANGLE = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)?\s*\*?\s*(pi|π)?\s*(?:/\s*(\d+\.?\d*))?\s*$")


def parse_angle(text: str | float) -> float:
    """Parse an angle in radians: ``2.9``, ``0.95pi``, ``pi/4``, ``3pi/8``, ``-0.5*pi``.

    Raises ``ValueError`` for anything else.
    """
    if isinstance(text, (int, float)):
        return float(text)
    m = _ANGLE.match(str(text))
    if not m or (m.group(1) is None and m.group(2) is None):
        raise ValueError(f"cannot read angle {text!r}: use radians (2.9) or multiples of pi (0.95pi, pi/4, 3pi/8)")
    value = float(m.group(1)) if m.group(1) is not None else 1.0
    if m.group(2):
        value *= math.pi
    if m.group(3):
        den = float(m.group(3))
        if den == 0.0:
            raise ValueError(f"cannot read angle {text!r}: division by zero")
        value /= den
    if not math.isfinite(value):
        raise ValueError(f"angle must be finite, got {text!r}")
    return value


def add_body_options(parser: argparse.ArgumentParser) -> None:
    """--a --I1 --I2 | --eps --I3 --g, or --polar-cap D (defaults: the paper's body)."""
    grp = parser.add_argument_group("body (defaults: the paper's a=0.05, I3=0.4, I1=(1-5a/2)I3, g=9.87)")
    grp.add_argument("--a", type=float, default=None, help=f"mass-centre offset, 0 <= a < 1 (default {PAPER_A})")
    grp.add_argument("--I1", type=float, default=None, help="moment I1 (default (1-5a/2) I3)")
    grp.add_argument("--I2", type=float, default=None, help="moment I2 (default (1+eps) I1); exclusive with --eps")
    grp.add_argument("--eps", type=float, default=None, help="asymmetry eps = (I2-I1)/I1 (default 0)")
    grp.add_argument("--I3", type=float, default=None, help=f"moment I3 (default {PAPER_I3})")
    grp.add_argument("--g", type=float, default=None, help=f"gravity (default {PAPER_G})")
    grp.add_argument("--polar-cap", type=float, default=None, metavar="D",
                     help="bowling ball with the polar cap above height D=cos(Theta) removed (paper App. A.1); "
                          "exclusive with --a/--I1/--I3")


def body_from_args(args: argparse.Namespace) -> Body:
    """Build the Body from the options of :func:`add_body_options`."""
    if args.I2 is not None and args.eps is not None:
        raise ValueError("give either --I2 or --eps, not both")
    eps = 0.0 if args.eps is None else args.eps
    g = PAPER_G if args.g is None else args.g
    if args.polar_cap is not None:
        if any(v is not None for v in (args.a, args.I1, args.I3, args.I2)):
            raise ValueError("--polar-cap fixes a, I1 and I3: do not combine it with --a, --I1, --I2 or --I3")
        return Body.from_polar_cap(args.polar_cap, g=g, epsilon=eps)
    a = PAPER_A if args.a is None else args.a
    I3 = PAPER_I3 if args.I3 is None else args.I3
    I1 = paper_I1(a, I3) if args.I1 is None else args.I1
    if args.I2 is not None:
        return Body(a=a, I1=I1, I2=args.I2, I3=I3, g=g)
    return Body(a=a, I1=I1, I2=I1, I3=I3, g=g).with_epsilon(eps)


def add_initial_state_options(parser: argparse.ArgumentParser, theta0_default: str = "0.95pi") -> None:
    """--theta0 --phi0 --psi0 --theta-dot0 --phi-dot0 --psi-dot0, or --omega W1 W2 W3 (body frame)."""
    grp = parser.add_argument_group("initial state (angles accept 0.95pi, pi/4, ...)")
    grp.add_argument("--theta0", type=str, default=theta0_default, help=f"tilt in [0, pi] (default {theta0_default})")
    grp.add_argument("--phi0", type=str, default="0", help="azimuth (default 0)")
    grp.add_argument("--psi0", type=str, default="0", help="spin angle (default 0)")
    grp.add_argument("--theta-dot0", type=float, default=0.0, help="tilt rate (default 0)")
    grp.add_argument("--phi-dot0", type=float, default=0.0, help="azimuth rate (default 0)")
    grp.add_argument("--psi-dot0", type=float, default=0.0, help="spin rate (default 0)")
    grp.add_argument("--omega", type=float, nargs=3, default=None, metavar=("W1", "W2", "W3"),
                     help="body-frame angular velocity instead of the Euler rates")


def initial_state_from_args(args: argparse.Namespace) -> EulerState:
    """Build the EulerState from the options of :func:`add_initial_state_options`."""
    theta, phi, psi = parse_angle(args.theta0), parse_angle(args.phi0), parse_angle(args.psi0)
    if args.omega is not None:
        if args.theta_dot0 or args.phi_dot0 or args.psi_dot0:
            raise ValueError("give either --omega or the Euler rates (--theta-dot0 ...), not both")
        return EulerState.from_omega(theta, phi, psi, args.omega)
    return EulerState(theta, phi, psi, args.theta_dot0, args.phi_dot0, args.psi_dot0)
