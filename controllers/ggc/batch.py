"""GGC's per-robot neighbourhood queries for a whole chunk of robots at once (numpy).

A mover asks three integer questions of its neighbourhood every tick: which are the nearest
two robots whose edge it follows, which robots of another group in Coverage within d_cover
outrank it (Section 4.3), and which moving robots with a larger id are within yield_distance
(give way). A waiting robot (Detection) asks three more: is a Surplus robot of its group near,
what is its gradient (Algorithm 1), and does a neighbour within d_cover outrank it (Algorithm
7). Asked one robot at a time they cost ~10-30 us of numpy and Python overhead per robot;
here they are masks over every row of the chunk at once, handed to each robot
(:class:`Precomputed`, :class:`WaitingAnswers`), which uses them in the same tick instead of
asking. Only integer and boolean tests: the answers are the same."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from controllers.gradient import INF_GRADIENT
from swarmsim.controller import NO_SENDER, NeighbourBatch

from .moverrows import mover_rows
from .statuses import ARRIVE, COVERAGE, DETECTION, STOP, SURPLUS
from .waitrows import waiting_answers

NOT_BLOCKED, BLOCKED_BY_WAITING, BLOCKED_BY_MOVER = 0, 1, 2
"""GGCRobot.blocked's answers."""
FIELDS = ("group", "status", "id", "moving", "gradient", "enclosed")
"""The broadcast fields the queries read."""
WAITING_CODES = np.array([ARRIVE, SURPLUS, STOP, COVERAGE], dtype=np.int64)
"""The status codes waitrows.waiting_answers tells apart, in its order."""
_new_tuple = tuple.__new__
"""``_new_tuple(Cls, values)`` makes a NamedTuple without its Python-level __new__."""


class Precomputed(NamedTuple):
    """One robot's answers for this tick (indices into its own perception's rows)."""

    edge: list[int]
    """The nearest two edge robots (GGCRobot.nearest_edge_robots)."""
    movers: list[int]
    """Other groups' movers in Coverage within d_cover with a larger id
    (GGCRobot.other_group_mover, before its stop_ahead_only filter)."""
    ahead: list[int]
    """Moving robots with a larger id within yield_distance (GGCRobot.give_way, before
    its direction filter)."""


class WaitingAnswers(NamedTuple):
    """A waiting robot's (Detection) answers for this tick."""

    surplus: bool
    """A Surplus robot of its group within d_cover + arrive_tolerance (GGCRobot.hears_surplus;
    False when the surplus rule is off)."""
    grad: int | None
    """GGCRobot.gradient_from(p, 1.5 d_min)."""
    blocker: int
    """GGCRobot.blocked(p), judged with the gradient above (the robot takes it first)."""


class MoverAnswers:
    """A chunk's movers' answers as arrays over its rows; :meth:`precomputed` hands one
    robot its :class:`Precomputed` (only robots that take ``step`` need one)."""

    __slots__ = ("ahead_array", "ahead_first", "ahead_first_array", "ahead_rows", "has_movers",
                 "has_movers_array", "mover_first", "mover_rows", "nearest", "second",
                 "starts")

    def __init__(self, robots: list, chunk: Chunk):
        p, first = robots[0].p, next(r for r in robots if r.status in (COVERAGE, STOP))
        m = chunk.m
        nearest, second, movers, movers_first, ahead, ahead_first = mover_rows(
            chunk.starts, chunk.d, m["group"], m["status"], m["id"], m["moving"],
            chunk.own_group, chunk.own_id, p.follow_other_formations or first.groups == 1,
            p.d_cover, p.yield_distance, ARRIVE, SURPLUS, COVERAGE, NO_SENDER)
        self.nearest, self.second = nearest, second
        """(robots,) each robot's nearest and second edge robot (rows, -1: none)."""
        self.mover_rows, self.mover_first = movers.tolist(), movers_first.tolist()
        self.ahead_rows, self.ahead_first = ahead.tolist(), ahead_first.tolist()
        self.ahead_array, self.ahead_first_array = ahead, ahead_first
        """The same as arrays (for the compiled movers' kernel)."""
        self.has_movers_array = movers_first[1:] != movers_first[:-1]
        """(robots,) robot k hears another group's mover that outranks it (Section 4.3)."""
        self.has_movers = self.has_movers_array.tolist()
        self.starts: list[int] = chunk.starts.tolist()

    def ahead(self, k: int) -> list[int]:
        """Robot k's rows of moving robots it gives way to (before the direction test)."""
        return self.ahead_rows[self.ahead_first[k]:self.ahead_first[k + 1]]

    def precomputed(self, k: int) -> Precomputed:
        """Robot k's answers, as indices into its own perception's rows."""
        start, a, b = self.starts[k], int(self.nearest[k]), int(self.second[k])
        edge = [] if a < 0 else [a - start] if b < 0 else [a - start, b - start]
        movers = self.mover_rows[self.mover_first[k]:self.mover_first[k + 1]]
        ahead = self.ahead(k)
        return _new_tuple(Precomputed, (edge, [r - start for r in movers],
                                        [r - start for r in ahead]))


class Chunk(NamedTuple):
    """A chunk's rows with, on each row, the listening robot's index, group and id.

    ``m`` holds the broadcast fields the queries read, each as its own contiguous array
    (a comparison over a field of the structured rows is ~6x slower: it strides)."""

    m: dict[str, np.ndarray]
    d: np.ndarray
    starts: np.ndarray
    segment: np.ndarray
    own_group: np.ndarray
    own_id: np.ndarray
    movers: MoverAnswers | None = None
    """The movers' answers, when the chunk has robots in Coverage or Stop."""


