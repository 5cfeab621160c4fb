"""CVT's decision for a chunk of robots, compiled (numba): :func:`decide_chunk` runs, for every
robot of the chunk in one call, what ``CVTRobot.step`` (robot.py) does after its local map
has sensed, with the same arithmetic in the same order, so the same numbers to the bit:
numpy's row sums (``mean(axis=0)`` adds the rows in order), Python's ``math.hypot``
(controllers/common/pyhypot.py) and the push of controllers/common/push.py.

The robots' state lives in the columns of :class:`Rows`, the chunk's sensing in
:class:`Sensed`, the parameters in :class:`Params`; the kernel writes the chunk's actions into
:class:`Out`. Robot k of the chunk is robot ``rows[k]`` and owns neighbour rows
``starts[k]:starts[k + 1]``.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from controllers.common.mapbatch import lattice_values
from controllers.common.push import push_away
from controllers.common.pyhypot import py_hypot

from .params import DISC_DEADBAND, DISC_STEPS, MOVING, RESTING, SEEKING


class Rows(NamedTuple):
    """The run's robots' state, row i robot i's (the kernel updates the chunk's rows)."""

    status: np.ndarray  # (N,) int8: SEEKING, MOVING or RESTING
    extent: np.ndarray  # (N,) radius of the disc its cell is sampled in, units
    heard: np.ndarray  # (N,) how far it listened for this tick's perception, units
    reach: np.ndarray  # (N,) its cell's farthest point, units (0: no cell)
    still: np.ndarray  # (N,) bool: it stood still the tick before without settling
    still_extent: np.ndarray  # (N,) (extent, heard) it sampled in then, units
    still_heard: np.ndarray
    odo: np.ndarray  # (N, 2) its local map (controllers/common/mapbatch.py MapRows)
    origin: np.ndarray  # (N, 2) int64
    grid: np.ndarray  # (N, size, size) int8


class Sensed(NamedTuple):
    """A chunk's sensing (swarmsim.controller.DecideBatch), as C-contiguous arrays."""

    rows: np.ndarray  # (R,) int64, the chunk's robots
    starts: np.ndarray  # (R + 1,) int64, where each robot's neighbour rows start
    offsets: np.ndarray  # (P, 2) neighbours' offsets, units
    distances: np.ndarray  # (P,) their distances, units
    on_target: np.ndarray  # (R,) bool, the floor sensor
    beacons: np.ndarray  # (R, 2) unit bearings to the beacon (zeros without one)
    has_beacon: bool


class Params(NamedTuple):
    """CVTParams' values and the map's and sampling disc's constants."""

    cell_radius: float
    d_safe: float
    v: float
    gain: float
    repulsion_gain: float
    tolerance: float
    map_cell: float  # the local map's lattice spacing, units
    map_radius2: float  # its squared sensing radius, units^2
    disc: np.ndarray  # (D, 2) the unit disc's sample points (params.DISC)


class Out(NamedTuple):
    """The chunk's actions, row k robot k's."""

    velocity: np.ndarray  # (R, 2) units per tick
    listen: np.ndarray  # (R,) units
    status: np.ndarray  # (R,) int8, its broadcast status
    moving: np.ndarray  # (R,) bool, its broadcast "moving"
    sleep: np.ndarray  # (R,) bool


class Work(NamedTuple):
    """The kernel's scratch, reused robot after robot."""

    mine: np.ndarray  # (D, 2) the robot's cell's sample points, units
    values: np.ndarray  # (D,) int8 its map at the sampling disc's points
    near: np.ndarray  # (most neighbours, 2) the offsets of those that may own a point, units


@njit(cache=True)
def decide_chunk(s, sensed, p, out):  # pragma: no cover - compiled
    """Decide the chunk's robots (``s``: Rows, ``sensed``: Sensed, ``p``: Params; ``out``:
    Out, written). Their maps must have sensed this tick (MapRows.sense). Returns -1, or the
    first chunk robot whose map lacked a lattice point within its radius (then nothing
    after it is decided)."""
    most = 0
    for k in range(sensed.rows.shape[0]):
        most = max(most, sensed.starts[k + 1] - sensed.starts[k])
    work = Work(mine=np.empty((p.disc.shape[0], 2)),
                values=np.empty(p.disc.shape[0], dtype=np.int8), near=np.empty((most, 2)))
    for k in range(sensed.rows.shape[0]):
        if not _decide_one(k, s, sensed, p, out, work):
            return k
    return -1


@njit(cache=True)
def _decide_one(k, s, sensed, p, out, work):  # pragma: no cover - compiled
    """Robot k's tick (CVTRobot.step after its map's move); False if its map lacked a point."""
    i = sensed.rows[k]
    a, b = sensed.starts[k], sensed.starts[k + 1]
    on = sensed.on_target[k]
    was_extent, was_heard = s.extent[i], s.heard[i]
    n = _cell(i, a, b, s, sensed, p, work)
    if n < 0:
        return False
    rest = False
    vx = vy = 0.0
    if n > 0:
        cx, cy = _centroid(work.mine, n, s.extent[i])
        vx, vy = p.gain * cx, p.gain * cy
        rest = py_hypot(cx, cy) < p.tolerance * s.reach[i] and on
        s.status[i] = MOVING if on else SEEKING
    elif not on and sensed.has_beacon:
        vx, vy = sensed.beacons[k, 0] * p.v, sensed.beacons[k, 1] * p.v
        s.status[i] = SEEKING
    else:
        rest = True
    if rest:
        vx = vy = 0.0
    push = push_away(sensed.offsets[a:b], sensed.distances[a:b], p.d_safe, p.repulsion_gain)
    vx, vy = vx + push[0], vy + push[1]
    speed = py_hypot(vx, vy)
    if speed > p.v:
        vx, vy = vx * (p.v / speed), vy * (p.v / speed)
    moving = vx != 0 or vy != 0
    settled = False
    if not moving:
        s.status[i] = RESTING if on else SEEKING
        settled = _settle_disc(i, s, p, was_extent, was_heard)
    else:
        s.still[i] = False
    out.velocity[k, 0], out.velocity[k, 1] = (0.0, 0.0) if settled else (vx, vy)
    out.listen[k] = s.heard[i]
    out.status[k] = s.status[i]
    out.moving[k] = moving
    out.sleep[k] = settled
    return True


