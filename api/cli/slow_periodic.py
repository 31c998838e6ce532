"""``rocknroller slow`` from a start on a periodic orbit of the map: pure rocking and its stability.

A release from rest at ψ0 = 0 or π/2 (mod π) rocks in a principal plane (pure rocking: Q = 0 at every maximum, by
the reflection symmetry of the body): a fixed point of the slow map, and of the direct ODE's step.  Its Q stays at
round-off, so the finite-time indicators, the horizon and the relative errors of its extents would be measured on
round-off (MEGNO of a perturbation growing from 1e-16, a "horizon" of a few rocks, relative errors against extents of
0).  Such a start, and any the map returns to itself or to its reflection S x in one step to round-off
(:func:`rocknroller.analysis.slow.dynamics.periodic_starts.periodic_start`), is reported instead as that periodic orbit: its
period, points, multipliers and Greene's residue (stable for 0 < R < 1, unstable for R < 0 or R > 1;
:mod:`rocknroller.analysis.slow.dynamics.periodic_orbits`), with the extents and Φ of the orbit itself and no indicators,
horizon, statistics or relative errors.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["periodic_summary", "periodic_lines", "apply_periodic"]


def periodic_summary(orbit: Any, rocking: bool) -> dict[str, Any] | None:
    """The summary's ``periodic_orbit`` entry of a :class:`~rocknroller.analysis.slow.dynamics.periodic_orbits.PeriodicOrbit`
    (None for None); ``rocking``: the start is pure rocking (ψ0 = 0 or π/2 from rest)."""
    if orbit is None:
        return None
    return {"kind": "pure rocking" if rocking else ("fixed point" if orbit.period == 1 else "period-2 orbit"),
            "period": orbit.period, "order": orbit.order,
            "psi": [float(np.mod(0.5 * p[2], math.pi)) for p in orbit.points],
            "QR": [float(q[0]) for q in orbit.Q], "QJ": [float(q[1]) for q in orbit.Q],
            "residue": orbit.residue, "stable": orbit.stable,
            "multipliers": [[float(m.real), float(m.imag)] for m in orbit.multipliers],
            "residual": orbit.residual, "residual_bound": orbit.residual_bound}


def apply_periodic(summary: dict[str, Any]) -> None:
    """Replace, in ``summary``, what a periodic start's run measured on round-off by the orbit's own values: extents
    and Φ over its points, no slow period, line, regions runs or crossings; no relative errors (the ODE's extents are
    round-off about 0 as well)."""
    po = summary["periodic_orbit"]
    rocking = po["kind"] == "pure rocking"  # Q = 0 by symmetry; the map's fixed point within its tables' error of it
    summary.update(slow_period=None, QR_extent=0.0 if rocking else float(np.ptp(po["QR"])),
                   QJ_extent=0.0 if rocking else float(np.ptp(po["QJ"])), Phi=0.0,
                   line_slope=None, region_runs=[], crossings=[], rocks_per_region={})
    if "rel_error" in summary:
        summary["rel_error"] = {q: None for q in summary["rel_error"]}
        summary["ode"].update(slow_period=None, region_runs=[], rocks_per_region={})
        if (summary.get("pendulum") or {}).get("rel_error") is not None:
            summary["pendulum"]["rel_error"] = {q: None for q in summary["pendulum"]["rel_error"]}


def periodic_lines(s: dict[str, Any]) -> list[str]:
    """The text lines of a periodic start (:func:`periodic_summary`)."""
    po = s.get("periodic_orbit")
    if po is None:
        return []
    R = po["residue"]
    mult = ", ".join(f"{complex(*m):.6g}".strip("()") for m in po["multipliers"])
    kind = ("stable (elliptic: 0 < R < 1, the multipliers on the unit circle)" if po["stable"] else
            "unstable (" + ("hyperbolic: R < 0" if R < 0 else "inverse hyperbolic: R > 1")
            + ": round-off grows from it by the largest |multiplier| per " + ("rock" if po["period"] == 1 else
                                                                              "two rocks") + ")")
    where = ("psi = " + ", ".join(f"{p:.6g}" for p in po["psi"]) + " mod pi" +
             ("" if po["kind"] == "pure rocking" else f", Q = ({po['QR'][0]:.6g}, {po['QJ'][0]:.6g})"))
    return [f"periodic orbit: {po['kind']} ({where}): a {'fixed point' if po['period'] == 1 else 'period-2 orbit'} of "
            f"the map of order {po['order']} to |F(x) - x| = {po['residual']:.2g}",
            f"  Greene's residue R = {R:.6g}, multipliers {mult}: {kind}",
            "  no finite-time indicators, horizon or relative errors: on this orbit they would measure round-off"]
