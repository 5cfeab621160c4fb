"""Kilobot programmable self-assembly (Rubenstein, Cornejo & Nagpal, Science 345:795, 2014),
the GGC paper's comparison algorithm [41], in the GGC paper's units.

Rules (reconstructed from the supplementary pseudocode as mirrored by public
implementations; /work/shared/research/algorithms.md section 2):

* Start: the swarm stands as one hexagonal formation (spacing ``d_min``) around the seed
  (the RobotSetup leader, gradient 0; no grouping: every robot follows the one seed). The
  Kilobot seeds stand next to the shape, so the seed first leads the formation there, as GGC
  does: it heads for the beacon and broadcasts a travel command; every robot copies its
  gradient parent's command one tick later (the formation moves rigidly) and the seed halts
  when its floor sensor finds the target. It then stays, joined.
* Gradient: a waiting robot's gradient is 1 + the smallest gradient among stationary
  neighbours within 1.5 * d_min (hop count from the seed through the formation); a moving
  robot's is 1 + the smallest among stationary neighbours within ``gradient_reach * d_cover``
  (Kilobot's GRADIENT_DIST / DESIRED_DIST ~ 1.3).
* Start moving (WAIT -> MOVE): only when no moving robot is within ``quiet_range``, and no
  waiting neighbour within ``start_range`` has a larger gradient, or the same gradient and a
  larger id (so the outermost robots peel off one per neighbourhood).
* Edge-following: keep ``d_cover`` from the nearest stationary robot, rotating around it
  (``orbit`` -1: clockwise, as the Kilobots do); yield (wait) while a moving robot with a
  larger id is within ``yield_distance`` ahead.
* Join (stop for good), only on the target and at least d_cover - arrive_tolerance from the
  nearest stationary robot: when the floor probe ``probe_distance`` ahead leaves the target
  ("about to leave the shape"), or when the nearest stationary robot has joined with a
  gradient >= this robot's (its layer is full). A robot outside the target never joins.
* Our additions for robustness (documented; the Kilobot paper has no such rule): a robot that
  has circled the same robot all the way round, or has moved less than ``theta`` in ``T_r``
  ticks without yielding (trapped in a pocket narrower than d_cover), joins if it is on the
  target and otherwise heads for the beacon for T_r ticks; trapped a third time in a row off
  the target, it stops there for good (so that it cannot keep every waiting robot near it
  waiting forever); a moving robot that senses no stationary robot heads for the beacon.

Kilobots localize by trilateration and test their estimated position against a stored shape
bitmap; here the floor sensor and a 1-unit probe play that role, like GGC's robots.

Sensing: distances and bearings of neighbours within max(gradient_reach * d_cover,
quiet_range), their broadcast gradient, id, status and travel command, the floor sensor, a
floor probe 1 unit ahead, and (seed only) the beacon's bearing: the same class of sensing as
GGC (hop counts and distances); no map of the target.

The run's robots are one :class:`KilobotSwarm` (swarm.py): their state in arrays, a chunk of
robots decided in compiled calls (chunk.py). robot.py's :class:`KilobotRobot` is the same
controller one robot at a time, its reference.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from controllers.common.pyhypot import warm_up as _warm_up_hypot
from swarmsim.controller import RobotSetup

from .params import KilobotDeclarations, KilobotParams
from .swarm import KilobotSwarm
from .swarm import warm_up as _warm_up_chunk


class Kilobot(KilobotDeclarations):
    """Kilobot self-assembly: peel off the formation, follow its edge, join inside the shape.

    The run's robots are one :class:`~controllers.kilobot.swarm.KilobotSwarm` (their state in
    arrays, decided in compiled chunks); :class:`~controllers.kilobot.robot.KilobotRobot` is
    the same controller one robot at a time, the reference its runs are held to, to the bit.
    """

    @classmethod
    def warm_up(cls) -> None:
        """Compile or load hypot's and the chunk's kernels before a run's clock starts."""
        _warm_up_hypot()
        _warm_up_chunk()

    @classmethod
    def create_swarm(cls, setups: Sequence[RobotSetup], params: KilobotParams,
                     rngs: Sequence[np.random.Generator]) -> KilobotSwarm:
        """The run's robots (row i: robot i); Kilobot draws no random numbers."""
        return KilobotSwarm(setups, params)


__all__ = ["Kilobot", "KilobotParams"]
