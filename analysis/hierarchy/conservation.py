"""Which quantities are first integrals of which loaded sphere: sympy proofs over every free parameter of a member.

The loaded sphere (unit mass, unit radius, rolling without slipping on a plane; paper fig. 1) has the state γ (the
upward vertical in body components, γ·γ = 1) and ω (the body angular velocity); c is the offset of the mass centre
from the geometric centre, r = γ + c runs from the contact point to the mass centre, and

    K(γ) ω̇ = P(γ, ω),   K = diag(I) + (r·r) 1 − r rᵀ,   γ̇ = γ × ω,

with P as in :func:`~rocknroller.analysis.model.equations.body_frame_rhs` (seven parameters c1, c2, c3, I1, I2, I3, g).
The flow is the package's own: that function is evaluated over sympy's field of rational functions in γ, ω and the
member's free parameters, so the proofs are about the equations the integrators use.

The quantities (``QUANTITIES``, by name; M = K ω is the angular momentum about the contact point, T = ½ ω·K ω)::

    energy              E     T + g c·γ (the constant g|c| of the package's V = g(|c| + c·γ) does not matter)
    jellett             M·r   Jellett's; I1(γ1ω1 + γ2ω2) + I3(γ3 − a)ω3, the paper's Q_J, where I1 = I2, c = (0, 0, −a)
    routh               Q_R²  ω3²(I3 + s² + (I3/I1) f²), s² = γ1² + γ2², f = γ3 + c3: Routh's quantity squared,
                              defined where c lies on the third axis (not for Chaplygin's top)
    momentum_squared    M·M   Chaplygin's integral of the ball
    momentum_vertical   M·γ   Chaplygin's area integral of the ball
    borisov_mamaev_g0   B     M·M − 2T r·r at g = 0 (where T = E): Borisov and Mamaev's quantity
    borisov_mamaev      B     the same M·M − 2T r·r with gravity

Method.  Along the flow dQ/dt = ∇_γQ·(γ × ω) + ∇_ωQ·K⁻¹P; times det K (times I1 for Q_R², to clear its I3/I1) it is a
polynomial N in γ, ω and the parameters, exactly (sympy's sparse polynomials over ℚ).  Its remainder modulo
γ·γ − 1, with γ3² → 1 − γ1² − γ2², has the form A + γ3 B with A, B free of γ3, and vanishes on the unit sphere (for
all ω and all parameters) if and only if A = B = 0.  As det K > 0, Q is a first integral of the member exactly when
the remainder is the zero polynomial.  Otherwise the proof carries an exact rational witness: a rational point of the
unit sphere (γ from a Pythagorean quadruple), a rational ω and rational physical parameters of the member, g ≠ 0
unless the quantity is stated without gravity, where dQ/dt ≠ 0, with its exact value.

The verdicts (:func:`proof_table`, every free parameter symbolic; about 3 s for the 27 proofs, the symbolic models
included, the slowest M·M of the top, ~0.6 s; +: conserved, −: not, blank: undefined):

    member                        free parameters     E    M·r  Q_R²  M·M  M·γ  B at g = 0  B
    Chaplygin's ball              I1, I2, I3          +    +    −     +    +    +           +
    rock'n'roller                 c3, I1, I2, I3, g   +    −    −     −    −    +           −
    Routh's sphere                c3, I1 = I2, I3, g  +    +    +     −    −    +           −
    Chaplygin's top               c, I1, I2, I3, g    +    −          −    −    +           −

For the ball gravity has no torque (c = 0) and r = γ, so B = M·M − 2T is conserved with gravity too; with E, M·M, M·γ
and Chaplygin's invariant measure (:mod:`rocknroller.analysis.hierarchy.measure`) the ball is integrable.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from functools import cache
from itertools import product
from typing import Any

from sympy import QQ
from sympy.polys.fields import FracField
from sympy.polys.rings import PolyElement

from rocknroller.analysis.model.body import MEMBERS
from rocknroller.analysis.model.equations import body_frame_rhs, dot

__all__ = ["PARAMETERS", "QUANTITIES", "Quantity", "SymbolicModel", "symbolic_model", "FlowDerivative",
           "derivative_along_flow", "exact_value", "Witness", "witness_points", "search_witness", "Proof", "prove",
           "proof_table"]

#: The parameters of the general equations, in the order of ``body_frame_rhs``'s seven-parameter form.
PARAMETERS = ("c1", "c2", "c3", "I1", "I2", "I3", "g")

#: Rational functions in the state and the parameters (γ3 first: :meth:`SymbolicModel.on_sphere` reduces its powers).
_FIELD = FracField(("gamma3", "gamma1", "gamma2", "omega1", "omega2", "omega3", *PARAMETERS), QQ)
_RING = _FIELD.ring

#: How each member writes (c1, c2, c3, I1, I2, I3) in its free parameters (None: zero).
_MEMBER_PARAMETERS = {
    MEMBERS[0]: (None, None, None, "I1", "I2", "I3"),
    MEMBERS[1]: (None, None, "c3", "I1", "I2", "I3"),
    MEMBERS[2]: (None, None, "c3", "I1", "I1", "I3"),
    MEMBERS[3]: ("c1", "c2", "c3", "I1", "I2", "I3"),
}

#: Rational physical parameters of each member for witnesses: the paper's moments and a = 1/20, gravity 987/100.
_WITNESS_PARAMETERS = {member: tuple(Fraction(x) for x in values) for member, values in {
    MEMBERS[0]: ("0", "0", "0", "7/20", "9/25", "2/5"),
    MEMBERS[1]: ("0", "0", "-1/20", "7/20", "9/25", "2/5"),
    MEMBERS[2]: ("0", "0", "-1/20", "7/20", "7/20", "2/5"),
    MEMBERS[3]: ("3/100", "-1/50", "-1/20", "7/20", "9/25", "2/5"),
}.items()}
_WITNESS_GRAVITY = Fraction(987, 100)
#: Rational points of the unit sphere (Pythagorean quadruples) and rational angular velocities tried for a witness.
_WITNESS_GAMMAS = tuple(tuple(Fraction(x) for x in v) for v in (("2/7", "3/7", "-6/7"), ("1/3", "-2/3", "2/3"),
                                                                ("2/3", "2/3", "1/3")))
_WITNESS_OMEGAS = tuple(tuple(Fraction(x) for x in v) for v in (("1", "2", "-1"), ("1/2", "-1", "3/2"),
                                                                ("-2", "1", "1")))

Vector = tuple[PolyElement, PolyElement, PolyElement]
#: A coordinate or parameter value: floats are taken as the rationals they are.
Number = float | Fraction


def _require_member(member: str) -> None:
    if member not in _MEMBER_PARAMETERS:
        raise ValueError(f"member must be one of {MEMBERS}, got {member!r}")


@dataclass(frozen=True)
class SymbolicModel:
    """The equations of one member as exact polynomials in (γ, ω) and its free parameters.

    ``gamma``, ``omega``, ``offset`` (c), ``inertia`` (I1, I2, I3), ``gravity`` (g or 0) and ``r`` = γ + c carry the
    member's constraints (zeros, I2 = I1); ``mass_matrix`` is K(γ) = diag(I) + (r·r) 1 − r rᵀ and ``det_mass_matrix``
    its determinant, positive for every physical body; ``gamma_dot`` = γ × ω and ``omega_dot_times_det`` =
    det K · ω̇ = adj(K) P come from ``body_frame_rhs``.

    Examples
    --------
    >>> from rocknroller.analysis.hierarchy.conservation import symbolic_model
    >>> model = symbolic_model("Routh's sphere")
    >>> print(model.inertia, model.offset)
    (I1, I1, I3) (0, 0, c3)
    """

    member: str
    without_gravity: bool
    gamma: Vector
    omega: Vector
    offset: Vector
    inertia: Vector
    gravity: PolyElement
    r: Vector
    mass_matrix: tuple[Vector, Vector, Vector]
    det_mass_matrix: PolyElement
    gamma_dot: Vector
    omega_dot_times_det: Vector

    @property
    def momentum(self) -> Vector:
        """M = K ω, the angular momentum about the contact point."""
        K, w = self.mass_matrix, self.omega
        return (dot(K[0], w), dot(K[1], w), dot(K[2], w))

    def on_sphere(self, poly: PolyElement) -> PolyElement:
        """The remainder of ``poly`` modulo γ·γ − 1, γ3^k → γ3^(k mod 2) (1 − γ1² − γ2²)^(k div 2): degree < 2 in
        γ3, zero exactly when ``poly`` vanishes on the unit sphere for all other variables.  (The same as sympy's
        ``poly.rem(γ·γ − 1)``, whose general division is ~25 times slower here.)"""
        by_power: dict[int, dict] = {}
        for monomial, coeff in poly.terms():
            by_power.setdefault(monomial[0], {})[(0, *monomial[1:])] = coeff
        g3, g1, g2 = self.gamma[2], self.gamma[0], self.gamma[1]
        rest = 1 - g1 * g1 - g2 * g2
        return sum((_RING.from_dict(terms) * rest ** (k // 2) * g3 ** (k % 2) for k, terms in by_power.items()),
                   _RING.zero)


@cache
def symbolic_model(member: str, without_gravity: bool = False) -> SymbolicModel:
    """The member's equations, built by :func:`~rocknroller.analysis.model.equations.body_frame_rhs` over ℚ(γ, ω, p).

    Parameters
    ----------
    member : str
        One of :data:`~rocknroller.analysis.model.body.MEMBERS`.
    without_gravity : bool
        Substitute g = 0.

    Examples
    --------
    >>> from rocknroller.analysis.hierarchy.conservation import symbolic_model
    >>> model = symbolic_model("Chaplygin's ball")
    >>> print(model.gamma_dot[2])
    gamma1*omega2 - gamma2*omega1
    >>> print(len(model.det_mass_matrix.terms()))
    16
    """
    _require_member(member)
    named = dict(zip(PARAMETERS, _RING.gens[6:]))
    c1, c2, c3, I1, I2, I3 = (_RING.zero if name is None else named[name] for name in _MEMBER_PARAMETERS[member])
    gravity = _RING.zero if without_gravity else named["g"]
    (g3, g1, g2, w1, w2, w3), offset, inertia = _RING.gens[:6], (c1, c2, c3), (I1, I2, I3)
    gamma, omega = (g1, g2, g3), (w1, w2, w3)
    zero = _FIELD.zero
    rhs = body_frame_rhs([_FIELD(x) for x in (*gamma, *omega)] + [zero] * 5,
                         [_FIELD(x) for x in (*offset, *inertia, gravity)])
    r = tuple(g + c for g, c in zip(gamma, offset))
    rr = dot(r, r)
    K = ((I1 + rr - r[0] * r[0], -r[0] * r[1], -r[0] * r[2]), (-r[1] * r[0], I2 + rr - r[1] * r[1], -r[1] * r[2]),
         (-r[2] * r[0], -r[2] * r[1], I3 + rr - r[2] * r[2]))
    det = (K[0][0] * (K[1][1] * K[2][2] - K[1][2] * K[2][1]) - K[0][1] * (K[1][0] * K[2][2] - K[1][2] * K[2][0])
           + K[0][2] * (K[1][0] * K[2][1] - K[1][1] * K[2][0]))
    return SymbolicModel(member, without_gravity, gamma, omega, offset, inertia, gravity, r, K, det,
                         tuple(x.numer.exquo(x.denom) for x in rhs[:3]),
                         tuple((det * x.numer).exquo(x.denom) for x in rhs[3:6]))


@dataclass(frozen=True)
class Quantity:
    """A candidate first integral: ``build(model)`` gives (λ Q, λ) as polynomials, λ a positive constant factor that
    clears Q's denominators (I1 for Q_R², else 1).

    Examples
    --------
    >>> from rocknroller.analysis.hierarchy.conservation import QUANTITIES
    >>> print(", ".join(q.symbol for q in QUANTITIES))
    E, M·r, Q_R², M·M, M·γ, B, B
    """

    name: str
    symbol: str
    definition: str
    build: Callable[[SymbolicModel], tuple[PolyElement, PolyElement]] = field(repr=False)
    on_axis_only: bool = False
    without_gravity: bool = False

    def defined_for(self, member: str) -> bool:
        """False for a quantity that needs c on the third axis and a member whose c may lie off it."""
        _require_member(member)
        return not (self.on_axis_only and _MEMBER_PARAMETERS[member][0] is not None)


def _kinetic_twice(m: SymbolicModel) -> PolyElement:
    return dot(m.omega, m.momentum)


def _routh_squared(m: SymbolicModel) -> tuple[PolyElement, PolyElement]:
    (g1, g2, _), (I1, _, I3) = m.gamma, m.inertia
    f = m.r[2]
    return m.omega[2] ** 2 * (I1 * I3 + I1 * (g1 * g1 + g2 * g2) + I3 * f * f), I1


def _borisov_mamaev(m: SymbolicModel) -> tuple[PolyElement, PolyElement]:
    return dot(m.momentum, m.momentum) - _kinetic_twice(m) * dot(m.r, m.r), _RING.one


QUANTITIES = (
    Quantity("energy", "E", "T + g c·γ, T = ½ ω·K ω",
             lambda m: (_kinetic_twice(m) * QQ(1, 2) + m.gravity * dot(m.offset, m.gamma), _RING.one)),
    Quantity("jellett", "M·r", "Jellett's M·r (the paper's Q_J where I1 = I2, c = (0, 0, −a))",
             lambda m: (dot(m.momentum, m.r), _RING.one)),
    Quantity("routh", "Q_R²", "ω3²(I3 + s² + (I3/I1) f²), s² = γ1² + γ2², f = γ3 + c3", _routh_squared,
             on_axis_only=True),
    Quantity("momentum_squared", "M·M", "M·M, M = K ω about the contact point",
             lambda m: (dot(m.momentum, m.momentum), _RING.one)),
    Quantity("momentum_vertical", "M·γ", "M·γ", lambda m: (dot(m.momentum, m.gamma), _RING.one)),
    Quantity("borisov_mamaev_g0", "B", "M·M − 2T r·r at g = 0", _borisov_mamaev, without_gravity=True),
    Quantity("borisov_mamaev", "B", "M·M − 2T r·r with gravity", _borisov_mamaev),
)
_QUANTITY = {q.name: q for q in QUANTITIES}


def _quantity(name: str) -> Quantity:
    if name not in _QUANTITY:
        raise ValueError(f"quantity must be one of {tuple(_QUANTITY)}, got {name!r}")
    return _QUANTITY[name]


def _exact(gamma: Sequence[Number], omega: Sequence[Number], params: Sequence[Number]) -> list:
    """The ring's 13 values (γ3, γ1, γ2, ω, params), as the exact rationals they are."""
    return [QQ(Fraction(v).numerator, Fraction(v).denominator) for v in (gamma[2], gamma[0], gamma[1], *omega, *params)]


