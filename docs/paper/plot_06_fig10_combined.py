"""
Paper fig. 10: the (Q_R, Q_J) orbits of figs. 7, 8 and 9 together, with the critical lines
==========================================================================================

Runs :mod:`rocknroller.papers.lynch_bustamante.fig10_combined` (``rocknroller reproduce --only fig10``).
"""

# %%
from rocknroller.papers.lynch_bustamante import reproduce

result = reproduce("fig10")
print(result.summary())
