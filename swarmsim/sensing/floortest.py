"""Is a point over the target? Compiled point-in-polygon tests for the floor sensor.

The target is a polygon with holes, of tens of edges, asked about a few hundred points a tick:
a crossing-number test over every edge (numba) answers that with no call into GEOS per batch.
A point counts when it lies in the interior, as shapely's ``contains_xy`` has it: a point
found on an edge (its cross product with the edge exactly zero, within the edge's box) is
outside. That is exact for axis-parallel edges; for others, points within rounding of the
edge may read either way, as they may in any floating-point test.
"""

from __future__ import annotations

import numpy as np
from numba import njit
from shapely.geometry import Polygon


def polygon_edges(polygon: Polygon) -> np.ndarray:
    """(E, 4) float64: every edge (x0, y0, x1, y1) of the polygon's outline and holes, units."""
    rings = [polygon.exterior, *polygon.interiors]
    parts = []
    for ring in rings:
        xy = np.asarray(ring.coords, dtype=np.float64)
        parts.append(np.hstack([xy[:-1], xy[1:]]))
    return np.ascontiguousarray(np.vstack(parts))


@njit(cache=True)
def inside(px, py, edges):  # pragma: no cover - compiled
    """Is (px, py) in the interior of the polygon whose edges (E, 4) are given?"""
    odd = False  # crossings so far
    for e in range(edges.shape[0]):
        x0, y0, x1, y1 = edges[e, 0], edges[e, 1], edges[e, 2], edges[e, 3]
        if (min(x0, x1) <= px <= max(x0, x1) and min(y0, y1) <= py <= max(y0, y1)
                and (x1 - x0) * (py - y0) - (y1 - y0) * (px - x0) == 0.0):
            return False  # on the boundary
        if (y0 > py) != (y1 > py) and px < (x1 - x0) * (py - y0) / (y1 - y0) + x0:
            odd = not odd
    return odd


@njit(cache=True)
def contains(xs, ys, edges):  # pragma: no cover - compiled
    """(N,) bool: is each point (xs[k], ys[k]), units, in the polygon's interior?"""
    out = np.empty(len(xs), dtype=np.bool_)
    for k in range(len(xs)):
        out[k] = inside(xs[k], ys[k], edges)
    return out


@njit(cache=True)
def probe(at, ks, offsets, limit2, edges):  # pragma: no cover - compiled
    """Robots' floor probes: (M,) bool, entry j is the floor at ``at[ks[j]] + offsets[j]``
    inside; and the first j whose offset reaches past ``limit2`` (squared units), or -1."""
    out = np.empty(len(ks), dtype=np.bool_)
    for j in range(len(ks)):
        ox, oy = offsets[j, 0], offsets[j, 1]
        if ox * ox + oy * oy > limit2:
            return out, j
        out[j] = inside(at[ks[j], 0] + ox, at[ks[j], 1] + oy, edges)
    return out, -1


@njit(cache=True)
def refresh(on_target, positions, before, edges):  # pragma: no cover - compiled
    """(N,) bool: ``on_target`` (the answers for the robots at ``before``) asked again only
    for the robots whose position differs from ``before`` (N, 2), units."""
    out = on_target.copy()
    for i in range(positions.shape[0]):
        if positions[i, 0] != before[i, 0] or positions[i, 1] != before[i, 1]:
            out[i] = inside(positions[i, 0], positions[i, 1], edges)
    return out


@njit(cache=True)
def edge_distance(xs, ys, edges):  # pragma: no cover - compiled
    """(N,) float64: each point's (xs[k], ys[k]) distance to the nearest edge (E, 4) of the
    polygon (outline or hole), units: how far the point is from where the floor changes."""
    out = np.empty(len(xs), dtype=np.float64)
    for k in range(len(xs)):
        px, py = xs[k], ys[k]
        best = np.inf
        for e in range(edges.shape[0]):
            x0, y0, x1, y1 = edges[e, 0], edges[e, 1], edges[e, 2], edges[e, 3]
            dx, dy = x1 - x0, y1 - y0
            length2 = dx * dx + dy * dy
            t = 0.0
            if length2 > 0.0:
                t = min(1.0, max(0.0, ((px - x0) * dx + (py - y0) * dy) / length2))
            ex, ey = x0 + t * dx - px, y0 + t * dy - py
            best = min(best, ex * ex + ey * ey)
        out[k] = np.sqrt(best)
    return out
