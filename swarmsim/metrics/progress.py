"""The progress part: how far the swarm has got and what it cost: distance walked, robots
moving, awake and on the target, robots placed, and when coverage settled."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from swarmsim.metrics.coverage import CoveragePart
from swarmsim.metrics.part import MetricPart, Observation, Reporter, RobotReporter, RunEnd
from swarmsim.metrics.settled import SettledPart
from swarmsim.metrics.tallies import count_above, enter_settled, step_lengths

MOVING_FRACTION = 0.01
"""A robot counts as moving in a tick (time series column ``moving``) when it moved more
than this fraction of the top speed v_max during that tick."""
NOT_YET = -1
"""RobotTracks.settle_tick of a robot that never entered a settled status."""


class RobotTracks:
    """Per-robot odometry and settle ticks, updated once a tick with whole-swarm arrays.

    Attributes:
        distance: (N,) each robot's path length so far: the sum over ticks of the length of
            its displacement in that tick, units.
        settle_tick: (N,) the tick at which each robot last entered one of the controller's
            settled statuses (NOT_YET if it never did); read with its status at the end: a
            robot that left a settled status again keeps the tick of its last entry.
        moving_now: robots that moved more than ``moving_eps`` units in the last tick.

    Args:
        n: number of robots.
        codes: status codes that mean "settled" (index into the controller's STATUSES).
        moving_eps: displacement in one tick above which a robot counts as moving, units.
    """

    def __init__(self, n: int, codes: tuple[int, ...], moving_eps: float):
        self.codes = tuple(int(c) for c in codes)
        self._codes = np.asarray(self.codes, dtype=np.int64)
        self.moving_eps = moving_eps
        self.distance = np.zeros(n)
        self.settle_tick = np.full(n, NOT_YET, dtype=np.int64)
        self._in_settled = np.zeros(n, dtype=bool)
        self.moving_now = 0

    def observe(self, tick: int, step: np.ndarray | None, messages: np.ndarray) -> None:
        """Account for ``tick``: ``step`` (N,) is each robot's displacement length during it
        (None for the first observed state), ``messages`` the broadcasts at its end (a status
        is read only if their dtype has a ``status`` field)."""
        if step is not None:
            self.distance += step
            self.moving_now = count_above(step, self.moving_eps)
        if not len(self._codes) or "status" not in (messages.dtype.names or ()):
            return
        enter_settled(tick, messages["status"], self._codes, self.settle_tick,
                      self._in_settled)


class ProgressPart(MetricPart):
    """Distance, motion, robots on the target and placed, and the settle point of coverage.

    Attributes:
        total_distance: the robots' summed path length so far, units.
        longest_step: the longest move of one robot in the last tick, units (0.0 before the
            first tick).
        tracks: per-robot odometry and settle ticks (RobotTracks).

    Args:
        n: number of robots.
        coverage: the run's coverage part (observed before this one).
        settled: the run's settled part (which robots are settled, for robots_placed).
        settled_codes: status codes that mean "settled".
        config: the run's SimConfig (v_max, plateau_delta).
        counts_broadcast_moving: the broadcasts have a ``moving`` field (the time series
            then has a ``broadcast_moving`` column).
    """

    name = "progress"

    def __init__(self, n: int, coverage: CoveragePart, settled: SettledPart,
                 settled_codes: tuple[int, ...], config: Any, counts_broadcast_moving: bool):
        self.coverage = coverage
        self.settled = settled
        self.plateau_delta = config.plateau_delta
        self.counts_broadcast_moving = counts_broadcast_moving
        self.tracks = RobotTracks(n, settled_codes, MOVING_FRACTION * config.v_max)
        self.total_distance = 0.0
        self.longest_step = 0.0
        self.completion_distance = 0.0
        self._rises: list[tuple[float, int, float]] = []  # (coverage, tick, distance) at highs
        self._prev: np.ndarray | None = None
        self._on_target = self._awake = self._broadcast_moving = 0
        self._placed = self._end_on_target = 0
        self._settle = (0, 0.0)

    def observe(self, now: Observation) -> None:
        step = None
        if self._prev is not None:
            step, self.longest_step = step_lengths(now.positions, self._prev)
            self.total_distance += float(step.sum())
        self._prev = now.positions
        self.tracks.observe(now.tick, step, now.messages)
        coverage = self.coverage.coverage
        if self.coverage.completion_tick == now.tick:
            self.completion_distance = self.total_distance
        if not self._rises or coverage > self._rises[-1][0]:
            self._rises.append((coverage, now.tick, self.total_distance))
        self._on_target = int(np.count_nonzero(now.on_target))
        self._awake = now.awake
        if self.counts_broadcast_moving:
            self._broadcast_moving = int(np.count_nonzero(now.messages["moving"]))

    def settled_at(self) -> tuple[int, float]:
        """(tick, total distance in units) when coverage settled: the completion tick, or the
        first tick coverage came within plateau_delta of its current value. (Robots passing
        over uncovered floor make coverage flicker by a few tenths of a percent; the last rise
        would count their walking.)"""
        if self.coverage.completion_tick is not None:
            return self.coverage.completion_tick, self.completion_distance
        return first_within(self._rises, self.coverage.coverage - self.plateau_delta)

    def conclude(self, end: RunEnd) -> None:
        on_target = np.asarray(end.on_target, dtype=bool)
        self._placed = int((self.settled.watch.settled & on_target).sum())
        self._end_on_target = int(end.on_target.sum())
        self._settle = self.settled_at()

    def columns(self) -> Mapping[str, Reporter]:
        moving = ({"broadcast_moving": lambda: self._broadcast_moving}
                  if self.counts_broadcast_moving else {})
        return {"total_distance": lambda: round(self.total_distance, 4),
                "robots_on_target": lambda: self._on_target,
                "moving": lambda: self.tracks.moving_now,
                **moving,
                "awake": lambda: self._awake}

    def robot_columns(self) -> Mapping[str, RobotReporter]:
        return {"distance": lambda: np.round(self.tracks.distance, 4).tolist(),
                "settle_tick": lambda: ["" if tick == NOT_YET else tick
                                        for tick in self.tracks.settle_tick.tolist()]}

    def summary_fields(self) -> Mapping[str, Reporter]:
        """``settle_tick``/``distance_at_settle``: :meth:`settled_at` (unlike total_distance
        it leaves out the walking of robots that could no longer add coverage).
        ``robots_placed``: robots settled (the controller's settled statuses) on the target
        at the end; ``distance_per_placed_robot``: total_distance / robots_placed (units;
        None when none is placed)."""
        return {"total_distance": lambda: round(self.total_distance, 3),
                "robots_placed": lambda: self._placed,
                "distance_per_placed_robot": lambda: (round(self.total_distance / self._placed, 3)
                                                      if self._placed else None),
                "settle_tick": lambda: self._settle[0],
                "distance_at_settle": lambda: round(self._settle[1], 3),
                "robots_on_target": lambda: self._end_on_target}


def first_within(rises: list[tuple[float, int, float]], floor: float) -> tuple[int, float]:
    """(tick, distance) of the first of the coverage highs ``rises`` (coverage, tick,
    distance), in tick order, whose coverage is at least ``floor``; (0, 0.0) if none is."""
    for coverage, tick, distance in rises:
        if coverage >= floor:
            return tick, distance
    return 0, 0.0


__all__ = ["MOVING_FRACTION", "NOT_YET", "ProgressPart", "RobotTracks", "first_within"]
