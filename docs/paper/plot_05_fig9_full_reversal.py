"""
Paper fig. 9: a start on the critical line Q_J = Q_J,0^crit (full-angle reversals), ψ̇0 = 0.378
===============================================================================================

Runs :mod:`rocknroller.papers.lynch_bustamante.fig9_full_reversal` (``rocknroller reproduce --only fig9``).
"""

# %%
from rocknroller.papers.lynch_bustamante import reproduce

result = reproduce("fig9")
print(result.summary())
