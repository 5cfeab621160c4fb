"""Worlds from any shape (``swarmsim make-world``): a target shape -> a world file.

The shape (from :mod:`swarmsim.world.shapes`) is scaled to ``size`` units high (default: the
height at which its area is the shipped K world's, 13,280 units^2), its separate parts are
joined by bridges (a world has one target polygon, and robots spread from one structure), it
is simplified and validated. The spawn band goes below it (15 units below, as in K), as wide as
the target and large enough for the robots' formations; the beacon goes at the target's pole
of inaccessibility (the point farthest from its edges); ``defaults.robots`` follows the lattice
capacity at ``d_cover`` (capacity / 0.7, K's ratio).
"""

from __future__ import annotations

import math
import os
import tempfile
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import shapely
import shapely.affinity
from shapely.geometry import Polygon
from shapely.geometry.base import BaseGeometry
from shapely.ops import polylabel

from swarmsim.errors import ConfigError
from swarmsim.limits import GROUPS_SIZE, MAX_COORDINATE, MAX_GROUPS, MAX_ROBOTS, check_count
from swarmsim.world.world import World, world_from_dict
from swarmsim.world.worldinfo import describe_world, fine_grid_size, hex_capacity, layout_rng

K_AREA = 13_280.0  # the shipped K world's target area, units^2
CAPACITY_SHARE = 0.7  # lattice capacity / robots, as the shipped worlds are sized
ROBOTS_PER_GROUP = 200  # default groups: one per this many robots (K: 603 robots, 3 groups)
MAX_DEFAULT_GROUPS = 10
SPAWN_GAP = 15.0  # from the spawn band's top to the target's bottom, units (as K)
SPAWN_AREA_PER_ROBOT = 6.6  # units^2 per robot in the spawn band (K: 3,960 / 603)
LEFT, BOTTOM = 10.0, 10.0  # the spawn band's lower left corner, units
DECIMALS = 2
LAYOUT_SEEDS = 5  # the formation start is tried for seeds 0..4


@dataclass(frozen=True)
class WorldSpec:
    """How to build a world from a shape.

    Attributes:
        name: the world's name.
        description: its one-line description.
        size: the target's height, units; None: the height at which its area is K_AREA.
        d_cover: the coverage distance the robot count is sized for, units.
        robots: robot count; None: lattice capacity at d_cover / CAPACITY_SHARE.
        groups: number of groups; None: one per ROBOTS_PER_GROUP robots (1..10).
    """

    name: str
    description: str
    size: float | None = None
    d_cover: float = 6.0
    robots: int | None = None
    groups: int | None = None

    def __post_init__(self) -> None:
        for key, text in (("--name", self.name), ("--text", self.description)):
            try:
                toml_string(text)
            except ValueError as exc:
                raise ConfigError(str(exc), key=key) from None
        if self.size is not None and not (math.isfinite(self.size) and self.size > 0):
            raise ConfigError(f"must be positive and finite, got {self.size!r}", key="--size")
        if not (math.isfinite(self.d_cover) and self.d_cover > 0):
            raise ConfigError(f"must be positive and finite, got {self.d_cover!r}",
                              key="--d-cover")
        if self.robots is not None:
            check_count("--robots", self.robots, MAX_ROBOTS, "robots in one run")
        if self.groups is not None:
            check_count("--groups", self.groups, MAX_GROUPS, GROUPS_SIZE)
        if self.robots and self.groups and self.groups > self.robots:
            raise ConfigError(f"{self.groups} groups need at least as many robots (robots = "
                              f"{self.robots})", key="--groups")


@dataclass(frozen=True)
class BuiltWorld:
    """A world made from a shape: its TOML data, the validated World, and notes for the user
    (bridges added, sizes chosen)."""

    data: dict
    world: World
    notes: tuple[str, ...]