def _as_fraction(value: Any) -> Fraction:
    return Fraction(int(value.numerator), int(value.denominator))


def _point(member: str, without_gravity: bool, gamma: Sequence[Number], omega: Sequence[Number],
           params: Sequence[Number]) -> list:
    """The ring's 13 values (γ3, γ1, γ2, ω, params) as exact rationals, after checking the member's constraints."""
    if len(gamma) != 3 or len(omega) != 3 or len(params) != len(PARAMETERS):
        raise ValueError(f"need gamma and omega of 3 components and params {PARAMETERS}, got {gamma!r}, {omega!r}, "
                         f"{params!r}")
    spec = _MEMBER_PARAMETERS[member]
    named = dict(zip(PARAMETERS, params))
    for name, expr in zip(PARAMETERS[:6], spec):
        if named[name] != (0 if expr is None else named[expr]):
            raise ValueError(f"{member} needs {name} = {expr or 0}, got params {tuple(params)!r}")
    if without_gravity and named["g"] != 0:
        raise ValueError(f"this quantity is stated at g = 0, got g = {named['g']!r}")
    return _exact(gamma, omega, params)


def exact_value(member: str, numerator: PolyElement, denominator: PolyElement, gamma: Sequence[Number],
                omega: Sequence[Number], params: Sequence[Number], *, without_gravity: bool = False) -> Fraction:
    """``numerator / denominator`` at a point of ``member``, exactly (floats are taken as the rationals they are).

    ``params`` are (c1, c2, c3, I1, I2, I3, g) as ``body_frame_rhs`` takes them and must satisfy the member's
    constraints (zeros of c, I2 = I1 for Routh's sphere; g = 0 ``without_gravity``), else a ValueError.

    Examples
    --------
    >>> from rocknroller.analysis.hierarchy.conservation import exact_value, symbolic_model
    >>> m = symbolic_model("Routh's sphere")
    >>> one = m.det_mass_matrix.ring.one
    >>> print(exact_value("Routh's sphere", m.det_mass_matrix, one, (0, 0, 1), (0, 0, 0),
    ...                   (0, 0, -0.5, 0.25, 0.25, 0.5, 1)))
    1/8
    """
    point = _point(member, without_gravity, gamma, omega, params)
    return _as_fraction(numerator(*point) / denominator(*point))


