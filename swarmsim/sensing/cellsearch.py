"""Compiled neighbourhood views: a cell grid and one sorted pass per robot (numba).

The same views as the k-d tree pass in sensing.py (``NeighbourSearch._pairs_within`` and its
sorts), to the bit: the offsets are the same differences, the squared distances the same two
products added (numba keeps IEEE arithmetic: no fast-math, no fused multiply-add), each robot's
own radius is compared with the same ``r * r``, and each robot's neighbours are ordered by
(squared distance, index), the total order the numpy path sorts by. Why compiled code: a
robot's view is ~5-40 rows, so numpy spends its time in per-call overhead and in five 16-bit
radix passes over the whole chunk; here it is one loop (docs/reports/performance-log.md has the
figures).

The first call compiles the kernel (seconds); ``cache=True`` keeps the machine code in
``__pycache__``, so later processes (sweep workers, the next run) load it at once.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from swarmsim.kernels.carrays import c_array
from swarmsim.kernels.warmup import kernel_warm_up

MAX_CELLS_PER_ROBOT = 4
"""The grid has at most this many cells per robot: a tiny radius over a wide swarm gets
larger cells (the same views; only fewer empty cells to build)."""

CELL_SPLIT = 3
"""The views' grid cells are this many times smaller than the widest listening radius, so a
robot that listens less far looks at fewer robots (the same views for any value)."""


def cell_views(positions: np.ndarray, robots: np.ndarray, radii: np.ndarray,
               ordered: bool = True) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Every robot within ``radii[k]`` of ``robots[k]`` (itself excluded), per robot in
    order, each robot's rows sorted by (squared distance, index).

    Args:
        positions: (N, 2) robot centres, units.
        robots: (R,) indices of the robots whose views are wanted.
        radii: (R,) their sensing radii, units (>= 0).
        ordered: False leaves each robot's rows unsorted (in no promised order).

    Returns:
        neighbours (P,) indices, offsets (P, 2) relative to the robot (units), squared
        distances (P,) (units^2) and counts (R,): robot k's rows follow robot k-1's.
    """
    # contiguous and writeable: one compiled signature (a read-only array is another type)
    positions = c_array(positions, np.float64, writeable=True)
    robots = c_array(robots, np.int64, writeable=True)
    radii = c_array(radii, np.float64, writeable=True)
    if len(robots) == 0 or len(positions) == 0:
        return (np.zeros(0, dtype=np.intp), np.zeros((0, 2)), np.zeros(0),
                np.zeros(len(robots), dtype=np.int64))
    if not _all_finite(positions):
        raise ValueError("robot positions must be finite (a body left the world?)")
    flat, offsets, d2, counts = _views(positions, robots, radii, MAX_CELLS_PER_ROBOT,
                                       ordered)
    return flat.astype(np.intp, copy=False), offsets, d2, counts


@njit(cache=True)
def _all_finite(values):  # pragma: no cover - compiled
    """Whether every entry of the (N, 2) ``values`` is finite (np.isfinite(...).all())."""
    for i in range(values.shape[0]):
        if not (math.isfinite(values[i, 0]) and math.isfinite(values[i, 1])):
            return False
    return True


@kernel_warm_up("neighbour views")
def warm_up() -> None:
    """Compile (first time on a machine) or load (from the cache) the kernels now, so that a
    run's clock does not count it."""
    cell_views(np.zeros((2, 2)), np.zeros(1, dtype=np.int64), np.ones(1))
    _all_finite(np.zeros((1, 2)))


@njit(cache=True)
def _cell_size(width, height, n, radius, per_robot):  # pragma: no cover - compiled
    """A cell at least the widest radius (a hair more: a neighbour is then never more than
    one cell away, whatever the division rounds), and not so small that a ``width`` x
    ``height`` grid over ``n`` robots has more than ``per_robot`` cells per robot."""
    cell = radius * (1 + 1e-9) + 1e-12
    most = per_robot * n + 16
    if (width / cell + 1) * (height / cell + 1) > most:
        cell = max(cell, math.sqrt(width * height / most) * 1.01, width / most, height / most)
    return cell


@njit(cache=True)
def grid_frame(positions, radius, per_robot):  # pragma: no cover - compiled
    """The grid's lower corner (x0, y0), its cell size (units) and its width and height in
    cells, for cells of at least ``radius`` over ``positions`` (see _cell_size)."""
    x0, y0 = positions[:, 0].min(), positions[:, 1].min()
    width, height = positions[:, 0].max() - x0, positions[:, 1].max() - y0
    cell = _cell_size(width, height, positions.shape[0], radius, per_robot)
    return x0, y0, cell, int(width / cell) + 1, int(height / cell) + 1


@njit(cache=True)
def grid(positions, x0, y0, cell, nx, ny):  # pragma: no cover - compiled
    """Robots ordered by cell (ties by index), their coordinates in that order, each cell's
    first row, each robot's cell and the grid's width and height in cells, for the frame
    :func:`grid_frame` gave (corner x0, y0, cell size, nx x ny cells)."""
    n = positions.shape[0]
    cell_of = np.empty(n, dtype=np.int64)
    starts = np.zeros(nx * ny + 1, dtype=np.int64)
    for i in range(n):
        cx = min(int((positions[i, 0] - x0) / cell), nx - 1)
        cy = min(int((positions[i, 1] - y0) / cell), ny - 1)
        cell_of[i] = cy * nx + cx
        starts[cell_of[i] + 1] += 1
    for c in range(nx * ny):
        starts[c + 1] += starts[c]
    fill = starts[:-1].copy()
    members = np.empty(n, dtype=np.int64)
    xs = np.empty(n, dtype=np.float64)
    ys = np.empty(n, dtype=np.float64)
    for i in range(n):
        m = fill[cell_of[i]]
        members[m] = i
        xs[m] = positions[i, 0]
        ys[m] = positions[i, 1]
        fill[cell_of[i]] += 1
    return members, xs, ys, starts, cell_of, nx, ny


