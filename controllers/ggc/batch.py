"""GGC's per-robot neighbourhood queries for many movers at once (numpy over a chunk's rows).

A mover asks three integer questions of its neighbourhood every tick: which are the nearest
two robots whose edge it follows, which robots of another group in Coverage within d_cover
outrank it (Section 4.3), and which moving robots with a larger id are within
yield_distance (give way). Asked one robot at a time they cost ~10 us of numpy and Python
overhead per mover; here they are masks over every row of the chunk at once, handed to each
robot as Python lists (:class:`Precomputed`) that it uses in the same tick instead of asking.
Only integer and boolean tests: the answers are the same indices.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from swarmsim.controller import NO_SENDER, NeighbourBatch

from .statuses import ARRIVE, COVERAGE, STOP, SURPLUS


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


def prepare_movers(robots: list, batch: NeighbourBatch) -> None:
    """Give each robot in Coverage or Stop its :class:`Precomputed` answers (``robot.pre``)."""
    chosen = [k for k, r in enumerate(robots) if r.status == COVERAGE or r.status == STOP]
    if not chosen:
        return
    p = robots[chosen[0]].p
    m, d, starts = batch.messages, batch.distances, batch.starts
    segment = np.repeat(np.arange(len(robots)), np.diff(starts))
    own_group = np.array([r.group for r in robots])[segment]
    own_id = np.array([r.id for r in robots])[segment]
    group, status, sender, moving = m["group"], m["status"], m["id"], m["moving"]
    edge = ~moving
    if not (p.follow_other_formations or robots[chosen[0]].groups == 1):
        edge &= ((group == own_group) | (status == ARRIVE) | (status == SURPLUS)
                 | (sender == NO_SENDER))
    movers = ((d <= p.d_cover) & (group != own_group) & (sender > own_id)
              & (status == COVERAGE))
    ahead = (d <= p.yield_distance) & moving & (sender > own_id)
    found = [_rows_by_robot(mask, segment, len(robots)) for mask in (edge, movers, ahead)]
    start_of = starts.tolist()
    (edge_rows, edge_first), (mover_rows, mover_first), (ahead_rows, ahead_first) = found
    for k in chosen:
        start = start_of[k]
        robots[k].pre = Precomputed(_rows_of(edge_rows, edge_first, k, start, limit=2),
                                    _rows_of(mover_rows, mover_first, k, start),
                                    _rows_of(ahead_rows, ahead_first, k, start))


def _rows_by_robot(mask: np.ndarray, segment: np.ndarray, robots: int
                   ) -> tuple[list[int], list[int]]:
    """The rows where ``mask`` holds, and where each robot's share of them begins."""
    rows = np.flatnonzero(mask)
    first = np.searchsorted(segment[rows], np.arange(robots + 1))
    return rows.tolist(), first.tolist()


def _rows_of(rows: list[int], first: list[int], k: int, start: int,
             limit: int | None = None) -> list[int]:
    """Robot k's rows among ``rows`` (the first ``limit``), as indices into its own
    perception."""
    a, b = first[k], first[k + 1]
    if a == b:
        return []
    if limit is not None:
        b = min(b, a + limit)
    return [r - start for r in rows[a:b]]
