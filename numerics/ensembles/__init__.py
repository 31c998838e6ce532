"""Many direct runs at once, on top of the single run of :mod:`rocknroller.numerics.integrate`.

In the order data flows through them:

``batch``
    Runs in the lanes of heyoka's batch integrator (the CPU's SIMD width), each lane with its own body, t_end, events
    and stretches.
``lanes``
    How many lanes the ensembles use by default: heyoka's recommendation, or the width ``rocknroller warm`` measured
    faster on this machine.
``ensemble``
    Many runs at once: in this process, in threads, or on a dask.distributed cluster, boiled down to plain summaries.
"""
