"""Signatures of the compiled dense-output evaluator (C source ``_dense.c``), for type checkers: a C extension carries
none."""

import numpy as np
from numpy.typing import NDArray

def states(tcs: NDArray[np.float64], times: NDArray[np.float64], t: NDArray[np.float64], col: NDArray[np.int64],
           out: NDArray[np.float64], /) -> None:
    """Fill ``out`` (m, V) with the states at times ``t`` (m,) of lanes ``col`` (m,) from a batch dense output's
    Taylor coefficients ``tcs`` (S, V, P, W) and step ends ``times`` (S + 1, W) (see ``_dense.c``)."""

def turns(tcs: NDArray[np.float64], times: NDArray[np.float64], t: NDArray[np.float64], col: NDArray[np.int64],
          y: NDArray[np.float64], fine: NDArray[np.float64], limit: float, max_bisections: int, shortest: float,
          out: NDArray[np.float64], /) -> None:
    """Fill ``out`` (2, m) with the whole turns of φ and ψ since each lane's first point, from the states ``y`` (m, V)
    at times ``t`` (m,) of lanes ``col`` (m,), the intervals refined on the dense output as
    ``trajectory._unwrapped_angles`` refines them (see ``_dense.c``)."""
