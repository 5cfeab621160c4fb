"""Per-robot controllers driven as a :class:`~swarmsim.controller.Swarm`.

The engine decides every run through a Swarm. A per-robot controller class is wrapped here:
one object per robot, each asked ``step(perception)``. An exception of the class's own code is
raised as a ControllerError naming the robot and the tick (the exception its cause).
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from typing import Any

import numpy as np

from swarmsim.controller import Action, DecideBatch, RobotSetup
from swarmsim.errors import ControllerError, raised


class RobotSwarm:
    """The robots of a per-robot controller class.

    Args:
        cls: the controller class.
        setups, params, rngs: what each robot is made with (``cls(setup, params, rng)``).
        shuffled: call the robots of a chunk in a random order drawn from ``order_rng``
            (a check: no robot's action may depend on another's call); index order if False.
        order_rng: the Generator of that order.
    """

    def __init__(self, cls: type, setups: Sequence[RobotSetup], params: Any,
                 rngs: Sequence[np.random.Generator], shuffled: bool = False,
                 order_rng: np.random.Generator | None = None):
        self.robots = [_made(cls, s, params, rng) for s, rng in zip(setups, rngs, strict=True)]
        self.cls = cls
        self._shuffled = shuffled
        self._order_rng = order_rng if order_rng is not None else np.random.default_rng(0)
        self.decider = "step()"
        """What this swarm calls its robots' actions by in errors."""

    def decide(self, robots: np.ndarray, batch: DecideBatch) -> list[Action]:
        deciding = [self.robots[i] for i in robots.tolist()]
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

    def fail(self, robots: np.ndarray, mode: str) -> None:
        """Robots ``robots`` fail as ``mode`` says: each one's controller's ``fail(mode)``
        (swarmsim.controller.FailingController); an exception is raised as a ControllerError
        naming the robot."""
        for i in np.asarray(robots, dtype=np.intp).tolist():
            try:
                self.robots[i].fail(mode)
            except Exception as exc:
                raise ControllerError(raised("fail()", exc), robot=i) from exc

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


def _made(cls: type, setup: RobotSetup, params: Any, rng: np.random.Generator) -> Any:
    """One robot's controller, ``cls(setup, params, rng)``."""
    try:
        return cls(setup, params, rng)
    except Exception as exc:
        raise ControllerError(raised("__init__()", exc), robot=setup.robot_id) from exc


__all__ = ["RobotSwarm"]
