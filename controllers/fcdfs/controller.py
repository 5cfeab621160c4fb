"""FCDFS: Find-Corner Depth-First Search uniform dispersal (Amir & Bruckstein), the GGC
paper's "angle-first" comparison algorithm [43], on a square lattice in continuous space.

Source: M. Amir and A. M. Bruckstein, "Minimizing Travel in the Uniform Dispersal Problem for
Robotic Sensors", AAMAS 2019 (arXiv:1903.03259), extended as "Time, Travel, and Energy in the
Uniform Dispersion Problem" (arXiv:2404.19564), where it is named "Find-Corner Depth-First
Search" (FCDFS). (The GGC paper's ref. [43] text was not available; "FCDFS" and "angle-first",
i.e. find-corner-first, match this algorithm, and the GGC paper's description fits it: robots
enter through a door one after another, in a line, and settle in a regular arrangement with
intervals, so coverage cannot reach 1.) The rules were read from the arXiv abstracts and a
public summary of the 2024 paper (Kristofy/uniform-dispersion-problem, docs/riport.md).

FCDFS works on a grid: robots enter at a door cell, at most one per cell, and each robot,
every step, takes the first rule that applies:

1. if the cell in its primary direction P is free, move there;
2. else if the cell in its secondary direction S (P turned 90 degrees) is free, move there;
3. else if at least 3 of its 4 neighbouring cells are blocked (wall or settled robot), settle
   (a dead end; we settle only if the robot came in through the free side, else it turns
   there: this matters at the entry cell, which a robot enters from the door robot's cell);
4. else (exactly P and S blocked) if the diagonal cell opposite the blocked corner is free, or
   it stood there two steps ago, it is in a corner: settle;
5. else it is in a corridor bend: turn P to the free direction it did not come from, move.

Settling only in corners keeps the free region simply connected, so every robot finds a
shortest path and the area fills completely. In the asynchronous variant a robot waits while
an active robot occupies the cell it wants.

Our continuous-space version (the paper's grid is abstract; every choice here is ours):

* The lattice: square, spacing ``cell`` (default d_cover = 6, so the settled arrangement has
  the "intervals" the GGC paper mentions: a square lattice needs spacing <= 4 sqrt(2) = 5.66
  for gap-free coverage at r = 4), axis-aligned (robots share a compass), origin at the door.
  A cell is a wall when the floor probe says its centre is not target floor.
* The door: the swarm starts as a hexagonal formation (like GGC); the leader leads it toward
  the beacon (travel command copied from the gradient parent, GGC's way) and halts as soon as
  it hears a robot report target floor under it; it names that robot (the nearest such) the
  door. The door robot steps ``door_depth`` into the target along P (so that entering robots
  can pass it) and stays there as cell (0, 0); P is the lattice axis nearest the beacon's
  bearing. Everything is relayed through the formation with the halt command. The door's
  cell is a wall for FCDFS; the entry cell (FCDFS's door cell, filled last) is the first of
  the door's neighbours in the order P, S, -S, -P that is target floor.
* The line: the other robots queue toward a point 0.6 door_radius behind the door (away
  from the lattice; straight at it when they sense the door, else toward their neighbour with the
  fewest hops to it), keeping ``queue_gap`` from the robot ahead, and step away from an entering robot closer than avoid_range + 0.5. The queued
  robot nearest the door steps onto the entry cell when no entered robot is still moving
  within ``entry_clearance`` of the door and the entry cell is neither settled nor taken.
* Moving robots go from cell centre to cell centre (dead reckoning from the door), side-step
  robots in their way, and broadcast the cell they are heading to; settled robots broadcast
  their cell. A robot that has waited ``patience`` ticks settles where it is (deadlock guard).

Sensing: relative positions (bearing and distance) of neighbours within 2 * cell, their
broadcast status, lattice cell, hop count and travel command; the floor sensor; a floor probe
reaching the neighbouring lattice cells (``min_probe_range`` 9: one cell diagonally, where
GGC's robots probe 2 units); odometry; and (leader only) the beacon's bearing. Moving robots
need metric relative positions (to keep to the lattice), unlike GGC's hop counts.

The run's robots are one :class:`FCDFSSwarm` (swarm.py): their state in arrays, a chunk of
robots decided in compiled calls (chunk.py). robot.py's :class:`FCDFSRobot` is the same
controller one robot at a time, its reference.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from controllers.common.pyhypot import warm_up as _warm_up_hypot
from swarmsim.controller import RobotSetup

from .params import FCDFSDeclarations, FCDFSParams
from .swarm import FCDFSSwarm
from .swarm import warm_up as _warm_up_chunk


class FCDFS(FCDFSDeclarations):
    """Find-Corner DFS: enter through a door in a line, settle in lattice corners.

    The run's robots are one :class:`~controllers.fcdfs.swarm.FCDFSSwarm` (their state in
    arrays, decided in compiled chunks); :class:`~controllers.fcdfs.robot.FCDFSRobot` is the
    same controller one robot at a time, the reference its runs are held to, to the bit.
    """

    @classmethod
    def warm_up(cls) -> None:
        """Compile or load hypot's and the chunk's kernels before a run's clock starts."""
        _warm_up_hypot()
        _warm_up_chunk()

    @classmethod
    def create_swarm(cls, setups: Sequence[RobotSetup], params: FCDFSParams,
                     rngs: Sequence[np.random.Generator]) -> FCDFSSwarm:
        """The run's robots (row i: robot i); FCDFS draws no random numbers."""
        return FCDFSSwarm(setups, params)


__all__ = ["FCDFS", "FCDFSParams"]
