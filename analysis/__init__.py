"""The model of the rolling sphere and its exact and asymptotic results, one subpackage per subject.

Data flows up, in this order (a subpackage imports only those above it in this list, and :mod:`rocknroller.numerics`
between the first and the second):

``model``
    What a body and a state are: :class:`~rocknroller.analysis.model.body.Body`, kinematics, the invariants
    (E, Q_J, Q_R, V_φ, V_ψ), the initial state and the equations of motion as formulas, the diagnostics of
    turning-point samples.
``routh``
    Routh's sphere (I1 = I2, integrable): the reduction θ̇² = F(θ), turning points, the quadratures of T_θ, Δφ and
    Δψ (double and mpmath), steady rolling, small-amplitude rocking.
``criticality``
    The critical Jellett lines, the regions I–IV, the Laurent expansions, cos θ_z and the δ^½ bound, starts on a
    critical line, the reversal analysis of a run.
``slow``
    The ε-averaged slow motion of the rock'n'roller (I1 ≠ I2): orbit and exact step, tables, the compiled map,
    the prediction, its limits, the pendulum closed form, period doubling, the atlas.
"""
