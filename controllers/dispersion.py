"""Potential-field dispersion: the classic deployment baseline (Howard, Mataric & Sukhatme 2002).

Every robot is repelled by neighbours closer than ``d_cover`` (force growing as they get closer)
and attracted toward the beacon while it is off the target; once on the target it stays on it:
a step whose probe says it would leave the target is cancelled. Robots with no neighbour within
range and nothing to do sleep.

Sensing: relative positions of neighbours within d_cover, the floor sensor, a floor probe
``probe_distance`` ahead, and the beacon's bearing. It broadcasts nothing of its own.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from swarmsim.controller import Action, Perception, RobotSetup, make_action, require_positive

IDLE, SEEKING, SPREADING = 0, 1, 2


@dataclass(frozen=True)
class DispersionParams:
    """Parameters (units; speeds in units per tick).

    Attributes:
        d_cover: neighbours closer than this repel (the desired spacing).
        v: top speed (paper: 0.1).
        gain: repulsion gain (speed per unit of missing distance).
        deadband: speeds below this are treated as zero (the robot rests).
        probe_distance: how far ahead the floor probe looks before a step.
    """

    d_cover: float = 6.0
    v: float = 0.1
    gain: float = 0.05
    deadband: float = 0.005
    probe_distance: float = 1.0

    def __post_init__(self) -> None:
        require_positive(self, "d_cover", "v", "gain", "probe_distance")
        if self.deadband < 0:
            raise ValueError(f"deadband must be >= 0, got {self.deadband!r}")


class Dispersion:
    """Repel neighbours within d_cover; head for the beacon until on the target; stay on it."""

    name = "dispersion"
    Params = DispersionParams
    STATUSES = ("Idle", "Seeking", "Spreading")
    MESSAGE_FIELDS: ClassVar[list] = []

    @classmethod
    def sensing_range(cls, params: DispersionParams) -> float:
        return params.d_cover

    def __init__(self, setup: RobotSetup, params: DispersionParams, rng: np.random.Generator):
        self.id = setup.robot_id
        self.params = params

    def step(self, perception: Perception) -> Action:
        v = np.zeros(2)
        close = perception.distances < self.params.d_cover
        if close.any():
            d = np.maximum(perception.distances[close], 1e-6)
            push = (self.params.d_cover - d) / d
            v -= self.params.gain * (perception.offsets[close] * push[:, None]).sum(axis=0)
        if not perception.on_target and perception.beacon is not None:
            v += perception.beacon * self.params.v
        speed = float(np.hypot(*v))
        if speed > self.params.v:
            v *= self.params.v / speed
            speed = self.params.v
        if (speed > self.params.deadband and perception.on_target
                and not perception.probe(v / speed * self.params.probe_distance)):
                v[:] = 0.0
                speed = 0.0
        status = (SPREADING if speed > self.params.deadband else
                  SEEKING if not perception.on_target else IDLE)
        msg = (self.id, status, speed > self.params.deadband)
        if speed <= self.params.deadband:
            return make_action((0.0, 0.0), msg, sleep=True)
        return make_action((float(v[0]), float(v[1])), msg)
