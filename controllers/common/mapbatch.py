"""Many robots' local maps of the floor as arrays, for a swarm that decides a chunk of robots
at once (:class:`MapRows`): the same lattice, window and answers as one
:class:`~controllers.common.localmap.LocalMap` per robot, to the bit.

Robot i's map is row i of each array: its odometry (``odo``), the lattice index of its window's
first row and column (``origin``) and the window of remembered floor answers (``grid``: 1
target, 0 not, -1 not yet probed). A chunk's tick is two steps:

1. :meth:`MapRows.sense` adds each robot's displacement, moves its window when the robot left
   it (:func:`advance`: as ``LocalMap._recentre``) and probes, in one ``probe_many`` query for
   the whole chunk, every lattice point within the radius not yet known (as
   ``LocalMap.sense``). After a robot's first sensing, every point within the radius is known;
   a robot that moved at most ``step`` since can find unknown points only on the stencil's
   rim (:func:`rim_cells`), so only the rim is searched (the same points, in the same order);
2. a controller's compiled kernel reads a robot's map at any offsets with
   :func:`lattice_values` (as ``LocalMap.lookup``). After step 1 every lattice point within
   the radius is known, so a lookup never needs a probe (``LocalMap.lookup`` probed none
   either once ``sense`` ran); :func:`lattice_values` reports such a point instead.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from numba import njit

from .localmap import LocalMap

ProbeMany = Callable[[np.ndarray, np.ndarray], np.ndarray]
"""``probe_many(ks, offsets)``: (M,) bool, the floor at chunk robot ``ks[j]``'s position plus
``offsets[j]`` (units) is target (swarmsim.controller.DecideBatch.probe_many)."""


class MapRows:
    """The local maps of a run's robots (row i: robot i), each as ``LocalMap(radius, cell)``.

    Args:
        robots: how many.
        radius: points within this distance of a robot are sensed, units.
        cell: lattice spacing, units.
    """

    def __init__(self, robots: int, radius: float, cell: float):
        self.radius = float(radius)
        self.cell = float(cell)
        self.reach = math.ceil(self.radius / self.cell) + 1  # as LocalMap's stencil
        self.size = 2 * (self.reach + LocalMap.MARGIN) + 1
        self.odo = np.zeros((robots, 2))
        self.origin = np.full((robots, 2), -(self.reach + LocalMap.MARGIN), dtype=np.int64)
        self.grid = np.full((robots, self.size, self.size), -1, dtype=np.int8)
        self.sensed = np.zeros(robots, dtype=np.bool_)  # robot i's map sensed once at least
        self.step = 0.5 * self.cell  # a robot moved at most this since: only the rim is new
        self.rim = rim_cells(self.reach, self.cell, self.radius, self.step)

    @property
    def radius2(self) -> float:
        """The squared sensing radius, units^2 (as LocalMap computes it)."""
        return self.radius * self.radius

    def sense(self, rows: np.ndarray, moved: np.ndarray, probe_many: ProbeMany) -> None:
        """Step 1 of a chunk's tick for the robots at ``rows`` (C-contiguous int64; chunk
        robot k is robot ``rows[k]``): add ``moved[k]`` (R, 2), units, to each one's
        odometry, move its window if it must, and probe every lattice point within the
        radius not yet known (one ``probe_many`` call for the chunk); in place."""
        ks, offsets, cells = advance(rows, moved, self.odo, self.origin, self.grid, self.sensed,
                                     self.rim, self.step, self.reach, LocalMap.MARGIN, self.cell,
                                     self.radius2)
        if len(ks):
            store(rows, ks, cells, np.asarray(probe_many(ks, offsets), dtype=np.bool_),
                  self.grid)


def rim_cells(reach: int, cell: float, radius: float, step: float) -> np.ndarray:
    """The stencil's rim: (M, 2) int64 offsets (a, b), cells, in stencil order (a, then b),
    of the lattice points that can be within ``radius`` (units) of a robot anywhere in its
    lattice cell and farther than ``radius - step`` from some place in it. A robot that moved
    at most ``step`` (units) since its map was last sensed knows every point off the rim
    within the radius (it was within the radius then), so only the rim can be unknown.

    The bounds keep a margin of 1e-6 (radius + cell): the offsets a robot computes err by a
    few ulps of its odometry, far less while odometry stays far below 1e6 units.
    """
    a = np.arange(-reach, reach + 1)
    near = np.where(a > 0, a - 1, -a) * cell  # |a cell - f| over f in [0, cell]: least
    far = np.maximum(np.abs(a), np.abs(a - 1)) * cell  # and most
    margin = 1e-6 * (radius + cell)
    inner, outer = radius - step - margin, radius + margin
    near2 = near[:, None] ** 2 + near[None, :] ** 2
    far2 = far[:, None] ** 2 + far[None, :] ** 2
    keep = (near2 <= outer * outer) & ~((far2 < inner * inner) & (inner > 0))
    aa, bb = np.nonzero(keep)  # row by row: stencil order
    return np.column_stack([aa - reach, bb - reach]).astype(np.int64)


@njit(cache=True)
def advance(rows, moved, odo, origin, grid, sensed, rim, step, reach, margin, cell,
            radius2):  # pragma: no cover - compiled
    """Add each chunk robot's displacement ``moved[k]`` to ``odo[rows[k]]``, move its window
    so that the stencil of lattice points round it fits (``reach`` cells each way; a moved
    window keeps ``margin`` cells beyond it and forgets what falls out), and list the lattice
    points within the sensing radius (``radius2``, units^2) it does not know yet: on the
    stencil's ``rim`` (:func:`rim_cells`) when its map was ``sensed`` before and it moved at
    most ``step`` (units), else on the whole stencil. Sets ``sensed``.

    Returns ks (M,) the chunk robots asking, offsets (M, 2) each point from its robot, units,
    and cells (M, 2) each point's window row and column: all of robot k's before robot
    k + 1's, each robot's in LocalMap's stencil order.
    """
    size = grid.shape[1]
    stencil = (2 * reach + 1) * (2 * reach + 1)
    most = 64 + rows.shape[0]  # grown as needed: most ticks ask a few points a robot (a
    # chunk's whole stencils, allocated every tick, were 15 MB at K's 603 robots)
    ks = np.empty(most, dtype=np.int64)
    offsets = np.empty((most, 2))
    cells = np.empty((most, 2), dtype=np.int64)
    m = 0
    for k in range(rows.shape[0]):
        i = rows[k]
        odo[i, 0] = odo[i, 0] + moved[k, 0]
        odo[i, 1] = odo[i, 1] + moved[k, 1]
        b0 = np.int64(math.floor(odo[i, 0] / cell))
        b1 = np.int64(math.floor(odo[i, 1] / cell))
        _recentre(grid[i], origin[i], b0, b1, reach, margin, size)
        if m + stencil > most:
            most = 2 * most + stencil
            ks, offsets, cells = _grown(ks, m, most), _grown(offsets, m, most), _grown(cells, m,
                                                                                      most)
        if sensed[i] and moved[k, 0] * moved[k, 0] + moved[k, 1] * moved[k, 1] <= step * step:
            m = _unknown_on_rim(k, odo[i], grid[i], origin[i], b0, b1, rim, cell, radius2, ks,
                                offsets, cells, m)
        else:
            m = _unknown_in_stencil(k, odo[i], grid[i], origin[i], b0, b1, reach, cell,
                                    radius2, ks, offsets, cells, m)
        sensed[i] = True
    return ks[:m], offsets[:m], cells[:m]


@njit(cache=True)
def _unknown_in_stencil(k, odo_i, grid_i, origin_i, b0, b1, reach, cell, radius2, ks, offsets,
                        cells, m):  # pragma: no cover - compiled
    """List chunk robot k's unknown lattice points within the radius, the whole stencil round
    lattice cell (b0, b1) searched, from row ``m`` of ``ks``, ``offsets``, ``cells``; returns
    the rows used."""
    for a in range(-reach, reach + 1):
        for b in range(-reach, reach + 1):
            m = _ask_if_unknown(k, odo_i, grid_i, origin_i, b0 + a, b1 + b, cell, radius2, ks,
                                offsets, cells, m)
    return m


@njit(cache=True)
def _unknown_on_rim(k, odo_i, grid_i, origin_i, b0, b1, rim, cell, radius2, ks, offsets, cells,
                    m):  # pragma: no cover - compiled
    """As :func:`_unknown_in_stencil`, only the stencil's ``rim`` searched (offsets (a, b) in
    stencil order): the same points, by the same test, in the same order, when every point
    off the rim within the radius is known."""
    for j in range(rim.shape[0]):
        m = _ask_if_unknown(k, odo_i, grid_i, origin_i, b0 + rim[j, 0], b1 + rim[j, 1], cell,
                            radius2, ks, offsets, cells, m)
    return m


@njit(cache=True, inline="always")
def _ask_if_unknown(k, odo_i, grid_i, origin_i, p0, p1, cell, radius2, ks, offsets, cells,
                    m):  # pragma: no cover - compiled
    """Append lattice point (p0, p1) to chunk robot k's questions (row ``m`` of ``ks``,
    ``offsets``, ``cells``) when it lies within the radius and its map does not know it;
    returns the rows used."""
    dx, dy = p0 * cell - odo_i[0], p1 * cell - odo_i[1]
    c0, c1 = p0 - origin_i[0], p1 - origin_i[1]
    if dx * dx + dy * dy <= radius2 and grid_i[c0, c1] < 0:
        ks[m] = k
        offsets[m, 0], offsets[m, 1] = dx, dy
        cells[m, 0], cells[m, 1] = c0, c1
        m += 1
    return m


@njit(cache=True)
def _grown(rows, used, size):  # pragma: no cover - compiled
    """A new array of ``size`` rows whose first ``used`` rows are ``rows``'."""
    out = np.empty((size,) + rows.shape[1:], dtype=rows.dtype)
    out[:used] = rows[:used]
    return out


