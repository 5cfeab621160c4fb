"""GGC's Coverage movers of a chunk decided together: the edge-following geometry, the
circling counts and giving way of all of them in one compiled call (moverkernel.py), their
gradients and the common case's tests as arrays, and their new state written to their rows
of the run's :class:`~controllers.ggc.book.EdgeBook` at once. Only the rare tests go robot by
robot: an arrival (for movers at d_cover from their edge robot on the target), a progress
sample (once every T_r ticks), and with one group the surplus lap and the step-in.

Both give the same numbers as :meth:`~controllers.ggc.coverage.CoverageRules.coverage` to
the bit (see moverkernel.py; the gradients are integer tests). A mover whose tick is not
the common case (a neighbour at distance 0: ``coverage`` divides by it; an arrival, a dead
end, a Stop, a surplus robot giving up, a step-in) is left with nothing changed: it takes
``step``. (A mover decided here has no ``pre`` or ``pre_wait`` to clear: the chunk path
hands out none to movers, and a Detection robot's is cleared in the tick it is given.)
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from controllers.gradient import INF_GRADIENT
from swarmsim.controller import NO_SENDER, ChunkActions, DecideBatch

from .moverkernel import mover_geometry
from .moverrows import gradient_sources

if TYPE_CHECKING:
    from .book import EdgeBook
    from .fastpath import ChunkRows
    from .params import GGCParams
    from .robot import GGCRobot

KEEP_GRADIENT = -1
"""In :func:`mover_gradients`: the robot keeps its gradient (``follow_gradient`` found no
stationary neighbour of its group to take one from)."""


def decide_movers(robots: list[GGCRobot], ks: list[int], c: DecideBatch, f: ChunkRows,
                  out: ChunkActions, done: np.ndarray) -> None:
    """Decide the common case of the chunk's Coverage movers ``ks`` (indices in the chunk,
    each with a nearest edge robot): their actions into ``out``, ``done`` set for them; the
    others are left untouched (they take ``step``)."""
    lead = robots[ks[0]]
    p, book = lead.p, lead.book
    movers = [robots[k] for k in ks]
    rows = np.array([r.row for r in movers], dtype=np.intp)
    kk = np.asarray(ks, dtype=np.intp)
    answers = f.chunk.movers
    a, b = answers.nearest[kk], answers.second[kk]
    sender = f.sender[a].astype(np.int64)  # the id of the edge robot each mover follows
    velocity, heading, usable, bearing, circled, full, gives_way, give_way = mover_geometry(
        f.offset, f.distance, a, b, book.sense[rows], book.heading[rows], sender,
        book.circling_id[rows], book.last_bearing[rows], book.circled[rows],
        p.d_cover, p.radial_gain, p.v, NO_SENDER, kk, answers.ahead_array,
        answers.ahead_first_array, p.yield_distance)
    odometers = book.odometer[rows] + c.moved[kk]
    sampled = c.tick - book.progress_tick[rows] >= p.T_r
    mine = usable & ~full & ~_stops(lead, book, rows, kk, c, f)
    laps = _rare_tests(movers, ks, c, f, a, heading, odometers, sampled, mine)
    grads = mover_gradients(a, kk, f, p)
    changed = mine & (grads != KEEP_GRADIENT) & (grads != [r.grad for r in movers])
    w = np.flatnonzero(mine)
    _write_book(book, rows[w], c.tick, heading[w], odometers[w], sampled[w], sender[w],
                circled[w], bearing[w])
    for j in np.flatnonzero(mine & sampled).tolist():  # a sample that showed progress
        movers[j].in_deadlock = False
    for j, grad in zip(np.flatnonzero(changed).tolist(), grads[changed].tolist(), strict=True):
        movers[j].grad = grad
    for j, lap in laps.items():
        if mine[j]:
            r = movers[j]
            r.away, r.frontier, r.lap_whole, r.winding, r.beacon_angle = lap
    decided = kk[w]
    out.velocities[decided] = np.where(gives_way[w, None], give_way[w], velocity[w])
    out.listen[decided] = lead.listen_range()  # the same for every robot in Coverage
    for j in np.flatnonzero(changed).tolist():  # the others repeat their broadcast
        out.messages[ks[j]] = movers[j].message()
    done[decided] = True


def _stops(lead: GGCRobot, book: EdgeBook, rows: np.ndarray, kk: np.ndarray,
           c: DecideBatch, f: ChunkRows) -> np.ndarray:
    """(M,) which movers Stop for another group's mover (Section 4.3): step() does that."""
    if lead.groups == 1:
        return np.zeros(len(rows), dtype=bool)
    p = lead.p
    stop = f.chunk.movers.has_movers_array[kk] & (c.tick >= book.pass_until[rows])
    if p.stop_on_target_only:
        stop &= np.asarray(c.on_target, dtype=bool)[kk]
    return stop


