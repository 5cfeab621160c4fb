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
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from controllers.common.localmap import MIN_MAP_CELL, LocalMap, clamp, sq_norms
from controllers.common.mapkernel import warm_up as _warm_up_map
from controllers.common.push import push_away
from controllers.common.push import warm_up as _warm_up_push
from swarmsim.controller import Action, Perception, RobotSetup, make_action, require_positive

from .kernel import owned
from .kernel import warm_up as _warm_up_cell

SEEKING, MOVING, RESTING = 0, 1, 2
STATUSES = ("Seeking", "Moving", "Resting")
MIN_PROBE_RANGE = 6.0
DISC_STEPS = 7  # the cell is sampled on a grid of radius / DISC_STEPS spacing
DISC_DEADBAND = 1.0  # a still robot keeps its disc unless the next differs by more grid steps
_g = np.arange(-DISC_STEPS, DISC_STEPS + 1) / DISC_STEPS
DISC = np.array([(x, y) for x in _g for y in _g if x * x + y * y <= 1.0 + 1e-9])


def repulsion(perception: Perception, radius: float, gain: float) -> np.ndarray:
    """Push away from neighbours closer than ``radius`` (grows as they get closer)."""
    return push_away(perception.offsets, perception.distances, radius, gain)


@dataclass(frozen=True)
class CVTParams:
    """Parameters of the CVT controller (lengths in units, speeds in units per tick).

    Attributes:
        d_safe: neighbours closer than this repel (paper Table 2: 1).
        cell_radius: a robot's Voronoi cell is limited to this radius; it senses the floor and
            its neighbours that far (at most the class's min_probe_range, 6).
        map_cell: spacing of the lattice of floor points a robot senses (at least 0.1).
        v: top speed (paper: 0.1).
        gain: speed per unit of distance to the centroid (1 = pure Lloyd, capped at v).
        repulsion_gain: d_safe repulsion, speed per unit of missing distance.
        tolerance: a robot rests while its centroid is closer than tolerance times the reach
            of its cell (its farthest point). A stop rule, not part of Lloyd's: at 0.04 robots
            in a crowd rested while the crowd's density still fell off toward free floor
            (each cell's centroid lies only a little way toward it), and CVT on K stopped at
            78 % coverage; at 0.01 the crowd spreads out (99 % by tick ~2,500).
    """

    d_safe: float = 1.0
    cell_radius: float = 6.0
    map_cell: float = 1.0
    v: float = 0.1
    gain: float = 1.0
    repulsion_gain: float = 0.05
    tolerance: float = 0.01

    def __post_init__(self) -> None:
        require_positive(self, "d_safe", "cell_radius", "map_cell", "v", "gain", "tolerance")
        if self.repulsion_gain < 0:
            raise ValueError(f"repulsion_gain must be >= 0, got {self.repulsion_gain!r}")
        if self.cell_radius > MIN_PROBE_RANGE:
            raise ValueError(f"cell_radius ({self.cell_radius}) must not exceed the probe range "
                             f"the controller requests ({MIN_PROBE_RANGE})")
        if not MIN_MAP_CELL <= self.map_cell <= self.cell_radius / 2:
            raise ValueError(f"map_cell ({self.map_cell}) must be at least {MIN_MAP_CELL} (the "
                             "floor points a robot senses) and at most cell_radius / 2")
        if self.tolerance >= 1:
            raise ValueError(f"tolerance must be < 1, got {self.tolerance!r}")


class CVT:
    """Limited-range Lloyd: move to the centroid of your Voronoi cell in the sensed target."""

    name = "cvt"
    Params = CVTParams
    STATUSES = STATUSES
    SETTLED_STATUSES = ("Resting",)  # done, standing still (collision instruments)
    MESSAGE_FIELDS: list = []  # noqa: RUF012 (the engine reads a plain list)
    requires_beacon = True
    min_probe_range = MIN_PROBE_RANGE

    @classmethod
    def sensing_range(cls, params: CVTParams) -> float:
        """Neighbours within 2 * cell_radius can own points of the cell."""
        return 2 * params.cell_radius

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


__all__ = ["CVT", "CVTParams"]
