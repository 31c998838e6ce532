"""
Paper fig. 7: released from rest (φ̇0 = ψ̇0 = 0, so Q_R = Q_J = 0), ε = 1e-3, ψ0 = π/4, 200 time units
======================================================================================================

Runs :mod:`rocknroller.papers.lynch_bustamante.fig7_rest_start` (``rocknroller reproduce --only fig7``).
"""

# %%
from rocknroller.papers.lynch_bustamante import reproduce

result = reproduce("fig7")
print(result.summary())