def build_world(shape: BaseGeometry, spec: WorldSpec) -> BuiltWorld:
    """Scale, join, place and size ``shape`` into a validated world (see the module doc)."""
    notes: list[str] = []
    x0, y0, _x1, y1 = shape.bounds
    height = spec.size or (y1 - y0) * math.sqrt(K_AREA / shape.area)
    check_size(shape, height, spec)
    scale = height / (y1 - y0)
    target = shapely.affinity.scale(shape, scale, scale, origin=(x0, y0))
    target = shapely.affinity.translate(target, -x0, -y0)
    target, bridges = _joined(target, width=max(2 * spec.d_cover, 0.08 * height))
    if bridges:
        notes.append(f"joined {bridges + 1} separate parts with {bridges} bridge(s): a world has "
                     "one target polygon, and robots spread from one structure")
    target = _simplified(target, tolerance=max(0.02, 0.002 * height))
    free = float(target.area)
    robots = spec.robots or max(1, round(hex_capacity(free, spec.d_cover) / CAPACITY_SHARE))
    groups = spec.groups or min(MAX_DEFAULT_GROUPS, max(1, round(robots / ROBOTS_PER_GROUP)))
    if groups > robots:
        raise ConfigError(f"{groups} groups need at least as many robots (robots = {robots})",
                          key="--groups")
    data = _world_data(target, robots, groups, spec)
    world = _check_start(data, robots, groups)
    notes.append(f"{robots} robots in {groups} group(s) for d_cover {spec.d_cover:g} (the lattice "
                 f"holds {hex_capacity(free, spec.d_cover)}); target {height:.0f} units high")
    return BuiltWorld(data=data, world=world, notes=tuple(notes))


def check_size(shape: BaseGeometry, height: float, spec: WorldSpec) -> None:
    """Refuse a target ``height`` units high that no run could take, from the shape's bounds
    and area alone (nothing laid out, so any size is refused at once): its extent (with the
    spawn band and the arena's margin, within +-MAX_COORDINATE) and, without ``spec.robots``,
    the robot count it would get (lattice capacity at d_cover / CAPACITY_SHARE, which grows
    with height^2) above MAX_ROBOTS."""
    x0, y0, x1, y1 = shape.bounds
    scale = height / (y1 - y0)
    extent = max(x1 - x0, y1 - y0) * scale
    most_extent = MAX_COORDINATE / 2  # room for the spawn band, the bridges and the margin
    if extent > most_extent:
        most = height * most_extent / extent
        raise ConfigError(f"{spec.size if spec.size else height:g} makes the target "
                          f"{(x1 - x0) * scale:.3g} x {(y1 - y0) * scale:.3g} units, beyond the "
                          f"+-{MAX_COORDINATE:,.0f} units a world may span: give --size "
                          f"{most:,.0f} or less", key="--size")
    if spec.robots is not None:
        return
    area = float(shape.area) * scale * scale
    robots = hex_capacity(area, spec.d_cover) / CAPACITY_SHARE
    if robots > MAX_ROBOTS:
        most = height * math.sqrt(MAX_ROBOTS / robots) * 0.99  # area estimated before joining
        given = f"{spec.size:g}" if spec.size else f"the default height {height:.0f}"
        raise ConfigError(f"{given} makes a target of {area:,.0f} units^2 that would take "
                          f"{robots:,.0f} robots at d_cover {spec.d_cover:g} (lattice capacity /"
                          f" {CAPACITY_SHARE}), more than the {MAX_ROBOTS:,} a run takes: give "
                          f"--size {math.floor(most):,} or less, a larger --d-cover, or "
                          "--robots", key="--size")


def _joined(target: BaseGeometry, width: float) -> tuple[Polygon, int]:
    """One polygon: each other part joined to the growing whole by a bridge ``width`` wide
    along the shortest line between them, nearest part first."""
    parts = sorted(shapely.get_parts(target), key=lambda p: -p.area)
    whole, bridges = parts[0], 0
    rest = parts[1:]
    while rest:
        k = min(range(len(rest)), key=lambda i: rest[i].distance(whole))
        part = rest.pop(k)
        if part.distance(whole) > 0:
            line = shapely.shortest_line(part, whole)
            whole = shapely.union_all([whole, part, line.buffer(width / 2)])
            bridges += 1
        else:
            whole = whole.union(part)
    whole = whole.buffer(0)
    if whole.geom_type != "Polygon":  # touching parts that unioned into pieces
        whole = max(shapely.get_parts(whole), key=lambda p: p.area)
    return whole, bridges


