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
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from swarmsim.controller import Action, Perception, RobotSetup, make_action, require_positive

from .cellkernel import owned
from .cellkernel import warm_up as _warm_up_cell
from .mapkernel import lattice_values, window_within
from .mapkernel import warm_up as _warm_up_map
from .pushkernel import push_away
from .pushkernel import warm_up as _warm_up_push

SEEKING, MOVING, RESTING = 0, 1, 2
STATUSES = ("Seeking", "Moving", "Resting")
MIN_PROBE_RANGE = 6.0
DISC_STEPS = 7  # the cell is sampled on a grid of radius / DISC_STEPS spacing
DISC_DEADBAND = 1.0  # a still robot keeps its disc unless the next differs by more grid steps
_g = np.arange(-DISC_STEPS, DISC_STEPS + 1) / DISC_STEPS
DISC = np.array([(x, y) for x in _g for y in _g if x * x + y * y <= 1.0 + 1e-9])


MIN_MAP_CELL = 0.1
"""Smallest lattice spacing of a LocalMap, units: a robot keeps ~(2 radius / cell + 2 MARGIN)^2
points and probes those within its radius (11,000 at radius 6); a spacing of 0.001 asked for
a hundred million per robot."""


class LocalMap:
    """A robot's memory of the floor on a square lattice, in its own odometry frame.

    The robot integrates its own displacement (``Perception.moved``); lattice points are fixed
    in that frame, so each is probed once (while it is within ``radius``) and remembered. Only a
    window of lattice points around the robot is kept, so memory stays small.

    Args:
        radius: points within this distance of the robot are sensed, units (must not exceed
            the engine's probe range).
        cell: lattice spacing, units.
    """

    MARGIN = 8  # lattice cells kept beyond the sensing radius before the window is moved

    def __init__(self, radius: float, cell: float):
        self.radius = float(radius)
        self.cell = float(cell)
        self.odo = np.zeros(2)
        reach = math.ceil(self.radius / self.cell) + 1
        ii, jj = np.meshgrid(np.arange(-reach, reach + 1), np.arange(-reach, reach + 1),
                             indexing="ij")
        self._stencil = np.column_stack([ii.ravel(), jj.ravel()])
        self._reach = reach
        self._size = 2 * (reach + self.MARGIN) + 1
        self._grid = np.full((self._size, self._size), -1, dtype=np.int8)
        self._origin = np.array([-(reach + self.MARGIN)] * 2)
        self._base: tuple[int, int] | None = None  # the lattice cell the window is for
        self._points = self._local = self._values = np.zeros((0, 2))

    def move(self, moved: np.ndarray) -> None:
        """Dead reckoning: add the robot's own displacement."""
        self.odo = self.odo + moved

    def _lattice_cell(self) -> tuple[int, int]:
        """The lattice cell the robot is in: floor(odo / cell)."""
        return math.floor(self.odo[0] / self.cell), math.floor(self.odo[1] / self.cell)

    def _recentre(self, base: tuple[int, int]) -> None:
        """Move the window of remembered points so the stencil round ``base`` fits in it."""
        reach, (o0, o1) = self._reach, self._origin.tolist()
        if (base[0] - reach >= o0 and base[1] - reach >= o1
                and base[0] + reach < o0 + self._size and base[1] + reach < o1 + self._size):
            return
        new_origin = np.array(base, dtype=np.int64) - (self._reach + self.MARGIN)
        grid = np.full_like(self._grid, -1)
        shift = new_origin - self._origin
        src_lo = np.maximum(shift, 0)
        src_hi = np.minimum(shift + self._size, self._size)
        if (src_hi > src_lo).all():
            dst_lo = src_lo - shift
            dst_hi = src_hi - shift
            grid[dst_lo[0]:dst_hi[0], dst_lo[1]:dst_hi[1]] = \
                self._grid[src_lo[0]:src_hi[0], src_lo[1]:src_hi[1]]
        self._grid = grid
        self._origin = new_origin

    def sense(self, perception: Perception, radius: float | None = None
              ) -> tuple[np.ndarray, np.ndarray]:
        """Lattice points within ``radius`` (default: the map's radius) of the robot.

        Returns their offsets from the robot (k, 2) and whether each is target floor (k,);
        points not yet known are probed now.
        """
        radius = self.radius if radius is None else min(float(radius), self.radius)
        cell = self._lattice_cell()
        if self._base != cell:  # a new lattice cell: the window of points around it
            self._base = cell
            self._recentre(cell)
            idx = self._stencil + np.array(cell, dtype=np.int64)
            self._points = idx * self.cell
            self._local = idx - self._origin
            self._values = self._grid[self._local[:, 0], self._local[:, 1]]
        values = self._values
        offsets, known, unknown, unknown_at = window_within(self._points, self.odo,
                                                            radius * radius, values)
        if len(unknown):
            known[unknown_at] = values[unknown] = probe_all(perception.probe, offsets[unknown_at])
            loc = self._local[unknown]
            self._grid[loc[:, 0], loc[:, 1]] = values[unknown]
        return offsets, known == 1


    def lookup(self, perception: Perception, offsets: np.ndarray) -> np.ndarray:
        """Target floor at arbitrary offsets, read from the nearest lattice point.

        Lattice points not yet known are probed (only those within ``radius``); farther ones
        count as not target.
        """
        self._recentre(self._lattice_cell())
        values, local, unknown, points = lattice_values(self.odo, offsets, self.cell,
                                                        self._origin, self._grid,
                                                        self.radius * self.radius)
        if len(unknown):
            values[unknown] = probe_all(perception.probe, points)
            self._grid[local[unknown, 0], local[unknown, 1]] = values[unknown]
            self._base = None  # cached window values are stale
        return values == 1


def probe_all(probe: Callable[[np.ndarray], bool], offsets: np.ndarray) -> np.ndarray:
    """(k,) bool: the floor probe at each of ``offsets`` (k, 2), units; in one query where the
    probe can (the engine's ``FloorProbe.many``), else one by one."""
    many = getattr(probe, "many", None)
    if many is not None:
        return many(offsets)
    return np.array([bool(probe(offset)) for offset in offsets], dtype=bool)


def repulsion(perception: Perception, radius: float, gain: float) -> np.ndarray:
    """Push away from neighbours closer than ``radius`` (grows as they get closer)."""
    return push_away(perception.offsets, perception.distances, radius, gain)


def sq_norms(v: np.ndarray) -> np.ndarray:
    """Squared length (units^2) of each row of ``v`` (k, 2): the same sums, to the bit, as
    ``(v * v).sum(axis=1)``, without the slow reduction over an axis of length 2."""
    x, y = v[:, 0], v[:, 1]
    return x * x + y * y


def clamp(v: np.ndarray, limit: float) -> np.ndarray:
    """``v`` shortened to at most ``limit``."""
    n = math.hypot(float(v[0]), float(v[1]))
    return v * (limit / n) if n > limit else v


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


__all__ = ["CVT", "CVTParams", "LocalMap"]
