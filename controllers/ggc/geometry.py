"""Small helpers shared by GGC's rules: 2-vectors, bearings and the size of a small view."""

from __future__ import annotations

import math
from itertools import pairwise

import numpy as np

SMALL_VIEW = 16
"""Up to this many neighbours a query loops over Python values instead of numpy masks
(same answers: integer and boolean tests only)."""
ENCLOSED_GAP = math.radians(100)
"""A robot whose neighbours within 1.5 d_min leave no angular gap wider than this is enclosed."""


def unit(v: np.ndarray) -> np.ndarray:
    """``v`` scaled to length 1 (zero stays zero). In Python floats: the same quotients as
    numpy's, several times faster on a 2-vector."""
    x, y = float(v[0]), float(v[1])
    n = math.hypot(x, y)
    return np.array([x / n, y / n]) if n > 1e-12 else np.zeros(2)


def widest_gap(offsets: np.ndarray) -> float:
    """Widest angle (radians) between the bearings of two or more neighbours (k, 2).

    In Python floats with ``math.atan2``, whatever the view's size: numpy's ``arctan2`` may
    take a SIMD kernel (AVX-512) whose last bit differs from the C library's, and the answer
    must not depend on the machine's vector unit. (Views are small: robots within 1.5 d_min.)
    """
    angles = sorted(math.atan2(y, x) for x, y in offsets.tolist())
    return max(max(b - a for a, b in pairwise(angles)), angles[0] + 2 * math.pi - angles[-1])
