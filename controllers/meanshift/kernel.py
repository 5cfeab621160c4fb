"""Mean-shift's per-tick arithmetic, compiled (numba): the exploring and interaction commands
of :class:`~controllers.meanshift.controller.MeanShiftRobot` in one pass each, where numpy made ~30 calls on
arrays of a few hundred points (~60 us a robot, most of a mean-shift tick).

The same sums as numpy's, to the bit: a 1-D ``sum()`` is numpy's pairwise summation
(:func:`~controllers.common.npsum.pairwise_sum`), ``(k, 2).sum(axis=0)`` and ``mean(axis=0)`` add rows in order. The
tests compare both ways on random inputs.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from controllers.common.npsum import pairwise_sum


@njit(cache=True)
def explore(points, target, offsets, distances, r_sense, r_occupied, kappa_fill, kappa_expl
            ):  # pragma: no cover - compiled
    """The exploring command (units per tick): ``kappa_fill`` times the raised-cosine kernel
    mean of the sensed target points (``points`` (n, 2), offsets in units, where ``target``)
    plus ``kappa_expl`` times that of those farther than ``r_occupied`` from every neighbour
    (``offsets``, ``distances``: the neighbours' offsets and distances, units; only those
    within r_sense + r_occupied can occupy a point)."""
    q = _rows_where(points, target)
    neighbours = _rows_where(offsets, distances <= r_sense + r_occupied)
    k = q.shape[0]
    out = np.zeros(2)
    if k == 0:
        return out
    w = np.empty(k)
    for i in range(k):
        d = np.sqrt(q[i, 0] * q[i, 0] + q[i, 1] * q[i, 1])
        w[i] = 0.5 * (1.0 + np.cos(np.pi * min(d / r_sense, 1.0)))
    _add_kernel_mean(out, w, q, k, kappa_fill)
    if neighbours.shape[0] == 0:
        _add_kernel_mean(out, w, q, k, kappa_expl)
        return out
    free = 0
    wf = np.empty(k)
    qf = np.empty((k, 2))
    limit = r_occupied ** 2
    for i in range(k):
        occupied = False
        for j in range(neighbours.shape[0]):
            dx = q[i, 0] - neighbours[j, 0]
            dy = q[i, 1] - neighbours[j, 1]
            d2 = dx * dx
            d2 += dy * dy
            if d2 <= limit:  # the nearest is at least this near: the point is taken
                occupied = True
                break
        if not occupied:
            wf[free] = w[i]
            qf[free, 0] = q[i, 0]
            qf[free, 1] = q[i, 1]
            free += 1
    _add_kernel_mean(out, wf, qf, free, kappa_expl)
    return out


@njit(cache=True)
def _rows_where(rows, mask):  # pragma: no cover - compiled
    """``rows[mask]`` for (n, 2) rows, as a new contiguous array."""
    out = np.empty((rows.shape[0], 2))
    k = 0
    for i in range(rows.shape[0]):
        if mask[i]:
            out[k, 0] = rows[i, 0]
            out[k, 1] = rows[i, 1]
            k += 1
    return out[:k]


@njit(cache=True)
def _add_kernel_mean(out, w, q, k, gain):  # pragma: no cover - compiled
    """``out += gain * (w[:k, None] * q[:k]).sum(axis=0) / w[:k].sum()`` where the weights
    sum to more than 0."""
    w_sum = pairwise_sum(w, 0, k)
    if not w_sum > 0:
        return
    sx = 0.0
    sy = 0.0
    for i in range(k):
        sx += w[i] * q[i, 0]
        sy += w[i] * q[i, 1]
    out[0] += gain * sx / w_sum
    out[1] += gain * sy / w_sum


@njit(cache=True)
def interact(offsets, distances, sender, vx, vy, velocity, d_cover, r_sense, kappa_avoid,
             kappa_cons, no_sender):  # pragma: no cover - compiled
    """The interaction command (units per tick): repulsion from neighbours closer than
    ``d_cover`` (units) and velocity consensus with those heard within ``r_sense`` (their
    broadcast ``vx``, ``vy``, float32; a ``sender`` of ``no_sender``: nothing heard)."""
    out = np.zeros(2)
    out[0], out[1] = interaction(offsets, distances, sender, vx, vy, velocity, d_cover,
                                 r_sense, kappa_avoid, kappa_cons, no_sender)
    return out


@njit(cache=True)
def interaction(offsets, distances, sender, vx, vy, velocity, d_cover, r_sense, kappa_avoid,
                kappa_cons, no_sender):  # pragma: no cover - compiled
    """:func:`interact`'s command as a pair (x, y), units per tick (no array made)."""
    o0 = 0.0
    o1 = 0.0
    sx = 0.0
    sy = 0.0
    close = 0
    for j in range(distances.shape[0]):
        if distances[j] < d_cover:
            d = max(distances[j], 1e-6)
            push = (d_cover - d) / d
            sx += offsets[j, 0] / d * push
            sy += offsets[j, 1] / d * push
            close += 1
    if close:
        o0 -= kappa_avoid * sx
        o1 -= kappa_avoid * sy
    if kappa_cons > 0:
        cx = 0.0
        cy = 0.0
        count = 0
        for j in range(distances.shape[0]):
            if distances[j] <= r_sense and sender[j] != no_sender:
                cx += velocity[0] - np.float64(vx[j])
                cy += velocity[1] - np.float64(vy[j])
                count += 1
        if count:
            o0 -= kappa_cons * (cx / count)
            o1 -= kappa_cons * (cy / count)
    return o0, o1


def warm_up() -> None:
    """Compile (first time on a machine) or load (from the cache) the kernels now."""
    q = np.zeros((1, 2))
    explore(q, np.ones(1, dtype=np.bool_), q, np.ones(1), 1.0, 1.0, 1.0, 1.0)
    rows = np.zeros(1, dtype=[("id", "i4"), ("vx", "f4"), ("vy", "f4")])  # strided fields
    interact(q, np.ones(1), rows["id"], rows["vx"], rows["vy"], np.zeros(2), 1.0, 1.0, 1.0, 1.0,
             -1)
