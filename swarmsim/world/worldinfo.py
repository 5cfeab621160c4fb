"""Describe a world before running it: free floor, lattice capacity, spawn room, beacon, and
warnings about what would make a run slow, wrong or impossible (``swarmsim worlds PATH``).

Pure geometry (shapely, numpy); no physics, no controller. Lengths in the paper's units,
areas in units^2.
"""

from __future__ import annotations

import dataclasses
import math
import textwrap
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from swarmsim.errors import ConfigError
from swarmsim.limits import MAX_GRID_SIZE
from swarmsim.world.floor import travel_distance
from swarmsim.world.world import HEX_CELL_FACTOR, World

LATTICE_SPACINGS = (1, 2, 4, 6, 8, 10)
DEFAULT_D_COVER = 6.0
ROBOT_RADIUS = 0.4  # PhysicsConfig's default body radius
START_SPACING = 1.0  # SimConfig's formation_spacing and spawn_spacing (d_safe)
COVERAGE_RADIUS = 4.0  # SimConfig's coverage_radius r
V_MAX = 0.1  # SimConfig's v_max, units per tick: the travel floor's speed
GRID_SIZE = 100  # SimConfig's grid_size
DEFAULT_ROBOTS = 100  # SimConfig's robots, when a world names none
NARROW_WARN = 1.0  # warn when at least this much free floor (units^2) is narrower than a robot
MIN_NARROW = 0.05  # narrow slivers smaller than this (units^2) are ignored
NEAR_SPAWN = 2.0  # warn when a spawn area comes closer than this to the target, units


def fit_number(value: float, width: int) -> str:
    """``value`` right-aligned in ``width`` characters: with thousands separators (rounded to
    a whole number) when that fits, else in scientific notation (1.23e+12), so that a table
    of huge worlds keeps its columns."""
    text = f"{value:,.0f}"
    if len(text) > width:
        text = f"{value:.{max(0, width - 6)}e}"
    return f"{text:>{width}}"


def readable(value: float) -> str:
    """``value`` for running text: thousands separators below a billion (13,280), three
    significant digits in scientific notation from there (2e+12)."""
    return f"{value:,.0f}" if abs(value) < 1e9 else f"{value:.3g}"


def hex_capacity(area: float, spacing: float) -> int:
    """Robots a hexagonal lattice of ``spacing`` (units) places on ``area`` (units^2)."""
    return int(area / (HEX_CELL_FACTOR * spacing**2))


@dataclass(frozen=True)
class WorldReport:
    """What ``swarmsim worlds PATH`` prints about one world.

    Attributes:
        world: the validated world.
        outline_area: area inside the target's outline, holes included, units^2.
        holes_area: area of the target's holes, units^2.
        obstacles_area: area of obstacles on the target (outside its holes), units^2.
        free_area: target floor robots can reach and cover: outline - holes - obstacles.
        free_parts: number of separate pieces of the free target floor.
        narrow_area: free floor narrower than a robot (2 * radius), where no robot fits.
        capacity: robots a hexagonal lattice of spacing d places on the free floor, per d.
        spawn_area: area of the spawn areas (overlaps counted once), units^2.
        spawn_capacity: robots a formation start (hexagonal, spacing 1) fits in the spawn areas.
        random_capacity: robots a random start places in the spawn areas (World's safe limit).
        beacon_depth: the beacon's distance inside the free target floor (negative: outside
            it, by that much), or None without a beacon or without free floor.
        travel_distance: the shortest-path distance from the spawn areas to the farthest
            point of the free target floor, units (swarmsim/world/floor.py).
        warnings: one line each, in the order they were found.
    """

    world: World
    outline_area: float
    holes_area: float
    obstacles_area: float
    free_area: float
    free_parts: int
    narrow_area: float
    capacity: dict[float, int]
    spawn_area: float
    spawn_capacity: int
    random_capacity: int
    beacon_depth: float | None
    travel_distance: float
    warnings: tuple[str, ...]


def free_floor(world: World) -> BaseGeometry:
    """The target minus its holes (already cut out) and minus the obstacles."""
    if not world.obstacles:
        return world.target
    return shapely.difference(world.target, shapely.union_all(world.obstacles)).buffer(0)


def narrow_floor(free: BaseGeometry, radius: float = ROBOT_RADIUS) -> BaseGeometry:
    """Parts of ``free`` where a disc of ``radius`` does not fit (a morphological opening with
    mitred joins, so that a polygon's corners do not count; slivers under MIN_NARROW units^2
    are dropped)."""
    opened = free.buffer(-radius, join_style="mitre", mitre_limit=10.0).buffer(
        radius, join_style="mitre", mitre_limit=10.0)
    parts = [p for p in shapely.get_parts(shapely.difference(free, opened))
             if p.geom_type == "Polygon" and p.area >= MIN_NARROW]
    return shapely.MultiPolygon(parts) if parts else shapely.Polygon()


