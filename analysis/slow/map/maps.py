"""The slow map and the exact map as objects: one small class per map, its tangent map and inverse beside it.
It holds :class:`SlowMap` (the averaged drift–kick–drift map of order 1 or 2 on the release tables of (body, θ0);
:func:`rocknroller.analysis.slow.map.compiled_map.iterate_slow_map`) and :class:`ExactMap` (the direct ODE's map from a
maximum of θ to the next one, :func:`rocknroller.analysis.slow.map.exact_step.exact_step`), at the energy E = U(θ0) of the
release from rest at θ0 (paper eq. energy) and the member I2 = (1 + ε) I1 of the body's family.

The state.  A maximum of θ at that energy is x = (Q_R, Q_J, Θ) (paper eqs. JelletandRouth_Qtys; Θ = 2ψ).  Θ counts
mod 2π (ψ is sampled at the maxima only, so the turns between them are not seen); both maps return Θ' continued
from Θ, within π of it (Θ' − Θ wrapped to (−π, π]), so that their orbits' Θ are continuous wherever the spin turns
by less than π a rock, and their derivatives are those of the map of the circle.

The tangent maps.  ``SlowMap.jacobian`` is the compiled kernel's tangent map of the step as implemented (the drifts'
∇W, the implicit midpoint's derivative by the implicit function theorem;
:func:`rocknroller.analysis.slow.map.compiled_map.chart_step`), in the table's chart (u, v, Θ), Q = u e + v n, and turned
into (Q_R, Q_J, Θ) by the chart's rotation B: J = B M Bᵀ.  ``ExactMap.jacobian``
is the chain rule through the one rock:

* the start y₀(x): the body-frame (γ, ω) at the maximum is fixed by six conditions, Q_R(y) = Q_R, Q_J(y) = Q_J,
  ψ(y) = Θ/2, E(y) = E, dγ3/dt = 0 and |γ|² = 1, so ∂y₀/∂x = C⁻¹ P with C their 6 × 6 gradient (fourth-order
  differences of the package's own invariants: exact to round-off for the polynomials E, Q_J, dγ3/dt, |γ|², h⁴ for
  Q_R and ψ) and P picking (1, 1, 1/2) for (Q_R, Q_J, ψ);
* the flow: the variational equations of the (γ, ω) system (heyoka,
  :func:`rocknroller.numerics.variational.tangent_to_maximum`), one run per column, to the next maximum at t₁;
* the event: t₁ moves with the start, ∂t₁ = −∇h·w/∇h·f (h = dγ3/dt, f the vector field at the maximum), so the
  state there moves by w + f ∂t₁;
* the outputs: ∇(Q_R, Q_J, 2ψ) there, on that.

The inverse.  Time reversal R: (Q, Θ) → (−Q, Θ) is a reversor of both maps (R F R = F⁻¹; docs/averaging.md,
"Reversible drift–kick–drift"; for the exact map the ODE's own reversibility), so ``inverse(y) = R F(R y)``, and
``inverse(self(x)) = x`` to the maps' evaluation error.  Neither map preserves volume in (Q_R, Q_J, Θ): the
reversor gives det DF(x) · det DF(R F x) = 1 along any orbit, not det DF = 1 (the tests check the former).
"""

from __future__ import annotations

import sys
from abc import ABC, abstractmethod
from dataclasses import InitVar, dataclass, field
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import Body, float_or_nan
from rocknroller.analysis.model.diagnostics import wrap_angle
from rocknroller.analysis.model.equations import body_frame_rhs, state_from_euler, turning_point_function
from rocknroller.analysis.model.invariants import energy
from rocknroller.analysis.slow.map.compiled_map import SlowSeries, _fast, chart_step, iterate_slow_map
from rocknroller.analysis.slow.map.exact_step import exact_step
from rocknroller.analysis.slow.map.family import directional_derivative, family_member, maximum_state, rest_energy
from rocknroller.analysis.slow.map.limits import MAX_MAXIMA, check_angle, check_map_theta0, check_release_theta0
from rocknroller.analysis.slow.map.orbit import _psi_of, _QJ_of, _QR_of, symmetric_data

if TYPE_CHECKING:
    from rocknroller.analysis.slow.map.chart import SecondOrderTable, SlowMapTable

__all__ = ["SlowMap", "ExactMap", "EXACT_MAX_STEPS", "EVALUATION_ULPS", "reverse"]

