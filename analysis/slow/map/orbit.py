"""The variational orbit: one step maximum → maximum of Routh's sphere with its first- and second-order ε-responses.
It holds the first-order step (:func:`first_order_step`, and :func:`first_order_steps` for many starts at once), the
integrators of the orbits (with one ε-response, two orders, or three turned responses: :func:`_harmonic_system`,
which :mod:`rocknroller.analysis.slow.map.harmonic` uses for the harmonics in Θ), the second-order step
(:func:`second_order_step`), T_θ, W and Δφ of the symmetric body from the quadratures of paper eqs. thetadotsq,
Delta_phi (:func:`symmetric_data`), and ∂f/∂ε of the equations of motion (:func:`eps_derivative_rhs`).  The responses are
those of Q_R, Q_J (paper eq. JelletandRouth_Qtys), Θ = 2ψ, the time and φ at the next maximum; this is the orbit
stage of the averaged slow map (:mod:`rocknroller.analysis.slow.prediction`; docs/averaging.md, "The slow map").

The symmetric orbit from a maximum θ_X at (E, Q, ψ_n) is integrated (heyoka) together with its first-order
variational equations in ε (I2 = (1 + ε) I1) on ``rocknroller.analysis.model.equations.body_frame_rhs``:

    ż = (∂f/∂y) z + ∂f/∂ε,   z(0) = ∂y₀/∂ε,

where z(0) is the shift of the starting maximum θ_X at fixed (E, Q, ψ) (the kinetic energy depends on I2),
and the shift of the event time (the next zero of dγ3/dt) is included:
dy_{n+1}/dε = z + f dt₁/dε,  dt₁/dε = −∇h·z / ∇h·f,  h = dγ3/dt.

By the rotational symmetry of Routh's sphere, the first-order response contains only the harmonics 0 and 2
of ψ_n (0 and 1 of Θ_n = 2ψ_n): three starts per Q (ψ_n = 0, π/3, 2π/3) determine it.  The same symmetry,
f(S y) = S f(y) for S a turn about the symmetry axis (:func:`rotate_about_axis`), makes the orbit from ψ_k the turned
orbit from 0 and its response S_k ẑ_k, where ẑ_k is integrated along the orbit from 0 under the forcing turned back,
S_kᵀ ∂f/∂ε(S_k y): one orbit carries all three responses (:func:`_harmonic_system`).

To second order (:func:`second_order_step`; :func:`second_order_steps` for many starts, in the batch lanes) the state
also carries w, the second ε-derivative along the start's curve y₀(ε)
(:func:`rocknroller.analysis.slow.map.family.maximum_state`, differenced in ε), with
ẇ = A w + D²f[z, z] + 2 ∂²f/∂y∂ε z + ∂²f/∂ε² (A = ∂f/∂y); the second derivative of the event time follows from
h = 0 at the next maximum as the first's does.

The orbits run in heyoka's batch mode, one per SIMD lane (:func:`first_order_steps`, ``harmonic_steps``): the
tables' nodes cost ~5× less than one orbit at a time (``validation/region_table.py``, docs/slow_validation.md); the
lanes differ from a one-lane run by the rounding of the vector kernels only (up to ~1e-11 of each response's largest
harmonic: the responses are central differences, which amplify it).
"""

from __future__ import annotations

import copy
import functools
import math
import threading
from dataclasses import dataclass
from typing import Any, Callable, Mapping

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.model.diagnostics import wrap_angle
from rocknroller.analysis.model.equations import body_frame_rhs, state_from_euler, turning_point_function
from rocknroller.analysis.model.invariants import energy, jellett, routh
from rocknroller.analysis.model.kinematics import angles_from_frame
from rocknroller.analysis.routh.quadrature import precession
from rocknroller.analysis.routh.reduction import effective_potential, state_from_turning_point
from rocknroller.analysis.routh.turning_points import turning_points
from rocknroller.analysis.slow.map.family import (_central_difference, _central_second_difference, _second_directional,
                                              directional_derivative, maximum_state)
from rocknroller.numerics.cache import compiling
from rocknroller.numerics.integrate import check_diskcache

