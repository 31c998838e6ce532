"""The hierarchy of loaded spheres (paper fig. 1, §2; Borisov & Mamaev 2002): Chaplygin's ball, Routh's sphere, the
rock'n'roller and Chaplygin's top, with their integrals and invariant measures.

``conservation``
    sympy proofs, member by member, that a quantity is a first integral of the general equations, or an exact
    rational point where its derivative along the flow is not zero.
``measure``
    sympy checks of a candidate invariant density, div(ρ f) = 0.
``phase_volume``
    the flow's divergence, its time average along a run forward and backward (the sum of the Lyapunov exponents),
    the densities of the members that have one, and the steady rotations about the vertical with their stability:
    Chaplygin's top's attractors and repellers (docs/theory/chaplygin_top.md).
``members``, ``drift``, ``table``
    the four members' representative bodies and starts, the quantities' drifts along the direct ODE, and the table
    that puts the proofs and the measurements side by side (``rocknroller hierarchy``).
"""