def describe_world(world: World) -> WorldReport:
    """Measure ``world`` and collect warnings (see WorldReport)."""
    target = world.target
    outline_area = float(shapely.Polygon(target.exterior).area)
    holes_area = outline_area - float(target.area)
    free = free_floor(world)
    free_area = float(free.area)
    narrow = narrow_floor(free) if free_area > 0 else free
    narrow_area = float(narrow.area)
    parts = [p for p in shapely.get_parts(free) if p.area > 1e-9]
    d_cover = float(world.defaults.get("d_cover", DEFAULT_D_COVER))
    spacings = sorted({*map(float, LATTICE_SPACINGS), d_cover})
    capacity = {d: hex_capacity(free_area, d) for d in spacings}
    spawn_area = world.spawn_area
    depth = None
    if world.beacon is not None and free_area > 0:
        point = shapely.Point(world.beacon)
        inside = free.contains(point)
        depth = float(free.boundary.distance(point)) * (1 if inside else -1)
    report = WorldReport(
        world=world, outline_area=outline_area, holes_area=holes_area,
        obstacles_area=float(target.area) - free_area, free_area=free_area,
        free_parts=len(parts), narrow_area=narrow_area, capacity=capacity,
        spawn_area=spawn_area, spawn_capacity=hex_capacity(spawn_area, START_SPACING),
        random_capacity=world.max_random_robots(START_SPACING), beacon_depth=depth,
        travel_distance=travel_distance(world), warnings=())
    return dataclasses.replace(report, warnings=tuple(_warnings(report, d_cover)))


def layout_rng(seed: int) -> np.random.Generator:
    """The generator a run with ``seed`` places its robots with (as Simulation derives it),
    so that a preview shows that run's start."""
    return np.random.default_rng(np.random.SeedSequence(seed).spawn(4)[0])


def _warnings(r: WorldReport, d_cover: float) -> list[str]:
    w, out = r.world, []
    if r.free_area <= 1e-9:
        out.append("the target has no free floor: obstacles cover all of it")
        return out
    disc = math.pi * COVERAGE_RADIUS**2
    if r.free_area < disc:
        out.append(f"tiny free floor: {r.free_area:.1f} units^2, less than one robot's "
                   f"coverage disc (pi r^2 = {disc:.1f} with r = {COVERAGE_RADIUS:g})")
    out.extend(_coarse_cells(w))
    if r.free_parts > 1:
        out.append(f"the free target floor is in {r.free_parts} separate parts: robots must "
                   "cross off-target floor between them")
    if r.narrow_area >= NARROW_WARN:
        out.append(f"{r.narrow_area:.1f} units^2 ({100 * r.narrow_area / r.free_area:.1f} %) of "
                   f"the target is narrower than a robot ({2 * ROBOT_RADIUS:g} units): no robot "
                   "fits in it (robots cover it only from beside it)")
    if r.beacon_depth is None:
        out.append("no beacon: controllers that head for one (ggc) cannot run here")
    elif r.beacon_depth < 0:
        where = _where(w, w.beacon)
        out.append(f"the beacon {list(w.beacon)} is not on the free target floor ({where}, "
                   f"{-r.beacon_depth:.1f} units from it): leaders head for it")
    elif r.beacon_depth < 2 * ROBOT_RADIUS:
        out.append(f"the beacon {list(w.beacon)} is {r.beacon_depth:.2f} units from the "
                   "target's edge: a robot at it barely fits")
    for i, sp in enumerate(w.spawns):
        gap = float(sp.distance(w.target))
        if gap < NEAR_SPAWN:
            out.append(f"spawn area {i} is {gap:.1f} units from the target: robots start "
                       "beside it (a formation may spill onto it)")
    robots = int(w.defaults.get("robots", DEFAULT_ROBOTS))
    need = r.capacity[d_cover]
    if robots < need:
        out.append(f"{robots:,} robots are fewer than the {readable(need)} a lattice at d_cover "
                   f"{d_cover:g} places: coverage cannot complete at that d_cover")
    if robots > r.spawn_capacity:
        out.append(f"{robots} robots do not fit in the spawn areas at spacing "
                   f"{START_SPACING:g} (a formation start holds ~{r.spawn_capacity}); "
                   "formations spill beside them")
    out.extend(_start_check(w, robots))
    return out


def fine_grid_size(width: float, height: float) -> int | None:
    """The grid_size a target of ``width`` x ``height`` units needs for coverage cells no
    wider than the coverage radius, or None when the default GRID_SIZE is fine enough."""
    need = needed_grid_size(width, height)
    return need if need > GRID_SIZE else None


def needed_grid_size(width: float, height: float) -> int:
    """The smallest grid_size whose cells over a ``width`` x ``height`` target (units) are no
    wider than the coverage radius."""
    return math.ceil(max(width, height) / COVERAGE_RADIUS)


