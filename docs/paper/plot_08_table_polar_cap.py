"""
Paper App. A.1: parameters of the bowling-ball rock'n'roller (polar cap with d = cos Θ removed)
===============================================================================================

Runs :mod:`rocknroller.papers.lynch_bustamante.table_polar_cap` (``rocknroller reproduce --only table_polar_cap``).
"""

# %%
from rocknroller.papers.lynch_bustamante import reproduce

result = reproduce("table_polar_cap")
print(result.summary())
