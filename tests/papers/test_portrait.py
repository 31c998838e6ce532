"""The phase portrait of the slow motion (:mod:`rocknroller.papers.portrait`): its orbits are the map's, p is the
standard map's, its files are written, bad input refused."""

from __future__ import annotations

import math
import types
import warnings

import numpy as np
import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.dynamics.chaos import map_indicators
from rocknroller.analysis.model.equations import EulerState
from rocknroller.analysis.slow.map.compiled_map import iterate_slow_map
from rocknroller.analysis.slow.map.family import rest_energy
from rocknroller.analysis.slow.map.limits import AveragingRangeError, AveragingValidityWarning
from rocknroller.analysis.slow.prediction import load_or_build_table, predict_slow_motion
from rocknroller.numerics.integrate import simulate
from rocknroller.numerics.megno import MIN_SAMPLES
from rocknroller.numerics.variational import direct_chaos_indicators
from rocknroller.papers.portrait import (MAX_PORTRAIT_ORBITS, orbit_values, plot_portrait, portrait_values,
                                         slow_portrait, theta0_of_energy)
from rocknroller.papers.portrait_output import write_portrait

THETA0 = 0.95 * math.pi


def test_release_line_orbits_are_the_predictions_and_the_ode_overlay_is_the_direct_run(tmp_path):
    """A grid start on p = 0 is the release from rest at ψ0 = Θ/2: its orbit is predict_slow_motion's bit for bit, at
    the one default order of both (default_order: 2).  The ODE overlay of that start is the direct run from rest (maximum_state at Q = 0 gives θ0 to
    rounding: maxima within 1e-10 in Q over 15 rocks, far below the map's own error).  The figure and the CSV are
    written, the CSV with one row per sample and the parameters in its header."""
    body = Body.paper(5e-3)
    P = slow_portrait(body, THETA0, [0.2, 1.0, 2.5], [0.0, 1.0], 200.0, ode_starts=[(0.2, 0.0)], progress=False)
    assert P.Theta0.tolist() == [0.2, 0.2, 1.0, 1.0, 2.5, 2.5] and P.p0.tolist() == [0.0, 1.0] * 3
    for k in (0, 2, 4):
        pred = predict_slow_motion(body, THETA0, 0.5 * P.Theta0[k], 200.0)
        assert P.order == pred.order == 2
        for name in ("t", "QR", "QJ", "Theta"):
            np.testing.assert_array_equal(getattr(P.orbits[k], name), getattr(pred.series, name))
    ode = simulate(body, EulerState(THETA0, 0.0, 0.1), 200.0, samples=False).maxima
    (m,) = P.ode
    assert len(m) == len(ode)
    assert np.max(np.hypot(m.QR - ode.QR, m.QJ - ode.QJ)) < 1e-10
    paths = write_portrait(P, tmp_path)
    assert sorted(p.name for p in paths) == ["portrait.csv", "portrait.pdf", "portrait.png", "portrait_orbits.csv"]
    assert all(p.stat().st_size > 0 for p in paths)
    text = (tmp_path / "portrait.csv").read_text().splitlines()
    header = [ln for ln in text if ln.startswith("#")]
    rows = [ln for ln in text if not ln.startswith("#")]
    assert any("K = eps kappa" in ln for ln in header) and any("value: MEGNO" in ln for ln in header)
    assert rows[0] == "source,orbit,Theta0,p0,value,t,Theta,p,QR,QJ"
    assert len(rows) - 1 == sum(o.t.size for o in P.orbits) + len(m)


def test_p_is_the_standard_map_momentum():
    """One step from (Θ0, p = 0): the standard map gives p1 = K sin Θ0 (K = ε κ from the table).  The map's p1 differs
    by O(ε²) relatively (the kick is ε C0 sin Θ + O(ε²) at Q = O(ε)): the deviation falls 4× per halving of ε."""
    dev = []
    for eps in (5e-3, 2.5e-3):
        P = slow_portrait(Body.paper(eps), THETA0, [0.5, 1.0, 2.0], [0.0], 100.0, progress=False, order=1)
        p1 = np.array([P.p(o.QR[0], o.QJ[0]) for o in P.orbits])
        dev.append(np.max(np.abs(p1 / (P.K * np.sin(P.Theta0)) - 1.0)))
        assert P.K == pytest.approx(eps * load_or_build_table(Body.paper(eps), THETA0).kappa, rel=1e-15)
    assert dev[0] < 1e-3
    assert 3.6 < dev[0] / dev[1] < 4.4  # slope 2 within ±0.15 in log2