@njit(cache=True)
def _span(at, reach, origin, cell, cells):  # pragma: no cover - compiled
    """The first and last cell (along one axis, ``cells`` of them) that may hold a point within
    ``reach`` units of coordinate ``at`` (the reach widened a hair: rounding cannot drop a
    neighbour; the exact distance test decides)."""
    lo = math.floor((at - reach - origin) / cell)  # an int in numba
    hi = math.floor((at + reach - origin) / cell)
    return max(lo, 0), min(hi, cells - 1)


@njit(cache=True)
def _views(positions, robots, radii, per_robot, ordered):  # pragma: no cover - compiled
    """Each robot's neighbours from the cells its own radius reaches, written (and sorted).

    The cells are CELL_SPLIT times smaller than the widest radius, so a robot listening less
    far than the widest looks at fewer cells (the same neighbours: the exact squared-distance
    test decides, whatever cells are looked at). A robot's rows are gathered into scratch
    arrays, sorted there by moving only their places and keys, and written once, in order,
    into the result: arrays sized for every robot in the cells looked at, returned as their
    first rows.

    The sort: a counting sort into as many buckets of squared distance as there are rows,
    then an insertion sort of the nearly sorted places (few moves, well-predicted branches),
    by (squared distance, index), a total order (indices differ), so any correct sort gives
    the same rows. One function on purpose: a compiled call per robot for the gather or the
    sort costs more than the sort's moves (docs/reports/performance-log.md has the figures).
    """
    x0, y0, cell, nx, ny = grid_frame(positions, radii.max() / CELL_SPLIT, per_robot)
    members, xs, ys, starts, _, _, _ = grid(positions, x0, y0, cell, nx, ny)
    size, widest = _bounds(positions, robots, radii, x0, y0, cell, nx, ny, starts)
    r = robots.shape[0]
    counts = np.empty(r, dtype=np.int64)
    flat = np.empty(size, dtype=np.int64)
    offsets = np.empty((size, 2), dtype=np.float64)
    d2 = np.empty(size, dtype=np.float64)
    # scratch: a view's squared distances, indices and offsets in the grid's order; the
    # sort's buckets, their counts, and the rows' places and keys in sorted order
    keys, ids, tx, ty = np.empty(widest), np.empty(widest, np.int64), np.empty(widest), \
        np.empty(widest)
    bucket, count = np.empty(widest, np.int64), np.empty(widest + 1, np.int64)
    place, sorted_keys = np.empty(widest, np.int64), np.empty(widest)
    at = 0
    for k in range(r):
        i = robots[k]
        r2 = radii[k] * radii[k]
        xi, yi = positions[i, 0], positions[i, 1]
        reach = radii[k] * (1 + 1e-9) + 1e-12
        lo_x, hi_x = _span(xi, reach, x0, cell, nx)
        lo_y, hi_y = _span(yi, reach, y0, cell, ny)
        n = 0
        for gy in range(lo_y, hi_y + 1):
            for m in range(starts[gy * nx + lo_x], starts[gy * nx + hi_x + 1]):  # one run
                dx = xs[m] - xi
                dy = ys[m] - yi
                dd = dx * dx + dy * dy
                if dd <= r2 and members[m] != i:
                    keys[n], ids[n], tx[n], ty[n] = dd, members[m], dx, dy
                    n += 1
        counts[k] = n
        if not ordered or n < 2:
            for s in range(n):
                place[s], sorted_keys[s] = s, keys[s]
        else:
            scale = n / r2 if r2 > 0 else 0.0
            count[:n + 1] = 0
            for s in range(n):
                q = min(int(keys[s] * scale), n - 1)
                bucket[s] = q
                count[q + 1] += 1
            for q in range(n):
                count[q + 1] += count[q]
            for s in range(n):
                o = count[bucket[s]]
                count[bucket[s]] = o + 1
                place[o], sorted_keys[o] = s, keys[s]
            for s in range(1, n):
                key, p = sorted_keys[s], place[s]
                t = s - 1
                while t >= 0 and (sorted_keys[t] > key
                                  or (sorted_keys[t] == key and ids[place[t]] > ids[p])):
                    sorted_keys[t + 1], place[t + 1] = sorted_keys[t], place[t]
                    t -= 1
                sorted_keys[t + 1], place[t + 1] = key, p
        for o in range(n):
            s = place[o]
            flat[at + o], offsets[at + o, 0], offsets[at + o, 1] = ids[s], tx[s], ty[s]
            d2[at + o] = sorted_keys[o]
        at += n
    return flat[:at], offsets[:at], d2[:at], counts


@njit(cache=True)
def _bounds(positions, robots, radii, x0, y0, cell, nx, ny, starts):  # pragma: no cover
    """How many rows the views can have in all (every robot in each one's cells) and the
    most any one view can have, for the grid :func:`grid` gave."""
    size = 0
    widest = 1
    for k in range(robots.shape[0]):
        i = robots[k]
        reach = radii[k] * (1 + 1e-9) + 1e-12
        lo_x, hi_x = _span(positions[i, 0], reach, x0, cell, nx)
        lo_y, hi_y = _span(positions[i, 1], reach, y0, cell, ny)
        rows = 0
        for gy in range(lo_y, hi_y + 1):
            rows += starts[gy * nx + hi_x + 1] - starts[gy * nx + lo_x]
        size += rows
        widest = max(widest, rows)
    return size, widest
