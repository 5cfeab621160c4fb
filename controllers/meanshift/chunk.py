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
margin of 1e-6 r_occupied) and marks those whose squared distance passes kernel.explore's
test, instead of every point asking every neighbour: the same points pass the same test on the
same numbers. (The margin holds while odometry stays far below 1e6 units: the computed offsets
err by a few ulps.) The marks are bits, a stencil row's in a few words (one while the
stencil is at most 64 cells wide), each row of a neighbour's marks or-ed in at once. The
raised-cosine weights, both kernel means' sums (all points, free points) and the free points'
weights are made in one pass, after the marking; the means add the same products in the same
order as kernel.explore's.

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

from controllers.common.npsum import pairwise_sum
from controllers.common.pyhypot import py_hypot as hypot

from .kernel import interaction

SEEKING, EXPLORING, RESTING = 0, 1, 2

Gains = namedtuple("Gains", ["d_cover", "r_sense", "r_occupied", "v", "kappa_enter",
                             "kappa_fill", "kappa_expl", "kappa_avoid", "kappa_cons",
                             "inertia", "deadband"])
"""MeanShiftParams' numbers as the kernels read them (floats, the same names)."""

Lattice = namedtuple("Lattice", ["cell", "reach", "radius2"])
"""A local map's lattice: spacing (units), stencil reach (cells), the squared sensing radius
(units^2)."""


@njit(cache=True)
def _sensed_target(grid_i, origin_i, odo_i, lattice, q, d2, qa, qb, qx, qy
                   ):  # pragma: no cover - compiled
    """The robot's sensed target points: their offsets into ``q`` (rows 0..k-1, stencil
    order), their squared distances (units^2, as the radius test computes them) into ``d2``
    and their stencil rows and columns into ``qa``, ``qb``, the offsets of the stencil's
    lattice rows and columns into ``qx``, ``qy`` (side,), units. Returns k and the robot's
    lattice cell."""
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
            s = dx * dx + dy * dy
            if s <= radius2 and grid_i[row, cy + b - reach - origin_i[1]] == 1:
                q[k, 0], q[k, 1] = dx, dy
                d2[k] = s
                qa[k], qb[k] = a, b
                k += 1
    return k, cx, cy


@njit(cache=True)
def _entering(on_target, q, d2, k, has_beacon, beacon, kappa_enter
              ):  # pragma: no cover - compiled
    """MeanShiftRobot.entering: toward the nearest sensed target point (squared distances
    ``d2``), else the beacon."""
    if on_target:
        return 0.0, 0.0
    if k > 0:
        best = 0
        best_d = d2[0]
        for j in range(1, k):
            if d2[j] < best_d:
                best, best_d = j, d2[j]
        gx, gy = q[best, 0], q[best, 1]
        n = hypot(gx, gy)
        if n > 1e-9:
            return kappa_enter * gx / n, kappa_enter * gy / n
    if has_beacon:
        return kappa_enter * beacon[0], kappa_enter * beacon[1]
    return 0.0, 0.0


@njit(cache=True)
def _exploring(q, d2, k, qa, qb, qx, qy, cx, cy, odo_i, offsets, distances, G, lattice, taken,
               scratch):  # pragma: no cover - compiled
    """kernel.explore's command (x, y), units per tick, for the robot's sensed target points
    ``q[:k]`` (squared distances ``d2``, stencil rows and columns ``qa``, ``qb``, lattice
    rows and columns at offsets ``qx``, ``qy``), its neighbours at ``offsets``,
    ``distances``: a point is occupied when some neighbour within r_sense + r_occupied lies
    within r_occupied of it, by the same test on the same numbers (:func:`_mark_taken`).
    ``taken`` (side, words) int64, ``scratch`` (3, side * side): work rows."""
    if k == 0:
        return 0.0, 0.0
    r_sense, r_occupied = G.r_sense, G.r_occupied
    _mark_taken(qx, qy, cx, cy, odo_i, offsets, distances, r_sense + r_occupied, r_occupied,
                lattice, taken, scratch[2])
    arg, w, wf = scratch[0], scratch[1], scratch[2]
    for i in range(k):
        arg[i] = np.pi * min(np.sqrt(d2[i]) / r_sense, 1.0)
    sx, sy, fx, fy, free = _kernel_sums(q, arg, k, qa, qb, taken, w, wf)
    o0 = 0.0
    o1 = 0.0
    w_sum = pairwise_sum(w, 0, k)
    if w_sum > 0:
        o0 += G.kappa_fill * sx / w_sum
        o1 += G.kappa_fill * sy / w_sum
    f_sum = w_sum if free == k else pairwise_sum(wf, 0, free)
    if f_sum > 0:
        o0 += G.kappa_expl * fx / f_sum
        o1 += G.kappa_expl * fy / f_sum
    return o0, o1


