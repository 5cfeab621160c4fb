"""One Kilobot robot at a time (a per-robot controller, :class:`KilobotRobot`): the
reference implementation of :class:`controllers.kilobot.Kilobot`, whose swarm
(swarm.py, chunk.py) makes the very same runs (tests/controllers/baselines/test_kilobot_swarm.py).
The rules: controllers/kilobot/__init__.py.
"""

from __future__ import annotations

import numpy as np

from controllers.common import formationkernel
from controllers.common.edges import CirclingWatch, ProgressWatch
from controllers.common.formation import CMD_HALT, CMD_NONE, CMD_TRAVEL, FormationTravel, unit
from controllers.common.gradient import INF_GRADIENT
from swarmsim.controller import NO_SENDER, Action, Perception, RobotSetup, make_action

from .params import (
    INSIDE,
    JOINED,
    MOVING,
    OUTSIDE,
    TRAVEL,
    WAIT,
    KilobotDeclarations,
    KilobotParams,
)


class KilobotRobot(KilobotDeclarations, FormationTravel, CirclingWatch, ProgressWatch):
    """One Kilobot robot: peel off the formation, follow its edge, join inside the shape
    (the reference of :class:`~controllers.kilobot.Kilobot`)."""

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


__all__ = ["KilobotRobot"]
