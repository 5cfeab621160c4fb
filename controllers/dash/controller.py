"""DASH-like adaptive-spacing coverage: the GGC paper's comparison algorithm [42], reconstructed.

**The original DASH paper could not be identified.** The GGC paper (Section 6.7) only says
that "the DASH algorithm dynamically adjusts the distance between the robots in real time, [so]
the speed of covering completion is relatively slow", and its Table 3 rates DASH: suits
complex environments, no communication delay, small computing cost, good stability, low
coverage rate, slow convergence. Searches of public papers, documentation, issue threads and
code (for "DASH" with swarm coverage / shape formation / self-assembly / adaptive spacing /
dispersion) found no swarm algorithm of that name, and the GGC paper's reference list was not
available. This module implements exactly the behaviour the GGC paper describes, as a
virtual-spring dispersion whose spacing is adjusted in real time; every rule below is ours.

Rules, each tick:

* Off the target: head for the beacon, keeping ``d_safe`` from neighbours (Seeking).
* On the target: keep a desired spacing ``s`` (broadcast): repel every neighbour closer than
  ``s`` (force grows as they get closer, like potential-field dispersion), and never step off
  the target (the floor probe looks ``probe_distance`` ahead).
* Adjust ``s`` in real time (from ``s_start``), by ``adapt_rate`` per tick at most: grow it
  while no neighbour is closer than ``s * (1 - tolerance)`` (there is room), shrink it while
  ``crowd`` or more neighbours are that close (the robots around are packed), but keep it
  within ``consensus_band`` of the on-target neighbours' mean spacing (a local consensus, so
  the spacing is uniform); keep it in [``s_start``, ``d_cover``].
* Rest (and sleep) when both the motion and the spacing have settled.

So the swarm enters densely and then slowly inflates toward d_cover spacing; robots that
cannot fit stay outside, pressing in.

Sensing: relative positions (bearing and distance) of neighbours within ``1.5 * d_cover``, their
broadcast spacing, the floor sensor, a floor probe ``probe_distance`` (1 unit) ahead and the
beacon's bearing: comparable to GGC (which needs distances and hop counts), far less than CVT
or mean shift (no local map).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from controllers.common.push import push_away
from controllers.common.push import warm_up as _warm_up_push
from swarmsim.controller import (
    NO_SENDER,
    Action,
    Perception,
    RobotSetup,
    make_action,
    require_positive,
)

from .kernel import spacing_view
from .kernel import warm_up as _warm_up_spacing

SEEKING, SPREADING, RESTING = 0, 1, 2
STATUSES = ("Seeking", "Spreading", "Resting")
MESSAGE_FIELDS = [("spacing", "f4")]


@dataclass(frozen=True)
class DashParams:
    """Parameters of the DASH-like controller (lengths in units, speeds in units per tick).

    Attributes:
        d_safe: smallest distance kept from any neighbour (paper Table 2: 1).
        d_cover: largest spacing a robot adapts to (GGC's coverage distance; default 6).
        s_start: spacing a robot starts from when it reaches the target.
        adapt_rate: change of the spacing per tick, units.
        consensus_band: a robot's spacing steps toward the mean spacing of its on-target
            neighbours within 1.5 * d_cover while it differs from it by more than this, units.
        tolerance: a neighbour closer than s * (1 - tolerance) counts as too close.
        crowd: with this many neighbours too close, the spacing shrinks.
        v: top speed (paper: 0.1).
        gain: repulsion gain (speed per unit of missing distance, per neighbour).
        deadband: speeds below this are treated as zero (the robot rests).
        probe_distance: how far ahead the floor probe looks before a step (<= 2, the
            engine's probe range).
    """

    d_safe: float = 1.0
    d_cover: float = 6.0
    s_start: float = 2.0
    adapt_rate: float = 0.004
    consensus_band: float = 0.2
    tolerance: float = 0.1
    crowd: int = 3
    v: float = 0.1
    gain: float = 0.05
    deadband: float = 0.005
    probe_distance: float = 1.0

    def __post_init__(self) -> None:
        require_positive(self, "d_safe", "d_cover", "s_start", "adapt_rate", "v", "gain",
                         "probe_distance", "crowd")
        if not self.d_safe <= self.s_start <= self.d_cover:
            raise ValueError(f"need d_safe <= s_start <= d_cover, got {self.d_safe}, "
                             f"{self.s_start}, {self.d_cover}")
        if not 0 <= self.tolerance < 1:
            raise ValueError(f"tolerance must be in [0, 1), got {self.tolerance!r}")
        if self.deadband < 0 or self.consensus_band < 0:
            raise ValueError("deadband and consensus_band must be >= 0")
        if self.probe_distance > 2.0:
            raise ValueError(f"probe_distance ({self.probe_distance}) must be <= 2 (the "
                             "engine's default probe range)")


class Dash:
    """DASH (reconstructed): dispersion whose spacing adapts in real time up to d_cover."""

    name = "dash"
    Params = DashParams
    STATUSES = STATUSES
    SETTLED_STATUSES = ("Resting",)  # done, standing still (collision instruments)
    MESSAGE_FIELDS = MESSAGE_FIELDS
    requires_beacon = True

    @classmethod
    def sensing_range(cls, params: DashParams) -> float:
        return 1.5 * params.d_cover

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


__all__ = ["Dash", "DashParams"]
