"""Imperfect robots: actuation noise, sensing noise and message loss (all off by default).

The paper's robots are ideal points that move exactly as commanded, sense exactly and never
miss a message. Collision-realism studies turn these on one at a time (run settings, see
:class:`swarmsim.engine.config.SimConfig`):

* ``speed_noise``: each tick a moving robot's commanded speed is multiplied by
  ``1 + speed_noise * N(0, 1)`` (relative standard deviation; 0.05 = 5 %).
* ``heading_noise``: and its commanded direction is turned by ``heading_noise * N(0, 1)``
  radians. A robot commanding zero velocity stays still (no drift while waiting).
* ``distance_noise``: each sensed neighbour distance d becomes ``d * (1 + distance_noise *
  N(0, 1))`` (relative, like infrared range estimates), never below 0.
* ``bearing_noise``: each sensed bearing is turned by ``bearing_noise * N(0, 1)`` radians.
  Neighbours come sorted by their *sensed* distance, as a robot would rank them.
* ``message_loss``: each neighbour's broadcast is lost with this probability, independently per
  receiver, neighbour and tick. A lost message reads like a silent neighbour (``id`` = -1,
  see :func:`swarmsim.controller.silent_message`): the robot is sensed but not heard.

Each imperfection draws from its own numpy Generator derived from the run seed, so one seed
still decides a run bit for bit, and switching one imperfection on leaves the others' draws as
they were. When every level is 0 nothing is drawn and runs are exactly the ideal runs.

Sleeping robots (waiting or arrived) are not re-evaluated, so they draw no sensing noise until
something near them changes: noise models what a robot does when it acts on its senses.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

STREAMS = {"actuation": 0xAC70, "sensing": 0x5E45, "messages": 0x1055}
"""Spawn keys of the imperfection Generators' SeedSequences (distinct from other streams)."""


@dataclass(frozen=True)
class NoiseLevels:
    """The imperfection settings of one run (see the module docstring for each meaning).

    Attributes:
        speed_noise: relative sd of the commanded speed (>= 0).
        heading_noise: sd of the commanded heading, radians (>= 0).
        distance_noise: relative sd of sensed neighbour distances (>= 0).
        bearing_noise: sd of sensed neighbour bearings, radians (>= 0).
        message_loss: probability that a neighbour's message is lost, in [0, 1].
    """

    speed_noise: float = 0.0
    heading_noise: float = 0.0
    distance_noise: float = 0.0
    bearing_noise: float = 0.0
    message_loss: float = 0.0

    @property
    def actuation(self) -> bool:
        return self.speed_noise > 0 or self.heading_noise > 0

    @property
    def sensing(self) -> bool:
        return self.distance_noise > 0 or self.bearing_noise > 0


class Imperfections:
    """Applies a run's :class:`NoiseLevels` with Generators derived from the run seed."""

    def __init__(self, levels: NoiseLevels, seed: int):
        self.levels = levels
        self._rng = {name: np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(key,)))
                     for name, key in STREAMS.items()}

    @property
    def perturbs_sensing(self) -> bool:
        return self.levels.sensing

    def actuate(self, velocities: np.ndarray) -> np.ndarray:
        """Commanded velocities (N, 2), units per tick, as the wheels carry them out."""
        lv = self.levels
        if not lv.actuation:
            return velocities
        moving = np.flatnonzero((velocities[:, 0] != 0) | (velocities[:, 1] != 0))
        if len(moving) == 0:
            return velocities
        draws = self._rng["actuation"].standard_normal((len(moving), 2))
        scale = np.maximum(0.0, 1.0 + lv.speed_noise * draws[:, 0])
        turn = lv.heading_noise * draws[:, 1]
        c, s = np.cos(turn), np.sin(turn)
        vx, vy = velocities[moving, 0], velocities[moving, 1]
        out = velocities.copy()
        out[moving, 0] = scale * (c * vx - s * vy)
        out[moving, 1] = scale * (s * vx + c * vy)
        return out

    def perturb_offsets(self, offsets: np.ndarray) -> np.ndarray:
        """Sensed neighbour offsets (P, 2), units: true offsets with distance/bearing noise."""
        lv = self.levels
        if not lv.sensing or len(offsets) == 0:
            return offsets
        draws = self._rng["sensing"].standard_normal((len(offsets), 2))
        dist = np.hypot(offsets[:, 0], offsets[:, 1])
        bearing = np.arctan2(offsets[:, 1], offsets[:, 0])
        dist = np.maximum(0.0, dist * (1.0 + lv.distance_noise * draws[:, 0]))
        bearing = bearing + lv.bearing_noise * draws[:, 1]
        return np.column_stack([dist * np.cos(bearing), dist * np.sin(bearing)])

    def lost(self, count: int) -> np.ndarray | None:
        """(count,) bool: which of ``count`` heard messages are lost (None: none can be)."""
        p = self.levels.message_loss
        if p <= 0 or count == 0:
            return None
        if p >= 1:
            return np.ones(count, dtype=bool)
        return self._rng["messages"].random(count) < p
