"""GGC's common cases decided a chunk at a time (the engine's ``decide_batch``).

Most of a run's robot-ticks are movers in Coverage following an edge (no arrival, no dead
end, no Stop), robots waiting in Stop or Detection, and formations travelling (Initial). For
those, :class:`BatchDecisions` does what the status's handler does (``coverage``,
``stopped``, ``detection``, ``initial``), reading the robot's own rows of the chunk's arrays
instead of a Perception, with the same float operations in the same order (``math.hypot``,
``math.atan2``, the same products), so the result is the same to the bit. The movers'
geometry, circling counts and giving way come from one compiled call over the whole chunk,
their gradients, common-case tests and state writes as arrays over their rows of the run's
:class:`~controllers.ggc.book.EdgeBook` (movers.py, moverkernel.py); the rare tests
(arrival, a progress sample, the surplus lap) robot by robot with the methods below. A robot
whose broadcast did not change sends none (message
None: the engine repeats its row). The path changes the robot's state only once it knows it
decides the tick. Every other case (an arrival, a dead end, a Stop, giving up after a
surplus lap, stepping in across the boundary, wandering, leaving, resuming, a halt, a
leader, and the two options it does not know: own edges, stop-ahead) returns None first,
and the robot takes its ``step`` with a full Perception. ``batch_decide = false`` (a run
setting) turns this off: results must not change (tests/test_ggc_fastpath.py).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from controllers.edges import turn_between
from controllers.gradient import INF_GRADIENT
from controllers.views import any_of
from swarmsim.controller import NO_SENDER, Action, ChunkActions, DecideBatch

from .batch import (
    BLOCKED_BY_MOVER,
    Chunk,
    any_by_robot,
    first_two_by_robot,
    formation_minimum,
    prepare_chunk,
)
from .coverage import two_arrived
from .enclosure import enclosed_robots
from .geometry import ENCLOSED_GAP
from .movers import decide_movers
from .statuses import (
    ARRIVE,
    CMD_HALT,
    CMD_TRAVEL,
    COVERAGE,
    DETECTION,
    INITIAL,
    STOP,
    SURPLUS,
)

if TYPE_CHECKING:
    from .robot import GGCRobot


class LapAnswers(NamedTuple):
    """Per robot of a chunk, over all its rows (the surplus lap's questions)."""

    waiting: list[bool]
    """A waiting robot (Initial, Detection) of its group is heard (``group_waiting_in``)."""
    surplus: list[bool]
    """A Surplus robot of its group is heard (``hears_group_surplus``)."""


class ChunkRows:
    """The chunk's arrays a robot reads, each field contiguous (rows as in the batch)."""

    __slots__ = ("_enclosed", "_lap", "chunk", "distance", "gradient", "group", "moving",
                 "offset", "own_group", "segment", "sender", "starts", "status",
                 "stepped")

    def __init__(self, chunk: Chunk, batch: DecideBatch):
        self.chunk = chunk
        """The chunk's rows as batch.py's queries read them."""
        m = chunk.m
        self.starts: list[int] = chunk.starts.tolist()
        # contiguous and writeable (as the chunk's distances): the kernels' one signature
        self.distance = chunk.d
        self.offset = np.require(batch.offsets, float, ("C", "W"))
        self.group, self.status, self.sender = m["group"], m["status"], m["id"]
        self.moving, self.gradient = m["moving"], m["gradient"]
        self.stepped = np.ascontiguousarray(batch.neighbours.messages["stepped"])
        self.segment = chunk.segment
        """(P,) the robot (its index in the chunk) each row belongs to."""
        self.own_group = chunk.own_group
        """(P,) the group of the robot each row belongs to."""
        self._lap: LapAnswers | None = None
        self._enclosed: list[bool] | None = None

    @property
    def lap(self) -> LapAnswers:
        """The surplus lap's answers, found for the whole chunk on first use."""
        if self._lap is None:
            n, mine = len(self.starts) - 1, self.group == self.own_group
            waiting = mine & ((self.status == INITIAL) | (self.status == DETECTION))
            surplus = mine & (self.status == SURPLUS)
            self._lap = LapAnswers(*(any_by_robot(rows, self.segment, n).tolist()
                                     for rows in (waiting, surplus)))
        return self._lap

    def enclosed(self, k: int, reach: float) -> bool:
        """``is_enclosed``: robot k's waiting neighbours within ``reach`` (units, the same for
        every robot: 1.5 d_min) leave no gap wider than ENCLOSED_GAP; found for the whole
        chunk on first use."""
        if self._enclosed is None:
            self._enclosed = enclosed_robots(
                self.offset, self.distance, self.status.astype(np.int64), self.chunk.starts,
                reach, INITIAL, DETECTION, ENCLOSED_GAP).tolist()
        return self._enclosed[k]

    def at_lattice_site(self, k: int, reach: float) -> bool:
        """``at_lattice_site``: two arrived robots within ``reach`` of robot k."""
        start, end = self.starts[k], self.starts[k + 1]
        return two_arrived(self.distance[start:end], self.status[start:end], reach)


class TravelAnswers(NamedTuple):
    """What each travelling robot of a chunk reads from its formation neighbours (within
    1.5 d_min, its group's), found with masks over the chunk's rows at once: the answers of
    ``gradient_in``, ``parent_in`` and ``touching_in`` (integer and boolean tests only)."""

    best: list[int]
    """The smallest gradient among the robot's formation neighbours (INF_GRADIENT: none)."""
    parent: list[int]
    """The row of its gradient parent (the nearest holding ``best``), or -1."""
    touched: list[bool]
    """Does one of them broadcast ``touch``?"""
    cmd: np.ndarray
    vx: np.ndarray
    vy: np.ndarray

    @classmethod
    def of(cls, robots: list[GGCRobot], batch: DecideBatch, f: ChunkRows) -> TravelAnswers:
        n, m, p, segment = len(robots), batch.neighbours.messages, robots[0].p, f.segment
        best = formation_minimum(f.chunk, p.d_min, n)
        mine = (f.distance <= 1.5 * p.d_min) & (f.group == f.own_group)
        held = mine & (f.sender != NO_SENDER) & ~f.moving
        parent, _ = first_two_by_robot(held & (f.gradient == best[segment]), segment, n)
        touched = any_by_robot(mine & m["touch"], segment, n)
        return cls(best.tolist(), parent, touched.tolist(),
                   *(np.ascontiguousarray(m[name]) for name in ("cmd", "vx", "vy")))


def decide_chunk(robots: list[GGCRobot], batch: DecideBatch) -> ChunkActions:
    """Each robot's action: the common cases from the arrays, the rest by ``step`` (after
    the chunk's queries of batch.py, as ``GGC.prepare`` would do)."""
    rows = ChunkRows(prepare_chunk(robots, batch.neighbours, hand_out=False), batch)
    out, done = ChunkActions.empty(len(robots)), np.zeros(len(robots), dtype=bool)
    if rows.chunk.movers is not None:  # robots in Coverage or Stop
        statuses = np.array([r.status for r in robots])
        movers = coverage_movers(robots, statuses, rows, batch.tick)
        if movers:
            decide_movers(robots, movers, batch, rows, out, done)
        waiting = stop_robots(robots, statuses, batch.tick)
        if waiting:
            decide_stops(robots, waiting, batch, rows, out, done)
    travel: TravelAnswers | None = None  # made for the chunk's first travelling robot
    for k in np.flatnonzero(~done).tolist():
        robot = robots[k]
        action, status = None, robot.status
        if status == DETECTION:
            action = robot.detection_in_batch(batch, rows, k)
        elif status == INITIAL and not robot.leader:
            travel = TravelAnswers.of(robots, batch, rows) if travel is None else travel
            action = robot.initial_in_batch(batch, travel, k)
        if action is None:
            if status == COVERAGE or status == STOP:
                robot.pre = rows.chunk.movers.precomputed(k)
            action = robot.step(batch.perceive(k))
        out.put(k, action)
    return out


def _batched(robots: list[GGCRobot], tick: int) -> bool:
    """May this run's Coverage and Stop robots be decided a chunk at a time this tick?
    (not with own edges or stop-ahead, nor while a scattered start selects leaders)"""
    lead = robots[0]
    return lead.batch_coverage and not (lead.scattered and tick < lead.selection_ticks)


def coverage_movers(robots: list[GGCRobot], statuses: np.ndarray, f: ChunkRows, tick: int
                    ) -> list[int]:
    """The chunk's robots in Coverage whose tick may be the common case: those movers.py
    decides (each has an edge robot to follow; not stepping in, not selecting leaders)."""
    if not _batched(robots, tick):
        return []
    found = (statuses == COVERAGE) & (f.chunk.movers.nearest >= 0)
    return [k for k in np.flatnonzero(found).tolist() if not robots[k].stepping_in]


def stop_robots(robots: list[GGCRobot], statuses: np.ndarray, tick: int) -> list[int]:
    """The chunk's robots in Stop that :func:`decide_stops` may decide."""
    return np.flatnonzero(statuses == STOP).tolist() if _batched(robots, tick) else []


def decide_stops(robots: list[GGCRobot], ks: list[int], c: DecideBatch, f: ChunkRows,
                 out: ChunkActions, done: np.ndarray) -> None:
    """:meth:`stopped` for the robots ``ks`` in Stop that keep waiting (T_s after a
    deadlock, or another group's mover still near): they stand, repeat their broadcast and
    restart their progress sample (waiting is not a lack of progress). Those that would
    resume are left untouched (``step`` does that)."""
    lead, tick = robots[ks[0]], c.tick
    p, book = lead.p, lead.book
    rows = np.array([robots[k].row for k in ks], dtype=np.intp)
    kk = np.asarray(ks, dtype=np.intp)
    waiting = tick < book.resume_tick[rows]
    if lead.groups > 1:
        near = f.chunk.movers.has_movers_array[kk]
        if p.stop_patience:
            near &= (np.asarray(c.on_target, dtype=bool)[kk]
                     | (tick - book.stop_since[rows] < p.stop_patience))
        waiting |= near
    rows, decided = rows[waiting], kk[waiting]
    book.progress_tick[rows] = tick
    book.odometer[rows] = 0.0
    out.listen[decided] = lead.listen_range()  # the same for every robot in Stop
    done[decided] = True


class BatchDecisions:
    """Mixin of :class:`~controllers.ggc.robot.GGCRobot`: the common cases of Coverage, Stop,
    Detection and Initial from a chunk's arrays."""

    def lap_in_batch(self: GGCRobot, c: DecideBatch, f: ChunkRows, k: int, a: int, da: float
                     ) -> tuple | None:
        """:meth:`track_winding` then :meth:`is_surplus`: the lap's new books (away,
        frontier, lap_whole, winding, beacon_angle), or None when is_surplus says yes."""
        p, winding, angle = self.p, self.winding, self.beacon_angle
        if c.beacons is not None:
            bearing = math.atan2(float(c.beacons[k, 1]), float(c.beacons[k, 0]))
            if angle is not None:
                winding += turn_between(angle, bearing)
            angle = bearing
        away = self.away or not f.lap.waiting[k]
        frontier, on_target = self.frontier, c.on_target[k]
        if on_target and frontier <= p.surplus_frontier:
            outward = -c.offsets[a] / max(da, 1e-9)
            if c.probe(k)(outward * p.boundary_probe):
                moved = c.moved[k]
                frontier += math.hypot(float(moved[0]), float(moved[1]))
        if p.surplus_spread and not on_target and f.lap.surplus[k]:
            return None
        books = (away, frontier, self.lap_whole, winding, angle)
        if f.sender.item(a) == NO_SENDER or f.group.item(a) != self.group:
            return books
        status = f.status.item(a)
        if status == SURPLUS:
            return None
        if not (away and status in (INITIAL, DETECTION)) or da > p.d_cover + p.arrive_tolerance:
            return books
        went_round = angle is None or abs(winding) >= math.radians(p.surplus_winding)
        if self.lap_whole and frontier <= p.surplus_frontier and went_round:
            return None
        return False, 0.0, True, 0.0, None  # restart_lap(): go round again

    def steps_in_batch(self: GGCRobot, c: DecideBatch, f: ChunkRows, k: int, a: int,
                       da: float) -> bool:
        """:meth:`target_inward`: off the target beside an arrived robot, target floor
        toward it."""
        p = self.p
        if c.on_target[k] or f.status.item(a) != ARRIVE or f.sender.item(a) in self.no_way_in:
            return False
        if f.stepped.item(a) or da < p.d_cover - p.arrive_tolerance:
            return False
        toward = c.offsets[a] / max(da, 1e-9)
        return bool(c.probe(k)(toward * p.boundary_probe))

    def arrives_in_batch(self: GGCRobot, c: DecideBatch, f: ChunkRows, k: int, a: int,
                         da: float, heading: np.ndarray) -> bool:
        """Does :meth:`should_arrive` say yes (on the target)?"""
        p = self.p
        if da < p.d_cover - p.arrive_tolerance:
            return False
        if any_of(heading) and not c.probe(k)(heading * p.probe_distance):
            return True  # rule (a)
        if f.sender.item(a) == NO_SENDER or f.status.item(a) != ARRIVE:
            return False
        reach = p.d_cover + p.arrive_tolerance
        if (p.lattice_stop and reach <= p.lattice_reach and self.groups == 1
                and not f.at_lattice_site(k, reach)):
            return False
        if f.group.item(a) != self.group:
            if p.junction_stop == "always":
                return True
            return p.junction_stop == "lattice" and f.at_lattice_site(k, reach)
        return f.gradient.item(a) >= self.grad

    def initial_in_batch(self: GGCRobot, c: DecideBatch, t: TravelAnswers, k: int
                         ) -> Action | None:
        """:meth:`initial` for a travelling robot that is not a leader and has a gradient
        parent, and no halt to pass on; None otherwise (step() does those)."""
        best, parent = t.best[k], t.parent[k]
        if best == INF_GRADIENT or (self.scattered and c.tick < self.selection_ticks):
            return None  # no gradient: the timeout and sleep of initial()
        cmd = t.cmd.item(parent)
        if cmd == CMD_HALT:
            return None  # the halt: step() stops me and passes it on
        self.odometer += c.moved[k]
        grad, touch = best + 1, c.on_target[k] or t.touched[k]
        vx, vy = t.vx.item(parent), t.vy.item(parent)
        travel = self.travel
        same = (grad == self.grad and touch == self.touch and cmd == self.cmd
                and vx == travel[0] and vy == travel[1])  # then my broadcast repeats
        self.grad, self.touch, self.cmd = grad, touch, cmd
        self.travel = np.array([vx, vy], dtype=float)
        self.remember_route()
        self.pre = self.pre_wait = None
        return self.act(self.travel if cmd == CMD_TRAVEL else (0.0, 0.0), repeat=same)

    def detection_in_batch(self: GGCRobot, c: DecideBatch, f: ChunkRows, k: int
                           ) -> Action | None:
        """:meth:`detection` for a waiting robot that goes on waiting (blocked, or enclosed
        by its formation); None when it leaves, turns Surplus or yields (step() does those)."""
        pre = self.pre_wait
        if (pre is None or self.yield_count or (self.surplus_rule and pre.surplus)
                or (self.scattered and c.tick < self.selection_ticks)):
            return None
        enclosed = self.enclosed_in_batch(c, f, k)
        if not (pre.blocker or enclosed):
            return None  # my turn: step() starts coverage
        self.odometer += c.moved[k]  # as step() does
        same = (pre.grad is None or pre.grad == self.grad) and enclosed == self.enclosed
        if pre.grad is not None:
            self.grad = pre.grad
        self.enclosed = enclosed
        self.pre = self.pre_wait = None
        if not pre.blocker:  # my turn, but no way out: let the others go
            return self.act(sleep=True, wake_range=1.5 * self.p.d_min, repeat=same)
        return self.act(sleep=True, wake_range=self.p.d_cover,
                        wake_on_motion=pre.blocker == BLOCKED_BY_MOVER, repeat=same)

    def enclosed_in_batch(self: GGCRobot, c: DecideBatch, f: ChunkRows, k: int) -> bool:
        """:meth:`is_enclosed` from the rows: waiting robots within 1.5 d_min all round."""
        return f.enclosed(k, 1.5 * self.p.d_min)