def _simplified(target: Polygon, tolerance: float) -> Polygon:
    """``target`` simplified and rounded to DECIMALS, still one valid polygon."""
    simple = target.simplify(tolerance, preserve_topology=True)
    for _ in range(3):
        rounded = shapely.set_precision(simple, 10.0**-DECIMALS)
        parts = [p for p in shapely.get_parts(rounded.buffer(0)) if p.geom_type == "Polygon"]
        if parts:
            best = max(parts, key=lambda p: p.area)
            if best.is_valid:
                return shapely.normalize(shapely.set_precision(best, 10.0**-DECIMALS))
        simple = simple.buffer(0)
    raise ConfigError("the shape could not be made a valid polygon", key="shape")


def _world_data(target: Polygon, robots: int, groups: int, spec: WorldSpec,
                grow: float = 1.0) -> dict:
    """The world as TOML-ready data: target above a spawn band sized for the formations."""
    tx0, ty0, tx1, _ty1 = target.bounds
    per_group = math.ceil(robots / groups)
    radius = math.sqrt(per_group * 0.866 / math.pi) + 1  # a formation's radius at spacing 1
    width = max(tx1 - tx0, groups * (2 * radius + 6))
    band = max(2 * radius + 6, SPAWN_AREA_PER_ROBOT * robots / width, 10.0) * grow
    shift_x = LEFT + (width - (tx1 - tx0)) / 2 - tx0
    shift_y = BOTTOM + band + SPAWN_GAP - ty0
    placed = shapely.affinity.translate(target, shift_x, shift_y)
    beacon = central_deep_point(placed)
    spawn = [[LEFT, BOTTOM], [LEFT + width, BOTTOM], [LEFT + width, BOTTOM + band],
             [LEFT, BOTTOM + band]]
    return {
        "name": spec.name,
        "description": spec.description,
        "target": {"outline": _ring(placed.exterior.coords),
                   "holes": [_ring(h.coords) for h in placed.interiors]},
        "spawn": [{"outline": [[round(x, DECIMALS), round(y, DECIMALS)] for x, y in spawn]}],
        "beacon": {"position": [round(beacon.x, DECIMALS), round(beacon.y, DECIMALS)]},
        "arena": {"margin": 20.0},
        "defaults": _defaults(robots, groups, float(spec.d_cover), placed),
    }


def _defaults(robots: int, groups: int, d_cover: float, target: Polygon) -> dict:
    """A made world's run defaults; a large target's grid_size, fine enough that coverage
    cells are no wider than the coverage radius."""
    x0, y0, x1, y1 = target.bounds
    grid = fine_grid_size(x1 - x0, y1 - y0)
    return {"robots": robots, "groups": groups, "d_cover": d_cover,
            **({"grid_size": grid} if grid is not None else {})}


def central_deep_point(target: Polygon, share: float = 0.8, samples: int = 100) -> shapely.Point:
    """A point deep inside ``target`` near its middle: of the points on a grid at least
    ``share`` of the greatest depth (distance to the edge) inside it, the one nearest the
    centre of its bounding box. Deep, so a formation heading there meets the target; central,
    so that robots spread both ways. Falls back to the pole of inaccessibility."""
    x0, y0, x1, y1 = target.bounds
    xs, ys = np.meshgrid(np.linspace(x0, x1, samples), np.linspace(y0, y1, samples))
    xs, ys = xs.ravel(), ys.ravel()
    inside = shapely.contains_xy(target, xs, ys)
    pole = polylabel(target, tolerance=0.5)
    if not inside.any():
        return pole
    xs, ys = xs[inside], ys[inside]
    depth = shapely.distance(target.boundary, shapely.points(xs, ys))
    best = max(float(depth.max()), float(target.boundary.distance(pole)))
    deep = depth >= share * best
    if not deep.any():
        return pole
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
    k = int(np.argmin(np.hypot(xs[deep] - cx, ys[deep] - cy)))
    return shapely.Point(xs[deep][k], ys[deep][k])


def _ring(coords) -> list[list[float]]:
    pts = [[round(float(x), DECIMALS), round(float(y), DECIMALS)] for x, y in coords]
    return pts[:-1] if len(pts) > 1 and pts[0] == pts[-1] else pts