__all__ = [
    "HARMONIC_PSI", "FIRST_ORDER_NAMES", "eps_derivative_rhs", "FirstOrderStep", "first_order_step",
    "first_order_steps", "second_order_step", "second_order_steps", "symmetric_data", "rotate_about_axis", "turn"
]

#: Spin angles ψ_n of the three orbits that determine the harmonics 0 and 2 of ψ_n.
HARMONIC_PSI = (0.0, math.pi / 3.0, 2.0 * math.pi / 3.0)
#: First-order responses per step: ε-derivatives of Q_R, Q_J, Θ = 2ψ, the event time and φ.
FIRST_ORDER_NAMES = ("QR", "QJ", "Theta", "t", "phi")
#: heyoka's names of the 11 components of form (i).
_STATE_NAMES = ("g1", "g2", "g3", "w1", "w2", "w3", "x1", "x2", "x3", "X", "Y")
#: The compiled integrators of this process (templates), each thread's copies, and the lock that guards the templates.
_INTEGRATOR: dict[str, Any] = {}
_PER_THREAD = threading.local()
_INTEGRATOR_LOCK = threading.Lock()
#: CPU seconds a compilation of :func:`_variational_integrator` of each order usually takes (measured, one core,
#: rounded up: 0.5 s for order 1, 0.8 s for the harmonic system).
_COMPILE_SECONDS: dict[int | str, float] = {1: 1.0, 2: 1.0, "harmonic": 1.0}


def eps_derivative_rhs(y: ArrayLike, body: Body) -> NDArray[np.float64]:
    """∂f/∂ε of ``body_frame_rhs`` at ε = 0, I2 = (1 + ε) I1, by the complex step (exact to round-off)."""
    a, I1, _, I3, g = body.params
    h = 1e-30
    out = body_frame_rhs(np.asarray(y, float).astype(complex), (a, I1, I1 * complex(1.0, h), I3, g))
    return np.array([complex(v).imag / h for v in out])


# functions of states (11,) or (11, N)
def _psi_of(y: NDArray[np.float64]) -> NDArray[np.float64]:
    return angles_from_frame(y[0:3], y[6:9])[2]


def _phi_of(y: NDArray[np.float64]) -> NDArray[np.float64]:
    return angles_from_frame(y[0:3], y[6:9])[1]


def _QR_of(body: Body) -> Callable[[NDArray[np.float64]], NDArray[np.float64]]:
    return lambda y: routh(body, y[0:3], y[3:6])


def _QJ_of(body: Body) -> Callable[[NDArray[np.float64]], NDArray[np.float64]]:
    return lambda y: jellett(body, y[0:3], y[3:6])


def _variational_system(order: int) -> list[tuple[Any, Any]]:
    """Form (i) with its variational equations in ε along a curve (y₀(ε), ε), to ``order`` 1 or 2: state (y, z) or
    (y, z, w), 22 or 33 components, ż = A z + ∂f/∂ε and ẇ = A w + D²f[z, z] + 2 ∂²f/∂y∂ε z + ∂²f/∂ε² (ẇ is ż's
    right-hand side differentiated along (z, w, ε)); parameters (a, I1, I3, g, ε) with I2 = (1 + ε) I1."""
    import heyoka as hy

    names = _STATE_NAMES
    y = hy.make_vars(*names)
    z = hy.make_vars(*("d" + n for n in names))
    w = hy.make_vars(*("dd" + n for n in names))
    a, I1, I3, g, eps = (hy.par[i] for i in range(5))
    f = body_frame_rhs(y, (a, I1, I1 * (1.0 + eps), I3, g))

    def along(exprs: list[Any], second: list[Any]) -> list[Any]:
        """∂e/∂ε + Σ_j ∂e/∂y_j z_j (+ Σ_j ∂e/∂z_j second_j) for each expression e."""
        out = []
        for e in exprs:
            acc = hy.diff(e, eps)
            for yj, zj in zip(y, z):
                acc = acc + hy.diff(e, yj) * zj
            for zj, sj in zip(z, second):
                acc = acc + hy.diff(e, zj) * sj
            out.append(acc)
        return out

    fz = along(f, [])
    eqs = list(zip(y, f)) + list(zip(z, fz))
    if order == 2:
        eqs += list(zip(w, along(fz, list(w))))
    return eqs


