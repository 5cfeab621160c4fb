"""Shared by edge-following controllers (GGC, Kilobot): noticing a full orbit, and sampling
progress (the paper's Equation 3)."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from swarmsim.controller import NO_SENDER, Perception

if TYPE_CHECKING:
    import numpy as np


def turn_between(before: float, after: float) -> float:
    """Signed turn (radians, in [-pi, pi)) from bearing ``before`` to bearing ``after``."""
    return (after - before + math.pi) % (2 * math.pi) - math.pi


class CirclingWatch:
    """Mixin: counts how far a robot has gone round the neighbour it follows.

    Needs ``circling_id``, ``circled`` (radians) and ``last_bearing`` attributes (set them to
    NO_SENDER, 0.0 and None in ``__init__``); setting ``circled = 0.0`` restarts the count.
    """

    circling_id: int
    circled: float
    last_bearing: float | None

    def circling(self, perception: Perception, nearest: int) -> bool:
        """True once the robot has gone all the way round the same neighbour."""
        sender = int(perception.messages["id"][nearest])
        offset = perception.offsets[nearest]
        bearing = math.atan2(-float(offset[1]), -float(offset[0]))
        if sender != self.circling_id or sender == NO_SENDER or self.last_bearing is None:
            self.circling_id, self.circled, self.last_bearing = sender, 0.0, bearing
            return False
        self.circled += turn_between(self.last_bearing, bearing)
        self.last_bearing = bearing
        return abs(self.circled) > 2 * math.pi


class ProgressWatch:
    """Mixin: samples a robot's displacement every ``params.T_r`` ticks (Equation 3).

    Needs ``params.T_r``, ``odometer`` (a 2-vector the robot adds its motion to each tick) and
    ``progress_tick`` (the tick of the last sample).
    """

    odometer: np.ndarray
    progress_tick: int

    def sample_progress(self, perception: Perception) -> float | None:
        """Displacement since the last sample (units) once T_r ticks have passed, else None."""
        if perception.tick - self.progress_tick < self.params.T_r:
            return None
        moved = math.hypot(*self.odometer)
        self.odometer[:] = 0.0
        self.progress_tick = perception.tick
        return moved
