"""The slow map and its tables, the lowest stage of the slow motion.

In the order data flows through them:

``limits``
    Where the averaged map applies, how long a run may be, the stable rocking axis and the period-doubling threshold.
``family``
    The family I2 = (1 + ε) I1 and where a slow orbit starts on it: the rest energy, the maximum of θ of a member
    with given (E, Q_R, Q_J, ψ), the first maximum of θ of any start, the differences along the family.
``orbit``
    One step maximum → maximum of Routh's sphere with its first- and second-order ε-responses (variational
    equations, heyoka).
``exact_step``
    The same step of the asymmetric body by the direct ODE, and its ε-derivatives by differences.
``chart``
    The charts of the tables (release, spindle, band) and their Chebyshev series (:class:`SlowMapTable`,
    :class:`SecondOrderTable`).
``table``
    Building, fitting, checking and caching the tables (the release tables built here).
``region``
    The region tables of one energy, for starts with velocity.
``compiled_map``
    The run-time form of a table and the compiled drift–kick–drift iteration (C kernel ``_kernel``).
``second_order``
    The second-order kick k₂ and its tables.
"""
