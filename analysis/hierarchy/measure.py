"""Invariant measures of the loaded spheres: which members have a density ρ(γ), decided by sympy.

A density ρ on the state space (γ, ω) (γ·γ = 1) is invariant under the flow f = (γ × ω, K⁻¹P) when
div(ρ f) = 0, i.e. f·∇ log ρ + div f = 0.  Two exact facts make the question for densities of γ alone decidable:

* div f = n(γ)·ω / det K with n polynomial: the γ-part γ × ω is divergence-free, and
  div_ω(K⁻¹P) = tr(K⁻¹ ∂P/∂ω) with P quadratic in ω plus gravity (free of ω), so div f is linear in ω
  (:func:`flow_divergence` checks this rather than assuming it).
* For ρ(γ), f·∇ log ρ = (γ × ω)·∇ log ρ = ω·(∇ log ρ × γ).  So an invariant ρ(γ) needs n/det K = γ × ∇ log ρ for every
  ω: (1) n·γ = 0 on the sphere, and (2) the tangent field α = −γ × n / det K, which must then be the surface
  gradient of log ρ, is closed: γ·curl α = 0 on the sphere.  Conversely (1) and (2) give log ρ by integrating α
  (the sphere is simply connected), unique up to a constant.

Where (1) fails, a witness is a state with ω ∥ γ: there f·∇ρ = 0 for every ρ(γ), so div(ρ f) = ρ div f ≠ 0.

The candidates, as densities in (γ, ω) (a density ρ_M in (γ, M), M = K ω, is ρ = det K · ρ_M here):

* ``chaplygin``: ρ = sqrt(det K), i.e. (det K)^(−1/2) in (γ, M), Chaplygin's measure of the ball (1903);
* ``routh``: ρ = det K (I3 + s² + (I3/I1) f²)^(−1/2), s² = γ1² + γ2², f = γ3 + c3, i.e. the paper's
  ρ = (I3 + s² + (I3/I1) f²)^(−1/2) (eq. measure) in (γ, M); defined where c lies on the third axis.

The verdicts (:func:`measure_table`, about 1 s; every member's parameters symbolic):

* Chaplygin's ball: a density ρ(γ) exists, and it is ``chaplygin``; ``routh`` is not invariant for the general ball
  (with I1 = I2, where r·r = 1, the two candidates agree up to a constant).
* Routh's sphere: a density ρ(γ) exists, and it is ``routh``, the paper's ρ in (γ, M); ``chaplygin`` is *not*
  invariant (det K = (I1 + r·r)(I1 I3 + I1 s² + I3 f²) here, and the factor I1 + r·r = I1 + 1 + 2 c3 γ3 + c3² is not
  conserved).
* The rock'n'roller (I1 ≠ I2) and Chaplygin's top: no density depending on γ alone exists, neither in (γ, ω) nor in
  (γ, M): n·γ ≠ 0 (and the closure condition fails too).  For the rock'n'roller, on the sphere,

      n·γ = −c3 (I1 − I2) γ1 γ2 (1 + I3 + c3 γ3),

  zero only where I1 = I2 (Routh's sphere), c3 = 0 (the ball) or γ1 γ2 = 0; for the top n·γ is an irreducible
  polynomial of 60 terms.  At the witness state ω = γ, div f ≠ 0 exactly.  This does not exclude a density that
  depends on ω.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from functools import cache

from sympy.polys.rings import PolyElement

from rocknroller.analysis.hierarchy.conservation import (Number, SymbolicModel, Witness, exact_value,
                                                         search_witness, symbolic_model, witness_points)
from rocknroller.analysis.model.body import MEMBERS
from rocknroller.analysis.model.equations import cross, dot

__all__ = ["DENSITIES", "Density", "FlowDivergence", "flow_divergence", "DensityCheck", "check_density",
           "MeasureResult", "measure", "measure_table"]

Vector = tuple[PolyElement, PolyElement, PolyElement]


def _gradient(m: SymbolicModel, poly: PolyElement) -> Vector:
    return (poly.diff(m.gamma[0]), poly.diff(m.gamma[1]), poly.diff(m.gamma[2]))


def _curl(m: SymbolicModel, v: Vector) -> Vector:
    x = m.gamma
    return (v[2].diff(x[1]) - v[1].diff(x[2]), v[0].diff(x[2]) - v[2].diff(x[0]), v[1].diff(x[0]) - v[0].diff(x[1]))


@dataclass(frozen=True)
class FlowDivergence:
    """div f = n·ω / det K of a member's flow f = (γ × ω, K⁻¹P) on R⁶.

    Attributes
    ----------
    member : str
    numerator : polynomial
        det K · div f = tr(adj K ∂P/∂ω) = Σ_i ∂(det K ω̇_i)/∂ω_i (adj K is free of ω).
    n : tuple of 3 polynomials
        The coefficients of ω in ``numerator``: functions of γ and the parameters.
    linear_in_omega : bool
        ``numerator`` equals n·ω exactly.

    Examples
    --------
    >>> from rocknroller.analysis.hierarchy.measure import flow_divergence
    >>> d = flow_divergence("rock'n'roller")
    >>> gamma = (0.6, 0.0, 0.8)  # at omega = gamma: n·gamma / det K, zero where gamma1 gamma2 = 0
    >>> print(d.linear_in_omega, d.at(gamma, gamma, (0, 0, -0.05, 0.35, 0.36, 0.4, 9.87)))
    True 0
    """

    member: str
    numerator: PolyElement
    n: Vector
    linear_in_omega: bool
    model: SymbolicModel = field(repr=False)

    def at(self, gamma: Sequence[Number], omega: Sequence[Number], params: Sequence[Number]) -> Fraction:
        """The exact div f at a point; params (c1, c2, c3, I1, I2, I3, g) satisfying the member's constraints."""
        return exact_value(self.member, self.numerator, self.model.det_mass_matrix, gamma, omega, params)


