"""
Package figure: the azimuth span Φ(ψ0) — direct ODE, averaged map, pendulum closed form, and π − 2ψ0
====================================================================================================

Runs :mod:`rocknroller.papers.lynch_bustamante.fig_azimuth_span` (``rocknroller reproduce --only fig_azimuth_span``).
"""

# %%
from rocknroller.papers.lynch_bustamante import reproduce

result = reproduce("fig_azimuth_span")
print(result.summary())
