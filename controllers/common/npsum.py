"""numpy's summation, compiled (numba), for kernels that must give numpy's numbers to the bit.

numpy sums a contiguous 1-D float array pairwise: up to 128 items in 8 running sums combined
in pairs, above that the two halves (split at a multiple of 8) summed alike and added. A plain
running sum differs in the last bits.
"""

from __future__ import annotations

import numpy as np
from numba import njit

_BLOCK = 128  # numpy's PW_BLOCKSIZE: pairwise summation splits above this many items


@njit(cache=True)
def pairwise_sum(a, lo, n):  # pragma: no cover - compiled
    """``a[lo:lo + n].sum()`` as numpy sums a contiguous float array, in its dtype (halves
    above 128 items, 8 accumulators below), so the result is the same to the bit.

    The halving is walked with an explicit stack: numba cannot load a recursive function
    from its cache (it crashed).
    """
    if n <= _BLOCK:
        return _block_sum(a, lo, n)
    starts = np.empty(64, dtype=np.int64)
    sizes = np.empty(64, dtype=np.int64)
    stages = np.empty(64, dtype=np.int64)  # 0: go left, 1: go right, 2: add the halves
    sums = np.empty(64, a.dtype)
    top, done = 0, 0
    starts[0], sizes[0], stages[0] = lo, n, 0
    while top >= 0:
        start, size = starts[top], sizes[top]
        if size <= _BLOCK:
            sums[done] = _block_sum(a, start, size)
            done += 1
            top -= 1
            continue
        half = size // 2
        half -= half % 8
        if stages[top] == 2:
            sums[done - 2] = sums[done - 2] + sums[done - 1]
            done -= 1
            top -= 1
            continue
        right = stages[top] == 1
        stages[top] += 1
        top += 1
        starts[top] = start + half if right else start
        sizes[top] = size - half if right else half
        stages[top] = 0
    return sums[0]


@njit(cache=True)
def _block_sum(a, lo, n):  # pragma: no cover - compiled
    """numpy's sum of at most 128 items: 8 running sums, combined in pairs, then the rest."""
    if n < 8:
        res = np.zeros(1, a.dtype)[0]
        for i in range(n):
            res += a[lo + i]
        return res
    r = a[lo:lo + 8].copy()
    whole = n - n % 8
    for i in range(8, whole, 8):
        for j in range(8):
            r[j] += a[lo + i + j]
    res = ((r[0] + r[1]) + (r[2] + r[3])) + ((r[4] + r[5]) + (r[6] + r[7]))
    for i in range(whole, n):
        res += a[lo + i]
    return res
