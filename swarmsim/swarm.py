"""Per-robot controllers driven as a :class:`~swarmsim.controller.Swarm`.

The engine decides every run through a Swarm. A per-robot controller class is wrapped here:
one object per robot, each asked ``step(perception)`` (or the class's optional ``prepare``
before them, or ``decide_batch`` in their place).
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from typing import Any

import numpy as np

from swarmsim.controller import Action, ChunkActions, DecideBatch, RobotSetup


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
        self.robots = (list(create(setups, params, rngs)) if create is not None else
                       [cls(s, params, rng) for s, rng in zip(setups, rngs, strict=True)])
        self.cls = cls
        self._shuffled = shuffled
        self._order_rng = order_rng if order_rng is not None else np.random.default_rng(0)
        self._prepare = getattr(cls, "prepare", None)
        self._decide_batch = (getattr(cls, "decide_batch", None)
                              if batch and not shuffled else None)

    def decide(self, robots: np.ndarray, batch: DecideBatch) -> ChunkActions | list[Action]:
        deciding = [self.robots[i] for i in robots.tolist()]
        if self._decide_batch is not None:
            return self._decide_batch(deciding, batch)
        if self._prepare is not None:
            self._prepare(deciding, batch.neighbours)
        perceive = batch.perceive
        if not self._shuffled:
            return [robot.step(perceive(k)) for k, robot in enumerate(deciding)]
        actions: list[Action] = [None] * len(deciding)  # type: ignore[list-item]
        perceptions = [perceive(k) for k in range(len(deciding))]  # drawn in index order
        for k in self._order_rng.permutation(len(deciding)).tolist():
            actions[k] = deciding[k].step(perceptions[k])
        return actions

    def summarize(self, failed: np.ndarray) -> dict[str, Any]:
        """The class's ``summarize(robots)`` figures, if it has one; its ``status_counts``
        count failed robots as "Failed", not under the status they had when they failed."""
        summarize = getattr(self.cls, "summarize", None)
        if summarize is None:
            return {}
        summary = summarize(self.robots)
        if "status_counts" in summary and failed.any():
            working = [r for r, f in zip(self.robots, failed.tolist(), strict=True) if not f]
            counts = Counter(summarize(working)["status_counts"])
            counts["Failed"] = int(failed.sum())
            summary["status_counts"] = dict(sorted(counts.items()))
        return summary


__all__ = ["RobotSwarm"]
