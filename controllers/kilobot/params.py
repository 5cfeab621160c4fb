"""Kilobot's declarations: its statuses, broadcasts and parameters (:class:`KilobotParams`)
and what the engine reads of a Kilobot controller class (:class:`KilobotDeclarations`), shared
by the batch controller (controller.py) and the per-robot reference (robot.py)."""

from __future__ import annotations

from dataclasses import dataclass

from controllers.common.gradient import COLOURINGS, GRADIENT_FIELDS, SILENT
from swarmsim.controller import require_positive

TRAVEL, WAIT, OUTSIDE, INSIDE, JOINED = range(5)
STATUSES = ("Travel", "Wait", "MoveOutside", "MoveInside", "Joined")
MOVING = (OUTSIDE, INSIDE)
MESSAGE_FIELDS = [*GRADIENT_FIELDS, ("cmd", "i1"), ("vx", "f4"), ("vy", "f4")]


@dataclass(frozen=True)
class KilobotParams:
    """Parameters of the Kilobot self-assembly controller (lengths in units, times in ticks).

    Attributes:
        d_safe: safe distance (paper Table 2: 1).
        d_cover: edge-following and joining distance (Kilobot's DESIRED_DIST; GGC's coverage
            distance, default 6).
        d_min: spacing of the start formation; waiting robots relay the gradient within
            1.5 * d_min.
        v: speed (paper Table 2: 0.1 per tick).
        gradient_reach: a moving robot takes its gradient from stationary neighbours within
            gradient_reach * d_cover.
        start_range: a waiting robot compares gradients with waiting neighbours this close.
        quiet_range: a waiting robot starts only when no moving robot is this close (default
            d_cover + d_safe: an edge-follower passing by blocks it).
        yield_distance: a moving robot waits while a moving robot with a larger id is this
            close ahead.
        radial_gain: edge following: radial correction per unit of distance error.
        arrive_tolerance: a robot joins only at least d_cover - arrive_tolerance from the
            nearest stationary robot.
        probe_distance: the floor probe looks this far ahead (<= 2, the engine's probe range).
        orbit: -1 follows edges clockwise (the Kilobots' sense), +1 counter-clockwise.
        init_timeout: a robot that has heard no gradient after this many ticks starts waiting
            with an infinite gradient.
        T_r: progress is checked every T_r ticks while moving (our robustness addition).
        theta: a moving robot that moved less than theta in T_r ticks (not counting ticks it
            yielded) is trapped: on the target it joins, off it it heads for the beacon.
    """

    d_safe: float = 1.0
    d_cover: float = 6.0
    d_min: float = 1.0
    v: float = 0.1
    gradient_reach: float = 1.3
    start_range: float = 6.0
    quiet_range: float = 7.0
    yield_distance: float = 2.0
    radial_gain: float = 1.0
    arrive_tolerance: float = 0.3
    probe_distance: float = 1.0
    orbit: int = -1
    init_timeout: int = 400
    T_r: int = 100
    theta: float = 1.0

    def __post_init__(self) -> None:
        require_positive(self, "d_safe", "d_cover", "d_min", "v", "gradient_reach", "start_range",
                         "quiet_range", "yield_distance", "radial_gain", "probe_distance",
                         "init_timeout", "T_r")
        if self.d_cover < self.d_safe:
            raise ValueError(f"d_cover ({self.d_cover}) must be >= d_safe ({self.d_safe})")
        if self.orbit not in (1, -1):
            raise ValueError(f"orbit must be 1 or -1, got {self.orbit!r}")
        if self.arrive_tolerance < 0 or self.theta < 0:
            raise ValueError("arrive_tolerance and theta must be >= 0")
        if self.probe_distance > 2.0:
            raise ValueError(f"probe_distance ({self.probe_distance}) must be <= 2 (the "
                             "engine's default probe range)")


class KilobotDeclarations:
    """What both Kilobot classes declare (controller API): the name, parameters, statuses,
    broadcasts and sensing."""

    name = "kilobot"
    Params = KilobotParams
    STATUSES = STATUSES
    SETTLED_STATUSES = ("Joined",)  # done, standing still (collision instruments)
    MESSAGE_FIELDS = MESSAGE_FIELDS
    SILENT = SILENT
    COLOURINGS = COLOURINGS
    LEADER_FIELD = "leader"
    GROUP_FIELD = "group"
    default_start = "formation"
    requires_beacon = True

    @classmethod
    def sensing_range(cls, params: KilobotParams) -> float:
        return max(params.gradient_reach * params.d_cover, params.quiet_range,
                   params.start_range, params.yield_distance, params.d_cover + 2)
