"""The stuck part: robots that push and do not get anywhere, against a wall or against robots.

A robot *presses* in a tick when it has not failed, its drive was told to move (its row of the
tick's commanded velocities is non-zero) and it touches another robot, a wall or an obstacle
(swarmsim.physics.physics.ContactState). It is *stuck* in a tick when it has pressed for the
last :data:`STUCK_WINDOW` ticks in a row and moved less than :data:`STUCK_SHARE` of what those
ticks could carry it at full speed (``STUCK_SHARE * STUCK_WINDOW * v_max`` units) net over
them. It is stuck *against a wall* when it touched a wall or an obstacle in any of those
ticks, else *against robots*. Ghost robots pass through each other, so only walls stop them.

Outputs: time-series column ``stuck`` (robots stuck at the end of the tick); summary fields
``stuck_robots`` (robots stuck at least once), ``stuck_robots_wall`` / ``stuck_robots_robots``
(robots stuck at least once against a wall / against robots; a robot can be both) and
``stuck_robot_ticks`` (the sum over ticks of the robots stuck).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from swarmsim.metrics.contacts import ContactsPart
from swarmsim.metrics.part import MetricPart, Observation, Reporter
from swarmsim.metrics.tallies import watch_stuck

STUCK_WINDOW = 50
"""Ticks a robot must press in a row before it can count as stuck."""
STUCK_SHARE = 0.05
"""A robot that pressed for STUCK_WINDOW ticks is stuck if it moved less than this share of
STUCK_WINDOW * v_max (the distance those ticks could carry it) net over them."""

AGAINST_WALL, AGAINST_ROBOTS = 1, 2
"""Codes of :attr:`StuckPart.against`: stuck against a wall, against robots only (as
swarmsim.metrics.tallies.watch_stuck writes them)."""


class StuckPart(MetricPart):
    """Robots stuck now (time series), ever, against what, and for how long (summary).

    Args:
        n: number of robots.
        contacts: the run's contacts part, observed before this one (its ``state`` is read).
        v_max: the robots' top speed, units per tick.
    """

    name = "stuck"

    def __init__(self, n: int, contacts: ContactsPart, v_max: float):
        self.contacts = contacts
        self.min_net = STUCK_SHARE * STUCK_WINDOW * v_max  # units
        self._ring = np.zeros((STUCK_WINDOW + 1, n, 2))  # positions of the last ticks
        self._pressing = np.zeros(n, dtype=np.int64)  # consecutive pressing ticks
        self._wall_tick = np.full(n, -STUCK_WINDOW - 1, dtype=np.int64)  # last wall contact
        self.against = np.zeros(n, dtype=np.int8)
        """(N,) now: 0 not stuck, AGAINST_WALL, AGAINST_ROBOTS."""
        self.ever_wall = np.zeros(n, dtype=bool)
        self.ever_robots = np.zeros(n, dtype=bool)
        self.stuck_now = 0
        self.stuck_robot_ticks = 0

    def observe(self, now: Observation) -> None:
        c = self.contacts.state
        self.stuck_now = watch_stuck(now.tick, now.positions, now.commanded, now.failed,
                                     c.in_contact, c.on_wall, self._ring, self._pressing,
                                     self._wall_tick, self.against, self.ever_wall,
                                     self.ever_robots, STUCK_WINDOW, self.min_net)
        self.stuck_robot_ticks += self.stuck_now

    def columns(self) -> Mapping[str, Reporter]:
        return {"stuck": lambda: self.stuck_now}

    def summary_fields(self) -> Mapping[str, Reporter]:
        return {"stuck_robots": lambda: int((self.ever_wall | self.ever_robots).sum()),
                "stuck_robots_wall": lambda: int(self.ever_wall.sum()),
                "stuck_robots_robots": lambda: int(self.ever_robots.sum()),
                "stuck_robot_ticks": lambda: self.stuck_robot_ticks}


__all__ = ["AGAINST_ROBOTS", "AGAINST_WALL", "STUCK_SHARE", "STUCK_WINDOW", "StuckPart"]
