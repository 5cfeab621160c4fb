"""Potential-field dispersion: the classic deployment baseline (Howard, Mataric & Sukhatme 2002).

Every robot is repelled by neighbours closer than ``d_cover`` (force growing as they get closer)
and attracted toward the beacon while it is off the target; once on the target it stays on it:
a step whose probe says it would leave the target is cancelled. Robots with no neighbour within
range and nothing to do sleep.

Sensing: relative positions of neighbours within d_cover, the floor sensor, a floor probe
``probe_distance`` ahead, and the beacon's bearing. It broadcasts nothing of its own.

The run's robots are one :class:`DispersionSwarm` (swarm.py), a chunk of robots decided in one
compiled pass (chunk.py). robot.py's :class:`DispersionRobot` is the same controller one robot
at a time, its reference.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from swarmsim.controller import RobotSetup

from .params import DispersionDeclarations, DispersionParams
from .swarm import DispersionSwarm


class Dispersion(DispersionDeclarations):
    """Repel neighbours within d_cover; head for the beacon until on the target; stay on it."""

    @classmethod
    def create_swarm(cls, setups: Sequence[RobotSetup], params: DispersionParams,
                     rngs: Sequence[np.random.Generator]) -> DispersionSwarm:
        """The run's robots (row i: robot i); dispersion draws no random numbers."""
        return DispersionSwarm(setups, params)


__all__ = ["Dispersion", "DispersionParams"]