@njit(cache=True)
def _cell(i, a, b, s, sensed, p, work):  # pragma: no cover - compiled
    """CVTRobot.cell: robot i's cell's sample points into ``work.mine`` (their count; -1 if
    its map lacked a point), its extent, heard and reach updated."""
    full = p.cell_radius
    radius = min(full, s.heard[i] / 2, s.extent[i])
    h = radius / DISC_STEPS
    if lattice_values(s.odo[i], s.origin[i], s.grid[i], p.map_cell, p.map_radius2, p.disc,
                      radius, work.values) >= 0:
        return -1
    m = _near(a, b, 2 * radius, sensed, work.near)
    n = 0
    for j in range(p.disc.shape[0]):
        if work.values[j] != 1:
            continue
        qx, qy = p.disc[j, 0] * radius, p.disc[j, 1] * radius
        if _owned(qx, qy, work.near, m):
            work.mine[n, 0], work.mine[n, 1] = qx, qy
            n += 1
    if n == 0:
        s.extent[i] = full
        s.reach[i] = 0.0
        if lattice_values(s.odo[i], s.origin[i], s.grid[i], p.map_cell, p.map_radius2,
                          p.disc, full, work.values) >= 0:
            return -1
        near_target = (work.values == 1).any()
        s.heard[i] = 2 * full if near_target else max(2 * p.d_safe, 1.0)
        return 0
    far = 0.0
    for j in range(n):
        far = max(far, work.mine[j, 0] * work.mine[j, 0] + work.mine[j, 1] * work.mine[j, 1])
    s.reach[i] = math.sqrt(far)
    margin = 2 * h + 2 * p.v
    s.extent[i] = full if s.reach[i] >= radius - 1.5 * h else min(full, s.reach[i] + margin)
    s.heard[i] = 2 * s.extent[i]
    return n


@njit(cache=True)
def _near(a, b, reach, sensed, near):  # pragma: no cover - compiled
    """The offsets of neighbour rows a..b-1 no farther than ``reach`` (by their distances),
    in order, into ``near``; their count. (Farther ones cannot own a point of the disc.)"""
    m = 0
    for r in range(a, b):
        if sensed.distances[r] <= reach:
            near[m, 0], near[m, 1] = sensed.offsets[r, 0], sensed.offsets[r, 1]
            m += 1
    return m


@njit(cache=True)
def _owned(qx, qy, near, m):  # pragma: no cover - compiled
    """Whether point (qx, qy) is at least as near the robot as each of the first ``m``
    ``near`` offsets (controllers/cvt/kernel.py's owned, one point)."""
    own = qx * qx + qy * qy
    for r in range(m):
        dx, dy = qx - near[r, 0], qy - near[r, 1]
        if own > dx * dx + dy * dy:
            return False
    return True


@njit(cache=True)
def _centroid(mine, n, extent):  # pragma: no cover - compiled
    """The mean of the cell's ``n`` points (rows added in order, as numpy's mean(axis=0)),
    or the point nearest it when it lies more than 1.5 grid steps of a disc of radius
    ``extent`` from every point (a centroid off a non-convex cell)."""
    sx = sy = 0.0
    for j in range(n):
        sx += mine[j, 0]
        sy += mine[j, 1]
    cx, cy = sx / n, sy / n
    best, nearest = math.inf, 0
    for j in range(n):
        dx, dy = mine[j, 0] - cx, mine[j, 1] - cy
        d = dx * dx + dy * dy
        if d < best:
            best, nearest = d, j
    nx, ny = mine[nearest, 0], mine[nearest, 1]
    if py_hypot(nx - cx, ny - cy) > 1.5 * extent / DISC_STEPS:
        return nx, ny
    return cx, cy


@njit(cache=True)
def _settle_disc(i, s, p, was_extent, was_heard):  # pragma: no cover - compiled
    """CVTRobot.settle_disc for robot i, standing still, its cell sampled in the disc
    (was_extent, was_heard): whether it may sleep (it then keeps that disc)."""
    full = p.cell_radius
    was = min(full, was_heard / 2, was_extent)
    now = min(full, s.heard[i] / 2, s.extent[i])
    if (abs(now - was) <= DISC_DEADBAND * was / DISC_STEPS
            or (s.still[i] and s.extent[i] == s.still_extent[i]
                and s.heard[i] == s.still_heard[i])):
        s.extent[i], s.heard[i] = was_extent, was_heard
        return True
    s.still[i] = True
    s.still_extent[i], s.still_heard[i] = was_extent, was_heard
    return False
