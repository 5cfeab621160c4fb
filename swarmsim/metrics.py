"""Run metrics, exactly as the paper defines them (pure numpy; no physics).

Coverage P(t): the target's bounding box is rasterised into a ``cols x rows`` pixel grid
(100 x 100 by default); a pixel belongs to the target when its centre lies on free target
floor (inside the target's outline, outside its holes and outside every obstacle), and it is
covered when its centre lies within ``r`` (default 4) of some robot.
P = covered target pixels / target pixels. Completion tick t_dpl = first tick with
1 - P <= eps0.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import shapely
from scipy.spatial import cKDTree
from shapely.geometry import Polygon

from swarmsim.carrays import c_array
from swarmsim.errors import ConfigError
from swarmsim.stamps import restamp
from swarmsim.tallies import count_above, enter_settled, step_lengths, watch_settled

MOVING_FRACTION = 0.01
"""A robot counts as moving in a tick (time series column ``moving``) when it moved more
than this fraction of the top speed v_max during that tick."""
NOT_YET = -1
"""RobotTracks.settle_tick of a robot that never entered a settled status."""


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
        self.update(positions)

    def update(self, positions: np.ndarray) -> float:
        """Re-stamp robots whose position changed; return the coverage fraction P."""
        g = self.grid
        self._covered += restamp(self._count, self._inside, self._positions,
                                 c_array(positions, np.float64), g.x0, g.y0, g.dx, g.dy,
                                 self._r2, self._half_i, self._half_j, self.rows, self.cols)
        pixels = self.grid.n_target_pixels
        return float(self._covered / pixels) if pixels else 0.0


STENCIL_CAP = 2**31
"""Largest half-size of a robot's coverage stencil, pixels: a robot is never that far from
the grid (robots stay inside the arena, a few grid widths across), so a wider radius covers
the same pixels; the cap keeps a huge (finite) coverage_radius within compiled integers."""


def _stencil_half(radius: float, pixel: float) -> int:
    """Half-size (pixels) of the stencil of pixels within ``radius`` of a robot's pixel."""
    return int(min(np.ceil(radius / pixel), STENCIL_CAP)) + 1


class SettledWatch:
    """Robots pushed out of place after they settled (GGC: Arrive), from their broadcasts.

    A robot is settled while it broadcasts one of the controller's settled statuses and is not
    moving on purpose; its anchor is where it settled. It counts as displaced once it is more
    than ``threshold`` units from its anchor: with rigid bodies only a push moves it.

    Args:
        n: number of robots.
        codes: status codes that mean "settled" (index into the controller's STATUSES).
        threshold: displacement that counts as "pushed out of place", units.
    """

    def __init__(self, n: int, codes: tuple[int, ...], threshold: float):
        self._is_settled = np.zeros(257, dtype=bool)  # status code + 128 -> settled?
        self._is_settled[np.asarray(codes, dtype=np.int64) + 128] = True
        self.threshold = threshold
        self.settled = np.zeros(n, dtype=bool)
        self.anchor = np.zeros((n, 2))
        self.max_shift = np.zeros(n)  # largest displacement of each robot while settled, units
        self._displaced_now = 0

    def observe(self, positions: np.ndarray, messages: np.ndarray) -> None:
        """Account for the state at the end of a tick (``messages``: the broadcasts)."""
        self._displaced_now = watch_settled(positions, messages["status"], messages["moving"],
                                            self._is_settled, self.settled, self.anchor,
                                            self.max_shift, self.threshold)

    @property
    def displaced_now(self) -> int:
        """Settled robots currently more than ``threshold`` from where they settled."""
        return self._displaced_now

    @property
    def ever_displaced(self) -> np.ndarray:
        """(N,) bool: robots that were once pushed more than ``threshold`` while settled."""
        return self.max_shift > self.threshold