def flow_divergence(member: str) -> FlowDivergence:
    """The divergence of the member's flow on the (γ, ω) space, exactly, over its free parameters.

    Examples
    --------
    >>> from rocknroller.analysis.hierarchy.measure import flow_divergence
    >>> print(flow_divergence("Chaplygin's ball").at((0, 0, 1), (1, 2, 3), (0, 0, 0, 1, 1, 1, 1)))
    0
    """
    m = symbolic_model(member)
    numerator = sum((dw.diff(w) for w, dw in zip(m.omega, m.omega_dot_times_det)), m.det_mass_matrix.ring.zero)
    n = (numerator.diff(m.omega[0]), numerator.diff(m.omega[1]), numerator.diff(m.omega[2]))
    return FlowDivergence(member, numerator, n, numerator == dot(n, m.omega), m)


@dataclass(frozen=True)
class Density:
    """A candidate density of γ alone, in (γ, ω): ρ = (det K)^e0 Π p_k^e_k, ``build(model)`` giving
    (e0, ((p_1, e_1), ...)).

    Examples
    --------
    >>> from rocknroller.analysis.hierarchy.measure import DENSITIES
    >>> print([d.name for d in DENSITIES])
    ['chaplygin', 'routh']
    """

    name: str
    formula: str
    build: Callable[[SymbolicModel], tuple[Fraction, tuple[tuple[PolyElement, Fraction], ...]]] = field(repr=False)
    on_axis_only: bool = False


def _routh_factor(m: SymbolicModel) -> PolyElement:
    """I1 ρ⁻² = I1 I3 + I1 s² + I3 f² (paper eq. measure, times the constant I1)."""
    (g1, g2, _), (I1, _, I3) = m.gamma, m.inertia
    return I1 * I3 + I1 * (g1 * g1 + g2 * g2) + I3 * m.r[2] ** 2


DENSITIES = (
    Density("chaplygin", "sqrt(det K) in (γ, ω) = (det K)^(-1/2) in (γ, M)", lambda m: (Fraction(1, 2), ())),
    Density("routh", "det K (I3 + s² + (I3/I1) f²)^(-1/2) in (γ, ω) = the paper's ρ in (γ, M)",
            lambda m: (Fraction(1), ((_routh_factor(m), Fraction(-1, 2)),)), on_axis_only=True),
)
_DENSITY = {d.name: d for d in DENSITIES}


