"""
Paper fig. 11: visible-angle reversal at high Q_R = 0.1, started slightly above Q_J,π^crit
==========================================================================================

Runs :mod:`rocknroller.papers.lynch_bustamante.fig11_high_QR` (``rocknroller reproduce --only fig11``).
"""

# %%
from rocknroller.papers.lynch_bustamante import reproduce

result = reproduce("fig11")
print(result.summary())