@njit(cache=True)
def _recentre(grid, origin, b0, b1, reach, margin, size):  # pragma: no cover - compiled
    """Move one robot's window (``grid``, ``origin``, in place) so the stencil round lattice
    cell (b0, b1) fits, as LocalMap._recentre: nothing if it fits already."""
    o0, o1 = origin[0], origin[1]
    if b0 - reach >= o0 and b1 - reach >= o1 and b0 + reach < o0 + size and b1 + reach < o1 + size:
        return
    n0, n1 = b0 - (reach + margin), b1 - (reach + margin)
    s0, s1 = n0 - o0, n1 - o1  # the shift
    old = grid.copy()
    grid[:, :] = -1
    lo0, lo1 = max(s0, 0), max(s1, 0)
    hi0, hi1 = min(s0 + size, size), min(s1 + size, size)
    if hi0 > lo0 and hi1 > lo1:
        grid[lo0 - s0:hi0 - s0, lo1 - s1:hi1 - s1] = old[lo0:hi0, lo1:hi1]
    origin[0], origin[1] = n0, n1


@njit(cache=True)
def store(rows, ks, cells, answers, grid):  # pragma: no cover - compiled
    """Write the probes' ``answers`` (M,) bool into the windows: answer j at window
    ``cells[j]`` of robot ``rows[ks[j]]``'s map."""
    for j in range(ks.shape[0]):
        grid[rows[ks[j]], cells[j, 0], cells[j, 1]] = 1 if answers[j] else 0