def test_orbits_that_leave_the_tables_are_cut_and_listed():
    """At ε = 1e-2 (K = 4.3) starts at 0.99 of the tables' reach in p leave them within a step or two: listed in
    ``left``, each drawn up to its last maximum inside (one step more leaves)."""
    body = Body.paper(1e-2)
    table = load_or_build_table(body, THETA0)
    P0 = slow_portrait(body, THETA0, [1.0], [0.0], 50.0, progress=False)
    reach = abs(float(P0.grad_W @ P0.e)) * table.U
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AveragingValidityWarning)
        P = slow_portrait(body, THETA0, [math.pi / 2, -math.pi / 2], [0.99 * reach, -0.99 * reach], 300.0,
                          progress=False)
    assert P.left and set(P.left) <= set(range(4))
    assert any(P.orbits[k].t.size < MIN_SAMPLES for k in P.left)
    for k in P.left:  # too short for indicators: no MEGNO (grey in the figure), never a number made up
        assert (P.chaos[k] is None) == (P.orbits[k].t.size < MIN_SAMPLES)
        assert math.isnan(P.megno[k]) == (P.orbits[k].t.size < MIN_SAMPLES)
        n = P.orbits[k].t.size
        with pytest.raises(AveragingRangeError):
            iterate_slow_map(table, body.epsilon, 0.5 * P.Theta0[k], 300.0, Q0=(P.p0[k] / float(P.grad_W @ P.e)) * P.e,
                             n_steps=n + 1)


def test_orbit_values():
    orbits = [object(), object(), object()]
    v, label = orbit_values(orbits)
    assert label == "orbit index" and v.tolist() == [0.0, 1.0, 2.0]
    v, label = orbit_values(orbits, [3.0, 2.0, 1.0])
    assert label == "value" and v.tolist() == [3.0, 2.0, 1.0]
    chaotic = [types.SimpleNamespace(chaos=types.SimpleNamespace(megno=m)) for m in (2.0, 2.1, 9.5)]
    v, label = orbit_values(chaotic)
    assert label == "MEGNO" and v.tolist() == [2.0, 2.1, 9.5]
    v, label = orbit_values(chaotic[:2] + [object()])  # not every orbit has one: the index
    assert label == "orbit index"
    for bad in ([1.0, 2.0], [1.0, math.nan, 2.0]):
        with pytest.raises(ValueError, match="values must be 3 finite numbers"):
            orbit_values(orbits, bad)


def test_theta0_of_energy_inverts_the_rest_energy():
    sym = Body.paper(0.0)
    for th in (0.8 * math.pi, THETA0, 0.99 * math.pi):
        assert theta0_of_energy(Body.paper(5e-3), rest_energy(sym, th)) == pytest.approx(th, rel=1e-14)
    with pytest.raises(ValueError, match="E must be the energy"):
        theta0_of_energy(sym, 10.0)


@pytest.mark.parametrize("kwargs, match", [
    (dict(body=Body.paper(0.0)), "eps must be > 0"),
    (dict(theta0=0.5 * math.pi), "theta0"),
    (dict(Theta=[7.0]), "Theta must be"),
    (dict(p=[1e3]), "p must be"),
    (dict(Theta=np.linspace(0, 1, 101), p=np.linspace(-1, 1, 100)), "MAX_PORTRAIT_ORBITS"),
    (dict(order=3), "order must be 1 or 2"),
    (dict(ode_starts=[(1.0,)]), "ode_starts must be"),
    (dict(ode_starts=[(1.0, 1e3)]), "ode_starts p"),
    (dict(ode_starts=[(0.2, 0.0)], ode_t_end=-1.0), "t_end"),
    (dict(t_end=math.inf), "t_end"),
    (dict(chaos="yes"), "chaos must be True or False"),
])
def test_bad_input_is_refused(kwargs, match):
    assert 101 * 100 > MAX_PORTRAIT_ORBITS
    args = dict(body=Body.paper(5e-3), theta0=THETA0, Theta=[1.0], p=[0.0], t_end=100.0) | kwargs
    with pytest.raises(ValueError, match=match):
        slow_portrait(args.pop("body"), args.pop("theta0"), args.pop("Theta"), args.pop("p"), **args, progress=False)


