"""CVT: limited-range Lloyd (centroidal Voronoi) coverage, the classic deployment baseline.

Cortes, Martinez, Karatas & Bullo, "Coverage control for mobile sensing networks" (IEEE T-RA
2004) and Cortes, Martinez & Bullo, "Spatially-distributed coverage optimization and control
with limited-range interactions" (ESAIM COCV 2005); the GGC paper's ref. [37]/[38] family
(Section 1, Table 3). Non-convex targets are handled as in Breitenmoser et al. (ICRA 2010):
each robot's cell is restricted to the target points it has sensed, and a centroid that falls
off the target is projected onto the nearest point of the cell.

Every tick, robot i:

* senses the floor on a square lattice of points (spacing ``map_cell``) within ``cell_radius``
  of itself (its local map, kept in its own odometry frame so each point is probed once);
* samples its Voronoi cell restricted to the disc of radius ``cell_radius`` and to the target
  (the sensed floor): points nearer to it than to any sensed neighbour, on a grid scaled to
  the cell's size (so a small cell in a crowd is resolved as well as a big one);
* moves toward the centroid of that cell (``gain`` per tick, capped at v), plus a short-range
  repulsion from neighbours closer than ``d_safe``;
* with no target point in its cell and off the target, heads for the beacon (the way in);
* rests (and sleeps) while the centroid is within ``tolerance`` times its cell's reach.

Sensing: relative positions (bearing and distance) of every neighbour within
2 * cell_radius, a local map of the target floor within cell_radius (``min_probe_range``: the
engine must let the floor probe reach that far; 6 units by default, where GGC's robots only
sense the floor under themselves and 2 units ahead), odometry, and the beacon's bearing. No
messages are needed. That is far more than GGC assumes (hop counts and distances only), and the
per-tick computation (a Voronoi cell over ~100 map points) is much larger, as the GGC paper's
Table 3 says.

The run's robots are one :class:`CVTSwarm` (swarm.py): their state in arrays, their local maps
in controllers/common/mapbatch.py, a chunk of robots decided in one compiled call (chunk.py).
robot.py's :class:`CVTRobot` is the same controller one robot at a time, its reference.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from controllers.common.mapbatch import warm_up as _warm_up_map
from controllers.common.push import warm_up as _warm_up_push
from controllers.common.pyhypot import warm_up as _warm_up_hypot
from swarmsim.controller import RobotSetup

from .params import CVTDeclarations, CVTParams
from .swarm import CVTSwarm


class CVT(CVTDeclarations):
    """Limited-range Lloyd: move to the centroid of your Voronoi cell in the sensed target."""

    @classmethod
    def warm_up(cls) -> None:
        """Compile or load the local maps', the push's and hypot's kernels before a run's
        clock starts (the chunk kernel: CVTSwarm.warm_up)."""
        _warm_up_map()
        _warm_up_push()
        _warm_up_hypot()

    @classmethod
    def create_swarm(cls, setups: Sequence[RobotSetup], params: CVTParams,
                     rngs: Sequence[np.random.Generator]) -> CVTSwarm:
        """The run's robots (row i: robot i)."""
        return CVTSwarm(setups, params, rngs)


__all__ = ["CVT", "CVTParams"]
