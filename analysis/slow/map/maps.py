"""The slow map and the exact map as objects: one small class per map, its tangent map and inverse beside it.
It holds :class:`SlowMap` (the averaged drift–kick–drift map of order 1 or 2 on the release tables of (body, θ0);
:func:`rocknroller.analysis.slow.map.compiled_map.iterate_slow_map`) and :class:`ExactMap` (the direct ODE's map from a
maximum of θ to the next one, :func:`rocknroller.analysis.slow.map.exact_step.exact_step`), at the energy E = U(θ0) of
the release from rest at θ0 (paper eq. energy) and the member I2 = (1 + ε) I1 of the body's family.

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

Arrays.  Every method takes one maximum x, shape (3,), or an array of them, shape (..., 3) (the last axis
(Q_R, Q_J, Θ)), and keeps its leading shape: ``F(x)`` and ``inverse(x)`` (..., 3), ``jacobian(x)`` (..., 3, 3),
``iterate(x, n)`` (..., n + 1, 3) (each point's orbit laid out as one point's).  Each row is the one-point call's, bit
for bit: the slow map makes one compiled-kernel call per row (its chart rotation, Θ continuation and checks are NumPy
operations on all rows at once, each element's arithmetic that of one point), the exact map one direct run per row.
The rows are checked one by one (three finite numbers, |Θ| ≤ ``ANGLE_MAX``; a ValueError names the rows that are
not).  A point whose step fails (the slow map: it leaves the tables or its implicit kick does not converge, an
AveragingRangeError; the exact map: (E, Q) admits no motion, a ValueError) fails alone, all rows being evaluated
first: with ``failed="raise"`` (the default) the first failing row's own error is raised, with a note naming every
failing row; with ``failed="nan"`` its row is NaN (a Jacobian its 3 × 3 block, an orbit its rows from the failure
on) and the others are returned.  Every value of a step that does not fail is finite, so ``np.isnan(y[..., 0])`` is
the mask of the failed points.  The slow step is not rewritten in NumPy: it is an implicit kick solved per point
(simplified Newton with its own stop, and halvings at the table's edge) in the C kernel, ~3 µs a point with the
call; the tables' interpolation in NumPy measured 1.1 µs a point per evaluation (2.5 with the derivatives), five or
more a step, and would round otherwise (benchmarks/bench_map_arrays.py: the array call against the loop over rows).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import InitVar, dataclass, field
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import Body, float_or_nan
from rocknroller.analysis.model.diagnostics import wrap_angle
from rocknroller.analysis.slow.map.compiled_map import SlowSeries, _fast, chart_step, iterate_slow_map
from rocknroller.analysis.slow.map.exact_step import exact_step, exact_step_jacobian
from rocknroller.analysis.slow.map.family import family_member, rest_energy
from rocknroller.analysis.slow.map.limits import (MAX_MAXIMA, check_map_theta0, check_points, check_release_theta0,
                                                  default_order, rows_text)

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
#: What the maps do with the points whose step fails (module docstring, "Arrays").
_FAILED = ("raise", "nan")

Failures = dict[int, ValueError]  # the failed rows of a stack of points: row index -> its error, unraised


def reverse(x: ArrayLike) -> NDArray[np.float64]:
    """The time reversal R(Q_R, Q_J, Θ) = (−Q_R, −Q_J, Θ) (a reversor of both maps: R F R = F⁻¹), of one point (3,)
    or of each row of an array (..., 3)."""
    x = np.array(x, float)
    x[..., :2] = -x[..., :2]
    return x


def _continued(theta: NDArray[np.float64], raw: NDArray[np.float64]) -> NDArray[np.float64]:
    """Θ' = Θ + (Θ'_raw − Θ wrapped to (−π, π]) (module docstring), elementwise."""
    return np.asarray(theta + wrap_angle(raw - theta), float)


def _check_n(n: int, limit: int, name: str) -> int:
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or not 0 <= n <= limit:
        raise ValueError(f"n must be an integer in [0, {limit}] ({name}), got n={n!r}")
    return int(n)


def _check_failed(failed: str) -> str:
    if not isinstance(failed, str) or failed not in _FAILED:
        raise ValueError(f"failed must be one of {_FAILED}, got failed={failed!r}")
    return failed


def _check_eps(eps: float, body: Body) -> float:
    """ε as a float in [0, I3/I1 − 1) (the family's members, I1 ≤ I2 < I3), else a ValueError naming eps."""
    e = float_or_nan(eps)
    family = body.I3 / body.I1 - 1.0
    if not 0.0 <= e < family:  # also NaN
        raise ValueError(f"eps must lie in [0, {family:.6g}) (I2 = (1 + eps) I1 below I3 = {body.I3:g}), got "
                         f"eps={eps!r}")
    return e


def _settle(y: NDArray[np.float64], failures: Failures, shape: tuple[int, ...], failed: str) -> NDArray[np.float64]:
    """The results y (N, ...) of the N rows of x, reshaped to x's leading ``shape``; with ``failed="raise"`` the first
    failed row's own error instead (for an array, with a note naming every failed row)."""
    if failures and failed == "raise":
        first = min(failures)
        err = failures[first]
        if shape:
            mask = np.zeros(len(y), bool)
            mask[list(failures)] = True
            where = ", ".join(str(int(i)) for i in np.unravel_index(first, shape))
            err.add_note(f"at x[{where}], the first of {rows_text(mask.reshape(shape))} of x (shape {shape + (3,)}) "
                         "whose step failed; failed='nan' returns the other rows, these NaN")
        raise err
    return y.reshape(shape + y.shape[1:])


def _check_body(body: object) -> None:
    """A ValueError unless ``body`` is a :class:`Body` (the slow maps are the paper's: the mass centre on the third
    axis), naming what was given."""
    if not isinstance(body, Body):
        raise ValueError(f"body must be a rocknroller Body (the mass centre on the third principal axis), got "
                         f"{getattr(body, 'kind', None) or type(body).__name__}")


class _MapMixin(ABC):
    """``__call__``, ``jacobian``, ``inverse`` and ``iterate`` on one point or an array of them (module docstring,
    "Arrays") from the map's steps and Jacobians of a stack of points (N, 3)."""

    _max_steps: ClassVar[tuple[int, str]]  # (the largest n of iterate, its name): private, not a field

    @abstractmethod
    def _steps(self, X: NDArray[np.float64]) -> tuple[NDArray[np.float64], Failures]:
        """F of each row of X (N, 3), its Θ' as the step gives it (the caller continues it), and the failed rows
        (NaN)."""

    @abstractmethod
    def _jacobians(self, X: NDArray[np.float64]) -> tuple[NDArray[np.float64], Failures]:
        """DF at each row of X (N, 3): (N, 3, 3), and the failed rows (NaN)."""

    def _orbits(self, X: NDArray[np.float64], n: int) -> tuple[NDArray[np.float64], Failures]:
        """The orbits (N, n + 1, 3) of the rows of X by n rounds of steps over the rows that have not failed (a failed
        orbit NaN from its failure on), and the failed rows."""
        out = np.full((len(X), n + 1, 3), np.nan)
        out[:, 0] = X
        failures: Failures = {}
        alive = np.arange(len(X))
        for k in range(n):
            y, bad = self._steps(out[alive, k])
            y[:, 2] = _continued(out[alive, k, 2], y[:, 2])
            out[alive, k + 1] = y
            failures.update({int(alive[i]): err for i, err in bad.items()})
            alive = np.delete(alive, list(bad))
        return out, failures

    def _call(self, x: ArrayLike, failed: str) -> NDArray[np.float64]:
        X = check_points(x)
        failed = _check_failed(failed)
        flat = X.reshape(-1, 3)
        y, failures = self._steps(flat)
        y[:, 2] = _continued(flat[:, 2], y[:, 2])
        return _settle(y, failures, X.shape[:-1], failed)

    def _jacobian(self, x: ArrayLike, failed: str) -> NDArray[np.float64]:
        X = check_points(x)
        failed = _check_failed(failed)
        J, failures = self._jacobians(X.reshape(-1, 3))
        return _settle(J, failures, X.shape[:-1], failed)

    def inverse(self, x: ArrayLike, *, failed: str = "raise") -> NDArray[np.float64]:
        """F⁻¹(x) = R F(R x), by the reversing symmetry R (module docstring): (3,) for one point, (..., 3) for an
        array (..., 3) of them, each row the one point's (module docstring, "Arrays"; ``failed`` as there).

        Raises
        ------
        ValueError
            x not three finite numbers (or not an array (..., 3) of them), naming the rows; F's own errors.
        """
        return reverse(self._call(reverse(check_points(x)), failed))

    def iterate(self, x: ArrayLike, n: int, *, failed: str = "raise") -> NDArray[np.float64]:
        """The orbit x, F(x), …, Fⁿ(x): an array (n + 1, 3) of (Q_R, Q_J, Θ) (Θ continued); for an array x (..., 3)
        one orbit per row, (..., n + 1, 3), each the one point's (module docstring, "Arrays": with ``failed="nan"``
        a failed orbit is NaN from its failing step on).

        Raises
        ------
        ValueError
            x not three finite numbers (or not an array (..., 3) of them), naming the rows; n not an integer in
            [0, the map's limit]; F's own errors.
        """
        X, n, failed = check_points(x), _check_n(n, *self._max_steps), _check_failed(failed)
        out, failures = self._orbits(X.reshape(-1, 3), n)
        return _settle(out, failures, X.shape[:-1], failed)


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
    order : 1 or 2 (2 builds or loads the second-order table, by ``workers`` processes); default 2 (``default_order``).
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

    An array of points (..., 3) gives the same leading shape, each row the one point's bit for bit:

    >>> X = np.array([[1e-3, 0.0, 1.0], [-2e-3, 1e-5, 4.0]])
    >>> F(X).shape, F.jacobian(X).shape, F.iterate(X, 3).shape
    ((2, 3), (2, 3, 3), (2, 4, 3))
    >>> bool(np.array_equal(F(X)[1], F(X[1])))
    True

    A point that leaves the tables fails alone: ``failed="nan"`` makes its row NaN (the default raises its error).

    >>> Y = F(np.array([[1e-3, 0.0, 1.0], [0.5, 0.0, 1.0]]), failed="nan")
    >>> np.isnan(Y[:, 0]), bool(np.array_equal(Y[0], F(x)))
    (array([False,  True]), True)

    Raises
    ------
    ValueError
        A parameter out of its range, naming it.
    """

    body: Body
    theta0: float
    eps: float
    order: int | None = None
    build: InitVar[bool] = True
    workers: InitVar[int] = 1
    table: "SlowMapTable" = field(init=False, repr=False, compare=False)
    second: "SecondOrderTable | None" = field(init=False, repr=False, compare=False)
    _B: NDArray[np.float64] = field(init=False, repr=False, compare=False)  # the chart's rotation (``chart``)
    _max_steps: ClassVar[tuple[int, str]] = (MAX_MAXIMA, "MAX_MAXIMA")

    def __post_init__(self, build: bool, workers: int) -> None:
        from rocknroller.analysis.slow.map.tables_at_once import release_tables

        _check_body(self.body)
        object.__setattr__(self, "order", default_order(self.theta0) if self.order is None else self.order)
        if self.order not in (1, 2) or isinstance(self.order, bool):
            raise ValueError(f"order must be 1 or 2, got order={self.order!r}")
        theta0 = check_map_theta0(self.theta0)
        eps = _check_eps(self.eps, self.body)
        table, second = release_tables(self.body, theta0, self.order, build=build, workers=workers)
        B = np.eye(3)
        B[:2, 0], B[:2, 1] = table.e, table.n
        for name, value in (("theta0", theta0), ("eps", eps), ("table", table), ("second", second), ("_B", B)):
            object.__setattr__(self, name, value)

    @property
    def kappa(self) -> float:
        """κ of the release table (K = εκ)."""
        return float(self.table.kappa)

    @property
    def chart(self) -> NDArray[np.float64]:
        """B, the chart's rotation: x = B (u, v, Θ), Q = u e + v n (columns e, n of the table, and Θ)."""
        return self._B.copy()

    def _chart_steps(self, X: NDArray[np.float64], jacobian: bool
                     ) -> tuple[NDArray[np.float64], NDArray[np.float64] | None, Failures]:
        """The kernel's step (and M) from each row of X (N, 3) in the chart (u, v, Θ), and the failed rows."""
        c = X.copy()  # (u, v) = (e·Q, n·Q) as iterate_slow_map reads Q0, by a stacked matmul (one product per row)
        c[:, :2] = np.matmul(X[:, None, :2], self._B[:2, :2])[:, 0]
        failures: Failures = {}
        y, M = chart_step(self.table, self.eps, c, self.second, jacobian, failures)
        return y, M, failures

    def _steps(self, X: NDArray[np.float64]) -> tuple[NDArray[np.float64], Failures]:
        y, _, failures = self._chart_steps(X, False)
        return np.matmul(self._B, y[..., None])[..., 0], failures  # B y per row (one matrix-vector product each)

    def _jacobians(self, X: NDArray[np.float64]) -> tuple[NDArray[np.float64], Failures]:
        _, M, failures = self._chart_steps(X, True)
        assert M is not None, "chart_step gives M with jacobian=True"
        return self._B @ M @ self._B.T, failures

    def __call__(self, x: ArrayLike, *, failed: str = "raise") -> NDArray[np.float64]:
        """F(x), x = (Q_R, Q_J, Θ) at a maximum of θ: the next maximum's (Q_R, Q_J, Θ); for an array x (..., 3) that of
        each row, (..., 3) (module docstring, "Arrays": one kernel call per row, the rest on all rows at once).

        Parameters
        ----------
        x : one maximum (3,) or an array of them (..., 3).
        failed : ``"raise"`` (the first failed row's error, after all rows, noting every failed row) or ``"nan"``
            (a failed row NaN, the others returned).

        Raises
        ------
        ValueError
            x not three finite numbers (or not an array (..., 3) of them), naming the rows; ``failed`` not one of
            ``"raise"``, ``"nan"``.
        AveragingRangeError
            A step leaves the tables (or the implicit kick does not converge), with ``failed="raise"``.
        """
        return self._call(x, failed)

    def jacobian(self, x: ArrayLike, *, failed: str = "raise") -> NDArray[np.float64]:
        """DF(x) = ∂(Q_R', Q_J', Θ')/∂(Q_R, Q_J, Θ): the kernel's exact tangent map of the step, B M Bᵀ (module
        docstring); (3, 3), or (..., 3, 3) for an array x (..., 3), each row's the one point's.  Raises as
        ``__call__``."""
        return self._jacobian(x, failed)

    def run(self, x: ArrayLike, t_end: float, *, n_steps: int | None = None, tangent: bool = False) -> SlowSeries:
        """The orbit from x over the time t_end (at most ``n_steps`` maxima), with its times, azimuth and, with
        ``tangent``, its tangent vector's growth: :func:`rocknroller.analysis.slow.map.compiled_map.iterate_slow_map` from
        the maximum x (its checks and limits; its Θ made continuous by ``unwrap_phase``).  The series holds the maxima
        after x, F(x) first, as a prediction's series does (x itself is the start, not a sample); :meth:`iterate`
        holds x as its first row.  One start x (3,): a ValueError for an array of them."""
        x = check_points(x)
        if x.shape != (3,):
            raise ValueError(f"run takes one maximum x = (Q_R, Q_J, Theta), got an array of shape {x.shape}")
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

    def iterate(self, x: ArrayLike, n: int, *, failed: str = "raise") -> NDArray[np.float64]:
        """The orbit x, F(x), …, Fⁿ(x) as an array (n + 1, 3), by the compiled kernel in one call (it stays in the
        chart: equal to n calls of F to the round-off of the chart's rotation, ~1 ulp of Q per call, carried by DF);
        for an array x (..., 3) one orbit per row, (..., n + 1, 3), each the one point's (with ``failed="nan"`` an
        orbit that leaves the tables keeps its maxima inside them, NaN from there on).

        Raises
        ------
        ValueError
            x not three finite numbers (or not an array (..., 3) of them), naming the rows; n not an integer in
            [0, ``MAX_MAXIMA``]; ``failed`` not one of ``"raise"``, ``"nan"``.
        AveragingRangeError
            The orbit leaves the tables, with ``failed="raise"``.
        """
        return super().iterate(x, n, failed=failed)

    def _orbits(self, X: NDArray[np.float64], n: int) -> tuple[NDArray[np.float64], Failures]:
        """One kernel run of n steps per row of X (N, 3) in the chart, then all rotated back and Θ continued at once
        (per orbit the arithmetic of one); an orbit that failed keeps its rows before the failure (NaN after)."""
        ft = _fast(self.table, self.second)
        rows = np.full((len(X), n, 5), np.nan)  # (t, u, v, Θ, φ) of each orbit's maxima
        failures: Failures = {}
        for i, x in enumerate(X):
            err = ft.steps(self.eps, float(ft.e @ x[:2]), float(ft.n @ x[:2]), float(x[2]), rows[i])
            if err is not None:
                failures[i] = err
        out = np.empty((len(X), n + 1, 3))
        out[:, 0] = X
        out[:, 1:] = np.matmul(rows[:, :, 1:4], self._B.T)
        raw = np.concatenate([X[:, 2:], rows[:, :, 3]], axis=1)
        out[:, :, 2] = np.cumsum(np.concatenate([X[:, 2:], wrap_angle(np.diff(raw, axis=1))], axis=1), axis=1)
        return out, failures


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
    >>> X = np.array([x, [-4e-3, 1e-4, 4.0]])                # one direct run per row
    >>> bool(np.array_equal(F(X), np.array([F(X[0]), F(X[1])])))
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

    def _steps(self, X: NDArray[np.float64]) -> tuple[NDArray[np.float64], Failures]:
        y, failures = np.full((len(X), 3), np.nan), {}
        for i, x in enumerate(X):
            try:
                y[i] = exact_step(self.sym, self.eps, self.E, float(x[0]), float(x[1]), 0.5 * float(x[2]))[:3]
            except ValueError as err:
                failures[i] = err
        return y, failures

    def _jacobians(self, X: NDArray[np.float64]) -> tuple[NDArray[np.float64], Failures]:
        J, failures = np.full((len(X), 3, 3), np.nan), {}
        for i, x in enumerate(X):
            try:
                J[i] = exact_step_jacobian(self.sym, self.eps, self.E, x)
            except ValueError as err:
                failures[i] = err
        return J, failures

    def __call__(self, x: ArrayLike, *, failed: str = "raise") -> NDArray[np.float64]:
        """F(x), x = (Q_R, Q_J, Θ) at a maximum of θ: the next maximum's (Q_R, Q_J, Θ) (one direct run); for an
        array x (..., 3) that of each row, (..., 3), one run per row (module docstring, "Arrays"; ``failed`` as
        there: ``"raise"`` or ``"nan"``).

        Raises
        ------
        ValueError
            x not three finite numbers (or not an array (..., 3) of them), naming the rows; ``failed`` not one of
            ``"raise"``, ``"nan"``; or (E, Q) admits no motion, with ``failed="raise"``.
        """
        return self._call(x, failed)

    def jacobian(self, x: ArrayLike, *, failed: str = "raise") -> NDArray[np.float64]:
        """DF(x) = ∂(Q_R', Q_J', Θ')/∂(Q_R, Q_J, Θ) by the variational equations of the direct ODE through the rock,
        with the start's and the event's dependence on x (module docstring; three variational runs,
        :func:`rocknroller.analysis.slow.map.exact_step.exact_step_jacobian`); (3, 3), or (..., 3, 3) for an array
        x (..., 3).  Raises as ``__call__``."""
        return self._jacobian(x, failed)