class RobotTracks:
    """Per-robot odometry and settle ticks, updated once a tick with whole-swarm arrays.

    Attributes:
        distance: (N,) each robot's path length so far: the sum over ticks of the length of
            its displacement in that tick, units.
        settle_tick: (N,) the tick at which each robot last entered one of the controller's
            settled statuses (NOT_YET if it never did); read with its status at the end: a
            robot that left a settled status again keeps the tick of its last entry.
        moving_now: robots that moved more than ``moving_eps`` units in the last tick.

    Args:
        n: number of robots.
        codes: status codes that mean "settled" (index into the controller's STATUSES).
        moving_eps: displacement in one tick above which a robot counts as moving, units.
    """

    def __init__(self, n: int, codes: tuple[int, ...], moving_eps: float):
        self.codes = tuple(int(c) for c in codes)
        self._codes = np.asarray(self.codes, dtype=np.int64)
        self.moving_eps = moving_eps
        self.distance = np.zeros(n)
        self.settle_tick = np.full(n, NOT_YET, dtype=np.int64)
        self._in_settled = np.zeros(n, dtype=bool)
        self.moving_now = 0

    def observe(self, tick: int, step: np.ndarray | None, messages: np.ndarray) -> None:
        """Account for ``tick``: ``step`` (N,) is each robot's displacement length during it
        (None for the first observed state), ``messages`` the broadcasts at its end (a status
        is read only if their dtype has a ``status`` field)."""
        if step is not None:
            self.distance += step
            self.moving_now = count_above(step, self.moving_eps)
        if not len(self._codes) or "status" not in (messages.dtype.names or ()):
            return
        enter_settled(tick, messages["status"], self._codes, self.settle_tick,
                      self._in_settled)


