"""Controllers that break the controller contract, each in one way, for
tests/engine/test_controller_errors.py: robot ``BAD_ROBOT`` misbehaves at tick ``BAD_TICK`` (the
others, and it before then, walk east as :class:`Walker` does), or at setup.

Run one as ``swarmsim run tiny --controller tests.bad_controllers:NanVelocity``.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from swarmsim.controller import Action, ChunkActions, DecideBatch, Perception, RobotSetup

BAD_ROBOT, BAD_TICK = 2, 3
"""Which robot misbehaves, and when."""


@dataclass(frozen=True)
class WalkerParams:
    """Attributes:
        v: speed, units per tick.
    """

    v: float = 0.05


def user_helper(value: float) -> float:
    """A frame of the user's own below ``step`` in a traceback."""
    return value / 0.0 if value > 1e9 else 1 / (value - value)


class Walker:
    """Walks east, broadcasting a field of its own ("x"); a good controller."""

    name = "walker"
    Params = WalkerParams
    STATUSES = ("Walking", "Resting")
    MESSAGE_FIELDS = (("x", "f4"), ("hops", "i2"))

    @classmethod
    def sensing_range(cls, params: WalkerParams) -> float:
        return 3.0

    def __init__(self, setup: RobotSetup, params: WalkerParams, rng: np.random.Generator):
        self.id = setup.robot_id
        self.v = params.v

    def step(self, perception: Perception) -> Action:
        if self.id == BAD_ROBOT and perception.tick == BAD_TICK:
            return self.bad(perception)
        return self.good(perception)

    def good(self, perception: Perception) -> Action:
        return Action((self.v, 0.0), (self.id, 0, True, 1.5, 2))

    def bad(self, perception: Perception) -> Action:
        return self.good(perception)


# ----------------------------------------------------------------------------- raising
class RaisesInStep(Walker):
    def bad(self, perception):
        return Action((user_helper(1.0), 0.0))


class RaisesInInit(Walker):
    def __init__(self, setup, params, rng):
        super().__init__(setup, params, rng)
        if setup.robot_id == BAD_ROBOT:
            raise RuntimeError("no battery")


class RaisesInSummarize(Walker):
    @classmethod
    def summarize(cls, robots):
        return {"mean": sum(r.v for r in robots) / 0}


class SummarizeReturnsList(Walker):
    @classmethod
    def summarize(cls, robots):
        return [1, 2]


class RaisesInSensingRange(Walker):
    @classmethod
    def sensing_range(cls, params):
        raise NotImplementedError("which range?")


# ----------------------------------------------------------------------------- returns
class ReturnsNone(Walker):
    def bad(self, perception):
        return None


class ReturnsTuple(Walker):
    def bad(self, perception):
        return (self.v, 0.0)


class NanVelocity(Walker):
    def bad(self, perception):
        return Action((float("nan"), 0.0))


class InfVelocity(Walker):
    def bad(self, perception):
        return Action((0.0, -float("inf")))


class StringVelocity(Walker):
    def bad(self, perception):
        return Action(("fast", 0.0))


class NumericStringVelocity(Walker):
    def bad(self, perception):
        return Action(("1", "0"))


class ThreeVelocity(Walker):
    def bad(self, perception):
        return Action((0.1, 0.0, 0.0))


class ScalarVelocity(Walker):
    def bad(self, perception):
        return Action(0.1)


class StringStatus(Walker):
    def bad(self, perception):
        return Action((0.0, 0.0), (self.id, "Walking", True, 1.5, 2))


class StatusOutOfRange(Walker):
    def bad(self, perception):
        return Action((0.0, 0.0), (self.id, 2, True, 1.5, 2))


class NegativeStatus(Walker):
    def bad(self, perception):
        return Action((0.0, 0.0), {"status": -1})


class ShortTuple(Walker):
    def bad(self, perception):
        return Action((0.0, 0.0), (self.id, 0, True))


class LongTuple(Walker):
    def bad(self, perception):
        return Action((0.0, 0.0), (self.id, 0, True, 1.5, 2, 7))


class UnknownField(Walker):
    def bad(self, perception):
        return Action((0.0, 0.0), {"status": 0, "speed": 3})


class TooBigForField(Walker):
    def bad(self, perception):
        return Action((0.0, 0.0), (self.id, 0, True, 1.5, 70000))


class FractionInIntField(Walker):
    def bad(self, perception):
        return Action((0.0, 0.0), {"hops": 2.5})


class StringInFloatField(Walker):
    def bad(self, perception):
        return Action((0.0, 0.0), {"x": "left"})


class MessageIsString(Walker):
    def bad(self, perception):
        return Action((0.0, 0.0), "hello")


class NegativeListen(Walker):
    def bad(self, perception):
        return Action((0.0, 0.0), listen=-1.0)


class NanListen(Walker):
    def bad(self, perception):
        return Action((0.0, 0.0), listen=float("nan"))


class StringListen(Walker):
    def bad(self, perception):
        return Action((0.0, 0.0), listen="far")


class StringSleep(Walker):
    def bad(self, perception):
        return Action((0.0, 0.0), sleep="no")


class NegativeWakeRange(Walker):
    def bad(self, perception):
        return Action((0.0, 0.0), sleep=True, wake_range=-2.0)


class NanWakeRange(Walker):
    def bad(self, perception):
        return Action((0.0, 0.0), sleep=True, wake_range=float("nan"))


class NegativeWakeTick(Walker):
    def bad(self, perception):
        return Action((0.0, 0.0), sleep=True, wake_tick=-5)


