"""Routh's sphere (I1 = I2): the integrable case, reduced to one degree of freedom.

In the order data flows through them:

``reduction``
    θ̇² = F(θ) (paper eq. thetadotsq), the effective potential, the conversions between Euler rates and
    (E, Q_R, Q_J).
``turning_points``
    The turning points θ_N, θ_X (vectorised, never raising) and the minimum of the effective potential.
``steady_rolling``
    Steady circular rolling (paper eq. om2om3) and a start's distance to it.
``rocking``
    Small-amplitude rocking about a principal axis (paper eqs. purerock, smallamprock).
``quadrature``
    T_θ, Δφ and Δψ in double precision (paper eq. Delta_phi), with their status.
``quadrature_mp``
    The same quadratures in mpmath at any precision: the reference of the double ones.
"""
