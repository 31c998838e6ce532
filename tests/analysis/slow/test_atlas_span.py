"""One span and one order for a start, wherever it is asked (``analysis/slow/atlas.py``): an atlas measures its chaos
layer over the span ``slow`` uses, max(t_end, 1000 rocks), at its named order, so a start taken from an atlas row gets
the same MEGNO, Lyapunov exponent and verdict from ``predict_slow_motion`` to the bit; the direct motion's indicators
that confirm the layer run over the same span."""

from __future__ import annotations

import math

import pytest

from rocknroller.analysis.model.body import Body
from rocknroller.analysis.slow.atlas import atlas_from_rest, atlas_seconds
from rocknroller.analysis.slow.atlas_check import chaos_span
from rocknroller.analysis.slow.prediction import predict_slow_motion

BODY = Body.paper(3e-3)
THETA0 = (0.9 * math.pi, 0.95 * math.pi)
PSI0 = (0.1, 0.7, 1.3)


@pytest.mark.parametrize("order", [1, 2])
def test_atlas_rows_get_slow_s_indicators_to_the_bit(order):
    """Six starts (two rows, three columns; regular and chaotic ones at ε = 3e-3) over t_end = 300, at each order:
    the atlas's MEGNO and λ equal the prediction's, bit for bit (the same tables, the same span, the same run); its
    span is the prediction's, 1000 rocks here, not t_end (it was t_end: one start, two verdicts)."""
    atlas = atlas_from_rest(BODY, THETA0, PSI0, 300.0, order=order, progress=False)
    assert atlas.order == order
    for i, t0 in enumerate(THETA0):
        for j, p0 in enumerate(PSI0):
            chaos = predict_slow_motion(BODY, t0, p0, 300.0, order=order).chaos
            assert atlas.values["megno"][i, j] == chaos.megno
            assert atlas.values["lyapunov"][i, j] == chaos.lyapunov
            assert bool(atlas.regular[i, j]) == chaos.regular
            span = chaos_span(BODY, t0, 300.0)
            assert span > 300.0 and span - 20.0 < chaos.span <= span  # the last maximum within one rock (< 20)


def test_the_estimate_counts_the_span():
    """The atlas's work estimate grows with the span of its chaos layer, not with t_end alone."""
    plain, _ = atlas_seconds(BODY, THETA0, 1000, 300.0, chaos=False, build=False, order=1)
    layer, _ = atlas_seconds(BODY, THETA0, 1000, 300.0, chaos=True, build=False, order=1)
    assert layer > 10 * plain  # 1000 rocks (~8000-13000 time units) against 300, with the tangent vector


def test_bad_order_is_refused():
    with pytest.raises(ValueError, match="order must be 1 or 2"):
        atlas_from_rest(BODY, THETA0, PSI0, 300.0, order=3)