def _density(name: str) -> Density:
    if name not in _DENSITY:
        raise ValueError(f"density must be one of {tuple(_DENSITY)}, got {name!r}")
    return _DENSITY[name]


def _on_axis(member: str) -> bool:
    """c1 = c2 = 0 for every body of the member."""
    return not any(symbolic_model(member).offset[:2])


@dataclass(frozen=True)
class DensityCheck:
    """Whether a candidate density is invariant for a member: div(ρ f)/ρ = f·∇ log ρ + div f = numerator/denominator
    vanishes on γ·γ = 1 for every ω and all the member's parameters.

    Attributes
    ----------
    member, density : str
    invariant : bool
    witness : Witness or None
        Where not invariant, an exact rational state with ``value`` = div(ρ f)/ρ ≠ 0.
    numerator, denominator : polynomial
        div(ρ f)/ρ times, and divided by, det K Π p_k.
    seconds : float
        Time taken (not compared; the member's model, built once by
        :func:`~rocknroller.analysis.hierarchy.conservation.symbolic_model`, not counted).

    Examples
    --------
    >>> from rocknroller.analysis.hierarchy.measure import check_density
    >>> print(check_density("Chaplygin's ball", "chaplygin").invariant)
    True
    """

    member: str
    density: str
    invariant: bool
    witness: Witness | None
    numerator: PolyElement = field(repr=False)
    denominator: PolyElement = field(repr=False)
    seconds: float = field(compare=False)

    def at(self, gamma: Sequence[Number], omega: Sequence[Number], params: Sequence[Number]) -> Fraction:
        """The exact div(ρ f)/ρ at a point; params (c1, c2, c3, I1, I2, I3, g) satisfying the member's constraints."""
        return exact_value(self.member, self.numerator, self.denominator, gamma, omega, params)


def check_density(member: str, density: str) -> DensityCheck:
    """Decide whether the candidate ``density`` (a name in ``DENSITIES``) is invariant for ``member``.

    With ρ = D^e0 Π p_k^e_k (D = det K): div(ρ f)/ρ = (e0 γ̇·∇D + n·ω)/D + Σ e_k γ̇·∇p_k/p_k; times D Π p_k a
    polynomial, reduced modulo γ·γ − 1.

    Examples
    --------
    >>> from rocknroller.analysis.hierarchy.measure import check_density
    >>> check = check_density("Routh's sphere", "chaplygin")
    >>> print(check.invariant, check.witness.value != 0)
    False True
    """
    d = _density(density)
    if d.on_axis_only and not _on_axis(member):
        raise ValueError(f"the {density} density is defined only where c lies on the third axis, not for {member}")
    symbolic_model(member)
    start = time.perf_counter()
    div = flow_divergence(member)
    m = div.model
    e0, factors = d.build(m)
    D = m.det_mass_matrix
    along = [dot(m.gamma_dot, _gradient(m, p)) for p, _ in factors]
    numerator = (dot(m.gamma_dot, _gradient(m, D)) * e0 + div.numerator) * _product([p for p, _ in factors], D.ring)
    for k, (_, e) in enumerate(factors):
        numerator += D * along[k] * e * _product([p for j, (p, _) in enumerate(factors) if j != k], D.ring)
    denominator = D * _product([p for p, _ in factors], D.ring)
    invariant = not m.on_sphere(numerator)
    witness = None if invariant else search_witness(numerator, denominator, witness_points(member))
    return DensityCheck(member, density, invariant, witness, numerator, denominator, time.perf_counter() - start)


def _product(polys: Sequence[PolyElement], ring) -> PolyElement:
    out = ring.one
    for p in polys:
        out *= p
    return out