@dataclass(frozen=True)
class Witness:
    """An exact rational state and parameters (γ·γ = 1, the member's constraints) where a quantity is not zero.

    Examples
    --------
    >>> from rocknroller.analysis.hierarchy.conservation import prove
    >>> w = prove("Chaplygin's top", "jellett").witness
    >>> print(sum(x * x for x in w.gamma) == 1, w.params[-1], w.value != 0)
    True 987/100 True
    """

    gamma: tuple[Fraction, Fraction, Fraction]
    omega: tuple[Fraction, Fraction, Fraction]
    params: tuple[Fraction, ...]
    value: Fraction


def witness_points(member: str, without_gravity: bool = False, omega_parallel: bool = False
                   ) -> Iterator[tuple[tuple[Fraction, ...], tuple[Fraction, ...], tuple[Fraction, ...]]]:
    """Candidate witness points (γ, ω, params): rational γ on the unit sphere, the member's physical parameters,
    g = 987/100 (or 0), and ω from a short list (or ω = γ with ``omega_parallel``).

    Examples
    --------
    >>> from rocknroller.analysis.hierarchy.conservation import witness_points
    >>> gamma, omega, params = next(witness_points("Routh's sphere"))
    >>> print(*gamma, "|", *params)
    2/7 3/7 -6/7 | 0 0 -1/20 7/20 7/20 2/5 987/100
    """
    params = (*_WITNESS_PARAMETERS[member], Fraction(0) if without_gravity else _WITNESS_GRAVITY)
    for gamma, omega in product(_WITNESS_GAMMAS, (None,) if omega_parallel else _WITNESS_OMEGAS):
        yield gamma, gamma if omega is None else omega, params


