"""A controller that drives its wheels: it heads for the beacon and stops on the target.

    swarmsim run tiny --controller examples.wheel_walker:WheelWalker --set drive=diff \\
        --max-ticks 1500
    (run from the repository root so that 'examples' is importable; drive=kilobot works too)

It declares ``COMMANDS = "wheels"``: its Action's velocity is (left, right) wheel speeds,
units per tick, not a wished velocity. A robot does not know its heading; it estimates it
(docs/drives.md): while it drives straight ahead its own displacement (``Perception.moved``,
in the shared world-aligned frame) points along its heading, and in between it adds up how
far it turned (``Perception.turned``, odometry).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from swarmsim.controller import Action, Perception, RobotSetup

MOVING, ARRIVED = 0, 1  # status codes: indices into STATUSES


@dataclass(frozen=True)
class WheelWalkerParams:
    """Attributes:
        wheel: wheel speed when driving, units per tick.
        aim: heading error within which it drives forward (steering as it goes), rad.
        steer: wheel speed difference per radian of heading error when driving, units/tick.
    """

    wheel: float = 0.1
    aim: float = 0.3
    steer: float = 0.05


def _wrap(angle: float) -> float:
    return (angle + math.pi) % (2 * math.pi) - math.pi


class WheelWalker:
    """Turn toward the beacon on the spot, then drive to it; stop (and sleep) on the target.

    Its heading estimate is None until it has driven straight for a tick."""

    name = "wheel-walker"
    Params = WheelWalkerParams
    STATUSES = ("Moving", "Arrived")
    SETTLED_STATUSES = ("Arrived",)
    COMMANDS = "wheels"  # Action.velocity holds (left, right) wheel speeds
    requires_beacon = True

    @classmethod
    def sensing_range(cls, params: WheelWalkerParams) -> float:
        return 2.0

    def __init__(self, setup: RobotSetup, params: WheelWalkerParams, rng: np.random.Generator):
        self.params = params
        self.heading: float | None = None  # estimated, rad
        self.straight = False  # did it drive straight last tick?

    def step(self, perception: Perception) -> Action:
        self._estimate_heading(perception)
        if perception.on_target or perception.beacon is None:
            self.straight = False
            return Action((0.0, 0.0), {"status": ARRIVED, "moving": False}, sleep=True)
        p = self.params
        if self.heading is None:  # drive straight a tick to learn the heading
            return self._drive(p.wheel, p.wheel, straight=True)
        goal = math.atan2(float(perception.beacon[1]), float(perception.beacon[0]))
        err = _wrap(goal - self.heading)
        if abs(err) > p.aim:  # turn on the spot: left wheel back, right forward (or mirrored)
            turn = math.copysign(p.wheel, err)
            return self._drive(-turn, turn, straight=False)
        bend = p.steer * err
        return self._drive(p.wheel - bend, p.wheel + bend, straight=abs(bend) < 1e-3)

    def _estimate_heading(self, perception: Perception) -> None:
        """Add last tick's turn; after a straight tick, take the heading from ``moved``."""
        dx, dy = float(perception.moved[0]), float(perception.moved[1])
        if self.straight and math.hypot(dx, dy) > 0.2 * self.params.wheel:
            self.heading = math.atan2(dy, dx)
        elif self.heading is not None:
            self.heading = _wrap(self.heading + perception.turned)

    def _drive(self, left: float, right: float, straight: bool) -> Action:
        self.straight = straight
        return Action((left, right), {"status": MOVING, "moving": True})