def rotate_about_axis(y: Any, psi: float) -> list[Any]:
    """S(ψ) y: the state of the symmetric body turned by ψ about its symmetry axis (the start at spin angle ψ_n + ψ
    from the start at ψ_n, ``_max_state``): γ, ω and the space X axis, in body components, turn by −ψ about e3; the
    contact point (X, Y) stays.  Works on numpy arrays (11,) or (11, N) and on heyoka expressions; S(0) is the
    identity, exactly.  :func:`turn` with (cos ψ, sin ψ)."""
    return list(y) if psi == 0.0 else turn(y, math.cos(psi), math.sin(psi))


def turn(y: Any, c: Any, s: Any) -> list[Any]:
    """S y for the turn with cosine c and sine s (:func:`rotate_about_axis`), in any arithmetic (exact rationals in
    the tests: Routh's sphere's f(S y) = S f(y) holds as an identity)."""
    out = []
    for i in (0, 3, 6):
        out += [c * y[i] + s * y[i + 1], -s * y[i] + c * y[i + 1], y[i + 2]]
    return out + [y[9], y[10]]


def _harmonic_system() -> list[tuple[Any, Any]]:
    """Form (i) with three first-order variational systems in ε along one orbit: state (y, ẑ_0, ẑ_1, ẑ_2), 44
    components, ẑ_k' = A ẑ_k + S_kᵀ ∂f/∂ε(S_k y) with S_k = ``rotate_about_axis``(·, ``HARMONIC_PSI[k]``).  By the
    symmetry f(S y) = S f(y) of Routh's sphere, the orbit from ψ_n = ψ_k is S_k y(t) and its response z_k = S_k ẑ_k
    (module docstring); parameters as :func:`_variational_system`'s."""
    import heyoka as hy

    y = hy.make_vars(*_STATE_NAMES)
    a, I1, I3, g, eps = (hy.par[i] for i in range(5))
    pars = (a, I1, I1 * (1.0 + eps), I3, g)
    f = body_frame_rhs(y, pars)
    jac = [[hy.diff(e, yj) for yj in y] for e in f]
    eqs = list(zip(y, f))
    for k, psi in enumerate(HARMONIC_PSI):
        z = hy.make_vars(*(f"d{k}{n}" for n in _STATE_NAMES))
        forcing = rotate_about_axis(body_frame_rhs(rotate_about_axis(y, psi), pars), -psi)
        for i, zi in enumerate(z):
            acc = hy.diff(forcing[i], eps)
            for j, zj in enumerate(z):
                acc = acc + jac[i][j] * zj
            eqs.append((zi, acc))
    return eqs


def _system(order: int | str) -> list[tuple[Any, Any]]:
    """The equations of :func:`_variational_system` (``order`` 1 or 2) or of :func:`_harmonic_system` ("harmonic")."""
    return _harmonic_system() if order == "harmonic" else _variational_system(int(order))


def _variational_integrator(order: int | str = 1, lanes: int | None = None) -> Any:
    """heyoka batch integrator of :func:`_variational_system` (``order`` 1 or 2) or of :func:`_harmonic_system`
    (``order`` "harmonic"), by default in lanes of heyoka's
    recommended SIMD width: one orbit per lane, each with its own steps (the lanes do not interact), so a batch runs
    several orbits for about the price of one (docs/slow_validation.md, "Cost"; ``lanes=1``: one orbit at a time).
    Compiled once per process, one copy per thread (threads may build tables side by side)."""
    import heyoka as hy

    lanes = int(hy.recommended_simd_size()) if lanes is None else int(lanes)
    key = f"batch{order}x{lanes}"
    mine = _PER_THREAD.__dict__.setdefault("integrators", {})
    if key in mine:
        return mine[key]
    with _INTEGRATOR_LOCK:
        if key not in _INTEGRATOR:
            eqs = _system(order)
            y = hy.make_vars("g1", "g2", "g3", "w1", "w2", "w3")
            ev = hy.t_event_batch(turning_point_function(y), callback=_NextMaximum())
            check_diskcache()
            what = "three harmonics" if order == "harmonic" else f"order {order}"
            with compiling(f"the averaging tables' variational integrator ({what}, {lanes} lanes)",
                           _COMPILE_SECONDS[order]):
                _INTEGRATOR[key] = hy.taylor_adaptive_batch(eqs, np.zeros((len(eqs), lanes)),
                                                            pars=np.zeros((5, lanes)), compact_mode=True, t_events=[ev])
        mine[key] = copy.deepcopy(_INTEGRATOR[key])
    return mine[key]


