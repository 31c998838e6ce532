"""The ε-averaged slow motion of (Q_R, Q_J) of the rock'n'roller, ε = (I2 − I1)/I1, to second order.

By stage, in the order data flows through them:

``map``
    The slow map and its tables: the limits of the averaging, the family and its starts, the variational orbit, the
    exact step, the charts, the release, region and second-order tables, and the compiled iteration (C kernel).
``dynamics``
    What the map's orbits do: the chaos indicators and the predictability horizon, the closed form near pure rocking,
    the period doubling of stable rocking and the periodic orbits.

On top of both, the answers users ask for:

``prediction``
    :func:`predict_slow_motion`: the prediction from a release or a state, with its diagnostics, chaos indicators
    and predictability horizon.
``atlas``
    The slow motion over a plane of starts, by the map or the direct ODE.
``ensemble_statistics``
    Where the slow motion is chaotic: statistics over a ball of starts, by the map and the direct ODE, and their test.
"""
