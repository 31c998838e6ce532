"""Integrating the model: the direct equations of motion of :mod:`rocknroller.analysis.model`, run and recorded.

Imports only :mod:`rocknroller.analysis.model`.  In the order data flows through them:

``provenance``
    The package version that stamps results.
``cache``
    The on-disk cache of plain arrays (key and checksum, never pickle) and the bounded in-memory caches.
``parallel``
    Blocks of independent work on "spawn" processes, with progress (table builds, atlases).
``events``
    The turning points of a stretch: the start's own root, the integrator's events checked and located on the
    dense output (of one run, or of several lanes evaluated together).
``trajectory``
    :class:`~rocknroller.numerics.trajectory.Trajectory` and the turning points of a run, with their diagnostics,
    φ and ψ unwrapped on the dense output; ``trajectory_plots`` its quick-look plots.
``run_limits``
    The limits of one run, checked before any work (:func:`~rocknroller.numerics.run_limits.check_run`), and the
    accuracy knob ``tol`` of the direct runs: its range, and what scales with it (the energy check, the smallest tilt
    resolved).
``backends``
    The two integrators, advanced stretch by stretch: heyoka's Taylor integrator, compiled once per process, and
    scipy's DOP853.
``integrate``
    :func:`~rocknroller.numerics.integrate.simulate`: heyoka's Taylor integrator (or scipy's DOP853) with every
    turning point of θ found as an event.
``megno``
    Chaos indicators of an orbit sampled at its θ-maxima (MEGNO, the finite-time Lyapunov exponent): one formula
    for the direct motion and the averaged slow map.
``variational``
    The direct motion's chaos indicators: heyoka's variational equations along the ODE, a tangent vector sampled and
    renormalised at the θ-maxima (:func:`~rocknroller.numerics.variational.direct_chaos_indicators`).
``ensembles``
    Many runs at once, on top of the rest: in the lanes of heyoka's batch integrator (``batch``), in this process, in
    threads, or on a dask.distributed cluster (``ensemble``).
"""
