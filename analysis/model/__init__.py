"""What a body and a state are, and the quantities defined on them; everything above is built on these.

In the order data flows through them:

``body``
    :class:`Body`, the frozen parameters (a, I1, I2, I3, g) and their checks (paper §2, §4, App. A.1).
``kinematics``
    Euler angles, the rotation and the angular velocity in the body and intermediate frames (paper §2, §4).
``invariants``
    E, Q_J, Q_R, ρ, and the rates V_φ, V_ψ of Routh's sphere (paper eqs. energy, jellett, routh, phidotCJQR,
    psidotCJQR).
``equations``
    The initial state :class:`EulerState` and the right-hand sides of the equations of motion in four formulations
    (paper eqs. thetaomega, ELtheta, App. A.2, A.3).
``diagnostics``
    What is measured on samples at the turning points: visible angles (``wrap_angle``), the azimuth span Φ, the slow
    period, extents.
``frames``
    Results as pandas DataFrames (pandas optional).
"""
