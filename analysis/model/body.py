"""Body parameters of the rock'n'roller (paper §2, §4 and App. A.1).

Unit mass and unit radius throughout.  The mass centre O lies a distance ``a``
below the geometric centre C along the body axis k (so that k points from O to
C); the principal moments about O are ``I1 <= I2 < I3`` and ``g`` is gravity.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass, replace

__all__ = [
    "Body", "LoadedSphere", "MEMBERS", "paper_I1", "as_float", "float_or_nan", "require_finite", "polar_cap_offset_as_printed", "PAPER_A", "PAPER_I3", "PAPER_G",
    "polar_cap_volume"
]

#: Paper defaults (paper §7: a = 0.05, I3 = 2/5, I1 = (1 - 5a/2) I3, g = 9.87).
PAPER_A = 0.05
PAPER_I3 = 0.4
PAPER_G = 9.87


#: Relative accuracy to which Body.from_polar_cap must represent its asymmetry I3 − I1.
POLAR_CAP_GAP_RTOL = 1e-6


def paper_I1(a: float, I3: float) -> float:
    """The paper's choice I1 = (1 − 5a/2) I3 (§numerics), used by Body.paper and as the CLI default."""
    return (1.0 - 2.5 * a) * I3


def as_float(name: str, value: float) -> float:
    """``float(value)`` (NaN and ±inf included, for the caller's range check), or a ValueError naming ``name`` if
    it is not a real number or is an int beyond the floats (``10**400``, whose ``float`` raises OverflowError)."""
    try:
        return float(value)
    except (TypeError, ValueError, OverflowError):
        raise ValueError(f"{name} must be a finite real number, got {value!r}") from None


def float_or_nan(value: float) -> float:
    """``float(value)``, or NaN where it is not a real number or is an int beyond the floats (``10**400``): for a
    range check that states its own range (``not lo <= v <= hi`` is then true)."""
    try:
        return float(value)
    except (TypeError, ValueError, OverflowError):
        return math.nan


def require_finite(name: str, value: float) -> float:
    """``float(value)``, or a ValueError naming ``name`` if it is not a finite real number."""
    v = as_float(name, value)
    if not math.isfinite(v):
        raise ValueError(f"{name} must be a finite real number, got {value!r}")
    return v


def polar_cap_volume(d: float) -> float:
    """Volume of the unit ball with the polar cap above height ``d`` removed.

    Paper App. A.1: V = π (2/3 + d − d³/3).
    """
    return math.pi * (2.0 / 3.0 + d - d**3 / 3.0)


def polar_cap_offset_as_printed(d: float) -> float:
    """The paper's App. A.1 formula a = (π/4)(d²(2 − d²) − 1)/V, kept to show its sign error.

    It equals −a for every d: d²(2 − d²) − 1 = −(1 − d²)².  See :meth:`Body.from_polar_cap`.
    """
    return (math.pi / 4.0) * (d * d * (2.0 - d * d) - 1.0) / polar_cap_volume(d)