class FloatWakeTick(Walker):
    def bad(self, perception):
        return Action((0.0, 0.0), sleep=True, wake_tick=perception.tick + 2.5)


class StringWakeOnMotion(Walker):
    def bad(self, perception):
        return Action((0.0, 0.0), sleep=True, wake_on_motion="never")


# ----------------------------------------------------------------------------- spoofing
class Spoofer(Walker):
    """Every robot claims to be robot 0, by tuple and (odd robots) by dict."""

    def good(self, perception):
        if self.id % 2:
            return Action((self.v, 0.0), {"id": 0, "status": 1, "x": 1.5})
        return Action((self.v, 0.0), (0, 0, True, 1.5, 2))


# ----------------------------------------------------------------------------- batch
class PutSwarm:
    """A batch controller's swarm made of per-robot controllers: each robot's ``step``
    written row by row into the sparse ChunkActions (``put``). ``edit(robot, tick, action)``,
    if given, may replace a robot's action."""

    def __init__(self, robots: list, edit: Callable[[Any, int, Action], Action] | None = None):
        self.robots, self.edit = robots, edit

    @classmethod
    def of(cls, robot_cls: type, setups: Sequence[RobotSetup], params: Any,
           rngs: Sequence[np.random.Generator], **options: Any) -> PutSwarm:
        """``robot_cls(setup, params, rng)`` for each robot, in such a swarm."""
        return cls([robot_cls(s, params, r) for s, r in zip(setups, rngs, strict=True)],
                   **options)

    def decide(self, robots: np.ndarray, batch: DecideBatch) -> ChunkActions:
        columns = ChunkActions.empty(len(robots))
        for k, i in enumerate(robots.tolist()):
            action = self.robots[i].step(batch.perceive(k))
            if self.edit is not None:
                action = self.edit(self.robots[i], batch.tick, action)
            columns.put(k, action)
        return columns

    def summarize(self, failed: np.ndarray) -> dict:
        return {}


class WalkerSwarm:
    """A batch controller's swarm: every robot walks east (dense columns), and robot
    BAD_ROBOT breaks the contract at BAD_TICK as ``breaks`` says."""

    def __init__(self, setups: Sequence[RobotSetup], params: WalkerParams, breaks: str):
        self.n, self.v, self.breaks = len(setups), params.v, breaks

    def decide(self, robots: np.ndarray, batch: DecideBatch) -> ChunkActions:
        r = len(robots)
        velocities = np.tile([self.v, 0.0], (r, 1))
        listen = np.full(r, np.nan)
        broadcast = np.zeros(r, dtype=batch.neighbours.messages.dtype)
        broadcast["id"] = robots
        sleep, wake_range = np.zeros(r, dtype=bool), np.full(r, np.nan)
        at = np.flatnonzero(robots == BAD_ROBOT)
        if batch.tick == BAD_TICK and len(at):
            k = int(at[0])
            if self.breaks == "nan":
                velocities[k, 1] = np.nan
            elif self.breaks == "status":
                broadcast["status"][k] = 9
            elif self.breaks == "listen":
                listen[k] = -3.0
            elif self.breaks == "wake_range":
                velocities[k] = 0.0
                sleep[k], wake_range[k] = True, -1.0
            elif self.breaks == "shape":
                velocities = velocities[:, :1]
            elif self.breaks == "flat":
                velocities = velocities[:, 0]
            elif self.breaks == "short":
                sleep = sleep[1:]
            elif self.breaks == "raise":
                raise ZeroDivisionError("batch division")
        if self.breaks == "spoof":  # every robot, every tick, claims to be robot 0
            broadcast["id"] = 0
        return ChunkActions.columns(velocities, listen, broadcast, sleep, wake_range,
                                    np.ones(r, dtype=bool), np.full(r, -1, dtype=np.int64))

    def summarize(self, failed: np.ndarray) -> dict:
        return {}


def batch_walker(breaks: str) -> type:
    """A batch controller class whose swarm breaks the contract as ``breaks`` says."""

    class BatchWalker:
        name = f"batch-{breaks}"
        Params = WalkerParams
        STATUSES = ("Walking",)

        @classmethod
        def sensing_range(cls, params):
            return 3.0

        @classmethod
        def create_swarm(cls, setups, params, rngs):
            return WalkerSwarm(setups, params, breaks)

    BatchWalker.__qualname__ = BatchWalker.__name__ = f"Batch_{breaks}"
    return BatchWalker


Batch_none = batch_walker("none")
Batch_nan = batch_walker("nan")
Batch_status = batch_walker("status")
Batch_listen = batch_walker("listen")
Batch_wake_range = batch_walker("wake_range")
Batch_shape = batch_walker("shape")
Batch_raise = batch_walker("raise")
Batch_spoof = batch_walker("spoof")
Batch_flat = batch_walker("flat")
Batch_short = batch_walker("short")


class CreateSwarmReturnsNone(Walker):
    @classmethod
    def create_swarm(cls, setups, params, rngs):
        return None


class RaisesInCreateSwarm(Walker):
    @classmethod
    def create_swarm(cls, setups, params, rngs):
        raise KeyError("layout")


@dataclass(frozen=True)
class RadiusParams:
    """Attributes:
        v: speed, units per tick.
        radius: named like the engine's robot radius (PhysicsConfig.radius): refused.
    """

    v: float = 0.05
    radius: float = 2.0


class ParamNamedRadius(Walker):
    Params = RadiusParams