def prepare_chunk(robots: list, batch: NeighbourBatch, hand_out: bool = True) -> Chunk:
    """Precompute the answers of the chunk's movers and waiting robots (``robot.pre_wait``)
    and return the chunk's rows. With ``hand_out``, each mover gets its ``robot.pre`` now;
    without, it is in the chunk's ``movers`` (:meth:`MoverAnswers.precomputed`). The other
    robots ask for themselves."""
    segment = np.repeat(np.arange(len(robots)), np.diff(batch.starts))
    fields = {name: np.ascontiguousarray(batch.messages[name]) for name in FIELDS}
    # contiguous and writeable, once: the one signature the compiled kernels are warmed up for
    distances = np.require(batch.distances, float, ("C", "W"))
    starts = np.require(batch.starts, np.int64, ("C", "W"))
    chunk = Chunk(fields, distances, starts, segment,
                  np.array([r.group for r in robots])[segment],
                  np.array([r.id for r in robots])[segment])
    movers = [k for k, r in enumerate(robots) if r.status == COVERAGE or r.status == STOP]
    waiting = [k for k, r in enumerate(robots) if r.status == DETECTION]
    if movers:
        chunk = chunk._replace(movers=MoverAnswers(robots, chunk))
        if hand_out:
            for k in movers:
                robots[k].pre = chunk.movers.precomputed(k)
    if waiting:
        prepare_waiting([robots[k] for k in waiting], waiting, chunk)
    return chunk


def prepare_waiting(robots: list, chosen: list[int], chunk: Chunk) -> None:
    """Give each waiting robot (Detection) its :class:`WaitingAnswers` (Algorithms 1 and 7):
    ``robots[j]`` is robot ``chosen[j]`` of the chunk (see waitrows.py)."""
    first = robots[0]
    p, m = first.p, chunk.m
    surplus, best, by_waiting, by_any = (answers.tolist() for answers in waiting_answers(
        chunk.starts, chunk.d,
        m["group"], m["status"], m["id"], m["moving"], m["gradient"], m["enclosed"],
        np.array(chosen, dtype=np.int64), *(np.array([getattr(r, name) for r in robots],
                                                     dtype=np.int64)
                                            for name in ("group", "id", "grad")),
        WAITING_CODES, np.array([p.d_cover + p.arrive_tolerance, 1.5 * p.d_min, p.d_cover]),
        INF_GRADIENT, NO_SENDER, first.surplus_rule, first.groups > 1))
    for j, robot in enumerate(robots):
        blocker = (BLOCKED_BY_WAITING if by_waiting[j] else BLOCKED_BY_MOVER if by_any[j]
                   else NOT_BLOCKED)
        grad = best[j] + 1 if best[j] < INF_GRADIENT else None
        robot.pre_wait = _new_tuple(WaitingAnswers, (surplus[j], grad, blocker))


def formation_minimum(chunk: Chunk, d_min: float, robots: int) -> np.ndarray:
    """(robots,) each robot's smallest gradient among its group's stationary robots within
    1.5 d_min that are not in Coverage (INF_GRADIENT: none): ``gradient_in``'s minimum, the
    gradient a robot takes minus one (Algorithm 1)."""
    m = chunk.m
    formed = ((chunk.d <= 1.5 * d_min) & (m["group"] == chunk.own_group)
              & (m["id"] != NO_SENDER) & ~m["moving"] & (m["gradient"] < INF_GRADIENT)
              & (m["status"] != COVERAGE))
    best = np.full(robots, INF_GRADIENT, dtype=np.int64)
    np.minimum.at(best, chunk.segment[formed], m["gradient"][formed])
    return best


def any_by_robot(mask: np.ndarray, segment: np.ndarray, robots: int) -> np.ndarray:
    """(robots,) bool: does ``mask`` hold on any of each robot's rows?"""
    return np.bincount(segment[mask], minlength=robots) > 0


def _row_spans(mask: np.ndarray, segment: np.ndarray, robots: int
               ) -> tuple[np.ndarray, np.ndarray]:
    """The rows where ``mask`` holds, and where each robot's share of them begins (then the
    end): robot k's are ``rows[first[k]:first[k + 1]]``."""
    rows = np.flatnonzero(mask)
    return rows, np.searchsorted(segment[rows], np.arange(robots + 1))


def first_two_by_robot(mask: np.ndarray, segment: np.ndarray, robots: int
                        ) -> tuple[list[int], list[int]]:
    """:func:`first_two_rows` as Python lists."""
    first, second = first_two_rows(mask, segment, robots)
    return first.tolist(), second.tolist()


def first_two_rows(mask: np.ndarray, segment: np.ndarray, robots: int
                   ) -> tuple[np.ndarray, np.ndarray]:
    """(robots,) each robot's first and (robots,) second row where ``mask`` holds (-1:
    none), without listing the others (in a formation nearly every row is a stationary
    robot)."""
    rows, first = _row_spans(mask, segment, robots)
    if len(rows) == 0:
        return np.full(robots, -1), np.full(robots, -1)
    found = []
    for j in (0, 1):
        at = first[:-1] + j
        found.append(np.where(at < first[1:], rows[np.minimum(at, len(rows) - 1)], -1))
    return found[0], found[1]