# ----------------------------------------------------------------------------- one orbit
@dataclass(frozen=True)
class FirstOrderStep:
    """One step maximum → maximum of the symmetric orbit with its first-order ε-responses.

    Attributes
    ----------
    QR, QJ, psi : float
        The starting point (Q_R, Q_J, ψ_n) at the maximum θ_X.  (Each field is an array for a batch of orbits,
        :func:`first_order_steps`.)
    theta_X : float
        The symmetric body's maximum for (E, Q_R, Q_J).
    T : float
        Time to the next maximum (symmetric orbit, event on dγ3/dt located to round-off).
    dpsi, dphi : float
        The symmetric increments of ψ and φ, wrapped to (−π/2, π/2] (mod π).
    d : dict
        ε-derivatives at fixed (E, Q_n, ψ_n) of Q_R, Q_J, Θ = 2ψ, the event time and φ at the
        next maximum (keys of ``FIRST_ORDER_NAMES``).
    """

    QR: float | NDArray[np.float64]
    QJ: float | NDArray[np.float64]
    psi: float | NDArray[np.float64]
    theta_X: float | NDArray[np.float64]
    T: float | NDArray[np.float64]
    dpsi: float | NDArray[np.float64]
    dphi: float | NDArray[np.float64]
    d: Mapping[str, float | NDArray[np.float64]]

    def at(self, *index: int) -> "FirstOrderStep":
        """The step of one orbit of a batch (fields of floats) at ``index`` of its arrays."""
        pick = (lambda v: float(np.asarray(v)[index]))  # noqa: E731
        return FirstOrderStep(QR=pick(self.QR), QJ=pick(self.QJ), psi=pick(self.psi), theta_X=pick(self.theta_X),
                              T=pick(self.T), dpsi=pick(self.dpsi), dphi=pick(self.dphi),
                              d={k: pick(v) for k, v in self.d.items()})


def _max_state(sym: Body, theta: ArrayLike, QR: ArrayLike, QJ: ArrayLike, psi: ArrayLike) -> NDArray[np.float64]:
    """The state(s) (11,) or (11, N) at the turning point θ with (Q_R, Q_J) and spin angle ψ."""
    st = state_from_turning_point(sym, theta, QR, QJ)
    return state_from_euler(theta, 0.0, psi, 0.0, st.phi_dot, st.psi_dot)


