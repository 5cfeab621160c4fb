"""Imperfect robots: actuation noise, sensing noise and message loss (all off by default).

The paper's robots are ideal points that move exactly as commanded, sense exactly and never
miss a message. Collision-realism studies turn these on one at a time (run settings, see
:class:`swarmsim.engine.config.SimConfig`):

* ``speed_noise``: each tick a moving robot's commanded speed is multiplied by
  ``1 + speed_noise * N(0, 1)`` (relative standard deviation; 0.05 = 5 %); a robot that
  commands its wheels (docs/drives.md) has each wheel's speed multiplied so, a draw per wheel.
* ``heading_noise``: and its commanded direction is turned by ``heading_noise * N(0, 1)``
  radians. A robot commanding zero velocity stays still (no drift while waiting).
* ``distance_noise``: each sensed neighbour distance d becomes ``d * (1 + distance_noise *
  N(0, 1))`` (relative, like infrared range estimates), never below 0.
* ``bearing_noise``: each sensed bearing is turned by ``bearing_noise * N(0, 1)`` radians.
  Neighbours come sorted by their *sensed* distance, as a robot would rank them.
* ``message_loss``: each neighbour's broadcast is lost with this probability, independently per
  receiver, neighbour and tick. A lost message reads like a silent neighbour (``id`` = -1,
  see :func:`swarmsim.controller.silent_message`): the robot is sensed but not heard.
  This is ``message_model = "uniform"`` (the default): loss that does not depend on distance.
* ``message_model = "logistic"``: a broadcast from a neighbour at true distance d (units)
  arrives with probability ``1 / (1 + exp((d - message_range50) / message_falloff))``
  (:func:`logistic_success`), independently per receiver, neighbour and tick: a logistic
  fall-off with range, the shape Pogosim fits to real robots' message success.
  ``message_range50`` is the distance at which half the messages arrive, ``message_falloff``
  the width over which success falls (from about 73 % at ``range50 - falloff`` to about 27 %
  at ``range50 + falloff``). ``message_loss`` combines with it as a loss that does not depend
  on distance: a message then arrives with probability ``(1 - message_loss) * logistic(d)``
  (one draw per message).
* ``floor_edge_band`` and ``floor_edge_misread``: a robot whose centre is within
  ``floor_edge_band`` units of the target's edge (its outline or a hole's, on either side)
  reads its floor sensor (``on_target``) wrongly with probability ``floor_edge_misread``,
  independently per robot and tick; farther from the edge the reading is exact. The floor
  probe stays exact. Both 0 (the default) is off; setting one without the other is refused.

Each imperfection draws from its own numpy Generator derived from the run seed, so one seed
still decides a run bit for bit, and switching one imperfection on leaves the others' draws as
they were. When every level is 0 (and the message model is uniform) nothing is drawn and runs
are exactly the ideal runs. The logistic model draws from the stream ``message_loss`` uses
(one draw per message for both); the floor's misreads from their own.

Sleeping robots (waiting or arrived) are not re-evaluated, so they draw no sensing noise until
something near them changes: noise models what a robot does when it acts on its senses.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

STREAMS = {"actuation": 0xAC70, "sensing": 0x5E45, "messages": 0x1055, "floor": 0xF1_00}
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
        message_model: "uniform" (message_loss) or "logistic" (success falls with distance).
        message_range50: logistic model: distance at which half the messages arrive, units.
        message_falloff: logistic model: width of the fall-off, units (> 0).
        floor_edge_band: distance from the target's edge within which the floor sensor may
            misread, units (0 = exact everywhere).
        floor_edge_misread: probability of a misread within that band, in [0, 1].
    """

    speed_noise: float = 0.0
    heading_noise: float = 0.0
    distance_noise: float = 0.0
    bearing_noise: float = 0.0
    message_loss: float = 0.0
    message_model: str = "uniform"
    message_range50: float = 0.0
    message_falloff: float = 0.0
    floor_edge_band: float = 0.0
    floor_edge_misread: float = 0.0

    @property
    def actuation(self) -> bool:
        return self.speed_noise > 0 or self.heading_noise > 0

    @property
    def sensing(self) -> bool:
        return self.distance_noise > 0 or self.bearing_noise > 0

    @property
    def logistic_messages(self) -> bool:
        """Messages arrive with a probability that falls with distance."""
        return self.message_model == "logistic"

    @property
    def floor_misreads(self) -> bool:
        """The floor sensor misreads near the target's edge."""
        return self.floor_edge_band > 0 and self.floor_edge_misread > 0


def logistic_success(distances: np.ndarray, range50: float, falloff: float) -> np.ndarray:
    """P(a message crosses each of ``distances``, units) under the logistic model:
    ``1 / (1 + exp((d - range50) / falloff))``, in [0, 1] (exp overflowing far out reads 0)."""
    with np.errstate(over="ignore"):
        return 1.0 / (1.0 + np.exp((np.asarray(distances, dtype=float) - range50) / falloff))


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

    def actuate_wheels(self, wheels: np.ndarray) -> np.ndarray:
        """Wheel speeds (N, 2) (left, right), units per tick, as the motors carry them out
        (a wheel-commanding controller's): with ``speed_noise``, both wheels of each robot
        with a wheel turning are scaled by ``max(0, 1 + speed_noise * N(0, 1))``, one draw per
        wheel, robots in index order, from the actuation stream. ``heading_noise`` does not
        apply (wheels have no direction to turn)."""
        lv = self.levels
        if not lv.speed_noise > 0:
            return wheels
        moving = np.flatnonzero((wheels[:, 0] != 0) | (wheels[:, 1] != 0))
        if len(moving) == 0:
            return wheels
        draws = self._rng["actuation"].standard_normal((len(moving), 2))
        out = wheels.copy()
        out[moving] *= np.maximum(0.0, 1.0 + lv.speed_noise * draws)
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

    @property
    def loss_needs_distances(self) -> bool:
        """Whether :meth:`lost` needs each message's distance (the logistic model)."""
        return self.levels.logistic_messages

    def lost(self, count: int, distances: np.ndarray | None = None) -> np.ndarray | None:
        """(count,) bool: which of ``count`` heard messages are lost (None: none can be).

        ``distances`` (count,), units: each message's true sender-receiver distance; needed
        (and only read) with the logistic model (:attr:`loss_needs_distances`)."""
        lv = self.levels
        if lv.logistic_messages:
            if distances is None or len(distances) != count:
                raise ValueError("the logistic message model needs each message's distance")
            if count == 0:
                return None
            success = logistic_success(distances, lv.message_range50, lv.message_falloff)
            if lv.message_loss > 0:
                success = success * (1.0 - lv.message_loss)
            return self._rng["messages"].random(count) >= success
        p = lv.message_loss
        if p <= 0 or count == 0:
            return None
        if p >= 1:
            return np.ones(count, dtype=bool)
        return self._rng["messages"].random(count) < p

    def read_floor(self, on_target: np.ndarray, edge_distance: Callable[[], np.ndarray]
                   ) -> np.ndarray:
        """What robots' floor sensors read, given the true ``on_target`` (R,) bool and
        ``edge_distance()`` (R,), units: their distances to the target's edge (asked only when
        the floor misreads). One draw per robot within the band, in the order given."""
        lv = self.levels
        if not lv.floor_misreads or len(on_target) == 0:
            return on_target
        near = np.flatnonzero(edge_distance() < lv.floor_edge_band)
        if len(near) == 0:
            return on_target
        flip = self._rng["floor"].random(len(near)) < lv.floor_edge_misread
        read = on_target.copy()
        read[near[flip]] = ~read[near[flip]]
        return read