def search_witness(numerator: PolyElement, denominator: PolyElement, points: Iterator) -> Witness:
    """The first point where ``numerator`` is not zero, with the exact value ``numerator / denominator`` there.

    Examples
    --------
    >>> from rocknroller.analysis.hierarchy.conservation import derivative_along_flow, search_witness, witness_points
    >>> d = derivative_along_flow("Chaplygin's ball", "routh")
    >>> w = search_witness(d.numerator, d.denominator, witness_points("Chaplygin's ball"))
    >>> print(*w.gamma, "|", *w.omega, "|", w.value)
    2/7 3/7 -6/7 | 1 2 -1 | 10403416/107884525
    """
    for gamma, omega, params in points:
        point = _exact(gamma, omega, params)
        value = numerator(*point)
        if value:
            return Witness(tuple(gamma), tuple(omega), tuple(params), _as_fraction(value / denominator(*point)))
    raise ValueError("the polynomial vanishes at every candidate point: add points")


@dataclass(frozen=True)
class FlowDerivative:
    """d Q/dt along a member's flow, as ``numerator / denominator`` with denominator = λ det K.

    Attributes
    ----------
    member, quantity : str
    value : polynomial
        λ Q (see :class:`Quantity`).
    denominator : polynomial
        λ det K.
    numerator : polynomial
        det K · d(λ Q)/dt, exact in all of R⁶ (off the unit sphere too).
    reduced : polynomial
        ``numerator`` modulo γ·γ − 1: zero exactly when Q is a first integral.

    Examples
    --------
    >>> from rocknroller.analysis.hierarchy.conservation import derivative_along_flow
    >>> d = derivative_along_flow("rock'n'roller", "jellett")
    >>> print(d.at((0.6, 0.0, -0.8), (1.0, 2.0, 0.0), (0, 0, -0.05, 0.35, 0.36, 0.4, 9.87)) != 0)
    True
    """

    member: str
    quantity: str
    value: PolyElement
    denominator: PolyElement
    numerator: PolyElement
    reduced: PolyElement

    def at(self, gamma: Sequence[Number], omega: Sequence[Number], params: Sequence[Number]) -> Fraction:
        """The exact d Q/dt at a point (floats are taken as the rationals they are); params as
        ``body_frame_rhs`` takes them, (c1, c2, c3, I1, I2, I3, g), satisfying the member's constraints."""
        return exact_value(self.member, self.numerator, self.denominator, gamma, omega, params,
                           without_gravity=_quantity(self.quantity).without_gravity)