def _start(sym: Body, theta_X: NDArray[np.float64], QR: NDArray[np.float64], QJ: NDArray[np.float64],
           psi: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """The maxima y₀ (11, N) at spin angles ψ, ∂y₀/∂θ_X there and ∂U/∂θ at θ_X (central differences)."""
    hth = 1e-4 * np.minimum(theta_X, math.pi - theta_X)
    dU = _central_difference(lambda th: effective_potential(th, QR, QJ, sym), theta_X, hth)
    dy_dth = _central_difference(lambda th: _max_state(sym, th, QR, QJ, psi), theta_X, hth)
    return _max_state(sym, theta_X, QR, QJ, psi), dy_dth, dU


def _theta_shift(sym: Body, y0: NDArray[np.float64], dU: NDArray[np.float64]) -> NDArray[np.float64]:
    """∂θ_X/∂ε of the maxima y₀ at fixed (E, Q, ψ): −(∂E/∂ε)/(∂U/∂θ), E being linear in I2 = (1 + ε) I1; the
    start's ε-derivative is z(0) = ∂y₀/∂θ_X ∂θ_X/∂ε."""
    e_half = 0.5 * (sym.I3 / sym.I1 - 1.0)
    dE_deps = (energy(sym.with_epsilon(e_half), y0[0:3], y0[3:6]) - energy(sym, y0[0:3], y0[3:6])) / e_half
    return -dE_deps / dU


def _responses(sym: Body, Y: NDArray[np.float64],
               Z: NDArray[np.float64]) -> dict[str, float | NDArray[np.float64]]:
    """The first-order responses (keys of ``FIRST_ORDER_NAMES``) from the states Y (11, N) at the next maxima and
    their ε-derivatives Z there, the event time's shift included (module docstring)."""
    fY = np.array(body_frame_rhs(Y, sym.params))
    dt1 = -directional_derivative(turning_point_function, Y, Z) / directional_derivative(turning_point_function, Y, fY)
    dY = Z + fY * dt1
    return {
        "QR": directional_derivative(_QR_of(sym), Y, dY),
        "QJ": directional_derivative(_QJ_of(sym), Y, dY),
        "Theta": 2.0 * directional_derivative(_psi_of, Y, dY, angle=True),
        "t": dt1,
        "phi": directional_derivative(_phi_of, Y, dY, angle=True),
    }


def first_order_steps(body: Body, E: float, QR: ArrayLike, QJ: ArrayLike, psi: ArrayLike,
                      theta_X: ArrayLike | None = None, *, lanes: int | None = None) -> FirstOrderStep:
    """:func:`first_order_step` for N starts at once (arrays of one shape, or scalars broadcast to it), their orbits
    run side by side in the lanes of the batch integrator (``lanes``: :func:`_variational_integrator`); the
    FirstOrderStep's fields are then arrays (N,) (:meth:`FirstOrderStep.at` picks one).  θ_X: the maxima
    θ_X(E, Q_R, Q_J) if known, else from ``reduction.turning_points``."""
    sym = body.symmetric()
    given = [v for v in (QR, QJ, psi, theta_X) if v is not None]
    flat = [np.ravel(v) for v in np.broadcast_arrays(*(np.asarray(v, float) for v in given))]
    QR, QJ, psi = flat[:3]
    theta_X = flat[3] if theta_X is not None else np.asarray(turning_points(E, QR, QJ, sym)[1], float)
    y0, dy_dth, dU = _start(sym, theta_X, QR, QJ, psi)
    t1, out = _to_next_maxima(1, sym, np.concatenate([y0, dy_dth * _theta_shift(sym, y0, dU)]), lanes)
    Y = out[:11]
    return FirstOrderStep(QR=QR, QJ=QJ, psi=psi, theta_X=theta_X, T=t1, dpsi=wrap_angle(_psi_of(Y) - psi, math.pi),
                          dphi=wrap_angle(_phi_of(Y) - _phi_of(y0), math.pi), d=_responses(sym, Y, out[11:]))


def first_order_step(body: Body, E: float, QR: float, QJ: float, psi: float, *,
                     theta_X: float | None = None) -> FirstOrderStep:
    """Integrate one step of the symmetric orbit and its first-order variational equations in ε.

    Parameters
    ----------
    body : Body
        Any body; its symmetric part (a, I1, I3, g) is used, with I2 = (1 + ε) I1.
    E : float
        The energy (exact, conserved by the asymmetric body too); for a release from rest at θ0,
        :func:`rest_energy`.
    QR, QJ : float
        Routh's and Jellett's quantities at the starting maximum.
    psi : float
        Spin angle ψ_n at the starting maximum.
    theta_X : float, optional
        The maximum θ_X(E, Q_R, Q_J) if already known (``reduction.turning_points``).
    """
    return first_order_steps(body, E, QR, QJ, psi, theta_X).at(0)


class _NextMaximum:
    """Terminal batch event callback on dγ3/dt (any direction): a lane's falling root is its θ-minimum (the lane goes
    on); its first rising root after that is the next θ-maximum, where the lane stops.  A rising root before the
    minimum is the start's own (the start is a maximum, dγ3/dt = 0 to its rounding) and is passed over."""

    def __init__(self) -> None:
        self.passed_min: NDArray[np.bool_] = np.zeros(0, bool)

    def reset(self, lanes: int) -> None:
        self.passed_min = np.zeros(lanes, bool)

    def __call__(self, ta: Any, d_sgn: Any, lane: int) -> bool:
        if int(d_sgn) < 0:
            self.passed_min[lane] = True
            return True
        return not self.passed_min[lane]


#: Most integration steps from a maximum to the next (a bound on one rocking period's: a few dozen are taken).
_MAX_STEPS_TO_MAXIMUM = 100_000


def _to_next_maxima(order: int | str, sym: Body, x0: NDArray[np.float64],
                    lanes: int | None = None) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Integrate the variational system of ``order`` (form (i) in its first 11 components, variational ones after)
    from the maxima x0[:11, k] at t = 0 with ε = 0 to the next maximum of θ, ``x0`` of shape (components, N), in
    batches of the integrator's lanes (the last padded with copies).  Each lane stops at its own next maximum, a
    terminal event of heyoka's batch integrator (:class:`_NextMaximum`), located by heyoka on the Taylor series of
    dγ3/dt and the state propagated to it there.  Returns (t1 (N,), the states at t1 (·, N))."""
    tb = _variational_integrator(order, lanes)
    lanes, n = tb.batch_size, x0.shape[1]
    watch = tb.t_events[0].callback
    t1, out = np.empty(n), np.empty_like(x0)
    for first in range(0, n, lanes):
        take = np.minimum(np.arange(first, first + lanes), n - 1)
        tb.set_time(np.zeros(lanes))
        tb.reset_cooldowns()
        tb.state[:] = x0[:, take]
        tb.pars[:] = np.array([sym.a, sym.I1, sym.I3, sym.g, 0.0])[:, None]
        watch.reset(lanes)
        # a batch's propagation returns at the end of the step in which some lane's event stopped it (outcome
        # -1 - i: terminal event i), the other lanes mid-way: they go on, the stopped ones are held where they are
        stopped, steps = np.zeros(lanes, bool), 0
        while not stopped.all():
            if steps > _MAX_STEPS_TO_MAXIMUM:
                raise RuntimeError(f"no next maximum of theta found within {_MAX_STEPS_TO_MAXIMUM} steps")
            tb.propagate_until(np.where(stopped, tb.time, np.finfo(float).max), max_steps=_MAX_STEPS_TO_MAXIMUM)
            stopped |= np.array([res[0].value == -1 for res in tb.propagate_res])
            steps += max(int(res[3]) for res in tb.propagate_res)
        keep = slice(0, min(lanes, n - first))
        t1[first:first + lanes] = np.asarray(tb.time)[keep]
        out[:, first:first + lanes] = np.asarray(tb.state)[:, keep]
    return t1, out


def second_order_step(body: Body, E: float, QR: float, QJ: float, psi: float, *,
                      h: float = 1e-3) -> dict[str, float]:
    """Second ε-derivatives at fixed (E, Q_n, ψ_n) of Q_R, Q_J, Θ = 2ψ, the event time and φ at the next maximum
    (keys of ``FIRST_ORDER_NAMES``), by the second-order variational equations: a second formulation of what
    :func:`rocknroller.analysis.slow.map.exact_step.eps_derivatives` differences.  One start of
    :func:`second_order_steps`, which documents the method."""
    out = second_order_steps(body, E, QR, QJ, psi, h=h)
    return {k: float(v[0]) for k, v in out.items()}


def second_order_steps(body: Body, E: float, QR: ArrayLike, QJ: ArrayLike, psi: ArrayLike,
                       theta_X: ArrayLike | None = None, *, h: float = 1e-3) -> dict[str, NDArray[np.float64]]:
    """:func:`second_order_step` for N starts at once (arrays of one shape, or scalars broadcast to it; raveled),
    their orbits run side by side in the lanes of the batch integrator; each value an array (N,).  θ_X: the
    symmetric maxima θ_X(E, Q_R, Q_J) if known, else from one vectorised ``turning_points`` for all starts.

    The start's curve y₀(ε) (the maximum with the same (E, Q, ψ) for I2 = (1 + ε) I1,
    :func:`rocknroller.analysis.slow.map.family.maximum_state`) is differenced in ε (step ``h``, fourth order: it is an
    algebraic solve, smooth on the scale of ε ~ 1); the flow's first and second derivatives along it are integrated
    (:func:`_variational_integrator` of order 2); the event time t₁(ε) of the next maximum, h(G(ε)) = 0 with
    G(ε) = y(t₁(ε)) and h = dγ3/dt (quadratic), follows from
    t₁' = −∇h·Z / ∇h·F and ∇h·G'' + D²h[G', G'] = 0, G' = Z + F t₁', G'' = W + 2 Ż t₁' + (A F) t₁'² + F t₁''.
    The outputs q(G) have q'' = ∇q·G'' + D²q[G', G'] (directional differences of q, exact for the quadratic Q_J).
    """
    sym = body.symmetric()
    given = [v for v in (QR, QJ, psi, theta_X) if v is not None]
    flat = [np.ravel(v) for v in np.broadcast_arrays(*(np.asarray(v, float) for v in given))]
    QR, QJ, psi = flat[:3]
    theta_X = flat[3] if theta_X is not None else np.asarray(turning_points(E, QR, QJ, sym)[1], float)
    x0 = np.empty((33, len(QR)))
    for k in range(len(QR)):
        args = (E, float(QR[k]), float(QJ[k]), float(psi[k]))

        def start(eps: float, args: tuple[float, ...] = args, thX: float = float(theta_X[k])) -> NDArray[np.float64]:
            st = maximum_state(sym, eps, *args, theta_X=thX)[2]  # the family's frame: the requested ψ
            return state_from_euler(st.theta, 0.0, args[3], 0.0, st.phi_dot, st.psi_dot)

        start = functools.lru_cache(maxsize=None)(start)  # the five solves are shared by both differences
        x0[:, k] = np.concatenate([start(0.0), _central_difference(start, 0.0, h),
                                   _central_second_difference(start, 0.0, h)])
    out = _to_next_maxima(2, sym, x0)[1]
    res = [_second_derivatives(sym, out[:, k]) for k in range(len(QR))]
    return {name: np.array([r[name] for r in res]) for name in FIRST_ORDER_NAMES}


def _second_derivatives(sym: Body, out: NDArray[np.float64]) -> dict[str, float]:
    """The second ε-derivatives of the outputs of one step from the state (Y, Z, W) (33,) at the next maximum
    (:func:`second_order_steps`)."""
    Y, Z, W = out[:11], out[11:22], out[22:]
    p0 = sym.params

    def rhs(v: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.array(body_frame_rhs(v, p0))

    F = rhs(Y)
    Zdot = _central_difference(lambda s: rhs(Y + s * Z), 0.0, 1e-4) + eps_derivative_rhs(Y, sym)
    AF = _central_difference(lambda s: rhs(Y + s * F), 0.0, 1e-4)

    def grad_h(v: NDArray[np.float64]) -> float:  # ∇h·v; h = dγ3/dt is quadratic: the differences are exact
        return float(directional_derivative(turning_point_function, Y, v))  # Y: one state, a float

    t1p = -grad_h(Z) / grad_h(F)
    G1 = Z + F * t1p
    partial = W + 2.0 * Zdot * t1p + AF * t1p * t1p
    t1pp = -(grad_h(partial) + _second_directional(turning_point_function, Y, G1)) / grad_h(F)
    G2 = partial + F * t1pp

    def second(fun: Callable[[NDArray[np.float64]], float | NDArray[np.float64]], angle: bool = False) -> float:
        return (float(directional_derivative(fun, Y, G2, angle=angle))
                + _second_directional(fun, Y, G1, angle=angle))

    return {"QR": second(_QR_of(sym)), "QJ": second(_QJ_of(sym)), "Theta": 2.0 * second(_psi_of, angle=True),
            "t": t1pp, "phi": second(_phi_of, angle=True)}


def symmetric_data(sym: Body, E: float, QR: ArrayLike, QJ: ArrayLike) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """(T_θ, W, Δφ mod π, θ_X) at energy E from the quadratures, vectorised."""
    pr = precession(E, QR, QJ, sym, rtol=1e-12)  # W errors are amplified by the twist: full precision
    bad = np.asarray(pr.status) != 0
    if np.any(bad):
        raise ValueError(f"the symmetric quadrature failed at some Q (status {pr.status_text()[bad][:3]})")
    return (np.asarray(pr.T_theta, float), np.asarray(wrap_angle(2.0 * np.asarray(pr.delta_psi) - 2.0 * math.pi)),
            np.asarray(pr.visible_half_phi, float), np.asarray(pr.theta_X, float))
