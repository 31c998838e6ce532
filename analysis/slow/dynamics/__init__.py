"""What the slow map's orbits do, from the map and its tables (:mod:`rocknroller.analysis.slow.map`).

In the order data flows through them:

``chaos``
    Order and chaos of the map: its chaos indicators (MEGNO, Lyapunov exponent) from a tangent vector carried through
    the compiled map, its per-step error against the exact step, and the predictability horizon.
``pendulum``
    The closed form near pure rocking: the standard map and its pendulum limit.
``period_doubling``
    The period doubling of stable rocking, from the exact step.
``periodic_orbits``
    Periodic orbits of the slow map and of the exact step, and their continuation in ε.
"""
