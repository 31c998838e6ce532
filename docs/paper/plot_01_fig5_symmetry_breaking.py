"""
Paper fig. 5: contact track and φ at the θ-maxima, symmetric body against ε = 1e-3, 1500 time units
===================================================================================================

Runs :mod:`rocknroller.papers.lynch_bustamante.fig5_symmetry_breaking` (``rocknroller reproduce --only fig5``).
"""

# %%
from rocknroller.papers.lynch_bustamante import reproduce

result = reproduce("fig5")
print(result.summary())
