"""The paper's coverage raster, and coverage kept up to date tick by tick.

Coverage P(t): the target's bounding box is rasterised into a ``cols x rows`` pixel grid
(100 x 100 by default); a pixel belongs to the target when its centre lies on free target
floor (inside the target's outline, outside its holes and outside every obstacle), and it is
covered when its centre lies within ``r`` (default 4) of some robot.
P = covered target pixels / target pixels. Completion tick t_dpl = first tick with
1 - P <= eps0.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import shapely
from scipy.spatial import cKDTree
from shapely.geometry import Polygon

from swarmsim.errors import ConfigError
from swarmsim.kernels.carrays import c_array
from swarmsim.metrics.stamps import new_stamps, restamp


@dataclass(frozen=True)
class CoverageGrid:
    """The paper's coverage raster over the target's bounding box.

    Geometry: ``cols x rows`` cells stretch over the bounding box of the target's outline
    (so a cell is ``dx = width / cols`` by ``dy = height / rows`` units: square only when the
    box is). A cell counts (is a target pixel) when its centre lies on free target floor:
    inside the outline, outside the holes and outside every obstacle. A target pixel is
    covered when a robot's centre is within ``radius`` (r) of the cell's centre (distance
    <= r). Coverage P = covered target pixels / target pixels.

    Attributes:
        x0, y0: lower-left corner of the bounding box, units.
        dx, dy: pixel size, units.
        inside: (rows, cols) bool, pixel centre on free target floor; row index grows with y.
        centres: (M, 2) centres of the target pixels (the True cells of ``inside``, row-major).
        radius: coverage radius r, units.
    """

    x0: float
    y0: float
    dx: float
    dy: float
    inside: np.ndarray
    centres: np.ndarray
    radius: float

    @classmethod
    def for_target(cls, target: Polygon, radius: float = 4.0, cols: int = 100,
                   rows: int = 100, obstacles: Sequence[Polygon] = ()) -> CoverageGrid:
        """The grid over ``target``'s bounding box; cells whose centre is inside one of
        ``obstacles`` do not count (see the class docstring).

        Raises ConfigError when no cell counts (a target thinner than a cell everywhere)."""
        if not (math.isfinite(radius) and radius > 0):
            raise ConfigError(f"must be positive and finite, got {radius!r}",
                              key="coverage_radius")
        xmin, ymin, xmax, ymax = target.bounds
        dx, dy = (xmax - xmin) / cols, (ymax - ymin) / rows
        xs = xmin + (np.arange(cols) + 0.5) * dx
        ys = ymin + (np.arange(rows) + 0.5) * dy
        gx, gy = np.meshgrid(xs, ys)
        inside = shapely.contains_xy(target, gx, gy)
        for obstacle in obstacles:
            inside &= ~shapely.contains_xy(obstacle, gx, gy)
        if not inside.any():
            raise ConfigError(f"no cell of the {cols} x {rows} coverage grid has its centre on "
                              "free target floor: the target is too thin for the grid (more "
                              "cells: grid_size) or covered by obstacles", key="grid_size")
        centres = np.column_stack([gx[inside], gy[inside]])
        return cls(xmin, ymin, dx, dy, inside, centres, float(radius))

    @property
    def shape(self) -> tuple[int, int]:
        return self.inside.shape

    @property
    def n_target_pixels(self) -> int:
        return int(self.centres.shape[0])

    def covered_pixels(self, positions: np.ndarray) -> np.ndarray:
        """(M,) bool: which target pixels (in ``centres`` order) are within r of a robot."""
        if len(positions) == 0:
            return np.zeros(self.n_target_pixels, dtype=bool)
        tree = cKDTree(positions)
        # the tree keeps distances strictly below its bound: a hair more keeps those equal to
        # r, as IncrementalCoverage does (a centre exactly r away is covered)
        bound = np.nextafter(self.radius, np.inf)
        dist, _ = tree.query(self.centres, k=1, distance_upper_bound=bound)
        return dist <= self.radius

    def coverage(self, positions: np.ndarray) -> float:
        """Coverage fraction P in [0, 1] for robots at ``positions`` (N, 2)."""
        return float(self.covered_pixels(positions).mean()) if self.n_target_pixels else 0.0

    def covered_grid(self, positions: np.ndarray) -> np.ndarray:
        """(rows, cols) bool image of covered target pixels, for drawing."""
        grid = np.zeros(self.shape, dtype=bool)
        grid[self.inside] = self.covered_pixels(positions)
        return grid

    def arrays(self, positions: np.ndarray) -> dict[str, np.ndarray]:
        """The raster for robots at ``positions``, as coverage.npz stores it.

        ``covered`` and ``target`` are (rows, cols) bool (row index grows with y); cell (i, j)
        has its centre at (x0 + (j + 0.5) dx, y0 + (i + 0.5) dy). Coverage P is
        ``covered.sum() / target.sum()``. ``x0, y0, dx, dy, r`` are float scalars, units.
        """
        return {"covered": self.covered_grid(positions), "target": self.inside.copy(),
                "x0": np.float64(self.x0), "y0": np.float64(self.y0),
                "dx": np.float64(self.dx), "dy": np.float64(self.dy),
                "r": np.float64(self.radius)}


class IncrementalCoverage:
    """Coverage kept up to date by re-stamping only the robots that moved.

    Each robot stamps the pixels whose centres lie within r of it into a per-pixel count; a
    target pixel is covered while its count is positive. Exactly the same rule as
    :meth:`CoverageGrid.coverage`, at a cost that follows the moving robots, not all robots.
    """

    def __init__(self, grid: CoverageGrid, positions: np.ndarray):
        self.grid = grid
        self.rows, self.cols = grid.shape
        self._half_i = _stencil_half(grid.radius, grid.dy)  # the stencil round a robot
        self._half_j = _stencil_half(grid.radius, grid.dx)
        # r^2 as before; a radius whose square overflows (> 1e154 units) covers everything
        self._r2 = grid.radius**2 if grid.radius < 1e150 else math.inf
        self._inside = c_array(grid.inside.ravel(), bool, writeable=True)  # one signature
        self._count = np.zeros(self.rows * self.cols, dtype=np.int64)
        self._covered = 0  # target pixels with a positive count
        self._positions = np.full(np.shape(positions), np.nan)  # stamped nowhere yet
        self._spans, self._runs = new_stamps(len(positions), self._half_i, self.rows)
        self.update(positions)

    def update(self, positions: np.ndarray) -> float:
        """Re-stamp robots whose position changed; return the coverage fraction P."""
        g = self.grid
        self._covered += restamp(self._count, self._inside, self._positions,
                                 c_array(positions, np.float64), self._spans, self._runs,
                                 g.x0, g.y0, g.dx, g.dy, self._r2, self._half_i,
                                 self._half_j, self.rows, self.cols)
        pixels = self.grid.n_target_pixels
        return float(self._covered / pixels) if pixels else 0.0


STENCIL_CAP = 2**31
"""Largest half-size of a robot's coverage stencil, pixels: a robot is never that far from
the grid (robots stay inside the arena, a few grid widths across), so a wider radius covers
the same pixels; the cap keeps a huge (finite) coverage_radius within compiled integers."""


def _stencil_half(radius: float, pixel: float) -> int:
    """Half-size (pixels) of the stencil of pixels within ``radius`` of a robot's pixel."""
    return int(min(np.ceil(radius / pixel), STENCIL_CAP)) + 1


__all__ = ["STENCIL_CAP", "CoverageGrid", "IncrementalCoverage"]