@dataclass(frozen=True)
class Body:
    """Parameters of a loaded sphere of unit mass and unit radius.

    Parameters
    ----------
    a : float
        Distance from the geometric centre to the mass centre, ``0 <= a < 1``.
    I1, I2, I3 : float
        Principal moments of inertia about the mass centre, ``0 < I1 <= I2 < I3``
        and ``I1 + I2 >= I3`` (triangle inequality of a real mass distribution).
    g : float
        Acceleration of gravity, ``g >= 0`` (``g = 0``: the body rolls in a weightless state, where the energy is the
        kinetic energy alone; the direct ODE accepts it, the averaged slow motion and the rocking need ``g > 0``).

    Raises
    ------
    ValueError
        If any parameter is non-finite or outside its allowed range; the message
        names the parameter and the range.

    Examples
    --------
    >>> import rocknroller as rr
    >>> body = rr.Body.paper(epsilon=1e-3)
    >>> print(f"a = {body.a}, I1 = {body.I1:.4f}, I2 = {body.I2:.5f}, I3 = {body.I3}, g = {body.g}")
    a = 0.05, I1 = 0.3500, I2 = 0.35035, I3 = 0.4, g = 9.87
    >>> print(body.epsilon_text(), body.is_symmetric)
    0.001 False
    >>> try:
    ...     rr.Body(a=0.05, I1=0.35, I2=0.35, I3=0.4, g=-1.0)
    ... except ValueError as err:
    ...     print(err)
    ...
    g must be >= 0, got g=-1.0
    """

    a: float
    I1: float
    I2: float
    I3: float
    g: float

    def __post_init__(self) -> None:
        for name in ("a", "I1", "I2", "I3", "g"):
            object.__setattr__(self, name, require_finite(name, getattr(self, name)))
        if not 0.0 <= self.a < 1.0:
            raise ValueError(f"a must satisfy 0 <= a < 1 (mass centre inside the sphere), got a={self.a!r}")
        for name in ("I1", "I2", "I3"):
            if getattr(self, name) <= 0.0:
                raise ValueError(f"{name} must be > 0, got {name}={getattr(self, name)!r}")
        if self.I1 > self.I2:
            raise ValueError(f"moments must be ordered I1 <= I2, got I1={self.I1!r} > I2={self.I2!r}")
        if self.I2 >= self.I3:
            raise ValueError(f"moments must be ordered I2 < I3, got I2={self.I2!r} >= I3={self.I3!r}")
        if self.I1 + self.I2 < self.I3:
            raise ValueError(
                "moments must satisfy the triangle inequality I1 + I2 >= I3, "
                f"got I1 + I2 = {self.I1 + self.I2!r} < I3 = {self.I3!r}"
            )
        if self.g < 0.0:
            raise ValueError(f"g must be >= 0, got g={self.g!r}")

    # ------------------------------------------------------------------ constructors
    @classmethod
    def paper(cls, epsilon: float = 0.0) -> "Body":
        """The paper's body: a = 0.05, I3 = 0.4, I1 = (1 − 5a/2) I3 = 0.35, I2 = (1 + ε) I1, g = 9.87.

        Parameters
        ----------
        epsilon : float
            Asymmetry ε = (I2 − I1)/I1, ``0 <= ε < I3/I1 − 1`` (= 1/7 for the paper body).
        """
        return cls._from_epsilon(PAPER_A, paper_I1(PAPER_A, PAPER_I3), PAPER_I3, PAPER_G, epsilon)

    @classmethod
    def from_polar_cap(cls, d: float, g: float = PAPER_G, epsilon: float = 0.0) -> "Body":
        """Homogeneous unit ball with the polar cap above height ``d`` = cos Θ removed (paper App. A.1).

        With V = π(2/3 + d − d³/3) the volume,

        * a = (π/4)(1 − d²)²/V  (the paper prints the opposite sign: d²(2 − d²) − 1 = −(1 − d²)²),
        * I3 = (π/2)(8/15 + d − 2d³/3 + d⁵/5)/V,
        * I1 = π(4/15 + d/4 + d³/6 − 3d⁵/20)/V − a²  (parallel-axis theorem, unit mass),

        computed as I1 = I3 − a(d + a): the difference of the two bracketed polynomials is
        (π/4) d (1 − d²)² = a V d, so I3 − I1 = a d + a², free of cancellation.

        Parameters
        ----------
        d : float
            Height of the planar face above the geometric centre.  The asymmetry I3 − I1 = a(d + a)
            ≈ (3/4)(1 − d)² vanishes at d = 1 (the homogeneous ball); d must satisfy −1 < d < 1 with
            I3 − I1 resolved in double precision to ``POLAR_CAP_GAP_RTOL`` = 1e-6 relative: I3 − I1 = I3 − (I3 − gap)
            is exact to ½ ulp(I3), so 1 − d ≳ √(½ ulp(I3) / (¾ · 1e-6)) ≈ 6e-6.
        g : float
            Gravity.
        epsilon : float
            Optional asymmetry ε, I2 = (1 + ε) I1.
        """
        d = require_finite("d", d)
        if not -1.0 < d < 1.0:
            raise ValueError(f"polar-cap height d = cos(Theta) must satisfy -1 < d < 1 (d = 1 is the homogeneous "
                             f"ball, I1 = I3), got d={d!r}")
        V = polar_cap_volume(d)
        a = (math.pi / 4.0) * (1.0 - d * d) ** 2 / V
        I3 = (math.pi / 2.0) * (8.0 / 15.0 + d - 2.0 * d**3 / 3.0 + d**5 / 5.0) / V
        gap = a * (d + a)
        I1 = I3 - gap
        if gap > 0.0 and not abs((I3 - I1) - gap) <= POLAR_CAP_GAP_RTOL * gap:
            limit = math.sqrt(0.5 * math.ulp(I3) / (0.75 * POLAR_CAP_GAP_RTOL))
            raise ValueError(
                f"polar-cap height d={d!r} is too close to 1: I3 - I1 = a(d + a) = {gap:.3g} cannot be represented "
                f"to {POLAR_CAP_GAP_RTOL:g} relative beside I3 in double precision; use -1 < d <= 1 - {limit:.1g}")
        return cls._from_epsilon(a, I1, I3, g, epsilon)

    @classmethod
    def _from_epsilon(cls, a: float, I1: float, I3: float, g: float, epsilon: float) -> "Body":
        epsilon = require_finite("epsilon", epsilon)
        if epsilon < 0.0:
            raise ValueError(f"epsilon = (I2 - I1)/I1 must be >= 0, got epsilon={epsilon!r}")
        if (1.0 + epsilon) * I1 >= I3:
            raise ValueError(
                f"epsilon must satisfy 0 <= epsilon < I3/I1 - 1 = {I3 / I1 - 1.0:.6g} "
                f"(so that I2 < I3), got epsilon={epsilon!r}"
            )
        I2 = (1.0 + epsilon) * I1
        if epsilon > 0.0 and I2 == I1:  # not silently the symmetric body
            raise ValueError(f"epsilon must be 0 or resolved by I2 = (1 + epsilon) I1 in double precision (above "
                             f"about {0.5 * sys.float_info.epsilon:.2g}), got epsilon={epsilon!r}, which makes I2 = I1")
        return cls(a=a, I1=I1, I2=I2, I3=I3, g=g)

    # ------------------------------------------------------------------ derived
    @property
    def epsilon(self) -> float:
        """Asymmetry parameter ε = (I2 − I1)/I1 (paper §6)."""
        return (self.I2 - self.I1) / self.I1

    @property
    def is_symmetric(self) -> bool:
        """True for Routh's sphere, I1 == I2 exactly."""
        return self.I1 == self.I2

    def with_epsilon(self, epsilon: float) -> "Body":
        """Same a, I1, I3, g with I2 = (1 + ε) I1."""
        return self._from_epsilon(self.a, self.I1, self.I3, self.g, epsilon)

    def symmetric(self) -> "Body":
        """Routh's sphere with the same a, I1, I3, g (I2 = I1)."""
        return replace(self, I2=self.I1)

    def require_symmetric(self, what: str) -> None:
        """Raise ``ValueError`` unless I1 == I2 (for results that hold only for Routh's sphere)."""
        if not self.is_symmetric:
            raise ValueError(
                f"{what} holds only for a symmetric body (I1 == I2, epsilon = 0); "
                f"got I1={self.I1!r}, I2={self.I2!r} (epsilon={self.epsilon:.3g}). Use body.symmetric()."
            )

    def require_gravity(self, what: str) -> None:
        """Raise ``ValueError`` unless g > 0 (for results that need gravity: the rocking, the averaged slow motion)."""
        if not self.g > 0.0:
            raise ValueError(f"gravity is needed for {what}: g must be > 0, got g={self.g!r} (without gravity the body "
                             f"does not rock about an equilibrium; the direct ODE, simulate, takes g = 0)")

    @property
    def params(self) -> tuple[float, float, float, float, float]:
        """(a, I1, I2, I3, g), the order used for runtime parameters of the integrators."""
        return (self.a, self.I1, self.I2, self.I3, self.g)

    @property
    def offset(self) -> tuple[float, float, float]:
        """The mass centre relative to the geometric centre in the principal frame, c = (0, 0, −a) (paper fig. 1)."""
        return (0.0, 0.0, -self.a)

    @property
    def offset_norm(self) -> float:
        """|c| = a, the distance from the geometric centre to the mass centre (the potential's half-range is g|c|)."""
        return self.a

    @property
    def kind(self) -> str:
        """The member of the loaded-sphere family (paper fig. 1): Chaplygin's ball (a = 0), Routh's sphere (I1 = I2)
        or the rock'n'roller."""
        return MEMBERS[0] if self.a == 0.0 else MEMBERS[2] if self.I1 == self.I2 else MEMBERS[1]

    def as_loaded_sphere(self) -> "LoadedSphere":
        """The same body as a :class:`LoadedSphere` with offset c = (0, 0, −a), for the family's general equations.

        The general equations give the same motion to round-off, not bit for bit: :func:`~rocknroller.numerics.
        integrate.simulate` keeps the on-axis form's own arithmetic for a :class:`Body`.
        """
        return LoadedSphere(self.I1, self.I2, self.I3, self.offset, self.g)

    @classmethod
    def chaplygin_top(cls, I1: float, I2: float, I3: float, offset: tuple[float, float, float],
                      g: float = PAPER_G) -> "LoadedSphere":
        """Chaplygin's top (paper fig. 1): the mass centre at ``offset`` = c from the geometric centre, anywhere
        inside the sphere, and three principal moments in any order (see :class:`LoadedSphere`).

        Examples
        --------
        >>> import rocknroller as rr
        >>> top = rr.Body.chaplygin_top(0.35, 0.37, 0.4, offset=(0.03, -0.02, -0.05))
        >>> print(top.kind, top.params)
        Chaplygin's top (0.03, -0.02, -0.05, 0.35, 0.37, 0.4, 9.87)
        """
        return LoadedSphere(I1, I2, I3, offset, g)

    @classmethod
    def chaplygin_ball(cls, I1: float, I2: float, I3: float, g: float = PAPER_G) -> "LoadedSphere":
        """Chaplygin's ball (paper fig. 1): the mass centre at the geometric centre, three moments in any order.

        Examples
        --------
        >>> import rocknroller as rr
        >>> print(rr.Body.chaplygin_ball(0.4, 0.3, 0.35).kind)
        Chaplygin's ball
        """
        return LoadedSphere(I1, I2, I3, (0.0, 0.0, 0.0), g)

    def describe(self) -> str:
        """One-line description for CSV headers and reports, exact and without round-off noise: a moment that is
        exactly the formula it was made by is shown as the formula (``I1=(1-5a/2)I3`` for the paper's 0.35000000000000003,
        ``I2=(1+epsilon)I1`` with ε as :meth:`epsilon_text` shows it), any other by its ``repr``."""
        I1 = "(1-5a/2)I3" if self.I1 == paper_I1(self.a, self.I3) else repr(self.I1)
        I2 = "I1" if self.I2 == self.I1 else "(1+epsilon)I1" if self.I2 == self._eps_shown_body().I2 else repr(self.I2)
        return f"a={self.a!r} I1={I1} I2={I2} I3={self.I3!r} g={self.g!r} epsilon={self.epsilon_text()}"

    def _eps_shown_body(self) -> "Body":
        """This body's a, I1, I3, g with I2 = (1 + ε) I1 at ε as :meth:`epsilon_text` shows it."""
        return replace(self, I2=(1.0 + float(self.epsilon_text())) * self.I1)

    def __repr__(self) -> str:
        """``Body.paper(epsilon=0.005)`` for a paper body (exactly that body), else the fields' reprs."""
        eps = self.epsilon_text()
        if self.I2 == self._eps_shown_body().I2 and self == Body.paper(float(eps)):
            return f"Body.paper(epsilon={eps})" if self.I2 != self.I1 else "Body.paper()"
        return (f"Body(a={self.a!r}, I1={self.I1!r}, I2={self.I2!r}, I3={self.I3!r}, g={self.g!r})")

    def epsilon_text(self) -> str:
        """ε with the digits its computation resolves: ε = (I2 − I1)/I1 from the stored moments carries an absolute
        round-off of up to u(1 + 2|ε|) (u the unit round-off: I2 rounded, then the difference and the quotient), so
        it is shown to ⌊−log10(u(1 + 2|ε|)/|ε|)⌋ significant digits: ``Body.paper(1e-3)`` shows 0.001, not
        0.0009999999999998899."""
        eps = self.epsilon
        if eps == 0.0:
            return "0"
        u = 0.5 * sys.float_info.epsilon
        digits = int(math.floor(-math.log10(u * (1.0 + 2.0 * abs(eps)) / abs(eps))))
        return f"{eps:.{min(max(digits, 1), 17)}g}"


