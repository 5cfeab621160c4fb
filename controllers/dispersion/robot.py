"""Dispersion one robot at a time (:class:`DispersionRobot`): the per-robot controller the
batch one (controller.py's Dispersion, swarm.py) was ported from, kept as its reference. It
makes the very runs ``dispersion`` makes (tests/controllers/baselines/
test_dispersion_swarm.py); run it as ``--controller controllers.dispersion.robot:DispersionRobot``.
The algorithm: controller.py's docstring.
"""

from __future__ import annotations

import numpy as np

from swarmsim.controller import Action, Perception, RobotSetup, make_action

from .params import IDLE, SEEKING, SPREADING, DispersionDeclarations, DispersionParams


class DispersionRobot(DispersionDeclarations):
    """Repel neighbours within d_cover; head for the beacon until on the target; stay on it."""

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


__all__ = ["DispersionRobot"]
