"""A robot's local map of the floor (CVT and mean-shift): a remembered square lattice of
floor-probe answers in the robot's odometry frame (:class:`LocalMap`), and the small vector
helpers both controllers use."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from swarmsim.controller import Perception

from .mapkernel import lattice_values, window_within

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


def sq_norms(v: np.ndarray) -> np.ndarray:
    """Squared length (units^2) of each row of ``v`` (k, 2): the same sums, to the bit, as
    ``(v * v).sum(axis=1)``, without the slow reduction over an axis of length 2."""
    x, y = v[:, 0], v[:, 1]
    return x * x + y * y


def clamp(v: np.ndarray, limit: float) -> np.ndarray:
    """``v`` shortened to at most ``limit``."""
    n = math.hypot(float(v[0]), float(v[1]))
    return v * (limit / n) if n > limit else v


__all__ = ["MIN_MAP_CELL", "LocalMap", "clamp", "probe_all", "sq_norms"]
