"""Signatures of the compiled kernel (C source ``_kernel.c``), for type checkers: a C extension carries none.

The arrays are C-contiguous float64 (any object with such a buffer; the kernel raises TypeError otherwise).
"""

import numpy as np
from numpy.typing import NDArray

def iterate(rows: NDArray[np.float64], rows_jac: NDArray[np.float64], geom: NDArray[np.float64],
            out: NDArray[np.float64], U: float, alpha: float, beta: float, dx: float, nv: int, eps: float, u: float,
            v: float, Theta: float, t: float, phi: float, t_end: float, rows2: NDArray[np.float64] | None = None,
            tangent: NDArray[np.float64] | None = None, rows_dw: NDArray[np.float64] | None = None,
            rows_kt: NDArray[np.float64] | None = None, rows2_kt: NDArray[np.float64] | None = None,
            scale: float = 1.0, /) -> tuple[int, int, float, float, int, int]:
    """Step the slow map from a maximum until t_end, filling the rows (t, u, v, Θ, φ) of ``out``:
    (n rows filled, status, u and v where the table was left, evaluations with and without the Jacobian).  With
    ``tangent`` (w_u, w_v, w_Θ, ℓ; updated in place) a tangent vector is carried along and ``out`` has a sixth
    column, ℓ (see ``_kernel.c``)."""

def evaluate(rows: NDArray[np.float64], geom: NDArray[np.float64], width: int, nv: int, U: float, alpha: float,
             beta: float, dx: float, u: float, v: float, /) -> list[float] | None:
    """The ``width`` run-time functions at (u, v), or None outside the table."""