#: Most steps of one ``ExactMap.iterate``: one exact step is one direct run over ~1.5 T_θ, ~25 ms (measured at
#: 0.95π), so 10 000 steps are ~4 CPU minutes.  (``SlowMap.iterate``: ``MAX_MAXIMA``, ~1 µs a step.)
EXACT_MAX_STEPS = 10_000
#: The maps' evaluation error, in ulp of 4π (|Θ'| ≲ 4π is the largest component either returns): the slow map's step
#: is exact arithmetic on its tables but for the implicit kick, solved to 1e-13 of the kick; the exact step is
#: heyoka at the unit round-off over one rock.  The scatter of F under relative perturbations of 1e-14 of x was
#: ≤ 1.3e-13 on both maps at 0.9π and 0.95π, ε = 1.05 and 1.5 × 4/κ (its Θ component; 2e-15 in Q_R, 6e-17 in Q_J):
#: 200 ulp of 4π = 5.6e-13 is four times that.
EVALUATION_ULPS = 200.0


def reverse(x: ArrayLike) -> NDArray[np.float64]:
    """The time reversal R(Q_R, Q_J, Θ) = (−Q_R, −Q_J, Θ) (a reversor of both maps: R F R = F⁻¹)."""
    x = np.array(x, float)
    x[:2] = -x[:2]
    return x


def _continued(theta: float, raw: float) -> float:
    """Θ' = Θ + (Θ'_raw − Θ wrapped to (−π, π]) (module docstring)."""
    return theta + float(wrap_angle(raw - theta))


def _check_x(x: ArrayLike) -> NDArray[np.float64]:
    try:  # a complex x is refused, not cast with a ComplexWarning (its imaginary part silently dropped)
        real = not isinstance(x, str) and not np.iscomplexobj(x)
        a = np.asarray(x, dtype=float) if real else np.array(np.nan)
    except (TypeError, ValueError):
        a = np.array(np.nan)
    if a.shape != (3,) or not np.all(np.isfinite(a)):
        raise ValueError(f"x must be three finite numbers (Q_R, Q_J, Theta), got x={x!r} (shape {np.shape(x)})")
    check_angle("Theta", a[2])
    return a.copy()


def _check_n(n: int, limit: int, name: str) -> int:
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or not 0 <= n <= limit:
        raise ValueError(f"n must be an integer in [0, {limit}] ({name}), got n={n!r}")
    return int(n)


def _check_eps(eps: float, body: Body) -> float:
    """ε as a float in [0, I3/I1 − 1) (the family's members, I1 ≤ I2 < I3), else a ValueError naming eps."""
    e = float_or_nan(eps)
    family = body.I3 / body.I1 - 1.0
    if not 0.0 <= e < family:  # also NaN
        raise ValueError(f"eps must lie in [0, {family:.6g}) (I2 = (1 + eps) I1 below I3 = {body.I3:g}), got "
                         f"eps={eps!r}")
    return e


class _MapMixin(ABC):
    """``inverse`` and ``iterate`` from ``__call__`` (both maps)."""

    _max_steps: ClassVar[tuple[int, str]]  # (the largest n of iterate, its name): private, not a field

    @abstractmethod
    def __call__(self, x: ArrayLike) -> NDArray[np.float64]:
        """F(x)."""

    def inverse(self, x: ArrayLike) -> NDArray[np.float64]:
        """F⁻¹(x) = R F(R x), by the reversing symmetry R (module docstring)."""
        return reverse(self(reverse(_check_x(x))))

    def iterate(self, x: ArrayLike, n: int) -> NDArray[np.float64]:
        """The orbit x, F(x), …, Fⁿ(x): an array (n + 1, 3) of (Q_R, Q_J, Θ) (Θ continued).

        Raises
        ------
        ValueError
            x not three finite numbers; n not an integer in [0, the map's limit].
        """
        x = _check_x(x)
        n = _check_n(n, *self._max_steps)
        out = np.empty((n + 1, 3))
        out[0] = x
        for k in range(n):
            out[k + 1] = self(out[k])
        return out



def _check_body(body: object) -> None:
    """A ValueError unless ``body`` is a :class:`Body` (the slow maps are the paper's: the mass centre on the third
    axis), naming what was given."""
    if not isinstance(body, Body):
        raise ValueError(f"body must be a rocknroller Body (the mass centre on the third principal axis), got "
                         f"{getattr(body, 'kind', None) or type(body).__name__}")

