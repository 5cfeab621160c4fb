"""GGC's Coverage movers of a chunk decided together: the edge-following geometry and the
gradients of all of them as arrays; the rest, robot by robot, in
:meth:`~controllers.ggc.fastpath.BatchDecisions.finish_coverage`.

The arrays give the same numbers as :meth:`~controllers.ggc.coverage.CoverageRules.coverage`
to the bit. Its arithmetic (``+ - * /``, comparisons, min and max against constants) is
IEEE on both sides: numpy applies one operation at a time on float64 and fuses none. Where
numpy's function and Python's differ in the last bit (``hypot``: numpy takes the C library's,
Python its own), each element takes ``math.hypot``. A mover the arrays cannot stand for (a
neighbour at distance 0: ``coverage`` divides by it) gets None: it takes ``step``.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from controllers.edges import turn_between
from swarmsim.controller import INF_GRADIENT, NO_SENDER, Action, DecideBatch

from .batch import first_two_rows

if TYPE_CHECKING:
    from .fastpath import ChunkRows
    from .params import GGCParams
    from .robot import GGCRobot

KEEP_GRADIENT = -1
"""In :func:`mover_gradients`: the robot keeps its gradient (``follow_gradient`` found no
stationary neighbour of its group to take one from)."""


def decide_movers(robots: list[GGCRobot], ks: list[int], c: DecideBatch, f: ChunkRows
                  ) -> list[Action | None]:
    """The actions of the chunk's Coverage movers ``ks`` (indices in the chunk, each with a
    nearest edge robot); None for those whose tick is not the common case (``step``)."""
    p = robots[ks[0]].p
    kk = np.asarray(ks, dtype=np.intp)
    nearest, second = f.chunk.movers.nearest, f.chunk.movers.second
    a, b = nearest[kk], second[kk]
    da, ox, oy = f.distance[a], c.offsets[a, 0], c.offsets[a, 1]
    db = np.where(b >= 0, f.distance[b], np.inf)
    sense = np.array([robots[k].sense for k in ks], dtype=float)
    velocity = edge_follow(ox, oy, da, sense, p)
    valley = np.flatnonzero(db < p.d_cover)
    usable = (da > 0) & (db > 0)  # coverage() divides by both
    if len(valley):
        found = valley[usable[valley]]
        bb = b[found]
        before = np.array([robots[ks[j]].heading for j in found.tolist()]).reshape(-1, 2)
        v, ok = valley_between(ox[found], oy[found], da[found], c.offsets[bb, 0],
                               c.offsets[bb, 1], db[found], before, sense[found], p)
        velocity[found[ok]] = v[ok]
    heading = scaled(velocity[:, 0], velocity[:, 1], 1.0)
    grads = mover_gradients(a, kk, f, p, len(robots)).tolist()
    circling = circling_counts([robots[k] for k in ks], f.sender[a], ox, oy)
    listen = robots[ks[0]].listen_range()  # the same for every robot in Coverage
    moves = list(zip(*(velocity[:, j].tolist() for j in (0, 1)), strict=True))
    return [robots[k].finish_coverage(c, f, k, row, dist, move, head, grad, count, listen)
            if ok else None
            for k, row, dist, move, head, grad, count, ok in zip(
                ks, a.tolist(), da.tolist(), moves, heading, grads, circling,
                usable.tolist(), strict=True)]


def hypot(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Elementwise ``math.hypot`` (Python's, which numpy's ``hypot`` may differ from in the
    last bit)."""
    return np.array([math.hypot(u, v) for u, v in zip(x.tolist(), y.tolist())]).reshape(-1)


def scaled(x: np.ndarray, y: np.ndarray, length: float) -> np.ndarray:
    """(M, 2) the vectors (x, y) scaled to ``length`` (``v / |v| * length``); vectors of
    length <= 1e-12 become zero (as ``unit`` and ``edge_follow`` do)."""
    norm = hypot(x, y)
    short = norm <= 1e-12
    norm[short] = 1.0
    out = np.column_stack((x / norm * length, y / norm * length))
    out[short] = 0.0
    return out


def clip_unit(x: np.ndarray) -> np.ndarray:
    """``max(-1.0, min(1.0, x))`` elementwise."""
    return np.maximum(-1.0, np.minimum(1.0, x))