def _rare_tests(movers: list[GGCRobot], ks: list[int], c: DecideBatch, f: ChunkRows,
                a: np.ndarray, heading: np.ndarray, odometers: np.ndarray,
                sampled: np.ndarray, mine: np.ndarray) -> dict[int, tuple]:
    """Clear ``mine`` (in place) for the movers that arrive, are stuck, give up after a
    surplus lap or step in across the boundary (step() does those); return the new lap
    books of the others that keep one (by index in ``movers``). Each test is pure, so
    their order does not matter."""
    lead = movers[0]
    p, on = lead.p, c.on_target
    da = f.distance[a]
    near = np.flatnonzero(mine & (da >= p.d_cover - p.arrive_tolerance)).tolist()
    for j in near:
        if on[ks[j]] and movers[j].arrives_in_batch(c, f, ks[j], int(a[j]), float(da[j]),
                                                     heading[j]):
            mine[j] = False
    for j in np.flatnonzero(mine & sampled).tolist():
        if math.hypot(*odometers[j]) <= p.theta:
            mine[j] = False  # stuck: step() turns round
    laps: dict[int, tuple] = {}
    if lead.surplus_rule or lead.boundary_fill:
        for j in np.flatnonzero(mine).tolist():
            mine[j], lap = _lap_and_step_in(movers[j], c, f, ks[j], int(a[j]), float(da[j]))
            if lap is not None:
                laps[j] = lap
    return laps


def _lap_and_step_in(robot: GGCRobot, c: DecideBatch, f: ChunkRows, k: int, a: int,
                     da: float) -> tuple[bool, tuple | None]:
    """Is robot k's tick still the common case after its surplus lap and the boundary
    fill's step-in test, and its lap's new books (None: it keeps none)."""
    lap = None
    if robot.surplus_rule:
        lap = robot.lap_in_batch(c, f, k, a, da)
        if lap is None:
            return False, None  # surplus: step() gives up
    if robot.boundary_fill and robot.steps_in_batch(c, f, k, a, da):
        return False, None  # boundary fill: step() steps in
    return True, lap


def _write_book(book: EdgeBook, rows: np.ndarray, tick: int, heading: np.ndarray,
                odometers: np.ndarray, sampled: np.ndarray, sender: np.ndarray,
                circled: np.ndarray, bearing: np.ndarray) -> None:
    """The movers' new rows, as ``coverage`` leaves them (a progress sample that showed
    progress zeroes the odometer and restarts the sample's clock)."""
    book.heading[rows] = heading
    odometers[sampled] = 0.0
    book.odometer[rows] = odometers
    book.progress_tick[rows[sampled]] = tick
    book.circling_id[rows] = sender
    book.circled[rows] = circled
    book.last_bearing[rows] = bearing


def mover_gradients(a: np.ndarray, kk: np.ndarray, f: ChunkRows, p: GGCParams
                    ) -> np.ndarray:
    """(M,) the gradient each mover takes (``follow_gradient``): its nearest edge robot's
    (rows ``a``) plus one, or with another group's robot there, its nearest stationary
    robot's of its own group within 1.5 d_cover; KEEP_GRADIENT where it keeps its own."""
    source = gradient_sources(a, kk, f.chunk.starts, f.distance, f.group, f.own_group,
                              f.moving, 1.5 * p.d_cover)
    gradient = f.gradient[source].astype(np.int64)
    take = (source >= 0) & (f.sender[source] != NO_SENDER) & (gradient < INF_GRADIENT)
    return np.where(take, gradient + 1, KEEP_GRADIENT)
