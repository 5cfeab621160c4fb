"""Write your own controller: a robot that heads for the beacon and stops on the target.

    swarmsim run tiny --controller examples.my_controller:GoToLight --max-ticks 600
    (run from the repository root so that 'examples' is importable)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from swarmsim.controller import Action, Perception, RobotSetup

MOVING, ARRIVED = 0, 1  # status codes: indices into STATUSES


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
    STATUSES = ("Moving", "Arrived")  # what its status codes mean (videos, summaries)
    SETTLED_STATUSES = ("Arrived",)  # done, standing still (metrics watch them being pushed)

    @classmethod
    def sensing_range(cls, params: GoToLightParams) -> float:
        return 2.0

    def __init__(self, setup: RobotSetup, params: GoToLightParams, rng: np.random.Generator):
        self.params = params

    def step(self, perception: Perception) -> Action:
        if perception.on_target or perception.beacon is None:
            return Action((0.0, 0.0), {"status": ARRIVED, "moving": False}, sleep=True)
        v = perception.beacon * self.params.v
        return Action((float(v[0]), float(v[1])), {"status": MOVING, "moving": True})
