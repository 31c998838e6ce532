"""Criticality: where V_φ vanishes at θ = 0 or π, and what that does to the precession.

In the order data flows through them:

``laurent``
    Laurent expansions of V_φ and V_ψ about θ = 0 and π (paper eqs. phidotCJQR th=0, th=pi), symbolic and numeric.
``lines``
    The critical Jellett lines Q_J,0^crit and Q_J,π^crit (paper eqs. QJcrit_0, QJcrit_pi) and the regions I–IV.
``theta_z``
    cos θ_z (the paper's formula corrected), θ_e, and the δ^½ bound near θ = π (paper eq. range_X).
``starts``
    Turning-point starts on a critical line or at a distance from it, and the seed paper's recession starts.
``reversals``
    The regions at every turning point of a direct run and its critical crossings (paper §Recession).
``drawing``
    The critical lines drawn on a (Q_R, Q_J) axes in the styles of paper fig. 4 (for the result types' ``plot``).
"""
