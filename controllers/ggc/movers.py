"""GGC's Coverage movers of a chunk decided together: the edge-following geometry, the
circling counts and giving way of all of them in one compiled call (moverkernel.py), their
gradients as arrays; the rest, robot by robot, in
:meth:`~controllers.ggc.fastpath.BatchDecisions.finish_coverage`.

Both give the same numbers as :meth:`~controllers.ggc.coverage.CoverageRules.coverage` to
the bit (see moverkernel.py; the gradients are integer tests). A mover they cannot stand for
(a neighbour at distance 0: ``coverage`` divides by it) gets None: it takes ``step``.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from swarmsim.controller import INF_GRADIENT, NO_SENDER, Action, DecideBatch

from .batch import first_two_rows
from .moverkernel import mover_geometry

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
    movers = [robots[k] for k in ks]
    kk = np.asarray(ks, dtype=np.intp)
    answers = f.chunk.movers
    a, b = answers.nearest[kk], answers.second[kk]
    sender = f.sender[a].astype(np.int64)  # the id of the edge robot each mover follows
    last = [math.nan if r.last_bearing is None else r.last_bearing for r in movers]
    velocity, heading, usable, bearing, circled, full, gives_way, give_way = mover_geometry(
        f.offset, f.distance, a, b, np.array([r.sense for r in movers], dtype=float),
        np.array([r.heading for r in movers], dtype=float).reshape(-1, 2),
        sender, np.array([r.circling_id for r in movers], dtype=np.int64),
        np.array(last), np.array([r.circled for r in movers], dtype=float),
        p.d_cover, p.radial_gain, p.v, NO_SENDER, kk, answers.ahead_array,
        answers.ahead_first_array, p.yield_distance)
    give_way = [tuple(v) if yes else None
                for yes, v in zip(gives_way.tolist(), give_way.tolist(), strict=True)]
    grads = mover_gradients(a, kk, f, p, len(robots)).tolist()
    circling = zip(sender.tolist(), circled.tolist(), bearing.tolist(), full.tolist(),
                   strict=True)
    listen = movers[0].listen_range()  # the same for every robot in Coverage
    moves = zip(*(velocity[:, j].tolist() for j in (0, 1)), strict=True)
    da = f.distance[a]
    odometers = np.array([r.odometer for r in movers], dtype=float).reshape(-1, 2) + c.moved[kk]
    return [robot.finish_coverage(c, f, k, row, dist, move, head, grad, count, listen, odo,
                                  way)
            if ok else None
            for robot, k, row, dist, move, head, grad, count, ok, odo, way in zip(
                movers, ks, a.tolist(), da.tolist(), moves, heading, grads, circling,
                usable.tolist(), odometers, give_way, strict=True)]


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
