"""The compiled driver's borrowed array views (controllers/ggc/borrow.py)."""

import numpy as np
from numba import njit

from controllers.ggc.borrow import borrowed


@njit
def _sum_and_mark(a, b):  # pragma: no cover - compiled
    """Sum of a borrowed view of ``a``; writes through a borrowed view of ``b``."""
    view = borrowed(a)
    out = borrowed(b)
    total = 0.0
    for i in range(view.shape[0]):
        for j in range(view.shape[1]):
            total += view[i, j]
    out[1:3] = 7
    return total, view[2:, 1].sum()


def test_a_borrowed_view_reads_and_writes_the_same_memory():
    a = np.arange(12.0).reshape(6, 2)
    b = np.zeros(5, dtype=np.int8)
    total, column = _sum_and_mark(a, b)
    assert total == a.sum() and column == a[2:, 1].sum()
    assert b.tolist() == [0, 7, 7, 0, 0]


def test_a_borrowed_view_leaves_the_arrays_reference_count_alone():
    import sys

    a = np.ones((4, 2))
    before = sys.getrefcount(a)
    for _ in range(1000):
        _sum_and_mark(a, np.zeros(5, dtype=np.int8))
    assert sys.getrefcount(a) == before and a.sum() == 8
