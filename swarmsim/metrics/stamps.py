"""Compiled coverage stamps: the pixels each robot covers, counted per pixel (numba).

Used by metrics.IncrementalCoverage. A robot at (x, y) covers the pixels whose centre
(cx, cy) has (cx - x)^2 + (cy - y)^2 <= r^2, with the same floats as the numpy stencil it
replaced: the robot's pixel is floor((x - x0) / dx), a centre is x0 + (j + 0.5) * dx, and
r^2 is computed by the caller. Why compiled code: a robot's stencil is ~80 pixels and ~150
robots move each tick; numpy built (robots x stencil) arrays and two whole-grid bincounts
per tick.

A moved robot's stamp is changed row by row: in a row, the pixels a robot covers are one run
of columns (the test's left side falls, then rises along the row: each rounding is monotonic), found
from its ends (a square root's guess, checked against the float test itself); each robot's
runs are kept, and only the pixels the old run or the new one holds alone are counted down
or up. A robot moving a fraction of a pixel (most ticks) touches no count at all.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

GUESS_LIMIT = 1e15
"""The run's ends are guessed only from guesses below this many columns (exact in an int64),
else every column of the stencil is asked."""


def new_stamps(robots: int, half_i: int, rows: int) -> tuple[np.ndarray, np.ndarray]:
    """What :func:`restamp` keeps of ``robots`` robots stamped nowhere yet: each one's
    stamped rows [first, end) ((robots, 2) int64, (rows, 0): none) and each such row's run of
    columns [lo, hi) ((robots, height, 2) int64, height the rows a stencil of half height
    ``half_i`` can span in a grid of ``rows`` rows)."""
    spans = np.empty((robots, 2), dtype=np.int64)
    spans[:, 0], spans[:, 1] = rows, 0
    return spans, np.zeros((robots, min(2 * half_i + 1, rows), 2), dtype=np.int64)


@njit(cache=True)
def restamp(count, inside, old, new, spans, runs, x0, y0, dx, dy, r2, half_i, half_j, rows,
            cols):  # pragma: no cover - compiled
    """For each robot whose ``new`` position differs from its ``old`` one: take its stamp
    away (as ``spans`` and ``runs`` keep it), add it at ``new`` (none where that is not
    finite), and copy ``new`` into ``old``.

    Args:
        count: (rows * cols,) int64 robots covering each pixel, updated in place.
        inside: (rows * cols,) bool, pixel centre inside the target.
        old: (N, 2) the positions last stamped (updated in place); new: (N, 2), units.
        spans, runs: each robot's stamp at ``old``, as :func:`new_stamps` made them and
            this function keeps them (updated in place).
        x0, y0, dx, dy: the grid's corner and pixel size, units; r2: radius^2, units^2.
        half_i, half_j: the stencil's half height and width, pixels (a robot's stencil is
            the pixels at most that many rows and columns from its own).

    Returns:
        The change in the number of covered target pixels.
    """
    now = np.empty((runs.shape[1], 2), np.int64)  # a moved robot's runs at ``new``
    change = 0
    for i in range(new.shape[0]):
        nx, ny = new[i, 0], new[i, 1]
        if old[i, 0] == nx and old[i, 1] == ny:
            continue
        a0, a1 = spans[i, 0], spans[i, 1]
        b0, b1 = _runs(nx, ny, x0, y0, dx, dy, r2, half_i, half_j, rows, cols, now)
        was = runs[i]
        for row in range(min(a0, b0), max(a1, b1)):
            lo, hi = (was[row - a0, 0], was[row - a0, 1]) if a0 <= row < a1 else (0, 0)
            nlo, nhi = (now[row - b0, 0], now[row - b0, 1]) if b0 <= row < b1 else (0, 0)
            change -= _count_run(count, inside, row * cols, lo, hi, nlo, nhi, -1)
            change += _count_run(count, inside, row * cols, nlo, nhi, lo, hi, 1)
        for k in range(b1 - b0):
            was[k, 0], was[k, 1] = now[k, 0], now[k, 1]
        spans[i, 0], spans[i, 1] = b0, b1
        old[i, 0], old[i, 1] = nx, ny
    return change


@njit(cache=True)
def _runs(x, y, x0, y0, dx, dy, r2, half_i, half_j, rows, cols,
          out):  # pragma: no cover - compiled
    """The stencil's rows [first, end) for a robot at (x, y) ((rows, 0) for none: a
    position not finite is stamped nowhere, a stencil beyond the grid has no rows), and in
    ``out[k]`` the columns [lo, hi) of row first + k that it covers (lo >= hi: none)."""
    if not (math.isfinite(x) and math.isfinite(y)):
        return rows, 0
    ci = math.floor((y - y0) / dy)  # an int in numba
    first, end = max(ci - half_i, 0), min(ci + half_i + 1, rows)
    if first >= end:
        return rows, 0
    cj = math.floor((x - x0) / dx)
    left, right = max(cj - half_j, 0), min(cj + half_j + 1, cols)
    u = (x - x0) / dx - 0.5  # the robot's column, as a pixel centre's (for the guesses)
    for row in range(first, end):
        ey = y0 + (row + 0.5) * dy - y
        ey = ey * ey
        if left >= right or not ey <= r2:  # ex * ex + ey >= ey > r2 (or NaN): none
            out[row - first, 0], out[row - first, 1] = 0, 0
        else:
            w = math.sqrt(r2 - ey) / dx  # the run's half width, columns (roughly)
            guess = dx > 0 and abs(u) < GUESS_LIMIT and w < GUESS_LIMIT  # (NaN: no guess)
            lo, hi = _run(x, x0, dx, ey, r2, left, right, u - w, u + w, guess)
            out[row - first, 0], out[row - first, 1] = lo, hi
    return first, end


@njit(cache=True, inline="always")
def _covers(x, j, x0, dx, ey, r2):  # pragma: no cover - compiled
    """Does the pixel of column ``j``, in a row ``ey`` (squared) from a robot at ``x``, lie
    within r of it? (The float test, as the stencil always computed it.)"""
    ex = x0 + (j + 0.5) * dx - x
    return ex * ex + ey <= r2


@njit(cache=True, inline="always")
def _run(x, x0, dx, ey, r2, left, right, start, stop, guess):  # pragma: no cover - compiled
    """[lo, hi): the columns among [left, right) of a row ``ey`` (squared) from a robot at
    ``x`` that it covers (lo >= hi: none). ``start`` and ``stop`` guess the run's ends (in
    columns; used if ``guess``), and are checked against the float test itself: the run is
    one run (the test is a valley along the row), so a covered column whose neighbour
    outward is not covered (or is past the stencil) is its end."""
    if guess:
        lo = min(max(math.ceil(start), left), right - 1)
        hi = min(max(math.floor(stop), left), right - 1)
        if (_covers(x, lo, x0, dx, ey, r2) and _covers(x, hi, x0, dx, ey, r2)
                and (lo == left or not _covers(x, lo - 1, x0, dx, ey, r2))
                and (hi == right - 1 or not _covers(x, hi + 1, x0, dx, ey, r2))):
            return lo, hi + 1
    lo = left  # no guess, or it missed (a pixel centre on the rim): every column asked
    while lo < right and not _covers(x, lo, x0, dx, ey, r2):
        lo += 1
    hi = right
    while hi > lo and not _covers(x, hi - 1, x0, dx, ey, r2):
        hi -= 1
    return lo, hi


@njit(cache=True, inline="always")
def _count_run(count, inside, base, lo, hi, skip_lo, skip_hi, sign):  # pragma: no cover
    """Add ``sign`` to the counts of row pixels [lo, hi) (``base``: the row's first pixel),
    leaving out [skip_lo, skip_hi); the number of target pixels that became covered (sign 1)
    or uncovered (sign -1)."""
    flipped = 0
    for j in range(lo, hi):
        if skip_lo <= j < skip_hi:
            continue
        c = base + j
        if inside[c] and count[c] == (0 if sign > 0 else 1):
            flipped += 1
        count[c] += sign
    return flipped