@dataclass(frozen=True)
class SlowMap(_MapMixin):
    """The averaged slow map of ``order`` (1, or 2 with the second-order kick) of the member I2 = (1 + ε) I1 of
    ``body``'s family at the energy of the release from rest at ``theta0`` (module docstring).

    Parameters
    ----------
    body : any member of the family (its a, I1, I3, g are used).
    theta0 : the release angle, in ``THETA0_RANGE`` (its release tables are loaded, or built and cached).
    eps : ε in [0, I3/I1 − 1) (beyond K = εκ ≈ 8 orbits soon leave the tables, and the first-order map's implicit
        kick may stop converging: an AveragingRangeError when evaluated).
    order : 1 or 2 (2 loads or builds the second-order table, by ``workers`` processes).
    build : build missing tables (else a ValueError says they are not cached).
    workers : processes building a second-order table.

    Examples
    --------
    >>> import math, numpy as np
    >>> import rocknroller as rr
    >>> F = rr.SlowMap(rr.Body.paper(0.0), 0.95 * math.pi, 0.005)
    >>> x = np.array([1e-3, 0.0, 1.0])                  # (Q_R, Q_J, Theta) at a maximum of theta
    >>> bool(np.allclose(F.inverse(F(x)), x, rtol=0.0, atol=1e-12))
    True
    >>> F.iterate(x, 3).shape, F.jacobian(x).shape
    ((4, 3), (3, 3))

    Raises
    ------
    ValueError
        A parameter out of its range, naming it.
    """

    body: Body
    theta0: float
    eps: float
    order: int = 1
    build: InitVar[bool] = True
    workers: InitVar[int] = 1
    table: "SlowMapTable" = field(init=False, repr=False, compare=False)
    second: "SecondOrderTable | None" = field(init=False, repr=False, compare=False)
    _max_steps: ClassVar[tuple[int, str]] = (MAX_MAXIMA, "MAX_MAXIMA")

    def __post_init__(self, build: bool, workers: int) -> None:
        from rocknroller.analysis.slow.map.table import load_or_build_table

        _check_body(self.body)
        if self.order not in (1, 2) or isinstance(self.order, bool):
            raise ValueError(f"order must be 1 or 2, got order={self.order!r}")
        theta0 = check_map_theta0(self.theta0)
        eps = _check_eps(self.eps, self.body)
        table = load_or_build_table(self.body, theta0, build=build)
        second = None
        if self.order == 2:
            from rocknroller.analysis.slow.map.second_order import load_or_build_second_order_table

            second = load_or_build_second_order_table(self.body, theta0, build=build, workers=workers)
        for name, value in (("theta0", theta0), ("eps", eps), ("table", table), ("second", second)):
            object.__setattr__(self, name, value)

    @property
    def kappa(self) -> float:
        """κ of the release table (K = εκ)."""
        return float(self.table.kappa)

    @property
    def chart(self) -> NDArray[np.float64]:
        """B, the chart's rotation: x = B (u, v, Θ), Q = u e + v n (columns e, n of the table, and Θ)."""
        B = np.eye(3)
        B[:2, 0], B[:2, 1] = self.table.e, self.table.n
        return B

    def _chart_step(self, x: NDArray[np.float64], jacobian: bool) -> tuple[NDArray[np.float64], Any]:
        ft = _fast(self.table, self.second)
        c = np.array([float(ft.e @ x[:2]), float(ft.n @ x[:2]), x[2]])  # as iterate_slow_map reads Q0
        return chart_step(self.table, self.eps, c, self.second, jacobian)

    def __call__(self, x: ArrayLike) -> NDArray[np.float64]:
        """F(x), x = (Q_R, Q_J, Θ) at a maximum of θ: the next maximum's (Q_R, Q_J, Θ).

        Raises
        ------
        ValueError
            x not three finite numbers.
        AveragingRangeError
            The step leaves the tables (or the implicit kick does not converge).
        """
        x = _check_x(x)
        c = self._chart_step(x, False)[0]
        y = self.chart @ c
        y[2] = _continued(x[2], y[2])
        return y

    def jacobian(self, x: ArrayLike) -> NDArray[np.float64]:
        """DF(x) = ∂(Q_R', Q_J', Θ')/∂(Q_R, Q_J, Θ): the kernel's exact tangent map of the step, B M Bᵀ (module
        docstring)."""
        M = self._chart_step(_check_x(x), True)[1]
        B = self.chart
        return B @ M @ B.T

    def run(self, x: ArrayLike, t_end: float, *, n_steps: int | None = None, tangent: bool = False) -> SlowSeries:
        """The orbit from x over the time t_end (at most ``n_steps`` maxima), with its times, azimuth and, with
        ``tangent``, its tangent vector's growth: :func:`rocknroller.analysis.slow.map.compiled_map.iterate_slow_map` from
        the maximum x (its checks and limits; its Θ made continuous by ``unwrap_phase``).  The series holds the maxima
        after x, F(x) first, as a prediction's series does (x itself is the start, not a sample); :meth:`iterate`
        holds x as its first row."""
        x = _check_x(x)
        return iterate_slow_map(self.table, self.eps, 0.5 * float(x[2]), t_end, Q0=x[:2], n_steps=n_steps,
                                second=self.second, tangent=tangent)

    @classmethod
    def from_prediction(cls, pred: Any) -> tuple["SlowMap", NDArray[np.float64]]:
        """The map of a release's prediction and its start x0: ``F, x0 = SlowMap.from_prediction(pred)``; then
        ``F.iterate(x0, n)[1:]`` are the prediction's maxima (its body, θ0, ε and order; x0 = (0, 0, 2ψ0), the
        release at rest being a maximum of θ with Q_R = Q_J = 0).  A start with velocity is predicted on the region
        tables of its energy, not on a release's map: a ValueError says so.

        Examples
        --------
        >>> import math, numpy as np
        >>> import rocknroller as rr
        >>> pred = rr.predict_slow_motion(rr.Body.paper(1e-3), 0.95 * math.pi, 0.3, 100.0, order=1)
        >>> F, x0 = rr.SlowMap.from_prediction(pred)
        >>> orbit = F.iterate(x0, 3)[1:]
        >>> bool(np.allclose(orbit[:, 0], pred.series.QR[:3], rtol=1e-9, atol=1e-15))
        True
        """
        if pred.start is not None or pred.body is None:
            raise ValueError("from_prediction takes a release from rest's prediction: a start with velocity is "
                             "predicted on the region tables of its energy (pred.start is its state)")
        return cls(pred.body, pred.theta0, pred.eps, order=pred.order), np.array([0.0, 0.0, 2.0 * float(pred.psi0)])

    def iterate(self, x: ArrayLike, n: int) -> NDArray[np.float64]:
        """The orbit x, F(x), …, Fⁿ(x) as an array (n + 1, 3), by the compiled kernel in one call (it stays in the
        chart: equal to n calls of F to the round-off of the chart's rotation, ~1 ulp of Q per call, carried by DF).

        Raises
        ------
        ValueError
            x not three finite numbers; n not an integer in [0, ``MAX_MAXIMA``].
        AveragingRangeError
            The orbit leaves the tables.
        """
        x = _check_x(x)
        n = _check_n(n, *self._max_steps)
        out = np.empty((n + 1, 3))
        out[0] = x
        if n:
            ft = _fast(self.table, self.second)
            rows, _ = ft.iterate(self.eps, float(ft.e @ x[:2]), float(ft.n @ x[:2]), float(x[2]), 0.0,
                                 sys.float_info.max, n)
            out[1:] = rows[:, 1:4] @ self.chart.T
            raw = np.concatenate([[x[2]], rows[:, 3]])
            out[:, 2] = np.cumsum(np.concatenate([[x[2]], wrap_angle(np.diff(raw))]))
        return out


