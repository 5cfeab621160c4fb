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

from swarmsim.controller import INF_GRADIENT, NO_SENDER, NeighbourBatch

from .moverrows import mover_rows
from .statuses import ARRIVE, COVERAGE, DETECTION, STOP, SURPLUS

NOT_BLOCKED, BLOCKED_BY_WAITING, BLOCKED_BY_MOVER = 0, 1, 2
"""GGCRobot.blocked's answers."""
FIELDS = ("group", "status", "id", "moving", "gradient", "enclosed")
"""The broadcast fields the queries read."""
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
                 "mover_first", "mover_rows", "nearest", "second", "starts")

    def __init__(self, robots: list, chunk: Chunk):
        p, first = robots[0].p, next(r for r in robots if r.status in (COVERAGE, STOP))
        m = chunk.m
        nearest, second, movers, movers_first, ahead, ahead_first = mover_rows(
            chunk.starts, np.require(chunk.d, float, ("C", "W")), m["group"], m["status"],
            m["id"], m["moving"], chunk.own_group, chunk.own_id,
            p.follow_other_formations or first.groups == 1, p.d_cover, p.yield_distance,
            ARRIVE, SURPLUS, COVERAGE, NO_SENDER)
        self.nearest, self.second = nearest, second
        """(robots,) each robot's nearest and second edge robot (rows, -1: none)."""
        self.mover_rows, self.mover_first = movers.tolist(), movers_first.tolist()
        self.ahead_rows, self.ahead_first = ahead.tolist(), ahead_first.tolist()
        self.ahead_array, self.ahead_first_array = ahead, ahead_first
        """The same as arrays (for the compiled movers' kernel)."""
        self.has_movers = [a != b for a, b in zip(self.mover_first, self.mover_first[1:])]
        """Robot k hears another group's mover that outranks it (Section 4.3)."""
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
    chunk = Chunk(fields, batch.distances, batch.starts, segment,
                  np.array([r.group for r in robots])[segment],
                  np.array([r.id for r in robots])[segment])
    movers = [k for k, r in enumerate(robots) if r.status == COVERAGE or r.status == STOP]
    waiting = [k for k, r in enumerate(robots) if r.status == DETECTION]
    if movers:
        chunk = chunk._replace(movers=MoverAnswers(robots, chunk))
        if hand_out:
            for k in movers:
                robots[k].pre = chunk.movers.precomputed(k)
    if waiting and 4 * len(waiting) <= len(robots):  # a few: masks over their rows only
        prepare_waiting([robots[k] for k in waiting], list(range(len(waiting))),
                        rows_of(chunk, waiting))
    elif waiting:
        prepare_waiting(robots, waiting, chunk)
    return chunk


def rows_of(chunk: Chunk, chosen: list[int]) -> Chunk:
    """The chunk's rows of the ``chosen`` robots only (robot j of the result is robot
    ``chosen[j]``; its rows in the same order)."""
    ks = np.asarray(chosen, dtype=np.intp)
    first, counts = chunk.starts[ks], chunk.starts[ks + 1] - chunk.starts[ks]
    starts = np.concatenate(([0], np.cumsum(counts)))
    rows = np.arange(starts[-1]) + np.repeat(first - starts[:-1], counts)
    return Chunk({name: field[rows] for name, field in chunk.m.items()}, chunk.d[rows],
                 starts, np.repeat(np.arange(len(ks)), counts), chunk.own_group[rows],
                 chunk.own_id[rows])


def prepare_waiting(robots: list, chosen: list[int], chunk: Chunk) -> None:
    """Give each chosen robot (Detection) its :class:`WaitingAnswers` (Algorithms 1 and 7)."""
    first = robots[chosen[0]]
    p, n = first.p, len(robots)
    m, d, seg, own_group, own_id = chunk.m, chunk.d, chunk.segment, chunk.own_group, chunk.own_id
    group, status, sender, moving, gradient = (m["group"], m["status"], m["id"], m["moving"],
                                               m["gradient"])
    mine = (group == own_group) & (sender != NO_SENDER)
    surplus = np.zeros(n, dtype=bool)
    if first.surplus_rule:
        near = (d <= p.d_cover + p.arrive_tolerance) & (status == SURPLUS) & (group == own_group)
        surplus = any_by_robot(near, seg, n)
    best = formation_minimum(chunk, p.d_min, n)
    grads = np.array([r.grad for r in robots], dtype=np.int64)
    grads = np.where(best < INF_GRADIENT, best + 1, grads)  # the gradient each robot takes
    rival = (d <= p.d_cover) & mine & (status != ARRIVE) & (status != SURPLUS) & ~m["enclosed"]
    if first.groups > 1:
        rival &= status != STOP  # a mover in Stop has left already (Section 4.3)
    g = grads[seg]
    rival &= (gradient > g) | ((gradient == g) & (sender > own_id))
    by_waiting = any_by_robot(rival & ~moving, seg, n).tolist()
    by_any = any_by_robot(rival, seg, n).tolist()
    surplus, best = surplus.tolist(), best.tolist()
    for k in chosen:
        blocker = (BLOCKED_BY_WAITING if by_waiting[k] else BLOCKED_BY_MOVER if by_any[k]
                   else NOT_BLOCKED)
        grad = best[k] + 1 if best[k] < INF_GRADIENT else None
        robots[k].pre_wait = _new_tuple(WaitingAnswers, (surplus[k], grad, blocker))


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