@dataclass(frozen=True)
class MeasureResult:
    """The invariant-measure verdict of one member.

    Attributes
    ----------
    member : str
    verdict : str
        One sentence, built from the facts below.
    linear_in_omega : bool
        div f = n(γ)·ω / det K exactly.
    normal_vanishes : bool
        n·γ = 0 on the sphere (needed for any density of γ alone).
    closed : bool
        γ·curl(γ × n / det K) = 0 on the sphere (the closure condition).
    density_exists : bool
        All three hold: a density ρ(γ) exists, unique up to a constant factor.
    parallel_witness : Witness or None
        Where ``normal_vanishes`` fails: an exact state with ω = γ and ``value`` = div f ≠ 0 there.
    candidates : tuple of DensityCheck
        The candidates of ``DENSITIES`` defined for the member.
    seconds : float
        Time taken, the candidates included (not compared; the member's model not counted).

    Examples
    --------
    >>> from rocknroller.analysis.hierarchy.measure import measure
    >>> result = measure("Chaplygin's top")
    >>> print(result.density_exists, result.parallel_witness.omega == result.parallel_witness.gamma)
    False True
    """

    member: str
    verdict: str
    linear_in_omega: bool
    normal_vanishes: bool
    closed: bool
    density_exists: bool
    parallel_witness: Witness | None
    candidates: tuple[DensityCheck, ...]
    seconds: float = field(compare=False)


def _verdict(member: str, exists: bool, linear: bool, witness: Witness | None,
             candidates: tuple[DensityCheck, ...]) -> str:
    good = [_density(c.density).formula for c in candidates if c.invariant]
    bad = [c.density for c in candidates if not c.invariant]
    if exists:
        found = f"it is {' and '.join(good)}" if good else "it is none of the candidates"
        return (f"{member}: an invariant density ρ(γ) exists, unique up to a constant factor; {found}"
                + (f"; not invariant: {', '.join(bad)}" if bad else ""))
    if witness is not None:
        return (f"{member}: no invariant density depending on γ alone: div f = {witness.value} ≠ 0 at ω = γ = "
                f"({', '.join(map(str, witness.gamma))}), where f·∇ρ = 0 for every ρ(γ)")
    reason = "the 1-form −γ × n / det K is not closed" if linear else "div f is not linear in ω"
    return f"{member}: no invariant density depending on γ alone: {reason}"


def measure(member: str) -> MeasureResult:
    """Decide whether ``member`` has an invariant density depending on γ alone, and which candidate it is.

    Examples
    --------
    >>> from rocknroller.analysis.hierarchy.measure import measure
    >>> print(measure("Routh's sphere").verdict)  # doctest: +ELLIPSIS
    Routh's sphere: an invariant density ρ(γ) exists, ...; it is det K (I3 + s² + (I3/I1) f²)^(-1/2) in (γ, ω) = ...
    """
    symbolic_model(member)
    start = time.perf_counter()
    div = flow_divergence(member)
    m = div.model
    D = m.det_mass_matrix
    normal = not m.on_sphere(dot(div.n, m.gamma))
    # α = −v/D, v = γ × n: D² γ·curl(v/D) = D γ·curl v − γ·(∇D × v) (the sign of α does not matter)
    v = cross(m.gamma, div.n)
    closed = not m.on_sphere(D * dot(m.gamma, _curl(m, v)) - dot(m.gamma, cross(_gradient(m, D), v)))
    linear = div.linear_in_omega
    exists = linear and normal and closed
    witness = None if normal else search_witness(div.numerator, D, witness_points(member, omega_parallel=True))
    candidates = tuple(check_density(member, d.name) for d in DENSITIES if not d.on_axis_only or _on_axis(member))
    return MeasureResult(member, _verdict(member, exists, linear, witness, candidates), linear, normal, closed, exists,
                         witness, candidates, time.perf_counter() - start)


@cache
def measure_table() -> tuple[MeasureResult, ...]:
    """:func:`measure` of every member (computed once).

    Examples
    --------
    >>> from rocknroller.analysis.hierarchy.measure import measure_table
    >>> for r in measure_table():
    ...     print(f"{r.member:16}", r.density_exists, [c.density for c in r.candidates if c.invariant])
    Chaplygin's ball True ['chaplygin']
    rock'n'roller    False []
    Routh's sphere   True ['routh']
    Chaplygin's top  False []
    """
    return tuple(measure(member) for member in MEMBERS)