def derivative_along_flow(member: str, quantity: str) -> FlowDerivative:
    """d Q/dt = ∇_γQ·(γ × ω) + ∇_ωQ·K⁻¹P for a member (one of ``MEMBERS``) and a quantity (a name in
    ``QUANTITIES``), over the member's free parameters.

    Examples
    --------
    >>> from rocknroller.analysis.hierarchy.conservation import derivative_along_flow
    >>> print(derivative_along_flow("Routh's sphere", "routh").reduced)
    0
    """
    q = _quantity(quantity)
    if not q.defined_for(member):
        raise ValueError(f"{q.symbol} ({q.name}) is defined only where c lies on the third axis, not for {member}")
    m = symbolic_model(member, q.without_gravity)
    value, scale = q.build(m)
    numerator = (m.det_mass_matrix * sum((value.diff(x) * dx for x, dx in zip(m.gamma, m.gamma_dot)), _RING.zero)
                 + sum((value.diff(w) * dw for w, dw in zip(m.omega, m.omega_dot_times_det)), _RING.zero))
    return FlowDerivative(member, quantity, value, scale * m.det_mass_matrix, numerator, m.on_sphere(numerator))


@dataclass(frozen=True)
class Proof:
    """Whether a quantity is a first integral of a member, decided by sympy for all its free parameters.

    Attributes
    ----------
    member, quantity : str
    conserved : bool
        d Q/dt vanishes identically on γ·γ = 1.
    witness : Witness or None
        For a quantity that is not conserved, an exact rational point with ``value`` = d Q/dt ≠ 0 there.
    remainder_terms : int
        Terms of the remainder of det K · λ dQ/dt modulo γ·γ − 1 (0 when conserved).
    seconds : float
        Time taken by the derivative, its reduction and the witness search (not compared; the member's model,
        built once by :func:`symbolic_model`, not counted).

    Examples
    --------
    >>> from rocknroller.analysis.hierarchy.conservation import prove
    >>> print(prove("rock'n'roller", "energy").verdict)
    rock'n'roller: E conserved
    """

    member: str
    quantity: str
    conserved: bool
    witness: Witness | None
    remainder_terms: int
    seconds: float = field(compare=False)

    @property
    def verdict(self) -> str:
        """One line: the member, the quantity, and the verdict with its witness."""
        symbol = _quantity(self.quantity).symbol + (" at g = 0" if _quantity(self.quantity).without_gravity else "")
        w = self.witness
        if w is None:
            return f"{self.member}: {symbol} conserved"
        return (f"{self.member}: {symbol} not conserved, dQ/dt = {w.value} at gamma = ({', '.join(map(str, w.gamma))})"
                f", omega = ({', '.join(map(str, w.omega))}), (c, I, g) = ({', '.join(map(str, w.params))})")