class RunMetrics:
    """Accumulates a run's metrics tick by tick and keeps the time series.

    Args:
        grid: the coverage raster.
        config: the run's SimConfig (eps0, record_every, plateau and stall settings).
        physics: the Physics whose contact counters and arbiters are read.
        settled_codes: the controller's status codes that mean "settled" (for SettledWatch).
    """

    def __init__(self, grid: CoverageGrid, config, physics, settled_codes: tuple[int, ...] = ()):
        self.grid = grid
        self.config = config
        self.physics = physics
        self.settled = SettledWatch(physics.n, settled_codes, config.displaced_threshold)
        self.tracks = RobotTracks(physics.n, settled_codes, MOVING_FRACTION * config.v_max)
        self.peak_impulse = 0.0
        self.overlap_sum = 0.0
        self.overlap_contacts = 0
        self.contact_ticks = np.zeros(physics.n, dtype=np.int64)
        self.coverage = 0.0
        self.completion_tick: int | None = None
        self.total_distance = 0.0
        self.max_overlap = 0.0
        self.total_impulse = 0.0
        self.contact_robot_ticks = 0
        self.plateau_tick = 0
        self.completion_distance = 0.0
        self._rises: list[tuple[float, int, float]] = []  # (coverage, tick, distance) at new highs
        self._plateau_ref = -1.0
        self.last_change_tick = 0
        self.rows: list[dict] = []
        self._prev: np.ndarray | None = None
        self._last_recorded = -1
        self._state: dict = {}
        self._coverage: IncrementalCoverage | None = None

    def observe(self, tick: int, positions: np.ndarray, on_target: np.ndarray,
                messages: np.ndarray, awake: int, changed: bool = False) -> None:
        """Account for the state at the end of ``tick``."""
        step = None
        if self._prev is not None:
            step, longest = step_lengths(positions, self._prev)
            self.total_distance += float(step.sum())
            if changed or longest > self.config.wake_eps:
                self.last_change_tick = tick
        self._prev = positions
        self.tracks.observe(tick, step, messages)
        if self._coverage is None:
            self._coverage = IncrementalCoverage(self.grid, positions)
        self.coverage = self._coverage.update(positions)
        if self.completion_tick is None and 1.0 - self.coverage <= self.config.eps0 + 1e-12:
            self.completion_tick = tick
            self.completion_distance = self.total_distance
        if self.coverage > self._plateau_ref + self.config.plateau_delta:
            self._plateau_ref = self.coverage
            self.plateau_tick = tick
        if not self._rises or self.coverage > self._rises[-1][0]:
            self._rises.append((self.coverage, tick, self.total_distance))
        self._observe_contacts()
        self.settled.observe(positions, messages)
        self._state.update({"on_target": int(on_target.sum()),
                            "moving": self.tracks.moving_now, "awake": awake,
                            "displaced": self.settled.displaced_now})
        if messages.dtype.names is not None and "moving" in messages.dtype.names:
            self._state["broadcast_moving"] = int(np.count_nonzero(messages["moving"]))
        self.record(tick)

    def _observe_contacts(self) -> None:
        c = self.physics.contact_state()
        self.max_overlap = max(self.max_overlap, c.max_overlap)
        self.total_impulse += c.impulse
        self.peak_impulse = max(self.peak_impulse, c.peak_impulse)
        self.overlap_sum += c.overlap_sum
        self.overlap_contacts += c.robot_pairs
        self.contact_ticks += c.in_contact
        touching = int(c.in_contact.sum())
        self.contact_robot_ticks += touching
        self._state = {"in_contact": touching, "impulse": c.impulse}

    def record(self, tick: int, force: bool = False) -> None:
        """Append a time-series row every ``record_every`` ticks (or now, if forced)."""
        if tick == self._last_recorded or not (force or tick % self.config.record_every == 0):
            return
        self._last_recorded = tick
        c = self.physics.contacts
        self.rows.append({"tick": tick, "coverage": round(self.coverage, 6),
                          "total_distance": round(self.total_distance, 4),
                          "robots_on_target": self._state.get("on_target", 0),
                          "moving": self._state.get("moving", 0),
                          **({"broadcast_moving": self._state["broadcast_moving"]}
                             if "broadcast_moving" in self._state else {}),
                          "awake": self._state.get("awake", 0),
                          "in_contact": self._state.get("in_contact", 0),
                          "contacts_robot_robot": c.robot_robot,
                          "contacts_robot_wall": c.robot_wall,
                          "max_overlap": round(self.max_overlap, 6),
                          "contact_impulse": round(self._state.get("impulse", 0.0), 6),
                          "settled_displaced": self._state.get("displaced", 0)})

    def summary(self, positions: np.ndarray, on_target: np.ndarray) -> dict:
        """Summary fields for summary.json.

        ``settle_tick`` is the completion tick, or else the first tick at which coverage came
        within plateau_delta of the coverage the run ends with, and ``distance_at_settle`` the
        total distance moved by then (units): unlike total_distance it leaves out the walking
        of robots that could no longer add coverage (surplus robots looking for a place).
        ``robots_placed``: robots settled (the controller's settled statuses) on the target at
        the end; ``distance_per_placed_robot``: total_distance / robots_placed (units; None
        when none is placed).
        """
        c = self.physics.contacts
        spacing = nearest_neighbour_spacing(positions[on_target])
        settle_tick, settle_distance = self.settled_at()
        placed = int((self.settled.settled & np.asarray(on_target, dtype=bool)).sum())
        per_placed = round(self.total_distance / placed, 3) if placed else None
        return {"coverage": round(self.coverage, 6), "completion_tick": self.completion_tick,
                "total_distance": round(self.total_distance, 3),
                "robots_placed": placed, "distance_per_placed_robot": per_placed,
                "settle_tick": settle_tick, "distance_at_settle": round(settle_distance, 3),
                "robots_on_target": int(on_target.sum()),
                "collisions_robot_robot": c.robot_robot, "collisions_robot_wall": c.robot_wall,
                "max_overlap": round(self.max_overlap, 6),
                "total_contact_impulse": round(self.total_impulse, 3),
                "contact_robot_ticks": self.contact_robot_ticks,
                **self._collision_summary(),
                "spacing_mean": spacing[0], "spacing_std": spacing[1], "spacing_cv": spacing[2]}

    def settled_at(self) -> tuple[int, float]:
        """(tick, total distance in units) when coverage settled: the completion tick, or the
        first tick coverage came within plateau_delta of its current value. (Robots passing
        over uncovered floor make coverage flicker by a few tenths of a percent; the last rise
        would count their walking.)"""
        if self.completion_tick is not None:
            return self.completion_tick, self.completion_distance
        return first_within(self._rises, self.coverage - self.config.plateau_delta)

    def _collision_summary(self) -> dict:
        """Collision-realism figures: per-robot contacts, overlap, impulse, pushed robots."""
        per_robot = self.physics.contacts.per_robot
        mean_overlap = self.overlap_sum / self.overlap_contacts if self.overlap_contacts else 0.0
        return {"mean_overlap": round(mean_overlap, 6),
                "peak_contact_impulse": round(self.peak_impulse, 6),
                "robots_touched": int((per_robot > 0).sum()),
                "contacts_per_robot_mean": round(float(per_robot.mean()), 3) if per_robot.size
                else 0.0,
                "contacts_per_robot_max": int(per_robot.max()) if per_robot.size else 0,
                "settled_displaced": int(self.settled.ever_displaced.sum()),
                "settled_max_displacement": round(float(self.settled.max_shift.max()), 4)
                if per_robot.size else 0.0}

    def robot_rows(self, final: FinalState | None = None) -> list[dict]:
        """One row per robot (robots.csv; docs/outputs.md lists the columns).

        Without ``final`` (the run's end state), only the columns the metrics know: distance
        moved, settle tick, contacts, time in contact and largest push while settled.
        """
        c = self.physics.contacts
        n = len(c.per_robot)
        lead = final.columns() if final is not None else [{} for _ in range(n)]
        distance = np.round(self.tracks.distance, 4).tolist()
        settle = self.tracks.settle_tick.tolist()
        per_robot, per_wall = c.per_robot.tolist(), c.per_robot_wall.tolist()
        ticks = self.contact_ticks.tolist()
        shift = np.round(self.settled.max_shift, 4).tolist()
        return [{"robot": i, **lead[i], "distance": distance[i],
                 "settle_tick": "" if settle[i] == NOT_YET else settle[i],
                 "contacts_robot": per_robot[i], "contacts_wall": per_wall[i],
                 "contact_ticks": ticks[i], "settled_max_displacement": shift[i]}
                for i in range(n)]




