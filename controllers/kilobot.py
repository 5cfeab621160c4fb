"""Kilobot programmable self-assembly (Rubenstein, Cornejo & Nagpal, Science 345:795, 2014),
the GGC paper's comparison algorithm [41], in the GGC paper's units.

Rules (reconstructed from the supplementary pseudocode as mirrored by public
implementations; /work/shared/research/algorithms.md section 2):

* Start: the swarm stands as one hexagonal formation (spacing ``d_min``) around the seed
  (the RobotSetup leader, gradient 0; no grouping: every robot follows the one seed). The
  Kilobot seeds stand next to the shape, so the seed first leads the formation there, as GGC
  does: it heads for the beacon and broadcasts a travel command; every robot copies its
  gradient parent's command one tick later (the formation moves rigidly) and the seed halts
  when its floor sensor finds the target. It then stays, joined.
* Gradient: a waiting robot's gradient is 1 + the smallest gradient among stationary
  neighbours within 1.5 * d_min (hop count from the seed through the formation); a moving
  robot's is 1 + the smallest among stationary neighbours within ``gradient_reach * d_cover``
  (Kilobot's GRADIENT_DIST / DESIRED_DIST ~ 1.3).
* Start moving (WAIT -> MOVE): only when no moving robot is within ``quiet_range``, and no
  waiting neighbour within ``start_range`` has a larger gradient, or the same gradient and a
  larger id (so the outermost robots peel off one per neighbourhood).
* Edge-following: keep ``d_cover`` from the nearest stationary robot, rotating around it
  (``orbit`` -1: clockwise, as the Kilobots do); yield (wait) while a moving robot with a
  larger id is within ``yield_distance`` ahead.
* Join (stop for good), only on the target and at least d_cover - arrive_tolerance from the
  nearest stationary robot: when the floor probe ``probe_distance`` ahead leaves the target
  ("about to leave the shape"), or when the nearest stationary robot has joined with a
  gradient >= this robot's (its layer is full). A robot outside the target never joins.
* Our additions for robustness (documented; the Kilobot paper has no such rule): a robot that
  has circled the same robot all the way round, or has moved less than ``theta`` in ``T_r``
  ticks without yielding (trapped in a pocket narrower than d_cover), joins if it is on the
  target and otherwise heads for the beacon for T_r ticks; trapped a third time in a row off
  the target, it stops there for good (so that it cannot keep every waiting robot near it
  waiting forever); a moving robot that senses no stationary robot heads for the beacon.

Kilobots localize by trilateration and test their estimated position against a stored shape
bitmap; here the floor sensor and a 1-unit probe play that role, like GGC's robots.

Sensing: distances and bearings of neighbours within max(gradient_reach * d_cover,
quiet_range), their broadcast gradient, id, status and travel command, the floor sensor, a
floor probe 1 unit ahead, and (seed only) the beacon's bearing: the same class of sensing as
GGC (hop counts and distances); no map of the target.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from controllers.common import formationkernel
from controllers.common.edges import CirclingWatch, ProgressWatch
from controllers.common.formation import CMD_HALT, CMD_NONE, CMD_TRAVEL, FormationTravel, unit
from controllers.common.gradient import COLOURINGS, GRADIENT_FIELDS, INF_GRADIENT, SILENT
from swarmsim.controller import (
    NO_SENDER,
    Action,
    Perception,
    RobotSetup,
    make_action,
    require_positive,
)

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


class Kilobot(FormationTravel, CirclingWatch, ProgressWatch):
    """Kilobot self-assembly: peel off the formation, follow its edge, join inside the shape."""

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

    def __init__(self, setup: RobotSetup, params: KilobotParams, rng: np.random.Generator):
        self.id = setup.robot_id
        self.group = setup.group
        self.leader = setup.leader
        self.params = params
        self.status = TRAVEL
        self.grad = 0 if self.leader else INF_GRADIENT
        self.cmd = CMD_NONE
        self.travel = np.zeros(2)
        self.heading = np.zeros(2)
        self.circling_id = NO_SENDER
        self.circled = 0.0
        self.last_bearing: float | None = None
        self.odometer = np.zeros(2)
        self.progress_tick = 0
        self.escape_until = -1
        self.traps = 0

    # ------------------------------------------------------------------ messages
    def act(self, velocity=(0.0, 0.0), sleep: bool = False,
            wake_range: float | None = None, wake_tick: int | None = None) -> Action:
        msg = (self.id, self.status, self.status in MOVING, self.grad, self.group, self.leader,
               self.cmd, float(self.travel[0]), float(self.travel[1]))
        return make_action((float(velocity[0]), float(velocity[1])), msg, sleep, wake_range,
                           self.listen_range(), wake_tick=wake_tick)

    def listen_range(self) -> float | None:
        """How far this robot needs to hear next tick (less is cheaper)."""
        if self.status == TRAVEL:
            return 1.5 * self.params.d_min
        if self.status == WAIT:
            return max(self.params.start_range, self.params.quiet_range, 1.5 * self.params.d_min)
        if self.status == JOINED:
            return self.params.d_safe
        return None

    def step(self, perception: Perception) -> Action:
        self.odometer += perception.moved
        if self.status == TRAVEL:
            return self.lead(perception) if self.leader else self.follow(perception)
        if self.status == WAIT:
            return self.wait(perception)
        if self.status in MOVING:
            return self.move(perception)
        return self.act(sleep=True, wake_range=0.0)

    # ------------------------------------------------------------------ travel
    def lead(self, perception: Perception) -> Action:
        """The seed heads for the beacon until its floor sensor finds the target."""
        if perception.on_target or perception.beacon is None:
            self.cmd, self.travel = CMD_HALT, np.zeros(2)
            self.status = JOINED
            return self.act()
        self.cmd, self.travel = CMD_TRAVEL, perception.beacon * self.params.v
        return self.act(self.travel)

    def follow(self, perception: Perception) -> Action:
        cmd = self.follow_travel(perception)
        if cmd is None:
            if perception.tick >= self.params.init_timeout:
                self.status = WAIT
            return self.act(sleep=True, wake_range=1.5 * self.params.d_min,
                            wake_tick=self.params.init_timeout)  # then the timeout above
        if cmd == CMD_HALT:
            self.status = WAIT
            return self.act()
        return self.act(self.travel)

    # ------------------------------------------------------------------ waiting
    def wait(self, perception: Perception) -> Action:
        grad = self.formation_gradient(perception)
        if grad is not None:
            self.grad = grad
        if self.blocked(perception):
            return self.act(sleep=True,
                            wake_range=max(self.params.start_range, self.params.quiet_range))
        self.status = INSIDE if perception.on_target else OUTSIDE
        self.odometer[:] = 0.0
        self.progress_tick = perception.tick
        return self.move(perception)

    def blocked(self, perception: Perception) -> bool:
        """Kilobot's start rule: wait while a robot moves nearby or a waiting one outranks."""
        return bool(formationkernel.blocked(perception.distances, perception.messages,
                                            self.params.quiet_range, self.params.start_range,
                                            self.grad, self.id, NO_SENDER, WAIT, TRAVEL))

    # ------------------------------------------------------------------ moving
    def move(self, perception: Perception) -> Action:
        self.status = INSIDE if perception.on_target else OUTSIDE
        structure = np.flatnonzero(~perception.messages["moving"])
        if len(structure) == 0:
            return self.wander(perception)
        nearest = int(structure[0])
        velocity = self.edge_follow(perception.offsets[nearest],
                                    float(perception.distances[nearest]))
        self.heading = unit(velocity)
        circled = self.circling(perception, nearest)
        if circled:
            self.circled = 0.0  # count the next lap afresh: one lap, one trap
        trapped = circled or self.stuck(perception)
        self.traps = self.traps + 1 if trapped else self.traps
        if (self.should_join(perception, nearest)
                or (trapped and (perception.on_target or self.traps > 2))):
            self.status = JOINED
            return self.act()
        if trapped and perception.beacon is not None:  # trapped off the target: make for the beacon
            self.escape_until = perception.tick + self.params.T_r
        if perception.tick < self.escape_until and perception.beacon is not None:
            velocity = perception.beacon * self.params.v
        self.update_gradient(perception)
        if self.must_yield(perception, velocity):
            self.progress_tick = perception.tick  # waiting for another robot is not being stuck
            self.odometer[:] = 0.0
            return self.act()
        return self.act(velocity)

    def edge_follow(self, offset: np.ndarray, dist: float) -> np.ndarray:
        radial = offset / max(dist, 1e-9)
        tangent = np.array([radial[1], -radial[0]]) * self.params.orbit
        error = max(-1.0, min(1.0, (dist - self.params.d_cover) * self.params.radial_gain))
        return unit(tangent + error * radial) * self.params.v

    def should_join(self, perception: Perception, nearest: int) -> bool:
        near = self.params.d_cover - self.params.arrive_tolerance
        if not perception.on_target or perception.distances[nearest] < near:
            return False
        if not perception.probe(self.heading * self.params.probe_distance):
            return True
        m = perception.messages[nearest]
        return bool(m["id"] != NO_SENDER and m["status"] == JOINED and m["gradient"] >= self.grad)

    def update_gradient(self, perception: Perception) -> None:
        low = formationkernel.lowest_gradient(perception.distances, perception.messages,
                                              self.params.gradient_reach * self.params.d_cover,
                                              NO_SENDER, INF_GRADIENT)
        if low >= 0:
            self.grad = int(low) + 1

    def stuck(self, perception: Perception) -> bool:
        """Moved less than theta over the last T_r ticks."""
        moved = self.sample_progress(perception)
        if moved is None:
            return False
        if moved > self.params.theta:
            self.traps = 0
        return moved <= self.params.theta

    def must_yield(self, perception: Perception, velocity: np.ndarray) -> bool:
        close = ((perception.distances <= self.params.yield_distance)
                 & perception.messages["moving"] & (perception.messages["id"] > self.id))
        if not close.any():
            return False
        return bool((perception.offsets[close] @ velocity > 0).any())

    def wander(self, perception: Perception) -> Action:
        """No stationary robot in range: head for the beacon (or keep going)."""
        if perception.beacon is not None and not perception.on_target:
            self.heading = perception.beacon
        if not self.heading.any():
            self.heading = np.array([1.0, 0.0])
        if perception.on_target and not perception.probe(self.heading * self.params.probe_distance):
            self.status = JOINED
            return self.act()
        return self.act(self.heading * self.params.v)


__all__ = ["FormationTravel", "Kilobot", "KilobotParams"]
