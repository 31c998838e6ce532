"""Turning-point starts on a critical line, or at a signed distance from it, and the seed paper's recession starts.

:func:`critical_start` solves the rates at a turning point (θ̇0 = 0) whose (Q_R, Q_J) lie on Q_J,0^crit or
Q_J,π^crit (or at a given offset in Q_J): at θ̇ = 0 the rates of Routh's sphere are V_φ, V_ψ (paper eqs. phidotCJQR,
psidotCJQR), so the start is exact for the symmetric body and, through its body-frame ω, for the asymmetric one.
The paper's starts of figs. 7–11 (§numerics: ε = 1e-3, θ0 = 0.95π, ψ0 = π/4) are placed on their lines by
:func:`start_on_line`, not by the paper's rounded rates.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.criticality.lines import QJ_crit, check_finite
from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.equations import EulerState
from rocknroller.analysis.model.invariants import V_phi, V_psi, rho
from rocknroller.analysis.model.kinematics import omega_from_rates
from rocknroller.analysis.routh.reduction import check_invariants, require_open_tilt

__all__ = [
    "CriticalStart", "critical_start", "EPSILON", "THETA0", "PSI0", "FIG8_PSI_DOT0", "FIG9_PSI_DOT0", "FIG11_QR0",
    "start_on_line", "paper_rate_starts"
]


# ----------------------------------------------------------------------------- starts on a critical line
@dataclass(frozen=True)
class CriticalStart:
    """A turning-point start (θ̇0 = 0) at a prescribed signed distance from a critical line.

    ``offset`` = Q_J − Q_J,e^crit(Q_R) (vertical distance in the (Q_R, Q_J) plane).  The authoritative state
    is (θ0, ψ0, ``omega``), the body-frame angular velocity, whose (Q_R, Q_J) lie on the target to round-off;
    the Euler rates reproduce it only to ~ε|ψ̇0|/|ω3'| relative, because ω3' = c φ̇0 + ψ̇0 cancels when the body
    spins and rolls with ψ̇ ≈ −c φ̇ (the usual case near θ = π).

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> cs = rr.critical_start(body, 0.95 * math.pi, math.pi / 4, "pi", QR=0.01, offset=1e-4)
    >>> print(cs.line, f"{cs.offset:.1e}", rr.region(cs.QR, cs.QJ, body))
    pi 1.0e-04 I
    >>> print(f"{cs.phi_dot0:.8f}", f"{cs.psi_dot0:.8f}")
    0.00776937 0.01544670
    """

    line: str
    theta0: NDArray[np.float64]
    psi0: NDArray[np.float64]
    phi_dot0: NDArray[np.float64]
    psi_dot0: NDArray[np.float64]
    omega: NDArray[np.float64]
    QR: NDArray[np.float64]
    QJ: NDArray[np.float64]
    offset: NDArray[np.float64]

    def state(self, phi0: float = 0.0) -> EulerState:
        """The start as an :class:`~rocknroller.analysis.model.equations.EulerState` (θ0, φ0, ψ0 and the body-frame
        ω, the authoritative rates), for :func:`rocknroller.numerics.integrate.simulate` and the slow map.

        Raises
        ------
        ValueError
            For a start computed over arrays of θ0, ψ0, ... (one state per start: index the arrays first).
        """
        if np.ndim(self.theta0) != 0 or np.ndim(self.psi0) != 0 or np.size(self.omega) != 3:
            raise ValueError("state() needs a single start: this CriticalStart holds arrays of shape "
                             f"{np.shape(self.theta0)}; compute it for one theta0 and psi0")
        return EulerState.from_omega(float(self.theta0), phi0, float(self.psi0),
                                     np.asarray(self.omega, float).reshape(3))


def _check_theta_range(theta0: NDArray) -> None:
    require_open_tilt(theta0, why=" to be a turning point (phi_dot is undefined at sin(theta0) = 0)")


def _check_turning_theta(theta0: NDArray, body: Body, QR: NDArray, QJ: NDArray) -> None:
    _check_theta_range(theta0)
    if body.is_symmetric:
        from rocknroller.analysis.routh.reduction import STEADY, state_from_turning_point
        from rocknroller.analysis.routh.turning_points import solve_turning_points

        E = state_from_turning_point(body, theta0, QR, QJ).E
        if np.any(solve_turning_points(E, QR, QJ, body).status == STEADY):
            raise ValueError("theta0 cannot be a turning point here: with these (QR, QJ) it is the tilt of "
                             "steady circular rolling (double root of F, theta_ddot = 0)")


def critical_start(body: Body, theta0: ArrayLike, psi0: ArrayLike = 0.0, line: str = "pi", *,
                   QR: ArrayLike | None = None, psi_dot0: ArrayLike | None = None,
                   offset: ArrayLike = 0.0) -> CriticalStart:
    """Initial rates that put (Q_R, Q_J) on a critical line, or at a signed distance from it (paper §numerics, figs. 8, 9).

    The start is a turning point, θ̇0 = 0, at θ0.  With the paper's definitions (eq. JelletandRouth_Qtys,
    valid for I1 ≠ I2 too) Q_J = I1 s² φ̇ + I3 f ω3' and Q_R = ω3'/ρ with ω3' = c φ̇ + ψ̇, independent of ψ0:

    * given Q_R: Q_J = Q_J,e^crit(Q_R) + offset, φ̇0 = V_φ(θ0), ψ̇0 = V_ψ(θ0) (eqs. phidotCJQR, psidotCJQR), and
      the body-frame ω = Σ(θ0, ψ0)(0, φ̇0, ·) (:func:`rocknroller.analysis.model.kinematics.omega_from_rates`) with ω3 = ω3' = ρ Q_R;
    * given ψ̇0: φ̇0 solves the linear equation Q_J(φ̇0) = k Q_R(φ̇0) + offset (k the line's slope), which fixes
      Q_R; then as above (the returned ψ̇0 equals the given one to rounding, see :class:`CriticalStart`).

    Vectorised (broadcasting) to generate many states.

    Parameters
    ----------
    body : Body
    theta0 : array_like
        Turning-point tilt, 0 < θ0 < π.
    psi0 : array_like
        Spin angle (enters ω only, not Q_R, Q_J).
    line : {"pi", "0"}
        Q_J,π^crit (visible-angle reversals) or Q_J,0^crit (full-angle reversals).
    QR, psi_dot0 : array_like
        Exactly one of them.
    offset : array_like
        Signed distance Q_J − Q_J,e^crit(Q_R).

    Raises
    ------
    ValueError
        θ0 outside (0, π) or (symmetric body) a steady-rolling tilt; neither or both of QR, psi_dot0; a ψ̇0 for
        which the line cannot be reached; non-finite input.

    Examples
    --------
    >>> import math
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> cs = rr.critical_start(body, 0.95 * math.pi, math.pi / 4, "pi", QR=0.01)
    >>> print(rr.region(cs.QR, cs.QJ, body), abs(cs.QJ / rr.QJ_crit_pi(cs.QR, body) - 1) < 1e-14)
    on QJpicrit True
    """
    if (QR is None) == (psi_dot0 is None):
        raise ValueError("give exactly one of QR and psi_dot0")
    theta0 = check_finite("theta0", theta0)
    psi0 = check_finite("psi0", psi0)
    offset = check_finite("offset", offset)
    _check_theta_range(theta0)
    slope = QJ_crit(line, 1.0, body)
    r = rho(theta0, body)
    if QR is not None:
        (QRv,) = check_invariants(QR=QR)
    else:
        assert psi_dot0 is not None  # exactly one of QR and psi_dot0 was given (checked above)
        pd = check_finite("psi_dot0", psi_dot0)
        c, s2 = np.cos(theta0), np.sin(theta0) ** 2
        f = c - body.a
        # I1 s² φ̇ + I3 f (c φ̇ + ψ̇) = k (c φ̇ + ψ̇)/ρ + offset
        den = body.I1 * s2 + body.I3 * f * c - slope * c / r
        scale = body.I1 * s2 + np.abs(body.I3 * f * c) + np.abs(slope * c / r)
        if np.any(np.abs(den) <= 64 * np.finfo(float).eps * scale):
            raise ValueError("with this psi_dot0 and theta0 no phi_dot0 reaches the critical line "
                             "(the line is parallel to the family of states); give QR instead")
        phi_dot = (slope * pd / r + offset - body.I3 * f * pd) / den
        QRv = (c * phi_dot + pd) / r
        try:
            check_invariants(QR=QRv)
        except ValueError as exc:
            raise ValueError(f"psi_dot0 with this theta0 puts the start outside the resolved range: {exc}") from None
    (offset,) = check_invariants(offset=offset)
    QJv = QJ_crit(line, QRv, body) + offset
    _check_turning_theta(theta0, body, QRv, QJv)
    z = np.zeros(np.broadcast(theta0, psi0, QRv, QJv).shape)
    phi_dot0 = V_phi(theta0, QR=QRv, QJ=QJv, body=body) + z
    omega = omega_from_rates(theta0 + z, psi0 + z, z, phi_dot0, z)
    omega[2] = r * QRv + z
    return CriticalStart(line=line, theta0=theta0 + z, psi0=psi0 + z, phi_dot0=phi_dot0,
                         psi_dot0=V_psi(theta0, QR=QRv, QJ=QJv, body=body) + z, omega=omega, QR=QRv + z, QJ=QJv + z,
                         offset=offset + z)


# ----------------------------------------------------------------------------- the seed paper's recession starts
#: Paper §numerics (figs. 7-11): ε = 1e-3, released at θ0 = 0.95π, ψ0 = π/4 with θ̇0 = 0, φ0 = 0.
EPSILON = 1e-3
THETA0 = 0.95 * math.pi
PSI0 = math.pi / 4
#: The rates the paper gives for its starts on a critical line: ψ̇0 of fig. 8 (on Q_J,π^crit) and of fig. 9 (on
#: Q_J,0^crit), and Q_R of fig. 11 (on Q_J,π^crit); φ̇0 is solved here so that each start lies on its line.
FIG8_PSI_DOT0 = 0.002
FIG9_PSI_DOT0 = 0.378
FIG11_QR0 = 0.1


def start_on_line(line: str, psi_dot0: float | None = None, *, QR: float | None = None,
                  offset: float = 0.0, of: Body | None = None) -> EulerState:
    """Turning-point start at θ0 = 0.95π, ψ0 = π/4 with the given ψ̇0 (or Q_R), on the critical line (or ``offset``
    above it in Q_J) of the body ``of`` (default the paper's at ε = 1e-3):
    :func:`rocknroller.analysis.criticality.starts.critical_start`."""
    cs = critical_start(of if of is not None else Body.paper(EPSILON), THETA0, PSI0, line, psi_dot0=psi_dot0, QR=QR,
                        offset=offset)
    return cs.state()


def paper_rate_starts() -> dict[str, tuple[float, float]]:
    """The paper's reversal starts at θ0 = 0.95π, ψ0 = π/4 as (φ̇0, ψ̇0), computed on their lines: fig. 7 (rest),
    fig. 8 (on Q_J,π^crit, ψ̇0 = 0.002), fig. 9 (on Q_J,0^crit, ψ̇0 = 0.378) and fig. 11 (on Q_J,π^crit at
    Q_R = 0.1; its run starts 2.5–3.5 % of the line's value above it:
    :mod:`rocknroller.papers.lynch_bustamante.fig11_high_QR`)."""
    _on_line = {"fig. 8": start_on_line("pi", FIG8_PSI_DOT0),
               "fig. 9": start_on_line("0", FIG9_PSI_DOT0),
               "fig. 11": start_on_line("pi", QR=FIG11_QR0)}
    return {"fig. 7": (0.0, 0.0), **{k: (s.phi_dot, s.psi_dot) for k, s in _on_line.items()}}