@njit(cache=True)
def _kernel_sums(q, arg, k, qa, qb, taken, w, wf):  # pragma: no cover - compiled
    """The raised-cosine weights ``w[i] = (1 + cos(arg[i])) / 2`` of the points ``q[:k]``
    and their weighted sums (sx, sy), the free points' (their bit in ``taken`` not set)
    weights into ``wf`` and weighted sums (fx, fy), each added in point order as
    kernel._add_kernel_mean adds them. Returns sx, sy, fx, fy and the number of free points."""
    sx = 0.0
    sy = 0.0
    fx = 0.0
    fy = 0.0
    free = 0
    for i in range(k):
        wi = 0.5 * (1.0 + np.cos(arg[i]))
        w[i] = wi
        sx += wi * q[i, 0]
        sy += wi * q[i, 1]
        b = qb[i]
        if not (taken[qa[i], b >> 6] >> (b & 63)) & 1:
            wf[free] = wi
            fx += wi * q[i, 0]
            fy += wi * q[i, 1]
            free += 1
    return sx, sy, fx, fy, free


@njit(cache=True)
def _mark_taken(qx, qy, cx, cy, odo_i, offsets, distances, near, r_occupied, lattice, taken,
                dy2):  # pragma: no cover - compiled
    """``taken`` (side, words) int64: bit b % 64 of word b // 64 of row a set when stencil
    cell (a, b) lies within ``r_occupied`` of a neighbour at most ``near`` away, by
    kernel.explore's test (dx * dx, then + dy * dy, <= r_occupied ** 2); ``dy2`` (side,):
    scratch."""
    cell, reach, _ = lattice
    side = 2 * reach + 1
    limit = r_occupied ** 2
    # the lattice rows and columns within r_occupied of a neighbour, and a little more: the
    # test's dx (computed as the sensed points' offsets are) is within a few ulps of
    # ix * cell - (odo + n), far less than this margin
    reach_out = r_occupied * (1.0 + 1e-6) + 1e-6 * cell
    taken[:, :] = 0
    for j in range(distances.shape[0]):
        if not distances[j] <= near:
            continue
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
            # gathered in a word and or-ed in once a word, without a branch a cell: where a
            # row's marks end is hard to predict
            word = b_lo >> 6
            m = np.int64(0)
            for b in range(b_lo, b_hi):
                if b >> 6 != word:
                    taken[a, word] |= m
                    word, m = b >> 6, np.int64(0)
                m |= np.int64(dx2 + dy2[b] <= limit) << (b & 63)
            taken[a, word] |= m


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
    d2 = np.empty(side * side)
    qa = np.empty(side * side, dtype=np.int64)
    qb = np.empty(side * side, dtype=np.int64)
    taken = np.empty((side, (side + 63) // 64), dtype=np.int64)
    scratch = np.empty((3, side * side))
    qx, qy = np.empty(side), np.empty(side)
    inertia, vmax, deadband = G.inertia, G.v, G.deadband
    for k in range(len(rows)):
        i = rows[k]
        n_q, cx, cy = _sensed_target(grid[i], origin[i], odo[i], lattice, q, d2, qa, qb, qx, qy)
        e0, e1 = _entering(on_target[k], q, d2, n_q, has_beacon, beacons[k], G.kappa_enter)
        a, b = starts[k], starts[k + 1]
        x0, x1 = _exploring(q, d2, n_q, qa, qb, qx, qy, cx, cy, odo[i], offsets[a:b],
                            distances[a:b], G, lattice, taken, scratch)
        f0, f1 = interaction(offsets[a:b], distances[a:b], sender[a:b], vx[a:b], vy[a:b],
                             velocity[i], G.d_cover, G.r_sense, G.kappa_avoid, G.kappa_cons,
                             no_sender)
        c0 = (e0 + x0) + f0
        c1 = (e1 + x1) + f1
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
