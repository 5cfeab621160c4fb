"""Start layouts: robots placed at random in the spawn areas, or as hexagonal formations.

All placement is deterministic given the numpy Generator passed in.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from scipy.spatial import cKDTree

from swarmsim.errors import ConfigError
from swarmsim.world.world import World

MAX_TRIES_PER_ROBOT = 400
BOX_TRIES = 20
"""Formation centres are drawn in the spawn region's bounding box while at least one draw in
BOX_TRIES lands in the region; below that, piece by piece (see formation_centres)."""


def check_capacity(world: World, n: int, start: str, spawn_spacing: float,
                   formation_spacing: float) -> None:
    """Refuse ``n`` robots that the start's floor cannot hold, from areas alone: no layout is
    built, so any count is refused in milliseconds.

    ``start`` "formation": every robot of a formation stands at least ``formation_spacing``
    (units) from every other, off the target, clear of obstacles and inside the walls (see
    check_formation_floor), so the discs of diameter ``formation_spacing`` round them are
    disjoint and lie on that floor: n <= its area / one disc's (max_formation_robots). Any
    other start is random placement at ``spawn_spacing`` in the spawn areas
    (World.max_random_robots). A count that passes may still fail to be laid out (formations
    that do not fit apart): the layout says so.
    """
    if start == "formation":
        limit = max_formation_robots(world, formation_spacing)
        if n > limit:
            floor = _formation_floor(world, formation_spacing).area
            raise ConfigError(
                f"{n} robots cannot start in formation at spacing {formation_spacing:g}: the "
                f"floor off the target inside the arena ({floor:.0f} units^2) holds at most "
                f"{limit}; use fewer robots", source=world.source, key="robots")
        return
    _check_random_capacity(world, n, spawn_spacing)


def _check_random_capacity(world: World, n: int, spacing: float) -> None:
    limit = world.max_random_robots(spacing)
    if n > limit:
        raise ConfigError(f"spawn areas (total area {world.spawn_area:.0f}) cannot hold {n} robots"
                          f" at spacing {spacing} (at most {limit})", source=world.source,
                          key="robots")


def max_formation_robots(world: World, spacing: float) -> int:
    """An upper bound on the robots formations at ``spacing`` (units) can place: the area
    where a robot's disc of diameter ``spacing`` may lie (the arena, minus the target shrunk
    by spacing / 2, minus the obstacles) over one disc's area."""
    return int(_formation_floor(world, spacing).area / (math.pi * spacing * spacing / 4))


def _formation_floor(world: World, spacing: float):
    """Where the discs (diameter ``spacing``) of robots in formation can lie; see
    max_formation_robots."""
    x0, y0, x1, y1 = world.arena
    blocked = [world.target.buffer(-spacing / 2), *world.obstacles]
    return shapely.difference(shapely.box(x0, y0, x1, y1), shapely.union_all(blocked))


