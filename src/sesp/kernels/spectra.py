"""Sums over Fourier spectra (the third virial coefficient's correlations)."""

import numpy as np
from numba import njit

from .common import JIT

__all__ = ["triple_sum"]


@njit(**JIT)
def _triple_sum(first, second, third, weights):
    total = 0.0
    for i in range(first.shape[0]):
        for j in range(first.shape[1]):
            z = first[i, j] * third[i, j] * weights[i, j]
            s = second[i, j]
            total += s.real * z.real + s.imag * z.imag
    return total


def triple_sum(first: np.ndarray, second: np.ndarray, third: np.ndarray, weights: np.ndarray) -> float:
    """Re Σ first · conj(second) · third · weights over 2-D complex arrays of one shape, in one pass."""
    return float(_triple_sum(first, second, third, weights))
