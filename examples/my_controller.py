"""Write your own controller: a robot that heads for the beacon and stops on the target.

    swarmsim run tiny --controller examples.my_controller:GoToLight --max-ticks 600
    (run from the repository root so that 'examples' is importable)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from swarmsim.controller import Action, Perception, RobotSetup


@dataclass(frozen=True)
class GoToLightParams:
    """Attributes:
        v: speed, units per tick.
    """

    v: float = 0.1


class GoToLight:
    """Head for the beacon; stop (and sleep) once the floor sensor says 'target'."""

    name = "go-to-light"
    Params = GoToLightParams
    STATUSES = ("Moving", "Arrived")
    MESSAGE_FIELDS: ClassVar[list] = []

    @classmethod
    def sensing_range(cls, params: GoToLightParams) -> float:
        return 2.0

    def __init__(self, setup: RobotSetup, params: GoToLightParams, rng: np.random.Generator):
        self.id, self.p = setup.robot_id, params

    def step(self, p: Perception) -> Action:
        if p.on_target or p.beacon is None:
            return Action((0.0, 0.0), (self.id, 1, 0, 0, False, False), sleep=True)
        v = p.beacon * self.p.v
        return Action((float(v[0]), float(v[1])), (self.id, 0, 0, 0, False, True))
