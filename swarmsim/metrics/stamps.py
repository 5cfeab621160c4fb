"""Compiled coverage stamps: the pixels each robot covers, counted per pixel (numba).

Used by metrics.IncrementalCoverage. A robot at (x, y) covers the pixels whose centre
(cx, cy) has (cx - x)^2 + (cy - y)^2 <= r^2, with the same floats as the numpy stencil it
replaced: the robot's pixel is floor((x - x0) / dx), a centre is x0 + (j + 0.5) * dx, and
r^2 is computed by the caller. Why compiled code: a robot's stencil is ~80 pixels and ~150
robots move each tick; numpy built (robots x stencil) arrays and two whole-grid bincounts
per tick.
"""

from __future__ import annotations

import math

from numba import njit


@njit(cache=True)
def restamp(count, inside, old, new, x0, y0, dx, dy, r2, half_i, half_j, rows,
            cols):  # pragma: no cover - compiled
    """For each robot whose ``new`` position differs from its ``old`` one: take its stamp
    away at ``old`` (skipped where that is NaN: not stamped yet), add it at ``new``, and
    copy ``new`` into ``old``.

    Args:
        count: (rows * cols,) int64 robots covering each pixel, updated in place.
        inside: (rows * cols,) bool, pixel centre inside the target.
        old: (N, 2) the positions last stamped (updated in place); new: (N, 2), units.
        x0, y0, dx, dy: the grid's corner and pixel size, units; r2: radius^2, units^2.
        half_i, half_j: the stencil's half height and width, pixels.

    Returns:
        The change in the number of covered target pixels.
    """
    change = 0
    for i in range(new.shape[0]):
        if old[i, 0] == new[i, 0] and old[i, 1] == new[i, 1]:
            continue
        if not math.isnan(old[i, 0]):
            change -= _stamp(count, inside, old[i, 0], old[i, 1], -1, x0, y0, dx, dy, r2,
                             half_i, half_j, rows, cols)
        change += _stamp(count, inside, new[i, 0], new[i, 1], 1, x0, y0, dx, dy, r2, half_i,
                         half_j, rows, cols)
        old[i, 0], old[i, 1] = new[i, 0], new[i, 1]
    return change


@njit(cache=True)
def _stamp(count, inside, x, y, sign, x0, y0, dx, dy, r2, half_i, half_j, rows,
           cols):  # pragma: no cover - compiled
    """Add ``sign`` to the count of every pixel within r of (x, y); the number of target
    pixels that became covered (sign 1) or uncovered (sign -1)."""
    if not (math.isfinite(x) and math.isfinite(y)):
        return 0  # nowhere: stamps nothing
    ci = math.floor((y - y0) / dy)  # an int in numba
    cj = math.floor((x - x0) / dx)
    flipped = 0
    for i in range(max(ci - half_i, 0), min(ci + half_i + 1, rows)):
        ey = y0 + (i + 0.5) * dy - y
        ey = ey * ey
        for j in range(max(cj - half_j, 0), min(cj + half_j + 1, cols)):
            ex = x0 + (j + 0.5) * dx - x
            if ex * ex + ey <= r2:
                c = i * cols + j
                if inside[c] and count[c] == (0 if sign > 0 else 1):
                    flipped += 1
                count[c] += sign
    return flipped
