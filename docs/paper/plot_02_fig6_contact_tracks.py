"""
Paper fig. 6: contact tracks for six initial spin phases ψ0, ε = 1e-3, 1000 time units, from rest at 0.95π
==========================================================================================================

Runs :mod:`rocknroller.papers.lynch_bustamante.fig6_contact_tracks` (``rocknroller reproduce --only fig6``).
"""

# %%
from rocknroller.papers.lynch_bustamante import reproduce

result = reproduce("fig6")
print(result.summary())
