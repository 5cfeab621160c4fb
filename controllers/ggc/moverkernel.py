"""GGC's Coverage movers' geometry, compiled (numba): edge following, the valley between two
edge robots, the new heading, the circling count and giving way, for all of a chunk's movers
in one call.

Each mover reads only its own rows (the offsets of its nearest two edge robots) and its own
state, as :mod:`controllers.ggc.movers` does with numpy. The numbers are the same to the bit:
``+ - * /``, comparisons, ``min``/``max`` and ``%`` are IEEE operations in the same order
(numba keeps IEEE arithmetic: no fast-math, so no fused multiply-add), ``math.atan2`` is the C
library's on both sides, and :func:`py_hypot` is CPython's own ``math.hypot`` (which numpy's
and the C library's ``hypot`` differ from in the last bit on ~0.6 % of inputs). Giving way
asks whether a robot is ahead with the dot product ``x * vx + y * vy``, two IEEE products
and a sum, as :meth:`~controllers.ggc.collisions.CollisionRules.give_way` does (both took
numpy's ``@`` before, whose BLAS kernel, and so its last bit, depends on the CPU).

Why compiled: a chunk has ~150 movers, and numpy spent its time on the overhead of some forty
calls over such short arrays and on one ``math.hypot`` per element in Python.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

_SPLIT = 134217729.0  # 2**27 + 1: Veltkamp's splitting constant for doubles


@njit(cache=True, inline="always")
def _two_product(x, y):  # pragma: no cover - compiled
    """x * y as an unevaluated sum hi + lo, exactly (Dekker's mul12 on Veltkamp splits)."""
    c = _SPLIT * x
    xh = c - (c - x)
    xl = x - xh
    c = _SPLIT * y
    yh = c - (c - y)
    yl = y - yh
    hi = x * y
    lo = ((xh * yh - hi) + xh * yl + xl * yh) + xl * yl
    return hi, lo


@njit(cache=True)
def py_hypot(x, y):  # pragma: no cover - compiled
    """CPython's ``math.hypot(x, y)`` to the bit (its ``vector_norm``: lossless scaling and
    squaring, then a differential correction). Normal and zero inputs; subnormal inputs,
    which robot geometry never meets, may differ."""
    ax, ay = abs(x), abs(y)
    if math.isnan(x) or math.isnan(y):
        return math.inf if math.isinf(x) or math.isinf(y) else math.nan
    big = max(ax, ay)
    if math.isinf(big) or big == 0.0:
        return big
    _, e = math.frexp(big)
    scale = math.ldexp(1.0, -e)
    csum, frac1, frac2 = 1.0, 0.0, 0.0
    for v in (ax, ay):
        hi, lo = _two_product(v * scale, v * scale)
        s = csum + hi
        frac2 += hi - (s - csum)
        csum = s
        frac1 += lo
    h = math.sqrt(csum - 1.0 + (frac1 + frac2))
    hi, lo = _two_product(-h, h)
    s = csum + hi
    frac2 += hi - (s - csum)
    csum = s
    frac1 += lo
    h += (csum - 1.0 + (frac1 + frac2)) / (2.0 * h)
    return h / scale


@njit(cache=True, inline="always")
def _scaled(x, y, length):  # pragma: no cover - compiled
    """(x, y) / |(x, y)| * length; zero at length <= 1e-12 (movers.scaled)."""
    norm = py_hypot(x, y)
    if norm <= 1e-12:
        return 0.0, 0.0
    return x / norm * length, y / norm * length


@njit(cache=True, inline="always")
def _clip_unit(x):  # pragma: no cover - compiled
    return max(-1.0, min(1.0, x))


@njit(cache=True, inline="always")
def _valley(oxa, oya, da, oxb, oyb, db, hx, hy, sense, radial_gain, v):  # pragma: no cover
    """movers.valley_between for one mover: (in a valley?, vx, vy)."""
    ax, ay, bx, by = oxa / da, oya / da, oxb / db, oyb / db
    if ax * bx + ay * by >= 0:
        return False, 0.0, 0.0
    ux, uy = _scaled(ax - bx, ay - by, 1.0)
    along_x, along_y = uy, -ux
    if not (hx != 0.0 or hy != 0.0):
        hx, hy = ay * sense, (-ax) * sense
    if along_x * hx + along_y * hy < 0:
        along_x, along_y = -along_x, -along_y
    half = 0.5 * _clip_unit((da - db) * radial_gain)
    vx, vy = _scaled(along_x + half * ux, along_y + half * uy, v)
    return True, vx, vy


@njit(cache=True, inline="always")
def _give_way(offsets, distances, rows, vx, vy, reach, v):  # pragma: no cover - compiled
    """collisions.give_way over ``rows`` (moving robots with a larger id, nearest first):
    (give way?, vx, vy): back away from the first one ahead (a positive dot product with my
    velocity) if it is closer than ``reach``, else wait."""
    for row in rows:
        ox, oy = offsets[row, 0], offsets[row, 1]
        if ox * vx + oy * vy > 0:
            if distances[row] >= reach:
                return True, 0.0, 0.0
            ux, uy = _scaled(ox, oy, 1.0)  # geometry.unit
            return True, -ux * v * 0.5, -uy * v * 0.5
    return False, 0.0, 0.0


@njit(cache=True)
def mover_geometry(offsets, distances, a, b, sense, before, sender, circling_id, last_bearing,
                   circled, d_cover, radial_gain, v, no_sender, movers, ahead, ahead_first,
                   yield_distance):  # pragma: no cover - compiled
    """The velocity, heading, circling count and giving way of M movers.

    Args:
        offsets: (P, 2) the chunk's neighbour offsets, units; distances: (P,) their lengths.
        a, b: (M,) each mover's nearest and second edge robot (rows; b -1: none).
        sense: (M,) orbit sense (+1 or -1); before: (M, 2) heading before this tick.
        sender: (M,) the id of robot ``a``; circling_id, last_bearing (NaN: none), circled
            (radians): each mover's circling count before this tick.
        d_cover, radial_gain, v: GGC's parameters (units, 1/unit, units per tick).
        no_sender: the id of a silent robot.
        movers: (M,) each mover's index in the chunk; ahead, ahead_first: the rows of the
            moving robots each robot of the chunk gives way to (robot k's are
            ``ahead[ahead_first[k]:ahead_first[k+1]]``); yield_distance: units.

    Returns:
        velocity (M, 2) units per tick; heading (M, 2) unit vectors; usable (M,) bool:
        False where a neighbour is at distance 0 (``coverage`` divides by it: the mover
        takes ``step``); bearing (M,) radians, the new last_bearing; circled_now (M,)
        radians; full (M,) bool: gone all round; gives_way (M,) bool and give_way (M, 2)
        units per tick: the velocity that replaces ``velocity`` where it gives way.
    """
    m = len(a)
    velocity, heading = np.empty((m, 2)), np.empty((m, 2))
    usable, full = np.empty(m, dtype=np.bool_), np.empty(m, dtype=np.bool_)
    bearing, circled_now = np.empty(m), np.empty(m)
    gives_way, give_way = np.empty(m, dtype=np.bool_), np.empty((m, 2))
    reach = yield_distance * 0.75
    for j in range(m):
        ox, oy, da = offsets[a[j], 0], offsets[a[j], 1], distances[a[j]]
        db = distances[b[j]] if b[j] >= 0 else math.inf
        scale = max(da, 1e-9)
        rx, ry = ox / scale, oy / scale
        error = _clip_unit((da - d_cover) * radial_gain)
        s = sense[j]
        vx, vy = _scaled(ry * s + error * rx, (-rx) * s + error * ry, v)
        usable[j] = da > 0 and db > 0
        if usable[j] and db < d_cover:
            valley, wx, wy = _valley(ox, oy, da, offsets[b[j], 0], offsets[b[j], 1], db,
                                     before[j, 0], before[j, 1], s, radial_gain, v)
            if valley:
                vx, vy = wx, wy
        velocity[j, 0], velocity[j, 1] = vx, vy
        heading[j, 0], heading[j, 1] = _scaled(vx, vy, 1.0)
        bearing[j] = math.atan2(-oy, -ox)
        last = last_bearing[j]
        same = circling_id[j] == sender[j] and sender[j] != no_sender and not math.isnan(last)
        turned = (bearing[j] - last + math.pi) % (2 * math.pi) - math.pi
        circled_now[j] = circled[j] + turned if same else 0.0
        full[j] = same and abs(circled_now[j]) > 2 * math.pi
        k = movers[j]
        gives_way[j], give_way[j, 0], give_way[j, 1] = _give_way(
            offsets, distances, ahead[ahead_first[k]:ahead_first[k + 1]], vx, vy, reach, v)
    return velocity, heading, usable, bearing, circled_now, full, gives_way, give_way


def warm_up() -> None:
    """Compile (first time on a machine) or load (from the cache) the kernel now."""
    ints, floats = np.zeros(1, dtype=np.intp), np.ones(1)
    mover_geometry(np.ones((1, 2)), floats, ints, ints - 1, floats, np.zeros((1, 2)),
                   np.zeros(1, dtype=np.int64), np.zeros(1, dtype=np.int64), floats, floats,
                   1.0, 1.0, 1.0, -1, ints, ints, np.zeros(2, dtype=np.intp), 1.0)
