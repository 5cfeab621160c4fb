"""DASH one robot at a time (:class:`DashRobot`): the per-robot controller the batch one
(controller.py's Dash, swarm.py) was ported from, kept as its reference. It makes the very runs
``dash`` makes (tests/controllers/baselines/test_dash_swarm.py); run it as
``--controller controllers.dash.robot:DashRobot``. The algorithm: controller.py's docstring.
"""

from __future__ import annotations

import math

import numpy as np

from controllers.common.push import push_away
from controllers.common.push import warm_up as _warm_up_push
from swarmsim.controller import NO_SENDER, Action, Perception, RobotSetup, make_action

from .kernel import spacing_view
from .kernel import warm_up as _warm_up_spacing
from .params import RESTING, SEEKING, SPREADING, DashDeclarations, DashParams


class DashRobot(DashDeclarations):
    """DASH (reconstructed), one robot: dispersion whose spacing adapts in real time up to
    d_cover."""

    @classmethod
    def warm_up(cls) -> None:
        """Compile or load the kernels before a run's clock starts."""
        _warm_up_spacing()
        _warm_up_push()

    def __init__(self, setup: RobotSetup, params: DashParams, rng: np.random.Generator):
        self.id = setup.robot_id
        self.params = params
        self.level = 0
        self.max_level = math.floor((params.d_cover - params.s_start) / params.adapt_rate)
        self.s = params.s_start
        self.status = SEEKING

    def message(self, moving: bool) -> tuple:
        return (self.id, self.status, moving, float(self.s))

    def act(self, v=(0.0, 0.0), moving: bool = False, sleep: bool = False) -> Action:
        """The action, listening only as far as the next decision needs (cheaper)."""
        listen = 1.5 * self.params.d_cover if self.status != SEEKING else 1.5 * self.params.d_safe
        return make_action((float(v[0]), float(v[1])), self.message(moving), sleep, None, listen)

    def push(self, perception: Perception, radius: float) -> np.ndarray:
        """Away from the neighbours closer than ``radius`` (units), harder the closer."""
        return push_away(perception.offsets, perception.distances, radius, self.params.gain)

    def adapt(self, perception: Perception) -> None:
        """Real-time spacing adjustment, one adapt_rate step per tick at most.

        Room (no neighbour too close) -> grow; crowd -> shrink; but stay within
        consensus_band of the on-target neighbours' mean spacing (step toward it otherwise).
        """
        params = self.params
        m = perception.messages
        mean, too_close = spacing_view(perception.distances, m["id"], m["status"], m["spacing"],
                                       1.5 * params.d_cover, self.s * (1 - params.tolerance),
                                       NO_SENDER, SEEKING)
        mean = self.s if math.isnan(mean) else mean  # no peer: its own
        band, rate = params.consensus_band, params.adapt_rate
        room = too_close == 0 and self.s + rate <= mean + band
        packed = too_close >= params.crowd and self.s - rate >= mean - band
        step = 0
        if room or self.s < mean - band:
            step = 1
        elif packed or self.s > mean + band:
            step = -1
        self.level = min(max(self.level + step, 0), self.max_level)
        self.s = params.s_start + self.level * params.adapt_rate

    def step(self, perception: Perception) -> Action:
        params = self.params
        settled = False
        if not perception.on_target:
            self.status = SEEKING
            self.level = 0
            self.s = params.s_start
            v = self.push(perception, params.d_safe * 1.5)
            if perception.beacon is not None:
                v = v + perception.beacon * params.v
        else:
            before = self.level
            self.adapt(perception)
            v = self.push(perception, self.s)
            self.status = SPREADING
            settled = self.level == before
        speed = math.hypot(float(v[0]), float(v[1]))
        if speed > params.v:
            v *= params.v / speed
            speed = params.v
        if (speed > params.deadband and perception.on_target
                and not perception.probe(v / speed * params.probe_distance)):
            v = np.zeros(2)
            speed = 0.0
        if speed <= params.deadband:
            if perception.on_target and settled:
                self.status = RESTING
                return self.act(sleep=True)
            return self.act()
        return self.act(v, moving=True)


__all__ = ["DashRobot"]