def random_layout(world: World, n: int, spacing: float, rng: np.random.Generator,
                  clearance: float = 0.0) -> np.ndarray:
    """(n, 2) centres uniformly at random in the spawn areas, pairwise >= ``spacing`` apart
    and at least ``clearance`` (the body radius, units) from obstacles and the arena walls."""
    _check_random_capacity(world, n, spacing)
    spawn = _clear_of_walls(world, shapely.union_all(world.spawns), clearance)
    shapely.prepare(spawn)
    xmin, ymin, xmax, ymax = spawn.bounds
    cell = spacing / math.sqrt(2)
    grid: dict[tuple[int, int], int] = {}
    out = np.empty((n, 2))
    placed, tries = 0, 0
    while placed < n:
        tries += 1
        if tries > MAX_TRIES_PER_ROBOT * n:
            raise ConfigError(f"could not place {n} robots at random in the spawn areas "
                              f"(placed {placed})", source=world.source, key="robots")
        x, y = rng.uniform(xmin, xmax), rng.uniform(ymin, ymax)
        if not shapely.contains_xy(spawn, x, y) or _crowded(grid, out, x, y, cell, spacing):
            continue
        out[placed] = (x, y)
        grid[(int(x // cell), int(y // cell))] = placed
        placed += 1
    return out


def _clear_of_walls(world: World, spawn, clearance: float):
    """``spawn`` without the parts within ``clearance`` of an obstacle or the arena walls (the
    same shape, and so the same draws, where it keeps clear of them anyway)."""
    if clearance <= 0:
        return spawn
    x0, y0, x1, y1 = world.arena
    inside = shapely.box(x0 + clearance, y0 + clearance, x1 - clearance, y1 - clearance)
    walls = [ob.buffer(clearance) for ob in world.obstacles]
    if spawn.within(inside) and not any(spawn.intersects(w) for w in walls):
        return spawn
    return shapely.difference(spawn.intersection(inside), shapely.union_all(walls))


def _crowded(grid: dict, out: np.ndarray, x: float, y: float, cell: float, spacing: float) -> bool:
    cx, cy = int(x // cell), int(y // cell)
    for gx in range(cx - 2, cx + 3):
        for gy in range(cy - 2, cy + 3):
            j = grid.get((gx, gy))
            if j is not None and (out[j, 0] - x) ** 2 + (out[j, 1] - y) ** 2 < spacing**2:
                return True
    return False


def hex_offsets(n: int, spacing: float) -> np.ndarray:
    """(n, 2) offsets of the n lattice sites nearest the origin on a hexagonal lattice.

    Row 0 is the origin (the leader's place); ties are broken by angle, so the layout is fixed.
    """
    rings = math.ceil(math.sqrt(n / 3.0)) + 2
    pts = []
    for a in range(-rings * 2, rings * 2 + 1):
        for b in range(-rings * 2, rings * 2 + 1):
            pts.append((a + b / 2.0, b * math.sqrt(3) / 2.0))
    pts = np.array(pts) * spacing
    d = np.round(np.hypot(pts[:, 0], pts[:, 1]), 9)
    ang = np.round(np.arctan2(pts[:, 1], pts[:, 0]), 9)
    order = np.lexsort((ang, d))
    return pts[order[:n]]


def formation_centres(world: World, k: int, radius: float,
                      rng: np.random.Generator) -> np.ndarray:
    """(k, 2) random, well-spread centres in the spawn areas for formations of ``radius``.

    Centres are drawn where a whole formation fits inside the spawn areas when possible, then
    spread by farthest-point sampling, so the seed decides where each group starts.
    """
    spawn = shapely.union_all(world.spawns)
    room = spawn.buffer(-radius)
    region = room if room.area > 0 else spawn
    shapely.prepare(region)
    xmin, ymin, xmax, ymax = region.bounds
    cand = []
    for _ in range(200 * k * BOX_TRIES):
        if len(cand) == 200 * k:
            break
        x, y = rng.uniform(xmin, xmax), rng.uniform(ymin, ymax)
        if shapely.contains_xy(region, x, y):
            cand.append((x, y))
    else:  # the region fills little of its box (pieces far apart): draw piece by piece
        cand = _points_in(region, 200 * k, rng, world.source)
    cand = np.array(cand)
    chosen = [0]
    dist = np.hypot(*(cand - cand[0]).T)
    for _ in range(k - 1):
        nxt = int(np.argmax(dist))
        chosen.append(nxt)
        dist = np.minimum(dist, np.hypot(*(cand - cand[nxt]).T))
    return cand[chosen]


def _points_in(region, count: int, rng: np.random.Generator, source: str) -> np.ndarray:
    """(count, 2) points uniformly at random in ``region`` (a polygon or several): each
    point's piece is drawn by area, then the point within that piece's bounding box, so pieces
    far apart (a box mostly empty) cost no more than one piece."""
    pieces = list(getattr(region, "geoms", [region]))
    areas = np.array([piece.area for piece in pieces])
    which = rng.choice(len(pieces), size=count, p=areas / areas.sum())
    out = np.empty((count, 2))
    for j, piece in enumerate(pieces):
        slots = np.flatnonzero(which == j)
        shapely.prepare(piece)
        xmin, ymin, xmax, ymax = piece.bounds
        found = 0
        for _ in range(MAX_TRIES_PER_ROBOT * max(len(slots), 1)):
            if found == len(slots):
                break
            x, y = rng.uniform(xmin, xmax), rng.uniform(ymin, ymax)
            if shapely.contains_xy(piece, x, y):
                out[slots[found]] = (x, y)
                found += 1
        else:
            raise ConfigError("could not place the formations' centres in the spawn areas",
                              source=source, key="spawn")
    return out


def formation_layout(world: World, n: int, k: int, spacing: float, rng: np.random.Generator
                     ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """k hexagonal formations of about n/k robots each, placed at random in the spawn areas.

    Robots are assigned to lattice places at random, so ids carry no information about
    position (as with robots that pick their ids at random).

    Returns positions (n, 2), group ids (n,) in 1..k and the indices (k,) of the robots at the
    formations' centres: the leaders of groups 1..k.
    """
    sizes = [n // k + (1 if g < n % k else 0) for g in range(k)]
    radius = spacing * math.sqrt(max(sizes) * 0.866 / math.pi) + spacing
    centres = formation_centres(world, k, radius, rng)
    pos = [hex_offsets(size, spacing) + c for size, c in zip(sizes, centres, strict=True)]
    slots = np.vstack(pos)
    slot_group = np.concatenate([np.full(size, g + 1) for g, size in enumerate(sizes)])
    check_formation_floor(world, slots, n, k, spacing)
    crowded = _first_crowded_group(slots, slot_group, spacing)
    if crowded is not None:
        raise ConfigError(f"{k} formations of {sizes[crowded - 1]} robots do not fit apart in "
                          "the spawn areas", source=world.source, key="groups")
    centre_slots = np.cumsum([0] + sizes[:-1])
    order = rng.permutation(n)  # robot i stands at slot order[i]
    robot_at = np.empty(n, dtype=np.intp)
    robot_at[order] = np.arange(n)
    return slots[order], slot_group[order], robot_at[centre_slots]


def _first_crowded_group(slots: np.ndarray, group: np.ndarray, spacing: float) -> int | None:
    """The first group (1..k) with a robot closer than ``spacing`` (units) to another
    group's, or None. Only pairs within 2 spacing are measured (a k-d tree finds them), so
    memory follows the robots, not their pairs; their distances are np.hypot's, as a full
    matrix's would be."""
    pairs = cKDTree(slots).query_pairs(2 * spacing, output_type="ndarray")
    pairs = pairs[group[pairs[:, 0]] != group[pairs[:, 1]]]
    gaps = np.hypot(*(slots[pairs[:, 0]] - slots[pairs[:, 1]]).T)
    close = pairs[gaps < spacing]
    return int(group[close].min()) if len(close) else None


def check_formation_floor(world: World, slots: np.ndarray, n: int, k: int, spacing: float
                          ) -> None:
    """Refuse formations that would put robots where no robot can start.

    A formation larger than the spawn areas spills over onto the floor beside them, which is
    fine; but a robot behind the arena's walls, inside an obstacle or already on the target
    would make a silently wrong run. ``slots`` (n, 2) are the robots' places, spacing in units.
    """
    x0, y0, x1, y1 = world.arena
    half = spacing / 2
    xs, ys = slots[:, 0], slots[:, 1]
    outside = int(np.count_nonzero((xs <= x0 + half) | (xs >= x1 - half)
                                   | (ys <= y0 + half) | (ys >= y1 - half)))
    on_target = int(np.count_nonzero(shapely.contains_xy(world.target, xs, ys)))
    blocked = sum(int(np.count_nonzero(shapely.contains_xy(o.buffer(half), xs, ys)))
                  for o in world.obstacles)
    problems = [f"{count} {where}" for where, count in (
        ("behind the arena walls", outside), ("on the target", on_target),
        ("in obstacles", blocked)) if count]
    if problems:
        formations = "one formation" if k == 1 else f"{k} formations"
        raise ConfigError(
            f"{n} robots in {formations} at spacing {spacing:g} do not fit the spawn areas "
            f"(total area {world.spawn_area:.0f}): {', '.join(problems)}; use fewer robots or "
            "more groups, larger spawn areas, or start=random", source=world.source, key="robots")