def prove(member: str, quantity: str) -> Proof:
    """Decide whether ``quantity`` is a first integral of ``member``, symbolically in its free parameters.

    Examples
    --------
    >>> from rocknroller.analysis.hierarchy.conservation import prove
    >>> proof = prove("Chaplygin's top", "borisov_mamaev")
    >>> print(proof.conserved, proof.witness.params[-1], proof.witness.value != 0)
    False 987/100 True
    """
    symbolic_model(member, _quantity(quantity).without_gravity)
    start = time.perf_counter()
    d = derivative_along_flow(member, quantity)
    conserved = not d.reduced
    witness = None if conserved else search_witness(d.numerator, d.denominator,
                                                    witness_points(member, _quantity(quantity).without_gravity))
    return Proof(member, quantity, conserved, witness, len(d.reduced), time.perf_counter() - start)


@cache
def proof_table() -> tuple[Proof, ...]:
    """Every member × every quantity defined for it (computed once).

    Examples
    --------
    >>> from rocknroller.analysis.hierarchy.conservation import QUANTITIES, proof_table
    >>> table = {(p.member, p.quantity): p.conserved for p in proof_table()}
    >>> for member in ("Chaplygin's ball", "rock'n'roller", "Routh's sphere", "Chaplygin's top"):
    ...     print(f"{member:16}", *("-" if (member, q.name) not in table else "yes" if table[member, q.name] else "no"
    ...                             for q in QUANTITIES))
    Chaplygin's ball yes yes no yes yes yes yes
    rock'n'roller    yes no no no no yes no
    Routh's sphere   yes yes yes no no yes no
    Chaplygin's top  yes no - no no yes no
    """
    return tuple(prove(member, q.name) for member in MEMBERS for q in QUANTITIES if q.defined_for(member))
