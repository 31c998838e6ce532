"""Borisov and Mamaev's table of the loaded spheres, with its evidence: for every member and every quantity, the sympy
verdict (:mod:`~rocknroller.analysis.hierarchy.conservation`) beside the drift measured along the direct ODE
(:mod:`~rocknroller.analysis.hierarchy.drift`), and for every member the invariant-measure verdict
(:mod:`~rocknroller.analysis.hierarchy.measure`).

A proof and its measurement agree when a conserved quantity stays within the run's round-off bound and a quantity
proved not conserved drifts at least ``FAR_ABOVE`` times past it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from rocknroller.analysis.hierarchy.drift import DRIFT_T_END, Drift, member_drifts
from rocknroller.analysis.hierarchy.members import member_body
from rocknroller.analysis.model.body import MEMBERS, LoadedSphere

if TYPE_CHECKING:  # sympy's modules, loaded by hierarchy_table when first called (``import rocknroller`` stays light)
    from rocknroller.analysis.hierarchy.conservation import Proof
    from rocknroller.analysis.hierarchy.measure import MeasureResult

__all__ = ["Entry", "MemberRow", "hierarchy_table", "FAR_ABOVE"]

#: A quantity proved not conserved must drift at least this many times past the run's round-off bound: far enough
#: above it that no rounding could explain the drift (the members' drifts are 1e-2 to 1, the bounds ~1e-12).
FAR_ABOVE = 1e3


@dataclass(frozen=True)
class Entry:
    """One quantity of one member: its sympy proof and its measured drift.

    Attributes
    ----------
    proof : Proof
        The sympy verdict (``proof.conserved``) and, where not conserved, its exact witness.
    drift : Drift
        The drift along the direct ODE and the run's round-off bound.
    """

    proof: Proof
    drift: Drift

    @property
    def agrees(self) -> bool:
        """True where the measurement confirms the proof (module docstring)."""
        if self.proof.conserved:
            return self.drift.drift <= self.drift.bound
        return self.drift.drift >= FAR_ABOVE * self.drift.bound


@dataclass(frozen=True)
class MemberRow:
    """One member of the hierarchy: its representative body, its quantities and its invariant measure."""

    member: str
    body: LoadedSphere
    entries: dict[str, Entry]
    measure: MeasureResult

    @property
    def integrals(self) -> tuple[str, ...]:
        """The names of the quantities proved conserved (with gravity, or at g = 0 where so stated)."""
        return tuple(name for name, e in self.entries.items() if e.proof.conserved)


def hierarchy_table(t_end: float = DRIFT_T_END) -> tuple[MemberRow, ...]:
    """The four members (``MEMBERS``), each with every quantity defined for it: proof, drift over ``t_end``, and
    the invariant measure.  The proofs are computed once per process (about half a minute of sympy).

    Examples
    --------
    >>> from rocknroller.analysis.hierarchy.table import hierarchy_table
    >>> rows = hierarchy_table(t_end=50.0)
    >>> for row in rows:
    ...     print(f"{row.member:16}", all(e.agrees for e in row.entries.values()), row.measure.density_exists,
    ...           ", ".join(row.integrals))
    Chaplygin's ball True True energy, jellett, momentum_squared, momentum_vertical, borisov_mamaev_g0, borisov_mamaev
    rock'n'roller    True False energy, borisov_mamaev_g0
    Routh's sphere   True True energy, jellett, routh, borisov_mamaev_g0
    Chaplygin's top  True False energy, borisov_mamaev_g0
    """
    from rocknroller.analysis.hierarchy.conservation import QUANTITIES, proof_table
    from rocknroller.analysis.hierarchy.measure import measure_table

    if not 1.0 <= t_end <= 1e4:
        raise ValueError(f"t_end must lie in [1, 1e4] (time units), got t_end={t_end!r}")
    proofs = {(p.member, p.quantity): p for p in proof_table()}
    measures = {m.member: m for m in measure_table()}
    rows = []
    for member in MEMBERS:
        drifts = member_drifts(member, t_end)
        entries = {q.name: Entry(proofs[member, q.name], drift) for q in QUANTITIES
                   if (drift := drifts[q.name]) is not None}
        rows.append(MemberRow(member, member_body(member), entries, measures[member]))
    return tuple(rows)
