"""A user's per-robot controller for the checkpoint tests (``tests.resume_bots:Crowder``):
robots crowd toward the beacon on noisy headings from their own random streams, push each
other, and now and then (often on the target) stop and sleep a random while (its wake_tick), so a run has
contacts, parked and sleeping bodies, and controller state (a counter, a random stream)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from swarmsim.controller import Action, Perception, RobotSetup

WALKING, RESTING = 0, 1


@dataclass(frozen=True)
class CrowderParams:
    """Attributes:
        v: speed, units per tick.
        noise: heading noise, radians (standard deviation).
    """

    v: float = 0.1
    noise: float = 0.6


class Crowder:
    """Walk toward the beacon with a noisy heading; now and then (often on the target) rest,
    asleep, a random number of ticks, then walk on."""

    name = "crowder"
    Params = CrowderParams
    STATUSES = ("Walking", "Resting")
    SETTLED_STATUSES = ("Resting",)

    @classmethod
    def sensing_range(cls, params: CrowderParams) -> float:
        return 3.0

    def __init__(self, setup: RobotSetup, params: CrowderParams, rng: np.random.Generator):
        self.params = params
        self.rng = rng
        self.rests = 0  # how many times this robot has rested

    def step(self, perception: Perception) -> Action:
        if self.rng.random() < (0.3 if perception.on_target else 0.01):
            self.rests += 1
            wake = perception.tick + int(self.rng.integers(100, 300))
            return Action((0.0, 0.0), {"status": RESTING, "moving": False}, sleep=True,
                          wake_tick=wake)
        beacon = perception.beacon if perception.beacon is not None else np.zeros(2)
        angle = float(np.arctan2(beacon[1], beacon[0]) + self.rng.normal(0, self.params.noise))
        v = self.params.v
        return Action((v * np.cos(angle), v * np.sin(angle)), {"status": WALKING, "moving": True})


class Interrupted(Crowder):
    """A Crowder whose run is interrupted (as by Ctrl-C) at tick 25."""

    name = "interrupted"

    def step(self, perception: Perception) -> Action:
        if perception.tick == 25:
            raise KeyboardInterrupt
        return super().step(perception)