def test_orbits_are_coloured_by_their_megno(tmp_path):
    """By default each orbit carries the map's indicators over the span slow measures over, max(t_end, 1000 rocks): for
    a release (p = 0) they are predict_slow_motion's to the bit (span, MEGNO, λ; its verdict is slow's), whatever
    t_end (a portrait over 1000 time units and one over 300 agree: one span rule).  Each orbit is coloured by its
    MEGNO: at ε = 5e-3, θ0 = 0.95π (K = 2.1) the release at ψ0 = 0.05 (Θ = 0.1) lies in the separatrix's chaotic
    layer (MEGNO > 3), as the direct motion's MEGNO over 1000 time units says too, and the one near the stable
    rocking (Θ = 3.0, ψ0 = 1.5) is regular.  The orbits are those of a
    portrait without indicators (chaos=False, coloured by index) to the bit; values override the colours."""
    body = Body.paper(5e-3)
    P = slow_portrait(body, THETA0, [0.1, 3.0], [0.0], 1000.0, progress=False)
    short = slow_portrait(body, THETA0, [0.1, 3.0], [0.0], 300.0, progress=False)
    for k in range(2):
        pred = predict_slow_motion(body, THETA0, 0.5 * P.Theta0[k], 1000.0)
        for chaos in (P.chaos[k], short.chaos[k]):
            assert (chaos.span, chaos.megno, chaos.lyapunov) == (pred.chaos.span, pred.chaos.megno, pred.chaos.lyapunov)
            assert chaos.verdict == pred.chaos.verdict and chaos.span > 1000.0
    assert P.megno[0] > 3.0 >= P.megno[1]
    for k, psi0 in ((0, 0.05), (1, 1.5)):
        ode = direct_chaos_indicators(body, EulerState(THETA0, 0.0, psi0), 1000.0).indicators
        assert ode.regular == P.chaos[k].regular, (psi0, ode.megno, P.megno[k])
    vals, label = portrait_values(P)
    assert label == "MEGNO" and vals.tolist() == P.megno.tolist()
    assert portrait_values(P, [5.0, 6.0]) == (pytest.approx([5.0, 6.0]), "value")
    plain = slow_portrait(body, THETA0, [0.1, 3.0], [0.0], 1000.0, progress=False, chaos=False)
    assert plain.chaos == () and portrait_values(plain)[1] == "orbit index"
    for a, b in zip(P.orbits, plain.orbits):
        np.testing.assert_array_equal(a.QR, b.QR)
        np.testing.assert_array_equal(a.Theta, b.Theta)
    with pytest.raises(ValueError, match="no chaos indicators"):
        plain.megno
    with pytest.raises(ValueError, match="orbits must be 2 objects"):
        portrait_values(P, orbits=[object()])
    fig = plot_portrait(P)
    assert fig.axes[-1].get_ylabel().startswith("MEGNO (clipped at 5")
    write_portrait(P, tmp_path)
    rows = [ln.split(",") for ln in (tmp_path / "portrait.csv").read_text().splitlines() if not ln.startswith("#")]
    value = {int(r[1]): float(r[4]) for r in rows[1:] if r[0] == "map"}
    assert value == {0: P.megno[0], 1: P.megno[1]}


