"""
Package figure: the slow period of the (Q_R, Q_J) oscillation against ψ0 and ε (ODE, map, closed form)
======================================================================================================

Runs :mod:`rocknroller.papers.lynch_bustamante.fig_slow_period` (``rocknroller reproduce --only fig_slow_period``).
"""

# %%
from rocknroller.papers.lynch_bustamante import reproduce

result = reproduce("fig_slow_period")
print(result.summary())
