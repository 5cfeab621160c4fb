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

    Up to four levels of halving (about 2,000 items) are nested calls that allocate nothing
    (a mean-shift robot sums a few hundred weights twice a tick); deeper ones are walked
    with an explicit stack: numba cannot load a recursive function from its cache (it
    crashed).
    """
    return _halved4(a, lo, n)


@njit(cache=True)
def _halved4(a, lo, n):  # pragma: no cover - compiled
    """``a[lo:lo + n].sum()``, numpy's: its first halving here, then :func:`_halved3`'s."""
    if n <= _BLOCK:
        return _block_sum(a, lo, n)
    half = _half(n)
    return _halved3(a, lo, half) + _halved3(a, lo + half, n - half)


@njit(cache=True)
def _halved3(a, lo, n):  # pragma: no cover - compiled
    """``a[lo:lo + n].sum()``, numpy's: as :func:`_halved4`, one level fewer."""
    if n <= _BLOCK:
        return _block_sum(a, lo, n)
    half = _half(n)
    return _halved2(a, lo, half) + _halved2(a, lo + half, n - half)


@njit(cache=True)
def _halved2(a, lo, n):  # pragma: no cover - compiled
    """``a[lo:lo + n].sum()``, numpy's: as :func:`_halved4`, two levels fewer."""
    if n <= _BLOCK:
        return _block_sum(a, lo, n)
    half = _half(n)
    return _halved1(a, lo, half) + _halved1(a, lo + half, n - half)


@njit(cache=True)
def _halved1(a, lo, n):  # pragma: no cover - compiled
    """``a[lo:lo + n].sum()``, numpy's: blocks of at most 128, else :func:`_stacked`."""
    if n <= _BLOCK:
        return _block_sum(a, lo, n)
    half = _half(n)
    return _stacked(a, lo, half) + _stacked(a, lo + half, n - half)


@njit(cache=True)
def _half(n):  # pragma: no cover - compiled
    """Where numpy splits n (> 128) items: half of them, rounded down to a multiple of 8."""
    half = n // 2
    return half - half % 8


@njit(cache=True)
def _stacked(a, lo, n):  # pragma: no cover - compiled
    """``a[lo:lo + n].sum()``, numpy's, for any n: the halving walked with a stack."""
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
        half = _half(size)
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
    r0, r1, r2, r3 = a[lo], a[lo + 1], a[lo + 2], a[lo + 3]
    r4, r5, r6, r7 = a[lo + 4], a[lo + 5], a[lo + 6], a[lo + 7]
    whole = n - n % 8
    for i in range(lo + 8, lo + whole, 8):
        r0 += a[i]
        r1 += a[i + 1]
        r2 += a[i + 2]
        r3 += a[i + 3]
        r4 += a[i + 4]
        r5 += a[i + 5]
        r6 += a[i + 6]
        r7 += a[i + 7]
    res = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    for i in range(whole, n):
        res += a[lo + i]
    return res
