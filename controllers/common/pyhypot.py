"""Python's ``math.hypot(x, y)``, compiled (numba), for kernels that must give the numbers of
controllers written with ``math.hypot`` to the bit.

CPython (3.8 on) does not call the C library's hypot: it scales the coordinates by a power of
two, squares them exactly (Veltkamp-Dekker splitting), sums the squares with compensation,
takes the square root and corrects it by one Newton step (Modules/mathmodule.c,
``vector_norm``). The C library's hypot, which numba's ``math.hypot`` calls, rounds some
results the other way. :func:`py_hypot` is that algorithm for two coordinates, step by step
(no fused multiply-add: numba does not contract without fastmath).
"""

from __future__ import annotations

import math

from numba import njit

_SPLIT = 134217729.0  # 2 ** 27 + 1, the Veltkamp splitting constant
_DBL_MIN = 2.2250738585072014e-308  # the smallest normal float


@njit(cache=True)
def py_hypot(x, y):  # pragma: no cover - compiled
    """``math.hypot(x, y)`` as CPython 3.11 computes it, to the bit (x, y: floats)."""
    x, y = abs(x), abs(y)
    if math.isinf(x) or math.isinf(y):
        return math.inf
    if math.isnan(x) or math.isnan(y):
        return math.nan
    big = max(x, y)
    if big == 0.0:
        return big
    _, exp = math.frexp(big)
    if exp < -1023:  # a subnormal largest coordinate: divide by it instead of scaling
        return _tiny_norm(x, y, big)
    scale = math.ldexp(1.0, -exp)
    csum, frac1, frac2, frac3 = 1.0, 0.0, 0.0, 0.0
    for v in (x, y):
        v *= scale
        hi, lo = _split(v)
        csum, frac1 = _add(csum, frac1, hi * hi)
        csum, frac2 = _add(csum, frac2, 2.0 * hi * lo)
        frac3 += lo * lo
    h = math.sqrt(csum - 1.0 + (frac1 + frac2 + frac3))
    hi, lo = _split(h)
    csum, frac1 = _add(csum, frac1, -hi * hi)
    csum, frac2 = _add(csum, frac2, -2.0 * hi * lo)
    csum, frac3 = _add(csum, frac3, -lo * lo)
    rest = csum - 1.0 + (frac1 + frac2 + frac3)
    return (h + rest / (2.0 * h)) / scale


@njit(cache=True, inline="always")
def _split(v):  # pragma: no cover - compiled
    """Veltkamp's split of ``v``: (hi, lo), hi + lo == v, each of half precision."""
    t = v * _SPLIT
    hi = t - (t - v)
    return hi, v - hi


@njit(cache=True, inline="always")
def _add(csum, frac, v):  # pragma: no cover - compiled
    """Add ``v`` to the running sum ``csum``, the lost low part to ``frac`` (Neumaier, with
    |csum| >= |v| by construction)."""
    old = csum
    csum += v
    return csum, frac + ((old - csum) + v)


@njit(cache=True)
def _tiny_norm(x, y, big):  # pragma: no cover - compiled
    """CPython's path for a subnormal largest coordinate ``big``."""
    csum, frac = 1.0, 0.0
    for v in (x, y):
        v /= big
        csum, frac = _add(csum, frac, v * v)
    return big * math.sqrt(csum - 1.0 + frac)


def warm_up() -> None:
    """Compile (first time on a machine) or load (from the cache) the kernel now."""
    py_hypot(3.0, 4.0)
