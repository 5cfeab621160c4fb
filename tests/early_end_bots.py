"""Controllers that end a run early, or keep its physics busy, for the tests of
tests/cli/test_nothing_left_behind.py (``--controller tests.early_end_bots:NAME``)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from swarmsim.controller import Action, Perception, RobotSetup

GO_FROM_TICK = 3
"""The tick from which the failing controllers fail (a few ticks run first)."""


@dataclass(frozen=True)
class NoParams:
    """No parameters."""


class _Base:
    """Heads for the beacon at full speed and never stops (robots crowd around it)."""

    name = "early-end-test"
    Params = NoParams
    STATUSES = ("Moving",)

    @classmethod
    def sensing_range(cls, params: NoParams) -> float:
        return 2.0

    def __init__(self, setup: RobotSetup, params: NoParams, rng: np.random.Generator):
        self.robot_id = setup.robot_id

    def step(self, perception: Perception) -> Action:
        v = perception.beacon if perception.beacon is not None else np.array([0.0, 1.0])
        return Action((float(v[0]), float(v[1])), {"status": 0, "moving": True})


class Crowd(_Base):
    """Every robot heads for the beacon: they meet and push, so contacts begin often."""


class RaisesInStep(_Base):
    """Raises a plain error from ``step`` at tick GO_FROM_TICK."""

    def step(self, perception: Perception) -> Action:
        if perception.tick >= GO_FROM_TICK:
            raise RuntimeError("a bug in the user's controller")
        return super().step(perception)


class NanVelocity(_Base):
    """Returns a NaN velocity from tick GO_FROM_TICK on."""

    def step(self, perception: Perception) -> Action:
        if perception.tick >= GO_FROM_TICK:
            return Action((float("nan"), 0.0), {"status": 0, "moving": True})
        return super().step(perception)


class Interrupted(_Base):
    """Raises KeyboardInterrupt from ``step`` at tick GO_FROM_TICK (Ctrl-C at that moment)."""

    def step(self, perception: Perception) -> Action:
        if perception.tick >= GO_FROM_TICK:
            raise KeyboardInterrupt
        return super().step(perception)


class UndeclaredField(_Base):
    """Broadcasts a field its class does not declare from tick GO_FROM_TICK on."""

    def step(self, perception: Perception) -> Action:
        if perception.tick >= GO_FROM_TICK:
            return Action((0.0, 0.0), {"status": 0, "moving": True, "mood": 3})
        return super().step(perception)