def _check_start(data: dict, robots: int, groups: int) -> World:
    """The validated world, its spawn band grown until the formation start fits for seeds
    0..LAYOUT_SEEDS-1 (drawn as a run draws them)."""
    from swarmsim.world import spawn

    for _ in range(8):
        world = world_from_dict(data, source=f"<{data['name']}>")
        try:
            for seed in range(LAYOUT_SEEDS):
                spawn.formation_layout(world, robots, groups, 1.0, layout_rng(seed))
            return world
        except ConfigError:
            band = data["spawn"][0]["outline"]
            top = band[2][1]
            lift = (top - band[0][1]) * 0.25
            _lift(data, lift)
    raise ConfigError(f"{groups} formations of {robots} robots do not fit below the shape; "
                      "use fewer robots or more groups", key="--robots")


def _lift(data: dict, dy: float) -> None:
    """Grow the spawn band by ``dy`` upward, moving the target and beacon up with it."""
    band = data["spawn"][0]["outline"]
    band[2][1] = band[3][1] = round(band[2][1] + dy, DECIMALS)
    target = data["target"]
    for ring in [target["outline"], *target["holes"]]:
        for pt in ring:
            pt[1] = round(pt[1] + dy, DECIMALS)
    data["beacon"]["position"][1] = round(data["beacon"]["position"][1] + dy, DECIMALS)


def to_toml(data: dict, header: str = "") -> str:
    """The world data as a TOML text (points six to a line)."""
    out = [f"# {line}".rstrip() for line in header.splitlines()] + [""] if header else []
    out += [f"name = {toml_string(data['name'])}",
            f"description = {toml_string(data['description'])}", "", "[target]"]
    out += _points("outline", data["target"]["outline"])
    if data["target"]["holes"]:
        out.append("holes = [")
        for hole in data["target"]["holes"]:
            out += ["    " + line for line in _points(None, hole)]
            out[-1] += ","
        out.append("]")
    for sp in data["spawn"]:
        out += ["", "[[spawn]]", *_points("outline", sp["outline"])]
    bx, by = data["beacon"]["position"]
    out += ["", "[beacon]", f"position = [{bx:g}, {by:g}]", "", "[arena]",
            f"margin = {data['arena']['margin']:.1f}", "", "[defaults]"]
    d = data["defaults"]
    out += [f"robots = {d['robots']}", f"groups = {d['groups']}", f"d_cover = {d['d_cover']!r}"]
    if "grid_size" in d:
        out.append(f"grid_size = {d['grid_size']}  # coverage cells no wider than the "
                   "coverage radius")
    return "\n".join(out) + "\n"


TOML_ESCAPES = {'"': '\\"', "\\": "\\\\", "\b": "\\b", "\t": "\\t", "\n": "\\n",
                "\f": "\\f", "\r": "\\r"}


def toml_string(text: str) -> str:
    """``text`` as a TOML basic string (quoted): quote, backslash and control characters
    escaped, every other character (any Unicode scalar value, emoji included) as itself, for
    a UTF-8 file. ValueError for a lone surrogate, which TOML (and UTF-8) cannot hold."""
    out = []
    for ch in text:
        code = ord(ch)
        if 0xD800 <= code <= 0xDFFF:
            raise ValueError(f"{text!r} holds a lone surrogate (U+{code:04X}), which a TOML "
                             "file cannot hold")
        if ch in TOML_ESCAPES:
            out.append(TOML_ESCAPES[ch])
        elif code < 0x20 or code == 0x7F:
            out.append(f"\\u{code:04X}")
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


def _points(key: str | None, pts: list[list[float]]) -> list[str]:
    cells = [f"[{x:g}, {y:g}]" for x, y in pts]
    rows = [", ".join(cells[i:i + 6]) + "," for i in range(0, len(cells), 6)]
    head = f"{key} = [" if key else "["
    return [head, *["    " + r for r in rows], "]"]


def write_world(built: BuiltWorld, path: Path, header: str = "") -> Path:
    """Write the world's TOML atomically (temp file + rename), then load it back as a check;
    a file that does not load is removed and the error raised."""
    from swarmsim.world.world import load_world

    path = Path(path)
    text = to_toml(built.data, header)
    world_from_dict(tomllib.loads(text), source=f"<{built.data['name']}>")  # before writing
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    try:
        load_world(path)
    except ConfigError:
        path.unlink(missing_ok=True)
        raise
    return path


def describe_built(built: BuiltWorld) -> list[str]:
    """Warnings about the built world (as ``swarmsim worlds PATH`` would print)."""
    return list(describe_world(built.world).warnings)