@dataclass(frozen=True)
class ExactMap(_MapMixin):
    """The direct ODE's map from a maximum of θ to the next of the member I2 = (1 + ε) I1 of ``body``'s family at
    the energy of the release from rest at ``theta0`` (:func:`rocknroller.analysis.slow.map.exact_step.exact_step`:
    heyoka at the unit round-off; module docstring).

    Parameters
    ----------
    body : any member of the family (its a, I1, I3, g are used).
    theta0 : the release angle in (0, 0.999π] (its energy U(θ0) is every state's).
    eps : ε in [0, I3/I1 − 1).

    Examples
    --------
    >>> import math, numpy as np
    >>> import rocknroller as rr
    >>> F = rr.ExactMap(rr.Body.paper(0.0), 0.95 * math.pi, 0.005)
    >>> x = np.array([1e-3, 0.0, 1.0])
    >>> bool(np.allclose(F.inverse(F(x)), x, rtol=0.0, atol=1e-11))
    True

    Raises
    ------
    ValueError
        A parameter out of its range, naming it.
    """

    body: Body
    theta0: float
    eps: float
    sym: Body = field(init=False, repr=False, compare=False)
    member: Body = field(init=False, repr=False, compare=False)
    E: float = field(init=False, repr=False, compare=False)
    _max_steps: ClassVar[tuple[int, str]] = (EXACT_MAX_STEPS, "EXACT_MAX_STEPS")

    def __post_init__(self) -> None:
        _check_body(self.body)
        theta0 = check_release_theta0(self.theta0)
        sym = self.body.symmetric()
        eps = _check_eps(self.eps, sym)
        for name, value in (("theta0", theta0), ("eps", eps), ("sym", sym), ("member", family_member(sym, eps)[0]),
                            ("E", rest_energy(sym, theta0))):
            object.__setattr__(self, name, value)

    def _period(self, x: NDArray[np.float64]) -> float:
        """The symmetric body's T_θ at (E, Q): the next maximum is the first after half of it."""
        return float(symmetric_data(self.sym, self.E, float(x[0]), float(x[1]))[0])

    def __call__(self, x: ArrayLike) -> NDArray[np.float64]:
        """F(x), x = (Q_R, Q_J, Θ) at a maximum of θ: the next maximum's (Q_R, Q_J, Θ) (one direct run).

        Raises
        ------
        ValueError
            x not three finite numbers, or (E, Q) admits no motion.
        """
        x = _check_x(x)
        y = exact_step(self.sym, self.eps, self.E, float(x[0]), float(x[1]), 0.5 * float(x[2]))[:3]
        y[2] = _continued(x[2], y[2])
        return y

    def _start(self, x: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The body-frame state (11,) at the maximum x and ∂(γ, ω)/∂x (6, 3) (module docstring)."""
        st = maximum_state(self.sym, self.eps, self.E, float(x[0]), float(x[1]), 0.5 * float(x[2]))[2]
        y0 = state_from_euler(st.theta, 0.0, st.psi, 0.0, st.phi_dot, st.psi_dot)
        C = np.vstack([self._gradient(f, y0, angle) for f, angle in self._conditions()])
        P = np.zeros((6, 3))
        P[0, 0], P[1, 1], P[2, 2] = 1.0, 1.0, 0.5
        return y0, np.asarray(np.linalg.solve(C, P), float)

    def _conditions(self) -> list[tuple[Any, bool]]:
        """The functions of y that fix the start (Q_R, Q_J, ψ, E, dγ3/dt, |γ|²), each with its ``angle`` flag."""
        member = self.member
        return [(_QR_of(self.sym), False), (_QJ_of(self.sym), False), (_psi_of, True),
                (lambda y: energy(member, y[0:3], y[3:6]), False), (turning_point_function, False),
                (lambda y: y[0] * y[0] + y[1] * y[1] + y[2] * y[2], False)]

    @staticmethod
    def _gradient(fun: Any, y: NDArray[np.float64], angle: bool) -> NDArray[np.float64]:
        """∂fun/∂(γ, ω) at the body-frame state y (11,): fourth-order differences along the six unit vectors."""
        V = np.zeros((11, 6))
        V[:6, :6] = np.eye(6)
        return np.asarray(directional_derivative(fun, np.repeat(y[:, None], 6, axis=1), V, angle=angle), float)

    def jacobian(self, x: ArrayLike) -> NDArray[np.float64]:
        """DF(x) = ∂(Q_R', Q_J', Θ')/∂(Q_R, Q_J, Θ) by the variational equations of the direct ODE through the rock,
        with the start's and the event's dependence on x (module docstring): three variational runs.

        Raises
        ------
        ValueError
            x not three finite numbers, or (E, Q) admits no motion.
        """
        from rocknroller.numerics.variational import tangent_to_maximum

        x = _check_x(x)
        T = self._period(x)
        y0, dy0 = self._start(x)
        Y1, W = np.zeros(11), np.empty((6, 3))
        for j in range(3):
            _, Y1[:6], W[:, j] = tangent_to_maximum(self.member, y0[:6], dy0[:, j], 0.5 * T, 1.5 * T)
        f = np.zeros(11)
        f[:6] = np.array(body_frame_rhs(Y1, self.member.params)[:6], float)
        dY = np.zeros((11, 3))
        dY[:6] = W
        dh = self._gradient(turning_point_function, Y1, False)
        dY[:6] -= np.outer(f[:6], dh @ W / (dh @ f[:6]))
        outputs = [(_QR_of(self.sym), False, 1.0), (_QJ_of(self.sym), False, 1.0), (_psi_of, True, 2.0)]
        return np.vstack([c * self._gradient(g, Y1, angle) @ dY[:6] for g, angle, c in outputs])