@njit(cache=True)
def lattice_values(odo, origin, grid, cell, radius2, points, scale,
                   values):  # pragma: no cover - compiled
    """What one robot's map knows of the floor at ``points * scale`` (offsets from the robot,
    units): each one's nearest lattice point's value into ``values`` (P,) int8, 1 target or 0
    not (0 outside the window, and -1, not yet probed, beyond the radius: as LocalMap.lookup
    reads them). ``odo`` (2,), ``origin`` (2,), ``grid`` (size, size): the robot's rows;
    ``points`` (P, 2); ``radius2``: the squared sensing radius, units^2.

    Returns -1, or the first j whose lattice point lies within the radius but was never
    probed (LocalMap.lookup would probe it; the values from j on are not written).
    """
    odo0, odo1, o0, o1 = odo[0], odo[1], origin[0], origin[1]
    size = grid.shape[0]
    for j in range(points.shape[0]):
        ix = np.int64(np.floor((odo0 + points[j, 0] * scale) / cell + 0.5))
        iy = np.int64(np.floor((odo1 + points[j, 1] * scale) / cell + 0.5))
        row, col = ix - o0, iy - o1
        value = grid[row, col] if 0 <= row < size and 0 <= col < size else 0
        if value < 0:
            px, py = ix * cell - odo0, iy * cell - odo1
            if px * px + py * py <= radius2:
                return j
            value = 0
        values[j] = value
    return -1


def warm_up() -> None:
    """Compile (first time on a machine) or load (from the cache) the kernels now, with the
    types :class:`MapRows` passes."""
    maps = MapRows(1, 1.0, 1.0)
    rows = np.zeros(1, dtype=np.int64)
    maps.sense(rows, np.zeros((1, 2)), lambda ks, offsets: np.ones(len(ks), dtype=np.bool_))
    lattice_values(maps.odo[0], maps.origin[0], maps.grid[0], maps.cell, maps.radius2,
                   np.zeros((1, 2)), 1.0, np.zeros(1, dtype=np.int8))
