"""
Paper §2.2 and §4.1: small-amplitude rocking frequencies about the two principal axes, and their ratio
======================================================================================================

Runs :mod:`rocknroller.papers.lynch_bustamante.table_small_amplitude` (``rocknroller reproduce --only table_small_amplitude``).
"""

# %%
from rocknroller.papers.lynch_bustamante import reproduce

result = reproduce("table_small_amplitude")
print(result.summary())