def test_chaotic_orbits_are_drawn_over_the_regular_ones_and_tick_labels_stay_apart(tmp_path):
    """The dots of both panels are drawn in the order of their MEGNO (grey, unmeasured, first): every chaotic
    maximum (MEGNO > 3) comes after every regular one, so that none hides under a regular orbit on the (Q_R, Q_J)
    line.  At ε = 3e-4, θ0 = 0.8π the (Q_R, Q_J) panel's x tick labels (−0.025 … 0.025 in steps of 0.005) ran into
    each other; no two drawn tick labels of either panel overlap now."""
    from matplotlib.collections import PathCollection

    from figure_checks import draw, overlapping, tick_labels

    P = slow_portrait(Body.paper(5e-3), THETA0, [0.1, 3.0, 6.0], None, 1000.0, progress=False)
    assert np.any(P.megno > 3.0) and np.any(P.megno <= 3.0)
    fig = plot_portrait(P)
    fig.savefig(tmp_path / "chaotic.png")
    for ax in fig.axes[:2]:
        dots = max((c for c in ax.collections if isinstance(c, PathCollection)), key=lambda c: len(c.get_offsets()))
        drawn = np.ma.filled(dots.get_array(), np.nan)
        assert drawn.size == sum(s.t.size for s in P.orbits)
        chaotic = np.flatnonzero(drawn > 3.0)
        regular = np.flatnonzero(drawn <= 3.0)
        assert chaotic.size and regular.size and chaotic.min() > regular.max()
    narrow = slow_portrait(Body.paper(3e-4), 0.8 * math.pi, [0.1, 3.0, 6.0], None, 500.0, progress=False)
    fig = plot_portrait(narrow)
    fig.savefig(tmp_path / "narrow.png")
    draw(fig)
    for ax in fig.axes[:2]:
        for axis in (ax.xaxis, ax.yaxis):
            labels = tick_labels(axis)
            assert len(labels) >= 3 and overlapping(fig, labels) == []


def test_each_orbit_lists_its_verdict_and_horizon_as_a_release_would():
    """The portrait's rows carry every orbit's verdict, MEGNO, λ, span and horizon; on the release line (p = 0) an
    orbit is the release from rest at ψ0 = Θ0/2, so its verdict and horizon are ``predict_slow_motion``'s at the same
    order, over the one span rule max(t_end, 1000 rocks), to the bit (the same map orbit, the same direct probe)."""
    from rocknroller.papers.portrait_output import orbit_rows

    body = Body.paper(5e-3)
    theta0, t_end = 0.93 * math.pi, 1000.0
    portrait = slow_portrait(body, theta0, [0.1, 1.0], [0.0], t_end, order=1, progress=False)
    rows = orbit_rows(portrait)
    assert {"verdict", "megno", "lyapunov", "span", "horizon", "horizon_method"} <= set(rows)
    for k, th in enumerate(portrait.Theta0):
        pred = predict_slow_motion(body, theta0, 0.5 * th, t_end, order=1)  # its default span: slow's
        h = pred.horizon_estimate()
        assert rows["verdict"][k] == pred.chaos.verdict
        assert rows["megno"][k] == pred.chaos.megno
        assert rows["horizon"][k] == h.t and rows["horizon_method"][k] == h.method


def test_the_orbits_horizons_are_costed_before_any_direct_run(monkeypatch):
    """Each orbit's horizon costs a direct run of PROBE_ROCKS rocks: the estimate grows with the orbits, and a budget
    below it refuses before any run (the direct ODE is not called)."""
    from rocknroller.numerics.budget import WorkBudgetError
    from rocknroller.papers import portrait_output

    body = Body.paper(5e-3)
    portrait = slow_portrait(body, 0.93 * math.pi, [0.1, 1.0], [0.0], 300.0, order=1, progress=False)
    one = portrait_output.horizons_seconds(body, portrait.theta0, 1)
    assert one > 0.0 and portrait_output.horizons_seconds(body, portrait.theta0, 7) == pytest.approx(7 * one)

    def no_run(*args, **kwargs):
        raise AssertionError("a direct run started")

    monkeypatch.setattr("rocknroller.numerics.integrate.simulate", no_run)
    with pytest.raises(WorkBudgetError, match="horizons of 2 orbits"):
        portrait_output.orbit_rows(portrait, budget=0.5 * 2 * one)
