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

The run's robots are one :class:`DashSwarm` (swarm.py): their spacing state in arrays, a chunk
of robots decided in one compiled pass (chunk.py). robot.py's :class:`DashRobot` is the same
controller one robot at a time, its reference.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from controllers.common.push import warm_up as _warm_up_push
from controllers.common.pyhypot import warm_up as _warm_up_hypot
from swarmsim.controller import RobotSetup

from .chunk import warm_up as _warm_up_chunk
from .kernel import warm_up as _warm_up_spacing
from .params import DashDeclarations, DashParams
from .swarm import DashSwarm


class Dash(DashDeclarations):
    """DASH (reconstructed): dispersion whose spacing adapts in real time up to d_cover."""

    @classmethod
    def warm_up(cls) -> None:
        """Compile or load the kernels before a run's clock starts."""
        _warm_up_spacing()
        _warm_up_push()
        _warm_up_hypot()
        _warm_up_chunk()

    @classmethod
    def create_swarm(cls, setups: Sequence[RobotSetup], params: DashParams,
                     rngs: Sequence[np.random.Generator]) -> DashSwarm:
        """The run's robots (row i: robot i); DASH draws no random numbers."""
        return DashSwarm(setups, params)


__all__ = ["Dash", "DashParams"]
