"""Per-robot controllers driven as a :class:`~swarmsim.controller.Swarm`.

The engine decides every run through a Swarm. A per-robot controller class is wrapped here:
one object per robot, each asked ``step(perception)`` (or the class's optional ``prepare``
before them, or ``decide_batch`` in their place). An exception of the class's own code is
raised as a ControllerError naming the robot and the tick (the exception its cause).
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from typing import Any

import numpy as np

from swarmsim.controller import Action, ChunkActions, DecideBatch, RobotSetup
from swarmsim.errors import ControllerError, raised


class RobotSwarm:
    """The robots of a per-robot controller class.

    Args:
        cls: the controller class.
        setups, params, rngs: what each robot is made with (``cls.create_robots`` if the
            class has it, else ``cls(setup, params, rng)`` for each).
        shuffled: call the robots of a chunk in a random order drawn from ``order_rng``
            (a check: no robot's action may depend on another's call); index order if False.
        order_rng: the Generator of that order.
        batch: use the class's ``decide_batch`` if it has one.
    """

    def __init__(self, cls: type, setups: Sequence[RobotSetup], params: Any,
                 rngs: Sequence[np.random.Generator], shuffled: bool = False,
                 order_rng: np.random.Generator | None = None, batch: bool = True):
        create = getattr(cls, "create_robots", None)
        self.robots = (_created(create, setups, params, rngs) if create is not None else
                       [_made(cls, s, params, rng) for s, rng in zip(setups, rngs, strict=True)])
        self.cls = cls
        self._shuffled = shuffled
        self._order_rng = order_rng if order_rng is not None else np.random.default_rng(0)
        self._prepare = getattr(cls, "prepare", None)
        self._decide_batch = (getattr(cls, "decide_batch", None)
                              if batch and not shuffled else None)
        self.decider = "decide_batch()" if self._decide_batch is not None else "step()"
        """What this swarm calls its robots' actions by in errors."""

    def decide(self, robots: np.ndarray, batch: DecideBatch) -> ChunkActions | list[Action]:
        deciding = [self.robots[i] for i in robots.tolist()]
        if self._decide_batch is not None:
            return self._decide_batch(deciding, batch)
        if self._prepare is not None:
            try:
                self._prepare(deciding, batch.neighbours)
            except Exception as exc:
                raise ControllerError(raised("prepare()", exc), tick=batch.tick) from exc
        perceive = batch.perceive
        actions: list[Action] = [None] * len(deciding)  # type: ignore[list-item]
        k = 0
        try:
            if not self._shuffled:
                for k, robot in enumerate(deciding):
                    actions[k] = robot.step(perceive(k))
            else:
                perceptions = [perceive(j) for j in range(len(deciding))]  # in index order
                for k in self._order_rng.permutation(len(deciding)).tolist():
                    actions[k] = deciding[k].step(perceptions[k])
        except Exception as exc:
            raise ControllerError(raised("step()", exc), robot=int(robots[k]),
                                  tick=batch.tick) from exc
        return actions

    def summarize(self, failed: np.ndarray) -> dict[str, Any]:
        """The class's ``summarize(robots)`` figures, if it has one; its ``status_counts``
        count failed robots as "Failed", not under the status they had when they failed."""
        summarize = getattr(self.cls, "summarize", None)
        if summarize is None:
            return {}
        # an exception here is the class's: the engine names it (Simulation._controller_call)
        summary = summarize(self.robots)
        if "status_counts" in summary and failed.any():
            working = [r for r, f in zip(self.robots, failed.tolist(), strict=True) if not f]
            counts = Counter(summarize(working)["status_counts"])
            counts["Failed"] = int(failed.sum())
            summary["status_counts"] = dict(sorted(counts.items()))
        return summary


def _created(create: Any, setups: Sequence[RobotSetup], params: Any,
             rngs: Sequence[np.random.Generator]) -> list:
    """The robots ``cls.create_robots`` makes, one per setup."""
    robots = list(create(setups, params, rngs))
    if len(robots) != len(setups):
        raise ControllerError(f"create_robots() returned {len(robots)} robots for "
                              f"{len(setups)} setups")
    return robots


def _made(cls: type, setup: RobotSetup, params: Any, rng: np.random.Generator) -> Any:
    """One robot's controller, ``cls(setup, params, rng)``."""
    try:
        return cls(setup, params, rng)
    except Exception as exc:
        raise ControllerError(raised("__init__()", exc), robot=setup.robot_id) from exc


__all__ = ["RobotSwarm"]
