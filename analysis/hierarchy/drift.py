"""The drift of each quantity of the hierarchy along the direct ODE, against the round-off bound of the run.

A quantity Q is sampled along :func:`~rocknroller.numerics.integrate.simulate`'s run (heyoka at its default tolerance,
the unit round-off) and its drift is max_t |Q(t) − Q(0)| / S, with S = max_t |Q(t)| (the quantity's own size; the
members' start, :func:`~rocknroller.analysis.hierarchy.members.member_start`, keeps every Q away from 0) and, for the
energy, the package's scale E(0) + g|c| (:func:`~rocknroller.numerics.run_limits.energy_scale`).  The bound is the
energy's, :func:`~rocknroller.numerics.run_limits.energy_error_bound`: each step errs by at most about the tolerance
of the state, the errors add up at worst linearly over the steps, and the evaluation adds a few u; × ``ENERGY_SLACK``
= 10.  It holds for every quantity here because each is a polynomial of degree ≤ 4 in (γ, ω) with O(1) terms at the
members' start, whose relative error is then at most a few times the state's.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rocknroller.analysis.hierarchy.members import VALUES, member_body, member_start
from rocknroller.analysis.model.body import LoadedSphere
from rocknroller.analysis.model.equations import EulerState
from rocknroller.numerics.integrate import simulate
from rocknroller.numerics.run_limits import energy_error_bound, energy_scale

__all__ = ["Drift", "quantity_drifts", "member_drifts", "DRIFT_T_END"]

#: Time over which the hierarchy's drifts are measured (about 60 rocking periods of the members' start).
DRIFT_T_END = 200.0


@dataclass(frozen=True)
class Drift:
    """The measured drift of one quantity along one run.

    Attributes
    ----------
    quantity : str
        The quantity's name (:data:`~rocknroller.analysis.hierarchy.conservation.QUANTITIES`).
    drift : float
        max_t |Q(t) − Q(0)| / S (module docstring).
    bound : float
        The round-off bound of the run, :func:`~rocknroller.numerics.run_limits.energy_error_bound`.
    g : float
        Gravity of the run (0 for Borisov and Mamaev's quantity).
    t_end : float
        Length of the run.
    """

    quantity: str
    drift: float
    bound: float
    g: float
    t_end: float

    @property
    def within_round_off(self) -> bool:
        """True where the drift is within the run's round-off bound."""
        return self.drift <= self.bound


def quantity_drifts(body: LoadedSphere, initial: EulerState, t_end: float, names: tuple[str, ...]) -> dict[str, Drift]:
    """The drift of each quantity named in ``names`` (keys of :data:`~rocknroller.analysis.hierarchy.members.VALUES`)
    along one run of ``body`` from ``initial`` (module docstring).

    Examples
    --------
    >>> import rocknroller as rr
    >>> from rocknroller.analysis.hierarchy.drift import quantity_drifts
    >>> from rocknroller.analysis.hierarchy.members import member_start
    >>> ball = rr.Body.chaplygin_ball(0.35, 0.37, 0.4)
    >>> d = quantity_drifts(ball, member_start(), 50.0, ("energy",))["energy"]
    >>> print(d.within_round_off, d.bound < 1e-11)
    True True
    """
    traj = simulate(body, initial, t_end, progress=False)
    gamma, omega = traj.gamma, traj.omega
    bound = energy_error_bound(traj.tolerance, traj.n_steps)
    out = {}
    for name in names:
        values = np.asarray(VALUES[name](body, gamma, omega), float)
        scale = energy_scale(body, values[0]) if name == "energy" else float(np.max(np.abs(values)))
        drift = float(np.max(np.abs(values - values[0]))) / scale if scale > 0.0 else 0.0
        out[name] = Drift(name, drift, bound, body.g, float(t_end))
    return out


def member_drifts(kind: str, t_end: float = DRIFT_T_END) -> dict[str, Drift | None]:
    """Every quantity's drift for the member ``kind`` (one of ``MEMBERS``) from :func:`member_start`: one run with
    gravity, one at g = 0 for the quantities stated there (Borisov and Mamaev's); None where a quantity is not
    defined for the member.

    Examples
    --------
    >>> from rocknroller.analysis.hierarchy.drift import member_drifts
    >>> drifts = member_drifts("Chaplygin's top", t_end=50.0)
    >>> print(drifts["routh"], drifts["energy"].within_round_off, drifts["jellett"].within_round_off)
    None True False
    """
    from rocknroller.analysis.hierarchy.conservation import QUANTITIES  # sympy, loaded when first needed

    start = member_start()
    out: dict[str, Drift] = {}
    for zero_g in (False, True):
        names = tuple(q.name for q in QUANTITIES if q.without_gravity == zero_g and q.defined_for(kind))
        out.update(quantity_drifts(member_body(kind, g=0.0 if zero_g else None), start, t_end, names))
    return {q.name: out.get(q.name) for q in QUANTITIES}
