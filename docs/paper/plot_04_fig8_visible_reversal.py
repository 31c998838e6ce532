"""
Paper fig. 8: a start on the critical line Q_J = Q_J,π^crit (visible-angle reversals), ψ̇0 = 0.002
==================================================================================================

Runs :mod:`rocknroller.papers.lynch_bustamante.fig8_visible_reversal` (``rocknroller reproduce --only fig8``).
"""

# %%
from rocknroller.papers.lynch_bustamante import reproduce

result = reproduce("fig8")
print(result.summary())
