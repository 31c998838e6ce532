"""What the slow map's orbits do, from the map and its tables (:mod:`rocknroller.analysis.slow.map`).

In the order data flows through them:

``chaos``
    Order and chaos of the map: its chaos indicators (MEGNO, Lyapunov exponent) from a tangent vector carried through
    the compiled map, its per-step error against the exact step, and the predictability horizon.
``pendulum``
    The closed form near pure rocking: the standard map and its pendulum limit.
``period_doubling``
    The period doubling of stable rocking, from the exact step.
``periodic_orbits``, ``periodic_starts``
    Periodic orbits of the slow map and of the exact step, and their continuation in ε; the one a release lies on.
``reversibility``, ``flow_volume``
    Is the chaos conservative? The exact map's reversors, log Π det DP around cycles, the Lyapunov sums forward and
    backward; the flow's volume along long direct runs and Livšic's test on its close returns.
``result_plots``, ``atlas_figure``
    The figures of the results above (the API's ``.plot()`` and the commands' figures alike).
"""
