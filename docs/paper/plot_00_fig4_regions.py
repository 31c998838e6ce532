"""
Paper fig. 4: the four critical regions of the (Q_R, Q_J) plane with V_φ(θ) in each (paper body, I1 = I2)
=========================================================================================================

Runs :mod:`rocknroller.papers.lynch_bustamante.fig4_regions` (``rocknroller reproduce --only fig4``).
"""

# %%
from rocknroller.papers.lynch_bustamante import reproduce

result = reproduce("fig4")
print(result.summary())
