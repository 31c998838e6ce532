"""
Paper §7.2: the periodic orbit near ψ0 = 2.965π/8 (ε = 1e-3, released at rest from θ0 = 0.95π)
==============================================================================================

Runs :mod:`rocknroller.papers.lynch_bustamante.table_periodic_orbit` (``rocknroller reproduce --only table_periodic_orbit``).
"""

# %%
from rocknroller.papers.lynch_bustamante import reproduce

result = reproduce("table_periodic_orbit")
print(result.summary())
