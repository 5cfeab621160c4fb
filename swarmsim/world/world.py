"""Worlds as data: TOML files -> validated, immutable :class:`World` objects.

Schema (lengths in the paper's units; robots are discs of radius 0.4 by default)::

    name = "K"                          # required, a short identifier
    description = "..."                 # optional
    [target]                            # required: the area to cover (robots never see it whole)
    outline = [[x, y], ...]             # >= 3 points, a simple polygon (concave is fine)
    holes = [[[x, y], ...], ...]        # optional holes inside the outline
    [[spawn]]                           # one or more areas where robots start
    outline = [[x, y], ...]
    [[obstacles]]                       # optional static polygons (robots collide with them);
    outline = [[x, y], ...]             # inside the target they are not floor to cover
    [beacon]                            # optional: the one global cue (a light) leaders head to
    position = [x, y]
    [arena]                             # optional: walls around everything
    margin = 20.0                       # distance from the bounding box of all areas to the walls
    [defaults]                          # optional run defaults
    robots = 603
    groups = 3

Any other key is an error. Every error names the file, the key and the value. Every number
must be finite, and every coordinate (and the margin) within +-MAX_COORDINATE units. The
beacon must be inside the arena's walls. The target's free floor (its outline minus its holes
minus the obstacles) must hold at least one robot's disc (MIN_FREE_FLOOR).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from importlib import resources
from pathlib import Path
from types import MappingProxyType
from typing import Any

import shapely
from shapely.geometry import Polygon
from shapely.validation import explain_validity

from swarmsim.errors import ConfigError, unknown_name
from swarmsim.limits import (
    GROUPS_SIZE,
    MAX_COORDINATE,
    MAX_GRID_SIZE,
    MAX_GROUPS,
    MAX_ROBOTS,
    MAX_TICKS,
    check_at_most,
)
from swarmsim.robots.drives import DRIVE_NAMES
from swarmsim.tomlfile import read_toml

HEX_CELL_FACTOR = math.sqrt(3) / 2  # area per robot on a hexagonal lattice = 0.866 * spacing^2
DEFAULT_ARENA_MARGIN = 20.0
TOP_LEVEL_KEYS = {"name", "description", "target", "spawn", "obstacles", "beacon", "arena",
                  "defaults"}
DEFAULT_KEYS = {"robots": int, "groups": int, "d_cover": float, "controller": str,
                "max_ticks": int, "start": str, "drive": str, "grid_size": int}
DEFAULT_BOUNDS = {"robots": (MAX_ROBOTS, "robots in one run"),
                  "groups": (MAX_GROUPS, GROUPS_SIZE),
                  "max_ticks": (MAX_TICKS, "ticks in one run"),
                  "grid_size": (MAX_GRID_SIZE, "a coverage raster of grid_size^2 cells")}
REPO_WORLDS_DIR = Path(__file__).resolve().parents[2] / "worlds"
"""The shipped worlds in a checkout run without installing (PYTHONPATH=.); installed, they are
the package data swarmsim.worlds."""
MIN_FREE_FLOOR = math.pi * 0.4**2
"""Least free target floor a world may have, units^2: one robot's disc (default body radius
0.4). Less, and no robot could stand on the target: every run would end at 0 % coverage."""


@dataclass(frozen=True)
class World:
    """A validated world. Polygons are shapely geometries; never mutate them.

    Attributes:
        name: short identifier, e.g. ``"K"``.
        source: the file it was loaded from (or ``"<dict>"``).
        target: the area to cover (may have holes).
        spawns: areas where robots start.
        obstacles: static polygons robots collide with.
        beacon: position of the optional global light, in world units.
        arena: ``(xmin, ymin, xmax, ymax)`` of the walls enclosing everything.
        defaults: run defaults from the file (robots, groups, ...).
    """

    name: str
    source: str
    target: Polygon
    spawns: tuple[Polygon, ...]
    obstacles: tuple[Polygon, ...] = ()
    beacon: tuple[float, float] | None = None
    arena: tuple[float, float, float, float] = (0.0, 0.0, 1.0, 1.0)
    description: str = ""
    defaults: Mapping[str, Any] = field(default_factory=lambda: MappingProxyType({}))

    @cached_property
    def free_target(self) -> shapely.Geometry:
        """The floor to cover: the target (holes already cut out) minus the obstacles (a
        Polygon or MultiPolygon). The target itself (the same object) when no obstacle
        overlaps it."""
        blocking = [ob for ob in self.obstacles if ob.intersection(self.target).area > 0]
        if not blocking:
            return self.target
        return shapely.difference(self.target, shapely.union_all(blocking))

    @property
    def target_area(self) -> float:
        """Area of the free target floor (outline minus holes minus obstacles), units^2."""
        return float(self.free_target.area)

    def lattice_capacity(self, d_cover: float) -> int:
        """Robots a hexagonal lattice of spacing ``d_cover`` places in the target (area-based)."""
        if not (math.isfinite(d_cover) and d_cover > 0):  # also rejects NaN
            raise ConfigError(f"d_cover must be positive and finite, got {d_cover!r}",
                              key="d_cover")
        return int(self.target_area / (HEX_CELL_FACTOR * d_cover * d_cover))  # no OverflowError

    @property
    def spawn_area(self) -> float:
        """Area of the spawn areas, units^2 (overlapping areas counted once)."""
        return float(shapely.union_all(self.spawns).area)

    def max_random_robots(self, spacing: float) -> int:
        """Robots that random sequential placement at ``spacing`` fits in the spawn areas, safely.

        Random sequential adsorption of discs jams at ~54.7 % area fraction; we allow 75 % of
        that so that placement always succeeds quickly.
        """
        if not (math.isfinite(spacing) and spacing > 0):
            raise ConfigError(f"spacing must be positive and finite, got {spacing!r}",
                              key="spacing")
        disc = math.pi * spacing * spacing / 4  # (a huge spacing: inf, no OverflowError)
        return int(0.75 * 0.547 * self.spawn_area / disc)


def _num(value: Any, source: str, key: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ConfigError(f"expected a finite number, got {value!r}", source=source, key=key)
    return float(value)


def _coordinate(value: Any, source: str, key: str) -> float:
    """A finite number within +-MAX_COORDINATE units (a point's x or y)."""
    x = _num(value, source, key)
    if abs(x) > MAX_COORDINATE:
        raise ConfigError(f"must be within +-{MAX_COORDINATE:,.0f} units (a world spans at "
                          f"most that: 2.5 million robot radii), got {value!r}", source=source,
                          key=key)
    return x


def _points(value: Any, source: str, key: str) -> list[tuple[float, float]]:
    if not isinstance(value, list) or len(value) < 3:
        raise ConfigError(f"expected a list of at least 3 [x, y] points, got {value!r}",
                          source=source, key=key)
    pts = []
    for i, pt in enumerate(value):
        if not isinstance(pt, list) or len(pt) != 2:
            raise ConfigError(f"point {i} must be [x, y], got {pt!r}", source=source, key=key)
        pts.append((_coordinate(pt[0], source, f"{key}[{i}][0]"),
                    _coordinate(pt[1], source, f"{key}[{i}][1]")))
    return pts


def _polygon(table: Any, source: str, key: str, allow_holes: bool = False) -> Polygon:
    if not isinstance(table, Mapping):
        raise ConfigError(f"expected a table with 'outline', got {table!r}", source=source, key=key)
    allowed = {"outline", "holes"} if allow_holes else {"outline"}
    unknown = set(table) - allowed
    if unknown:
        bad = min(unknown)
        raise ConfigError(f"{unknown_name('key', bad, allowed)} (value {table[bad]!r})",
                          source=source, key=f"{key}.{bad}")
    if "outline" not in table:
        raise ConfigError("missing 'outline'", source=source, key=key)
    shell = _points(table["outline"], source, f"{key}.outline")
    holes_raw = table.get("holes", [])
    if not isinstance(holes_raw, list):
        raise ConfigError(f"expected a list of point lists, got {holes_raw!r}",
                          source=source, key=f"{key}.holes")
    holes = [_points(h, source, f"{key}.holes[{i}]") for i, h in enumerate(holes_raw)]
    # Collinear or repeated points: say "zero area" (GEOS would call it a self-intersection).
    # The hull test keeps a bow-tie, whose signed areas cancel, out of this branch.
    if shapely.MultiPoint(shell).convex_hull.area <= 0:
        raise ConfigError(f"polygon has zero area: {table['outline']!r}", source=source,
                          key=f"{key}.outline")
    poly = Polygon(shell, holes)
    if not poly.is_valid and Polygon(shell).is_valid:
        _check_holes(Polygon(shell), holes, holes_raw, source, key)
    if not poly.is_valid:
        # A valid outline with bad holes (outside it, crossing it or each other): name the holes.
        part = "holes" if holes and Polygon(shell).is_valid else "outline"
        raise ConfigError(f"invalid polygon ({explain_validity(poly)}): {table[part]!r}",
                          source=source, key=f"{key}.{part}")
    if poly.area <= 0:
        raise ConfigError(f"polygon has zero area: {table['outline']!r}", source=source,
                          key=f"{key}.outline")
    return shapely.normalize(poly)


def _check_holes(shell: Polygon, holes: list[list[tuple[float, float]]], written: list,
                 source: str, key: str) -> None:
    """Name the hole that makes a polygon with a valid outline invalid, and how: not simple,
    outside or across the outline, touching it along an edge or at two points (which cuts the
    floor in two), or overlapping or touching another hole that way. ``written``: the holes
    as the file gives them (for the message)."""
    def fail(i: int, what: str) -> None:
        raise ConfigError(f"hole {i} {written[i]!r} {what}: a hole must lie inside the outline,"
                          " apart from it and from the other holes (a notch belongs in the "
                          "outline)", source=source, key=f"{key}.holes[{i}]")

    rings = [Polygon(h) for h in holes]
    for i, hole in enumerate(rings):
        if not hole.is_valid:
            fail(i, f"is not a simple polygon ({explain_validity(hole)})")
        if not shell.covers(hole):
            where = _where_met(hole.exterior, shell.exterior)
            fail(i, f"crosses the outline at {where}" if where else "lies outside the outline")
        if not Polygon(shell.exterior, [hole.exterior]).is_valid:
            fail(i, f"touches the outline at {_where_met(hole.exterior, shell.exterior)}")
    for i, a in enumerate(rings):
        for j in range(i + 1, len(rings)):
            if not Polygon(shell.exterior, [a.exterior, rings[j].exterior]).is_valid:
                met = _where_met(a.exterior, rings[j].exterior) or f"{_coords(rings[j])[0]}"
                fail(j, f"overlaps or touches hole {i} at {met}")


def _where_met(a: shapely.Geometry, b: shapely.Geometry) -> str:
    """Where rings ``a`` and ``b`` meet: "(x, y)", "(x, y) and (x, y)" or "(x, y) to (x, y)"
    (a shared edge), or "" when they do not."""
    met = a.intersection(b)
    if met.is_empty:
        return ""
    pts = [f"({x:g}, {y:g})" for x, y in shapely.get_coordinates(met)]
    if any(p.geom_type in ("LineString", "LinearRing") for p in shapely.get_parts(met)):
        return f"{pts[0]} to {pts[-1]} (a shared edge)"
    return " and ".join(dict.fromkeys(pts[:2]))


def _polygon_list(value: Any, source: str, key: str) -> tuple[Polygon, ...]:
    if not isinstance(value, list):
        raise ConfigError(f"expected an array of tables ([[{key}]]), got {value!r}",
                          source=source, key=key)
    return tuple(_polygon(t, source, f"{key}[{i}]") for i, t in enumerate(value))


def _defaults(value: Any, source: str) -> Mapping[str, Any]:
    if not isinstance(value, Mapping):
        raise ConfigError(f"expected a table, got {value!r}", source=source, key="defaults")
    out = {}
    for k, v in value.items():
        if k not in DEFAULT_KEYS:
            raise ConfigError(f"{unknown_name('run default', k, DEFAULT_KEYS)} (value {v!r})",
                              source=source, key=f"defaults.{k}")
        want = DEFAULT_KEYS[k]
        ok = isinstance(v, want) or (want is float and isinstance(v, int))
        if isinstance(v, bool) or not ok:
            raise ConfigError(f"expected {want.__name__}, got {v!r}", source=source,
                              key=f"defaults.{k}")
        if want in (int, float) and not (math.isfinite(v) and v > 0):  # also refuses nan
            raise ConfigError(f"must be a positive finite number, got {v!r}", source=source,
                              key=f"defaults.{k}")
        if k in DEFAULT_BOUNDS:
            check_at_most(f"defaults.{k}", v, *DEFAULT_BOUNDS[k], source=source)
        if k == "start" and v not in ("random", "formation"):
            raise ConfigError(f"must be 'random' or 'formation', got {v!r}", source=source,
                              key="defaults.start")
        if k == "drive" and v not in DRIVE_NAMES:
            raise ConfigError(f"must be one of {', '.join(DRIVE_NAMES)}, got {v!r}",
                              source=source, key="defaults.drive")
        if k == "controller":
            _check_controller_name(v, source)
        out[k] = v
    return MappingProxyType(out)


def _check_controller_name(name: str, source: str) -> None:
    """A world's default controller must exist (named with the file and key)."""
    from swarmsim.controller import get_controller

    try:
        get_controller(name)
    except ConfigError as exc:
        message = str(exc).removeprefix("key 'controller': ")
        raise ConfigError(message, source=source, key="defaults.controller") from None


def _beacon(value: Any, source: str) -> tuple[float, float]:
    if not isinstance(value, Mapping) or set(value) != {"position"}:
        raise ConfigError(f"expected a table with only 'position = [x, y]', got {value!r}",
                          source=source, key="beacon")
    pos = value["position"]
    if not isinstance(pos, list) or len(pos) != 2:
        raise ConfigError(f"expected [x, y], got {pos!r}", source=source, key="beacon.position")
    return (_coordinate(pos[0], source, "beacon.position[0]"),
            _coordinate(pos[1], source, "beacon.position[1]"))


def _check_beacon_inside(beacon: tuple[float, float], arena: tuple[float, float, float, float],
                         source: str) -> None:
    """Refuse a beacon on or beyond the arena's walls: no robot could ever reach it (one off
    the target but inside the walls is only unusual: ``swarmsim worlds`` warns)."""
    x0, y0, x1, y1 = arena
    bx, by = beacon
    if not (x0 < bx < x1 and y0 < by < y1):
        raise ConfigError(f"[{bx:g}, {by:g}] is outside the arena walls (x {x0:g}..{x1:g}, "
                          f"y {y0:g}..{y1:g}): no robot can reach it; put it on the target",
                          source=source, key="beacon.position")


def _arena(value: Any, source: str, geoms: list[Polygon]) -> tuple[float, float, float, float]:
    if not isinstance(value, Mapping) or not set(value) <= {"margin"}:
        raise ConfigError(f"expected a table with only 'margin', got {value!r}", source=source,
                          key="arena")
    margin = _coordinate(value.get("margin", DEFAULT_ARENA_MARGIN), source, "arena.margin")
    if margin <= 0:
        raise ConfigError(f"must be positive, got {margin!r}", source=source, key="arena.margin")
    xmin, ymin, xmax, ymax = shapely.union_all(geoms).bounds
    return (xmin - margin, ymin - margin, xmax + margin, ymax + margin)


def world_from_dict(data: Mapping[str, Any], source: str = "<dict>") -> World:
    """Validate a parsed TOML mapping and build a :class:`World`."""
    unknown = set(data) - TOP_LEVEL_KEYS
    if unknown:
        key = min(unknown)
        raise ConfigError(f"{unknown_name('top-level key', key, TOP_LEVEL_KEYS)} (value "
                          f"{data[key]!r})", source=source, key=key)
    name = data.get("name")
    if not isinstance(name, str) or not name:
        raise ConfigError(f"expected a non-empty string, got {name!r}", source=source, key="name")
    if "target" not in data:
        raise ConfigError("missing [target] table", source=source, key="target")
    target = _polygon(data["target"], source, "target", allow_holes=True)
    if "spawn" not in data:
        raise ConfigError("missing [[spawn]] areas", source=source, key="spawn")
    spawns = _polygon_list(data["spawn"], source, "spawn")
    if not spawns:
        raise ConfigError("at least one [[spawn]] area is needed", source=source, key="spawn")
    obstacles = _polygon_list(data.get("obstacles", []), source, "obstacles")
    _check_overlaps(spawns, obstacles, target, source)
    _check_free_floor(target, obstacles, source)
    beacon = _beacon(data["beacon"], source) if "beacon" in data else None
    arena = _arena(data.get("arena", {}), source, [target, *spawns, *obstacles])
    if beacon is not None:
        _check_beacon_inside(beacon, arena, source)
    description = data.get("description", "")
    if not isinstance(description, str):
        raise ConfigError(f"expected a string, got {description!r}", source=source,
                          key="description")
    return World(name=name, source=source, target=target, spawns=spawns, obstacles=obstacles,
                 beacon=beacon, arena=arena, description=description,
                 defaults=_defaults(data.get("defaults", {}), source))


def _check_overlaps(spawns: tuple[Polygon, ...], obstacles: tuple[Polygon, ...],
                    target: Polygon, source: str) -> None:
    for i, sp in enumerate(spawns):
        on_target = sp.intersection(target).area
        if on_target > 1e-9:  # robots would start on the target, covering it at tick 0
            raise ConfigError(f"spawn area {_coords(sp)} overlaps the target (overlap area "
                              f"{on_target:g}): robots must start off the target",
                              source=source, key=f"spawn[{i}].outline")
        for j, ob in enumerate(obstacles):
            overlap = sp.intersection(ob).area
            if overlap > 1e-9:
                raise ConfigError(f"spawn area {_coords(sp)} overlaps obstacles[{j}] "
                                  f"{_coords(ob)} (overlap area {overlap:g})", source=source,
                                  key=f"spawn[{i}].outline")


def _check_free_floor(target: Polygon, obstacles: tuple[Polygon, ...], source: str) -> None:
    """Refuse a target whose free floor (minus holes and obstacles) cannot hold a robot."""
    free = target.difference(shapely.union_all(obstacles)).area if obstacles else target.area
    if free < MIN_FREE_FLOOR:
        blame = ("the obstacles cover it" if obstacles and free < target.area
                 else "it is too small")
        key = "obstacles" if obstacles and free < target.area else "target.outline"
        raise ConfigError(f"the target has {free:.3g} units^2 of free floor (outline "
                          f"{_coords(target)}, area {target.area:.3g}): {blame}; a robot "
                          f"needs {MIN_FREE_FLOOR:.3g}", source=source, key=key)


def _coords(poly: Polygon) -> list[list[float]]:
    """Outline of ``poly`` as ``[[x, y], ...]`` (no closing point) for error messages."""
    return [[round(x, 6), round(y, 6)] for x, y in list(poly.exterior.coords)[:-1]]


def world_path(name_or_path: str | Path) -> Path:
    """Resolve a world name (``"K"``) or a path to a ``.toml`` file."""
    p = Path(name_or_path)
    if p.suffix != ".toml" and not p.is_file():  # a name, unless only a folder has it
        for candidate in _world_dirs():
            f = candidate / f"{name_or_path}.toml"
            if f.is_file():
                return f
    if p.suffix == ".toml" or p.exists():
        if not p.is_file():
            raise ConfigError(f"world file not found: {str(p)!r}", key="world")
        return p
    raise ConfigError(f"{unknown_name('world', str(name_or_path), available_worlds())} (a "
                      "shipped world's name or a .toml file)", key="world")


def _world_dirs() -> list[Path]:
    dirs = []
    try:
        dirs.append(Path(str(resources.files("swarmsim.worlds"))))
    except (ModuleNotFoundError, TypeError):
        pass
    if REPO_WORLDS_DIR.is_dir():
        dirs.append(REPO_WORLDS_DIR)
    return dirs


def available_worlds() -> list[str]:
    """Names of the shipped worlds."""
    names: set[str] = set()
    for d in _world_dirs():
        names.update(f.stem for f in d.glob("*.toml"))
    return sorted(names)


def load_world(name_or_path: str | Path) -> World:
    """Load and validate a world by shipped name (``"K"``, ``"house"``) or by file path."""
    path = world_path(name_or_path)
    data = read_toml(path)
    return world_from_dict(data, source=str(path))
