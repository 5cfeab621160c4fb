"""CVT one robot at a time (:class:`CVTRobot`): the per-robot controller the batch one
(controller.py's CVT, swarm.py) was ported from, kept as its reference. It makes the very
runs ``cvt`` makes (tests/controllers/baselines/test_cvt_swarm.py); run it as
``--controller controllers.cvt.robot:CVTRobot``. The algorithm: controller.py's docstring.
"""

from __future__ import annotations

import math

import numpy as np

from controllers.common.localmap import LocalMap, clamp, sq_norms
from controllers.common.mapkernel import warm_up as _warm_up_map
from controllers.common.push import push_away
from controllers.common.push import warm_up as _warm_up_push
from swarmsim.controller import Action, Perception, RobotSetup, make_action

from .kernel import owned
from .kernel import warm_up as _warm_up_cell
from .params import (
    DISC,
    DISC_DEADBAND,
    DISC_STEPS,
    MOVING,
    RESTING,
    SEEKING,
    CVTDeclarations,
    CVTParams,
)


def repulsion(perception: Perception, radius: float, gain: float) -> np.ndarray:
    """Push away from neighbours closer than ``radius`` (grows as they get closer)."""
    return push_away(perception.offsets, perception.distances, radius, gain)


class CVTRobot(CVTDeclarations):
    """Limited-range Lloyd, one robot: move to the centroid of your Voronoi cell in the sensed
    target."""

    @classmethod
    def warm_up(cls) -> None:
        """Compile or load the local map's, the cell's and the push's kernels before a run's
        clock starts."""
        _warm_up_map()
        _warm_up_cell()
        _warm_up_push()

    def __init__(self, setup: RobotSetup, params: CVTParams, rng: np.random.Generator):
        self.id = setup.robot_id
        self.params = params
        self.map = LocalMap(params.cell_radius, params.map_cell)
        self.status = SEEKING
        self.heard = 2 * params.cell_radius  # how far it listened for this tick's perception
        self.extent = params.cell_radius     # radius of the disc its cell is sampled in
        self.reach = 0.0
        # (extent, heard) of the tick before, when it stood still then
        self.still_disc: tuple[float, float] | None = None
        self.disc = DISC

    def message(self, moving: bool) -> tuple:
        return (self.id, self.status, moving)

    def cell(self, perception: Perception) -> np.ndarray:
        """Sample points of this robot's cell: target floor nearer to it than to any neighbour.

        The cell is sampled on a fine grid (``DISC`` points) over a disc of radius R, sized to
        the cell (the previous tick's extent, at most cell_radius and half the range the robot
        listened to), so small cells in a crowd are sampled as finely as big ones; target
        membership comes from the local map. Classification within R is exact: a neighbour
        farther than 2 R cannot own a point within R. When the cell reaches the edge of the
        disc, the next tick uses the full cell_radius.
        """
        full = self.params.cell_radius
        radius = self.disc_radius()
        self.map.sense(perception)
        h = radius / DISC_STEPS
        q = self.disc * radius
        q = q[self.map.lookup(perception, q)]
        if len(q):
            q = q[owned(q, perception.offsets[perception.distances <= 2 * radius])]
        if len(q) == 0:
            self.extent = full
            self.reach = 0.0
            target_near = bool(self.map.lookup(perception, self.disc * full).any())
            self.heard = 2 * full if target_near else max(2 * self.params.d_safe, 1.0)
            return q
        self.reach = math.sqrt(float(sq_norms(q).max()))
        margin = 2 * h + 2 * self.params.v
        self.extent = full if self.reach >= radius - 1.5 * h else min(full, self.reach + margin)
        self.heard = 2 * self.extent
        return q

    def act(self, v: np.ndarray, moving: bool, settled: bool) -> Action:
        """The tick's Action: sleep only when standing still is this robot's fixed point."""
        msg = self.message(moving)
        if settled:
            return make_action((0.0, 0.0), msg, sleep=True, wake_range=self.heard,
                               listen=self.heard)
        return make_action((float(v[0]), float(v[1])), msg, listen=self.heard)

    def disc_radius(self, disc: tuple[float, float] | None = None) -> float:
        """Radius (units) of the disc (extent, heard) a cell is sampled in (default: the
        next cell's)."""
        extent, heard = (self.extent, self.heard) if disc is None else disc
        return min(self.params.cell_radius, heard / 2, extent)

    def settle_disc(self, sampled_with: tuple[float, float]) -> bool:
        """Whether a robot standing still may sleep; it then keeps the disc (extent, heard)
        its cell was sampled in. It may when the disc its next cell would be sampled in is
        within DISC_DEADBAND grid steps of this one, or is the one of the tick before (two
        discs in turn, both answering "stand still"); a larger change keeps it awake.

        Asleep, a robot promises the same answer to the same perception, and a cell sampled
        in another disc can have another centroid: so it keeps the disc it sleeps with.
        (Sleeping at once with the new disc broke that promise; always keeping the old disc
        froze robots on too small a cell, at 77 % coverage on K; waiting for an exact fixed
        point kept ~440 still robots awake a tick, their discs jittering with every
        neighbour's move.)
        """
        was = self.disc_radius(sampled_with)
        if (abs(self.disc_radius() - was) <= DISC_DEADBAND * was / DISC_STEPS
                or (self.extent, self.heard) == self.still_disc):
            self.extent, self.heard = sampled_with
            return True
        self.still_disc = sampled_with
        return False

    def step(self, perception: Perception) -> Action:
        self.map.move(perception.moved)
        sampled_with = (self.extent, self.heard)
        mine = self.cell(perception)
        rest = False
        if len(mine):
            c = mine.mean(axis=0)
            nearest = mine[np.argmin(sq_norms(mine - c))]
            if math.hypot(*(nearest - c)) > 1.5 * self.extent / DISC_STEPS:
                c = nearest  # the centroid fell outside the (non-convex) cell: project it
            v = self.params.gain * c
            rest = (math.hypot(float(c[0]), float(c[1])) < self.params.tolerance * self.reach
                    and perception.on_target)
            self.status = MOVING if perception.on_target else SEEKING
        elif not perception.on_target and perception.beacon is not None:
            v = perception.beacon * self.params.v
            self.status = SEEKING
        else:
            v = np.zeros(2)
            rest = True
        if rest:
            v = np.zeros(2)
        push = repulsion(perception, self.params.d_safe, self.params.repulsion_gain)
        v = clamp(v + push, self.params.v)
        moving = bool(v.any())
        settled = False
        if not moving:
            self.status = RESTING if perception.on_target else SEEKING
            settled = self.settle_disc(sampled_with)
        else:
            self.still_disc = None
        return self.act(v, moving, settled)


__all__ = ["CVTRobot"]