#: The members of the loaded-sphere family (paper fig. 1, §2; Borisov & Mamaev 2002), from the most special.
MEMBERS = ("Chaplygin's ball", "rock'n'roller", "Routh's sphere", "Chaplygin's top")

#: Largest |c| a loaded sphere may have: the mass centre strictly inside the unit sphere.
_OFFSET_LIMIT = 1.0

#: The :class:`Body` attributes that assume the mass centre on the third principal axis below the geometric centre
#: (the paper's a, ε, Q_J, Q_R, ...): a :class:`LoadedSphere` refuses each of them with a ValueError.
_ON_AXIS_ONLY = frozenset({"a", "epsilon", "is_symmetric", "with_epsilon", "symmetric", "require_symmetric",
                           "epsilon_text"})


@dataclass(frozen=True)
class LoadedSphere:
    """A loaded sphere of unit mass and unit radius with its mass centre anywhere: the family of the paper's fig. 1.

    Chaplygin's top (the mass centre off every principal axis) is the general member; the rock'n'roller (on a
    principal axis), Routh's sphere (on the axis of a body of revolution) and Chaplygin's ball (at the geometric
    centre) are special cases.  :class:`Body` is the on-axis case c = (0, 0, −a) with I1 ≤ I2 < I3, and keeps its
    own arithmetic (bit for bit); this class carries the general equations
    (:func:`~rocknroller.analysis.model.equations.body_frame_rhs` with seven parameters).

    The paper's quantities that assume the mass centre on the third axis (a, ε, Q_J, Q_R, the critical lines, the
    slow motion) refuse a LoadedSphere with a ValueError; :meth:`to_body` gives the :class:`Body` where the mass
    centre lies there.  θ is the tilt of the body's third axis; :meth:`relabelled` renames the axes so that another
    principal axis is the third.

    Parameters
    ----------
    I1, I2, I3 : float
        Principal moments about the mass centre, in any order, each > 0 and each at most the sum of the other two
        (the triangle inequality of a real mass distribution).
    offset : (c1, c2, c3)
        The mass centre relative to the geometric centre, in the principal frame; |c| < 1.
    g : float
        Gravity, ``g >= 0``.

    Examples
    --------
    >>> import rocknroller as rr
    >>> top = rr.LoadedSphere(0.35, 0.37, 0.4, offset=(0.03, -0.02, -0.05), g=9.87)
    >>> print(top.kind, f"|c| = {top.offset_norm:.4f}")
    Chaplygin's top |c| = 0.0616
    >>> print(rr.Body.paper(1e-3).as_loaded_sphere().to_body() == rr.Body.paper(1e-3))
    True
    >>> try:
    ...     top.a
    ... except ValueError as err:
    ...     print(str(err)[:72])
    a is defined only for a mass centre on the third principal axis below th
    """

    I1: float
    I2: float
    I3: float
    offset: tuple[float, float, float]
    g: float

    def __post_init__(self) -> None:
        for name in ("I1", "I2", "I3", "g"):
            object.__setattr__(self, name, require_finite(name, getattr(self, name)))
        try:
            parts = tuple(self.offset)
        except TypeError:
            raise ValueError(f"offset must be three real numbers (c1, c2, c3), got {self.offset!r}") from None
        if len(parts) != 3:
            raise ValueError(f"offset must be three real numbers (c1, c2, c3), got {self.offset!r}")
        c = tuple(require_finite(f"offset c{i + 1}", v) for i, v in enumerate(parts))
        object.__setattr__(self, "offset", c)
        moments = (self.I1, self.I2, self.I3)
        for i, name in enumerate(("I1", "I2", "I3")):
            if moments[i] <= 0.0:
                raise ValueError(f"{name} must be > 0, got {name}={moments[i]!r}")
            others = sum(moments) - moments[i]
            if moments[i] > others:
                raise ValueError(f"moments must satisfy the triangle inequality: {name} = {moments[i]!r} exceeds the "
                                 f"sum of the other two, {others!r}")
        if not self.offset_norm < _OFFSET_LIMIT:
            raise ValueError(f"offset must satisfy |c| < 1 (mass centre inside the sphere), got c={c!r}, "
                             f"|c|={self.offset_norm!r}")
        if self.g < 0.0:
            raise ValueError(f"g must be >= 0, got g={self.g!r}")

    def __getattr__(self, name: str) -> None:
        if name in _ON_AXIS_ONLY:
            raise ValueError(
                f"{name} is defined only for a mass centre on the third principal axis below the geometric centre "
                f"(rr.Body, the paper's setting); this {self.kind} has c = {self.offset!r}, moments "
                f"({self.I1!r}, {self.I2!r}, {self.I3!r}). Where c = (0, 0, -a) with I1 <= I2 < I3, use "
                f"body.to_body()")
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    @property
    def offset_norm(self) -> float:
        """|c|, the distance from the geometric centre to the mass centre (the potential's half-range is g|c|)."""
        return math.hypot(*self.offset)

    @property
    def params(self) -> tuple[float, float, float, float, float, float, float]:
        """(c1, c2, c3, I1, I2, I3, g), the order of the general equations' runtime parameters."""
        return (*self.offset, self.I1, self.I2, self.I3, self.g)

    @property
    def kind(self) -> str:
        """The member (paper fig. 1): Chaplygin's ball (c = 0); Routh's sphere (c on a principal axis whose two
        transverse moments are equal); the rock'n'roller (c on another principal axis); Chaplygin's top (c off every
        principal axis)."""
        c = self.offset
        axes = [i for i in range(3) if c[i] != 0.0]
        if not axes:
            return MEMBERS[0]
        if len(axes) > 1:
            return MEMBERS[3]
        moments = (self.I1, self.I2, self.I3)
        j, k = (i for i in range(3) if i != axes[0])
        return MEMBERS[2] if moments[j] == moments[k] else MEMBERS[1]

    def relabelled(self, axis: int) -> "LoadedSphere":
        """The same body with its principal axes renamed cyclically so that ``axis`` (1, 2 or 3) is the third: θ and
        the turning points then follow the tilt of that axis.  A cyclic renaming keeps the frame right-handed; a
        state's body components are renamed the same way (component ``axis`` last).

        Examples
        --------
        >>> import rocknroller as rr
        >>> top = rr.Body.chaplygin_top(0.35, 0.37, 0.4, offset=(0.03, -0.02, -0.05))
        >>> print(top.relabelled(1).params)
        (-0.02, -0.05, 0.03, 0.37, 0.4, 0.35, 9.87)
        >>> print(top.relabelled(3) == top)
        True
        """
        if isinstance(axis, bool) or axis not in (1, 2, 3):
            raise ValueError(f"axis must be 1, 2 or 3 (the principal axis to follow as the third), got axis={axis!r}")
        order = [(axis + k) % 3 for k in range(3)]  # the old indices of the new axes 1, 2, 3
        moments = (self.I1, self.I2, self.I3)
        c = self.offset
        return LoadedSphere(moments[order[0]], moments[order[1]], moments[order[2]],
                            (c[order[0]], c[order[1]], c[order[2]]), self.g)

    def to_body(self) -> Body:
        """The :class:`Body` of this sphere where c = (0, 0, −a), a >= 0, with I1 <= I2 < I3; else a ValueError."""
        c1, c2, c3 = self.offset
        if c1 != 0.0 or c2 != 0.0 or c3 > 0.0:
            raise ValueError(f"to_body needs the mass centre on the third principal axis below the geometric centre, "
                             f"c = (0, 0, -a) with a >= 0; got c={self.offset!r}")
        return Body(a=-c3 + 0.0, I1=self.I1, I2=self.I2, I3=self.I3, g=self.g)

    def describe(self) -> str:
        """One-line description for CSV headers and reports."""
        return (f"{self.kind}: c={self.offset!r} I1={self.I1!r} I2={self.I2!r} I3={self.I3!r} g={self.g!r}")