@dataclass(frozen=True)
class FinalState:
    """What robots.csv reads from the end of a run.

    Attributes:
        positions: (N, 2) final positions, units.
        messages: (N,) the final broadcasts (structured array; any controller's dtype).
        statuses: the controller's status names, indexed by the ``status`` field.
        failed: (N,) bool, robots that failed during the run.
        fields: the broadcast fields copied into robots.csv (a controller's colourings and
            leader field: GGC's group, gradient, leader), each only if the messages have it.
        unknown: field values that mean "none" (the controller's SILENT values, e.g. an
            unknown gradient): written as an empty cell.
    """

    positions: np.ndarray
    messages: np.ndarray
    statuses: tuple[str, ...]
    failed: np.ndarray
    fields: tuple[str, ...] = ()
    unknown: Mapping[str, Any] = field(default_factory=dict)

    def columns(self) -> list[dict]:
        """Per robot: x, y, and status, group, gradient, leader as far as the broadcasts
        carry them. A failed robot's status reads "Failed"; a status code the controller
        does not name reads as an empty cell."""
        n = len(self.positions)
        xy = np.round(self.positions, 4).tolist()
        cols: dict[str, list] = {}
        names = self.messages.dtype.names or ()
        if "status" in names:
            codes = self.messages["status"].tolist()
            failed = self.failed.tolist()
            cols["status"] = ["Failed" if failed[i] else
                              self.statuses[code] if 0 <= code < len(self.statuses) else ""
                              for i, code in enumerate(codes)]
        for name in self.fields:
            if name not in names:
                continue
            values = self.messages[name]
            if values.ndim != 1:  # a field holding an array per robot: not a column
                continue
            out = values.tolist()
            if name in self.unknown:
                none = self.unknown[name]
                out = ["" if v == none else v for v in out]
            elif values.dtype == bool:
                out = [int(v) for v in out]
            cols[name] = out
        return [{"x": xy[i][0], "y": xy[i][1], **{k: v[i] for k, v in cols.items()}}
                for i in range(n)]


def nearest_neighbour_spacing(positions: np.ndarray) -> tuple[float | None, ...]:
    """Mean, standard deviation and coefficient of variation of nearest-neighbour distances.

    The spacing-uniformity measure of robots on the target (None when fewer than 2 robots).
    """
    if len(positions) < 2:
        return (None, None, None)
    d, _ = cKDTree(positions).query(positions, k=2)
    nn = d[:, 1]
    mean, std = float(nn.mean()), float(nn.std())
    return (round(mean, 4), round(std, 4), round(std / mean, 4) if mean > 0 else None)


def first_within(rises: list[tuple[float, int, float]], floor: float) -> tuple[int, float]:
    """(tick, distance) of the first of the coverage highs ``rises`` (coverage, tick,
    distance), in tick order, whose coverage is at least ``floor``; (0, 0.0) if none is."""
    for coverage, tick, distance in rises:
        if coverage >= floor:
            return tick, distance
    return 0, 0.0
