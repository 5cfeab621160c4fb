"""A formation's trip to the target, GGC's way, for controllers that start in formation
(Kilobot, FCDFS): hop gradients within the formation and a leader's travel command relayed
from each robot's gradient parent (:class:`FormationTravel`)."""

from __future__ import annotations

import math

import numpy as np

from swarmsim.controller import NO_SENDER, Perception, message_dtype

from . import formationkernel
from .gradient import INF_GRADIENT

CMD_NONE, CMD_TRAVEL, CMD_HALT = 0, 1, 2
"""A formation's travel commands: none yet, travel (along ``vx``, ``vy``), halt."""


def unit(v: np.ndarray) -> np.ndarray:
    n = math.hypot(float(v[0]), float(v[1]))
    return v / n if n > 1e-12 else np.zeros(2)


class FormationTravel:
    """The formation's trip to the target, GGC's way (Kilobot and FCDFS).

    The leader sets ``cmd``/``travel``; every other robot copies them from its gradient parent
    (the nearest stationary neighbour within 1.5 * d_min whose gradient is one less) one tick
    later. Subclasses provide ``grad``, ``params.d_min`` and ``params.init_timeout``.
    """

    grad: int
    cmd: int
    travel: np.ndarray
    STATUSES: tuple[str, ...]

    @classmethod
    def summarize(cls, robots) -> dict:
        """Per-run figures for the summary: how many robots end in each status."""
        counts: dict[str, int] = {}
        for r in robots:
            counts[cls.STATUSES[r.status]] = counts.get(cls.STATUSES[r.status], 0) + 1
        return {"status_counts": dict(sorted(counts.items()))}

    @classmethod
    def warm_up(cls) -> None:
        """Compile or load the formation's kernels for this class's broadcasts before a
        run's clock starts."""
        formationkernel.warm_up(message_dtype(cls.MESSAGE_FIELDS))

    def heard(self, perception: Perception) -> np.ndarray:
        return perception.messages["id"] != NO_SENDER

    def formation_gradient(self, perception: Perception) -> int | None:
        """1 + the smallest gradient of stationary neighbours within 1.5 d_min."""
        low = formationkernel.lowest_gradient(perception.distances, perception.messages,
                                              1.5 * self.params.d_min, NO_SENDER, INF_GRADIENT)
        return None if low < 0 else int(low) + 1

    def travel_parent(self, perception: Perception) -> np.void | None:
        """The nearest stationary neighbour within 1.5 d_min one gradient below mine."""
        k = formationkernel.first_parent(perception.distances, perception.messages,
                                         1.5 * self.params.d_min, self.grad - 1, NO_SENDER)
        return perception.messages[k] if k >= 0 else None

    def follow_travel(self, perception: Perception) -> int | None:
        """Copy the parent's travel command; returns the command, or None with no gradient."""
        grad = self.formation_gradient(perception)
        if grad is None:
            return None
        self.grad = grad
        parent = self.travel_parent(perception)
        if parent is None:
            return None
        self.cmd = int(parent["cmd"])
        self.travel = np.array([parent["vx"], parent["vy"]], dtype=float)
        if self.cmd != CMD_TRAVEL:
            self.travel[:] = 0.0
        return self.cmd


__all__ = ["CMD_HALT", "CMD_NONE", "CMD_TRAVEL", "FormationTravel", "unit"]