def _coarse_cells(world: World) -> list[str]:
    """A warning when the coverage raster's cells (the target's bounding box over grid_size
    x grid_size, the world's default or GRID_SIZE) are wider than the coverage radius: a cell
    then counts as covered when a robot is near its centre only, so coverage is measured
    coarsely."""
    x0, y0, x1, y1 = world.target.bounds
    grid = int(world.defaults.get("grid_size", GRID_SIZE))
    cell = max(x1 - x0, y1 - y0) / grid
    if cell <= COVERAGE_RADIUS:
        return []
    need = needed_grid_size(x1 - x0, y1 - y0)
    fix = (f"set grid_size={need}" if need <= MAX_GRID_SIZE else
           f"no grid_size up to {MAX_GRID_SIZE:,} makes cells that small: the target is very "
           "large for robots of this size")
    return [(f"coverage cells are {readable(cell)} units wide at grid_size {grid} (the "
            f"target is {readable(x1 - x0)} x {readable(y1 - y0)} units), wider than the "
            f"coverage radius {COVERAGE_RADIUS:g}: coverage is measured coarsely; {fix}")]


def _where(world: World, xy: tuple[float, float]) -> str:
    point = shapely.Point(xy)
    if any(o.contains(point) for o in world.obstacles):
        return "inside an obstacle"
    if shapely.Polygon(world.target.exterior).contains(point) and not world.target.contains(point):
        return "in a hole"
    return "outside the target"


def _start_check(world: World, robots: int) -> list[str]:
    """The world's default start, tried with seed 0: a one-line warning if it is refused."""
    from swarmsim.world import spawn

    groups = int(world.defaults.get("groups", 1))
    start = world.defaults.get("start", "formation")
    rng = layout_rng(0)
    try:
        if start == "formation":
            spawn.formation_layout(world, robots, groups, START_SPACING, rng)
        elif robots > world.max_random_robots(START_SPACING):
            return [(f"a random start of {robots} robots does not fit the spawn areas "
                    f"(at most {world.max_random_robots(START_SPACING)})")]
    except ConfigError as exc:
        text = str(exc).removeprefix(f"{world.source}: ")
        return [(f"the default start ({start}, {robots} robots, {groups} groups) is refused: "
                f"{text}")]
    return []


def format_report(r: WorldReport) -> list[str]:
    """The report as lines of text (at most 100 characters each, for short outlines)."""
    w = r.world
    x0, y0, x1, y1 = w.target.bounds
    lines = [f"world {w.name} ({w.source})"]
    if w.description:
        lines.append(f"  {w.description}")
    lines.append(f"  target      {readable(r.free_area)} units^2 of free floor = outline "
                 f"{readable(r.outline_area)} - holes {readable(r.holes_area)} - obstacles "
                 f"{readable(r.obstacles_area)}")
    lines.append(f"              {x1 - x0:g} x {y1 - y0:g} units (x {x0:g}..{x1:g}, "
                 f"y {y0:g}..{y1:g}), {r.free_parts} part(s), {len(w.target.interiors)} "
                 f"hole(s), {len(w.obstacles)} obstacle(s)")
    ds = list(r.capacity)
    lines.append("  capacity    d_cover " + "".join(f"{d:>8g}" for d in ds))
    lines.append("              robots  " + "".join(" " + fit_number(r.capacity[d], 7) for d in ds))
    lines.append(f"  spawn       {len(w.spawns)} area(s), {readable(r.spawn_area)} units^2: hold "
                 f"~{readable(r.spawn_capacity)} robots in formation (spacing "
                 f"{START_SPACING:g}),")
    lines.append(f"              {readable(r.random_capacity)} at a random start")
    if math.isfinite(r.travel_distance):
        lines.append(f"  floor       {readable(r.travel_distance / V_MAX)} ticks at v_max "
                     f"{V_MAX:g}: the farthest target point is {r.travel_distance:,.1f} units")
        lines.append("              from the spawn areas (shortest path, round the obstacles)")
    else:
        lines.append("  floor       none: obstacles wall part of the target off from the spawn "
                     "areas")
    if w.beacon is None:
        lines.append("  beacon      none")
    elif r.beacon_depth is None:  # no free floor to measure it against
        lines.append(f"  beacon      ({w.beacon[0]:g}, {w.beacon[1]:g})")
    else:
        side = "inside the free target" if (r.beacon_depth or 0) >= 0 else "OUTSIDE the target"
        lines.append(f"  beacon      ({w.beacon[0]:g}, {w.beacon[1]:g}), {side}, "
                     f"{abs(r.beacon_depth or 0):.1f} units from its edge")
    defaults = ", ".join(f"{k} {v}" for k, v in w.defaults.items()) or "none"
    lines.append(f"  defaults    {defaults}")
    lines.append(f"  arena       walls at x {w.arena[0]:g}..{w.arena[2]:g}, "
                 f"y {w.arena[1]:g}..{w.arena[3]:g}")
    if r.warnings:
        lines.append("  warnings")
        for text in r.warnings:
            lines.extend(textwrap.wrap(text, width=100, initial_indent="    - ",
                                       subsequent_indent="      "))
    else:
        lines.append("  warnings    none")
    lines.append("  capacity: robots a hexagonal lattice of spacing d_cover places on the free "
                 "floor,")
    lines.append("  free area / (0.866 d_cover^2)")
    return lines
