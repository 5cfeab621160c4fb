"""A world's travel floor: how far the farthest point of the target is from the spawn areas,
and how many ticks a robot at top speed needs to walk that far.

Definition (issue 70): the travel distance is the largest, over the points p of the free
target floor (the target minus its holes and the obstacles), of the length of the shortest
path from the spawn areas (their nearest point) to p. The path is a point's: it avoids the
obstacles' interiors (as the world gives them, not widened by a robot's radius, so a gap
narrower than a robot counts as open) and may cross the target's holes and the arena, whose
walls are convex and never lengthen a path. Without an obstacle in the way this is the
straight-line distance. The travel floor is that distance / v_max, in ticks: no robot leaving
the spawn areas can stand on the target's farthest point sooner.

How it is computed (pure geometry, nothing cached between calls):

- the distance of a point p: the straight segment to the nearest spawn point if no obstacle's
  interior cuts it (then it is exact); else the shortest of the straight first legs to each
  spawn edge's nearest point that are free, and of the paths through an obstacle vertex
  visible from p (a visibility graph over the obstacles' vertices, solved by Dijkstra), which
  is the exact shortest path among polygonal obstacles;
- the farthest point: the distance at every vertex of the free target floor, at points along
  its boundary and on a grid inside it (spacing SAMPLE_SHARE of the target's diagonal), then
  on a finer grid (REFINE_STEPS per spacing) round the best of those. The distance is
  1-Lipschitz along free paths, so the result is below the true maximum by at most
  0.71 x the fine spacing (well under 0.1 % of the distance); it is exact when the farthest
  point is a vertex of the target (always, with one convex spawn area and no obstacle).

Lengths in the world's units; the floor in ticks (v_max in units per tick).
"""

from __future__ import annotations

import heapq
import math

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from swarmsim.world.world import World

SAMPLE_SHARE = 1 / 250
"""Coarse sampling spacing of the target, as a share of its bounding box's diagonal."""
REFINE_STEPS = 8
"""The fine grid round the coarse maximum is REFINE_STEPS times denser."""
REFINE_CANDIDATES = 32
"""At most this many of the best coarse samples are refined."""
BLOCK_TOLERANCE = 1e-7
"""A segment is blocked when it cuts an obstacle shrunk by this much, units: paths may graze
an obstacle's edge or corner."""


def travel_distance(world: World) -> float:
    """The largest shortest-path distance from the spawn areas to a point of the free target
    floor, units (see the module's docstring). 0 when the target lies inside a spawn area;
    inf when obstacles wall part of the target off from every spawn area."""
    paths = _Paths(world)
    target = world.free_target
    x0, y0, x1, y1 = target.bounds
    step = max(math.hypot(x1 - x0, y1 - y0) * SAMPLE_SHARE, 1e-9)
    points = np.vstack([shapely.get_coordinates(target),
                        shapely.get_coordinates(shapely.segmentize(target.boundary, step)),
                        _grid_inside(target, (x0, y0, x1, y1), step)])
    reach = paths.distances(points)
    best = float(reach.max())
    near = np.flatnonzero(reach >= best - step * math.sqrt(2))
    near = near[np.argsort(-reach[near])][:REFINE_CANDIDATES]
    fine = step / REFINE_STEPS
    for x, y in points[near]:
        box = (x - step, y - step, x + step, y + step)
        extra = _grid_inside(target, box, fine)
        if len(extra):
            best = max(best, float(paths.distances(extra).max()))
    return best


def travel_floor_ticks(world: World, v_max: float) -> float:
    """The travel floor: :func:`travel_distance` / ``v_max`` (units per tick), in ticks (inf
    when no path reaches part of the target)."""
    if not (math.isfinite(v_max) and v_max > 0):
        raise ValueError(f"v_max must be positive and finite, got {v_max!r}")
    return travel_distance(world) / v_max


def _grid_inside(area: BaseGeometry, box: tuple[float, float, float, float],
                 step: float) -> np.ndarray:
    """(M, 2) points of a square grid of spacing ``step`` over ``box`` that lie in ``area``."""
    x0, y0, x1, y1 = box
    xs = np.arange(x0 + step / 2, x1, step)
    ys = np.arange(y0 + step / 2, y1, step)
    grid = np.stack(np.meshgrid(xs, ys), axis=-1).reshape(-1, 2)
    if not len(grid):
        return grid
    inside = shapely.contains_xy(area, grid[:, 0], grid[:, 1])
    return grid[inside]


