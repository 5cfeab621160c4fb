"""CVT's declarations: its parameters (:class:`CVTParams`), statuses, sampling disc and what
the engine reads of the class (:class:`CVTDeclarations`), shared by the batch controller
(controller.py's CVT) and the per-robot one (robot.py's CVTRobot)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from controllers.common.localmap import MIN_MAP_CELL
from swarmsim.controller import require_positive

SEEKING, MOVING, RESTING = 0, 1, 2
STATUSES = ("Seeking", "Moving", "Resting")
MIN_PROBE_RANGE = 6.0
DISC_STEPS = 7  # the cell is sampled on a grid of radius / DISC_STEPS spacing
DISC_DEADBAND = 1.0  # a still robot keeps its disc unless the next differs by more grid steps
_g = np.arange(-DISC_STEPS, DISC_STEPS + 1) / DISC_STEPS
DISC = np.array([(x, y) for x in _g for y in _g if x * x + y * y <= 1.0 + 1e-9])
"""(D, 2) the sample points of the unit disc, on a grid of 1 / DISC_STEPS (a cell of radius R
is sampled at R * DISC)."""


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


class CVTDeclarations:
    """What the engine reads of a CVT controller class (swarmsim.controller.ControllerClass)."""

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
