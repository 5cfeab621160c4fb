"""Mean-shift's chunk kernel (numba): a chunk's robots decided in one pass over their state
rows (:class:`~controllers.meanshift.swarm.MeanShiftSwarm`), once their local maps have
moved and been probed (controllers.common.mapbatch.MapRows.sense, one floor-probe query for
the chunk): :func:`decide_chunk` gives each robot's entering, exploring and interaction
commands, the low-pass filter and its rest, as
:meth:`MeanShiftRobot.step <controllers.meanshift.controller.MeanShiftRobot.step>` does.

The same numbers as the per-robot controller, to the bit: the same operations in the same
order (numpy's elementwise arithmetic, the kernels of kernel.py, Python's ``math.hypot`` as
controllers.common.pyhypot gives it). Only the test for occupied target points differs in
how it is searched: each neighbour visits the lattice points within r_occupied of it (and a
margin of 1e-6 r_occupied) and keeps each point's smallest squared distance, instead of every
point asking every neighbour; a point is occupied when that smallest sum passes kernel.explore's
test, so the same points pass the same test on the same numbers. (The margin holds while
odometry stays far below 1e6 units: the computed offsets err by a few ulps.)

A robot's map (controllers.common.mapbatch.MapRows, a LocalMap in arrays): ``grid[i]``
(size, size) int8 (1 target, 0 not, -1 not yet probed), the lattice index of its first row
and column ``origin[i]``, its odometry ``odo[i]`` (units). Its sensed points are the stencil
of lattice cells ``-reach..reach`` round its lattice cell, row by row, within its radius.
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit

from controllers.common.pyhypot import py_hypot as hypot

from .kernel import _add_kernel_mean, interact

SEEKING, EXPLORING, RESTING = 0, 1, 2

Gains = namedtuple("Gains", ["d_cover", "r_sense", "r_occupied", "v", "kappa_enter",
                             "kappa_fill", "kappa_expl", "kappa_avoid", "kappa_cons",
                             "inertia", "deadband"])
"""MeanShiftParams' numbers as the kernels read them (floats, the same names)."""

Lattice = namedtuple("Lattice", ["cell", "reach", "radius2"])
"""A local map's lattice: spacing (units), stencil reach (cells), the squared sensing radius
(units^2)."""


@njit(cache=True)
def _sensed_target(grid_i, origin_i, odo_i, lattice, q, qcell, qx, qy
                   ):  # pragma: no cover - compiled
    """The robot's sensed target points: their offsets into ``q`` (rows 0..k-1, stencil
    order) and their stencil cells (a * side + b) into ``qcell``, the offsets of the
    stencil's lattice rows and columns into ``qx``, ``qy`` (side,), units. Returns k and the
    robot's lattice cell."""
    cell, reach, radius2 = lattice
    side = 2 * reach + 1
    cx = np.int64(math.floor(odo_i[0] / cell))
    cy = np.int64(math.floor(odo_i[1] / cell))
    for a in range(side):
        qx[a] = (cx + a - reach) * cell - odo_i[0]
        qy[a] = (cy + a - reach) * cell - odo_i[1]
    k = 0
    for a in range(side):
        dx = qx[a]
        row = cx + a - reach - origin_i[0]
        for b in range(side):
            dy = qy[b]
            if dx * dx + dy * dy <= radius2 and grid_i[row, cy + b - reach - origin_i[1]] == 1:
                q[k, 0], q[k, 1] = dx, dy
                qcell[k] = a * side + b
                k += 1
    return k, cx, cy


@njit(cache=True)
def _entering(on_target, q, k, has_beacon, beacon, kappa_enter):  # pragma: no cover - compiled
    """MeanShiftRobot.entering: toward the nearest sensed target point, else the beacon."""
    if on_target:
        return 0.0, 0.0
    if k > 0:
        best = 0
        best_d = q[0, 0] * q[0, 0] + q[0, 1] * q[0, 1]
        for j in range(1, k):
            d = q[j, 0] * q[j, 0] + q[j, 1] * q[j, 1]
            if d < best_d:
                best, best_d = j, d
        gx, gy = q[best, 0], q[best, 1]
        n = hypot(gx, gy)
        if n > 1e-9:
            return kappa_enter * gx / n, kappa_enter * gy / n
    if has_beacon:
        return kappa_enter * beacon[0], kappa_enter * beacon[1]
    return 0.0, 0.0


@njit(cache=True)
def _exploring(q, k, qcell, qx, qy, cx, cy, odo_i, offsets, distances, G, lattice, w, wf, qf,
               taken, nearest):  # pragma: no cover - compiled
    """kernel.explore's command for the robot's sensed target points ``q[:k]`` (stencil
    cells ``qcell``, lattice rows and columns at offsets ``qx``, ``qy``), its neighbours at
    ``offsets``, ``distances``: a point is occupied when some neighbour within
    r_sense + r_occupied lies within r_occupied of it, by the same test on the same
    numbers; each neighbour marks the stencil cells round it (``taken``, one per cell)."""
    out = np.zeros(2)
    if k == 0:
        return out
    r_sense, r_occupied = G.r_sense, G.r_occupied
    for i in range(k):
        d = np.sqrt(q[i, 0] * q[i, 0] + q[i, 1] * q[i, 1])
        w[i] = 0.5 * (1.0 + np.cos(np.pi * min(d / r_sense, 1.0)))
    _add_kernel_mean(out, w, q, k, G.kappa_fill)
    if not _mark_taken(qx, qy, cx, cy, odo_i, offsets, distances, r_sense + r_occupied,
                       r_occupied, lattice, taken, nearest):
        _add_kernel_mean(out, w, q, k, G.kappa_expl)
        return out
    free = 0
    for p in range(k):
        if not taken[qcell[p]]:
            wf[free] = w[p]
            qf[free, 0], qf[free, 1] = q[p, 0], q[p, 1]
            free += 1
    _add_kernel_mean(out, wf, qf, free, G.kappa_expl)
    return out