def edge_follow(ox: np.ndarray, oy: np.ndarray, dist: np.ndarray, sense: np.ndarray,
                p: GGCParams) -> np.ndarray:
    """(M, 2) :meth:`~controllers.ggc.coverage.CoverageRules.edge_follow` for M movers:
    orbit the robot at offset (ox, oy), ``dist`` units away, in ``sense`` (+1 or -1)."""
    scale = np.maximum(dist, 1e-9)
    rx, ry = ox / scale, oy / scale
    error = clip_unit((dist - p.d_cover) * p.radial_gain)
    return scaled(ry * sense + error * rx, (-rx) * sense + error * ry, p.v)


def valley_between(oxa: np.ndarray, oya: np.ndarray, da: np.ndarray, oxb: np.ndarray,
                   oyb: np.ndarray, db: np.ndarray, heading: np.ndarray, sense: np.ndarray,
                   p: GGCParams) -> tuple[np.ndarray, np.ndarray]:
    """:meth:`~controllers.ggc.coverage.CoverageRules.valley_between` for M movers: (M, 2)
    velocities, and (M,) which movers are in a valley (the others follow the edge)."""
    ax, ay, bx, by = oxa / da, oya / da, oxb / db, oyb / db
    valley = ~(ax * bx + ay * by >= 0)
    axis = scaled(ax - bx, ay - by, 1.0)
    ux, uy = axis[:, 0], axis[:, 1]
    along_x, along_y = uy, -ux
    hx, hy = heading[:, 0], heading[:, 1]
    still = ~((hx != 0.0) | (hy != 0.0))
    hx, hy = np.where(still, ay * sense, hx), np.where(still, (-ax) * sense, hy)
    back = along_x * hx + along_y * hy < 0
    along_x, along_y = np.where(back, -along_x, along_x), np.where(back, -along_y, along_y)
    half = 0.5 * clip_unit((da - db) * p.radial_gain)
    return scaled(along_x + half * ux, along_y + half * uy, p.v), valley


def circling_counts(robots: list[GGCRobot], sender: np.ndarray, ox: np.ndarray,
                    oy: np.ndarray) -> list[tuple[int, float, float, bool]]:
    """Each mover's :meth:`~controllers.edges.CirclingWatch.circling` after this tick, as
    (circling_id, circled, last_bearing, gone all round?), for the robot ``sender`` it
    follows at offset (ox, oy). ``turn_between`` on arrays: its ``%`` is then numpy's
    ``mod``, the same remainder to the bit (CPython's algorithm)."""
    bearing = np.array([math.atan2(-y, -x) for x, y in zip(ox.tolist(), oy.tolist())])
    same = np.array([r.circling_id for r in robots]) == sender
    last = np.array([math.nan if r.last_bearing is None else r.last_bearing for r in robots])
    same &= (sender != NO_SENDER) & ~np.isnan(last)
    circled = np.array([r.circled for r in robots]) + turn_between(last, bearing)
    circled[~same] = 0.0
    full = same & (np.abs(circled) > 2 * math.pi)
    return list(zip(sender.tolist(), circled.tolist(), bearing.tolist(), full.tolist(),
                    strict=True))


def mover_gradients(a: np.ndarray, kk: np.ndarray, f: ChunkRows, p: GGCParams, robots: int
                    ) -> np.ndarray:
    """(M,) the gradient each mover takes (``follow_gradient``): its nearest edge robot's
    (rows ``a``) plus one, or with another group's robot there, its nearest stationary
    robot's of its own group within 1.5 d_cover; KEEP_GRADIENT where it keeps its own."""
    source = a.copy()
    foreign = f.group[a] != f.own_group[a]
    if foreign.any():
        mine = ~f.moving & (f.group == f.own_group) & (f.distance <= 1.5 * p.d_cover)
        first, _ = first_two_rows(mine, f.segment, robots)
        source[foreign] = first[kk[foreign]]
    gradient = f.gradient[source].astype(np.int64)
    take = (source >= 0) & (f.sender[source] != NO_SENDER) & (gradient < INF_GRADIENT)
    return np.where(take, gradient + 1, KEEP_GRADIENT)