class _Paths:
    """Shortest paths from a world's spawn areas round its obstacles (see the module)."""

    def __init__(self, world: World):
        self.spawn = shapely.union_all(world.spawns)
        self.edges = _edges(self.spawn)  # (E, 2, 2) the spawn areas' boundary segments
        self.blocker = None
        self.corners = np.empty((0, 2))
        self.corner_reach = np.empty(0)
        if world.obstacles:
            solid = shapely.union_all(world.obstacles)
            self.blocker = solid.buffer(-BLOCK_TOLERANCE, join_style="mitre")
            shapely.prepare(self.blocker)
            self.corners = np.unique(shapely.get_coordinates(solid.boundary), axis=0)
            self.corner_reach = self._dijkstra()

    def distances(self, points: np.ndarray) -> np.ndarray:
        """(M,) shortest-path distance from the spawn areas to each of ``points`` (M, 2)."""
        pts = shapely.points(points)
        nearest = shapely.shortest_line(pts, self.spawn)
        out = shapely.length(nearest)
        if self.blocker is None:
            return out
        blocked = np.flatnonzero(self._blocked(nearest))
        if len(blocked):
            out[blocked] = self._around(points[blocked])
        return out

    def _blocked(self, lines: np.ndarray) -> np.ndarray:
        return shapely.intersects(self.blocker, lines)

    def _first_legs(self, points: np.ndarray) -> np.ndarray:
        """(M,) the shortest free straight segment from each point to a spawn edge's nearest
        point (inf when every such segment is blocked)."""
        a, b = self.edges[:, 0], self.edges[:, 1]  # (E, 2)
        ab = b - a
        rel = points[:, None, :] - a[None]  # (M, E, 2)
        t = np.clip((rel * ab).sum(-1) / np.maximum((ab * ab).sum(-1), 1e-300), 0.0, 1.0)
        foot = a[None] + t[..., None] * ab[None]  # (M, E, 2)
        length = np.linalg.norm(points[:, None, :] - foot, axis=-1)
        segs = np.stack([np.broadcast_to(points[:, None, :], foot.shape), foot], axis=-2)
        blocked = self._blocked(shapely.linestrings(segs.reshape(-1, 2, 2)))
        length[blocked.reshape(length.shape) & (length > 0)] = np.inf
        return length.min(axis=1)

    def _around(self, points: np.ndarray) -> np.ndarray:
        """(M,) the shortest path to each point: a free first leg, or the way through a
        visible obstacle corner."""
        best = self._first_legs(points)
        for corner, reach in zip(self.corners, self.corner_reach, strict=True):
            if not math.isfinite(reach):
                continue
            segs = np.stack([points, np.broadcast_to(corner, points.shape)], axis=1)
            free = ~self._blocked(shapely.linestrings(segs))
            via = reach + np.linalg.norm(points - corner, axis=1)
            best = np.where(free & (via < best), via, best)
        return best

    def _dijkstra(self) -> np.ndarray:
        """(C,) shortest-path distance from the spawn areas to each obstacle corner."""
        corners = self.corners
        reach = self._first_legs(corners)
        count = len(corners)
        i, j = np.triu_indices(count, k=1)
        segs = np.stack([corners[i], corners[j]], axis=1)
        free = ~self._blocked(shapely.linestrings(segs))
        links: list[list[tuple[int, float]]] = [[] for _ in range(count)]
        for a, b in zip(i[free], j[free], strict=True):
            d = float(np.linalg.norm(corners[a] - corners[b]))
            links[a].append((b, d))
            links[b].append((a, d))
        heap = [(float(r), k) for k, r in enumerate(reach) if math.isfinite(r)]
        heapq.heapify(heap)
        while heap:
            d, k = heapq.heappop(heap)
            if d > reach[k]:
                continue
            for other, step in links[k]:
                if d + step < reach[other]:
                    reach[other] = d + step
                    heapq.heappush(heap, (d + step, other))
        return reach


def _edges(area: BaseGeometry) -> np.ndarray:
    """(E, 2, 2) the boundary segments of ``area``'s rings."""
    out = []
    for part in shapely.get_parts(area):
        for ring in shapely.get_rings(part):
            xy = shapely.get_coordinates(ring)
            out.append(np.stack([xy[:-1], xy[1:]], axis=1))
    return np.concatenate(out) if out else np.empty((0, 2, 2))