@njit(cache=True)
def _mark_taken(qx, qy, cx, cy, odo_i, offsets, distances, near, r_occupied, lattice, taken,
                nearest):  # pragma: no cover - compiled
    """``taken`` (side * side,): the stencil cells within ``r_occupied`` of a neighbour at
    most ``near`` away, by kernel.explore's test (dx * dx, then + dy * dy, <= r_occupied **
    2) on the smallest such sum over the neighbours (``nearest``, scratch). Returns whether
    any neighbour is that near."""
    cell, reach, _ = lattice
    side = 2 * reach + 1
    limit = r_occupied ** 2
    # the lattice rows and columns within r_occupied of a neighbour, and a little more: the
    # test's dx (computed as the sensed points' offsets are) is within a few ulps of
    # ix * cell - (odo + n), far less than this margin
    reach_out = r_occupied * (1.0 + 1e-6) + 1e-6 * cell
    dy2 = np.empty(side)
    nearest[:] = np.inf
    any_near = False
    for j in range(distances.shape[0]):
        if not distances[j] <= near:
            continue
        any_near = True
        nx, ny = offsets[j, 0], offsets[j, 1]
        a_lo = max(np.int64(math.ceil((odo_i[0] + nx - reach_out) / cell)) - cx + reach, 0)
        a_hi = min(np.int64(math.floor((odo_i[0] + nx + reach_out) / cell)) + 1 - cx + reach,
                   side)
        b_lo = max(np.int64(math.ceil((odo_i[1] + ny - reach_out) / cell)) - cy + reach, 0)
        b_hi = min(np.int64(math.floor((odo_i[1] + ny + reach_out) / cell)) + 1 - cy + reach,
                   side)
        for b in range(b_lo, b_hi):
            dy = qy[b] - ny
            dy2[b] = dy * dy
        for a in range(a_lo, a_hi):
            dx = qx[a] - nx
            dx2 = dx * dx
            row = a * side
            for b in range(b_lo, b_hi):
                nearest[row + b] = min(nearest[row + b], dx2 + dy2[b])
    for c in range(side * side):
        taken[c] = nearest[c] <= limit
    return any_near


@njit(cache=True)
def decide_chunk(rows, odo, grid, origin, velocity, status, on_target, has_beacon, beacons,
                 heard, G, lattice, no_sender, out_velocity, out_sleep
                 ):  # pragma: no cover - compiled
    """Decide the chunk's robots (robot k: state row ``rows[k]``, its map probed already):
    their commands into ``out_velocity`` (R, 2), units per tick, and ``out_sleep`` (R,);
    their filtered velocity and status into ``velocity`` and ``status``, in place.

    ``heard``: (starts, offsets, distances, sender, vx, vy), robot k's neighbours rows
    ``starts[k]:starts[k + 1]``; ``beacons`` (R, 2) when ``has_beacon``.
    """
    starts, offsets, distances, sender, vx, vy = heard
    side = 2 * lattice.reach + 1
    q = np.empty((side * side, 2))
    qf = np.empty((side * side, 2))
    w = np.empty(side * side)
    wf = np.empty(side * side)
    qcell = np.empty(side * side, dtype=np.int64)
    taken = np.empty(side * side, dtype=np.bool_)
    nearest = np.empty(side * side)
    qx, qy = np.empty(side), np.empty(side)
    inertia, vmax, deadband = G.inertia, G.v, G.deadband
    for k in range(len(rows)):
        i = rows[k]
        n_q, cx, cy = _sensed_target(grid[i], origin[i], odo[i], lattice, q, qcell, qx, qy)
        e0, e1 = _entering(on_target[k], q, n_q, has_beacon, beacons[k], G.kappa_enter)
        a, b = starts[k], starts[k + 1]
        x = _exploring(q, n_q, qcell, qx, qy, cx, cy, odo[i], offsets[a:b], distances[a:b], G,
                       lattice, w, wf, qf, taken, nearest)
        f = interact(offsets[a:b], distances[a:b], sender[a:b], vx[a:b], vy[a:b], velocity[i],
                     G.d_cover, G.r_sense, G.kappa_avoid, G.kappa_cons, no_sender)
        c0 = (e0 + x[0]) + f[0]
        c1 = (e1 + x[1]) + f[1]
        n = hypot(c0, c1)
        if n > vmax:
            c0, c1 = c0 * (vmax / n), c1 * (vmax / n)
        v0 = (1 - inertia) * c0 + inertia * velocity[i, 0]
        v1 = (1 - inertia) * c1 + inertia * velocity[i, 1]
        n = hypot(v0, v1)
        if n > vmax:
            v0, v1 = v0 * (vmax / n), v1 * (vmax / n)
        if hypot(v0, v1) < deadband and hypot(c0, c1) < deadband:
            velocity[i, 0], velocity[i, 1] = 0.0, 0.0
            status[i] = RESTING if on_target[k] else SEEKING
            out_velocity[k, 0], out_velocity[k, 1] = 0.0, 0.0
            out_sleep[k] = True
        else:
            velocity[i, 0], velocity[i, 1] = v0, v1
            status[i] = EXPLORING if on_target[k] else SEEKING
            out_velocity[k, 0], out_velocity[k, 1] = v0, v1
            out_sleep[k] = False
