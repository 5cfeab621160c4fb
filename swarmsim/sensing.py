"""Local sensing: one whole-swarm neighbour search per tick, sliced into per-robot views.

A robot senses the robots within its controller's sensing range: their positions relative to
its own (world-aligned frame), distances, and what they broadcast last tick. It also has a floor
sensor (is the floor under me part of the target?) and a short-range floor probe. Nothing here
gives a controller a global position.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable

import numpy as np
import shapely
from scipy.spatial import cKDTree
from shapely.geometry import Polygon


class FloorSensor:
    """Floor sensing against the target polygon (the floor is painted; robots read it locally).

    Args:
        target: the target area.
        probe_range: largest probe offset a robot may look at, units.
    """

    def __init__(self, target: Polygon, probe_range: float):
        if probe_range <= 0:
            raise ValueError(f"probe_range must be positive, got {probe_range!r}")
        self.target = target
        shapely.prepare(self.target)
        self.probe_range = float(probe_range)

    def on_target(self, positions: np.ndarray) -> np.ndarray:
        """(N,) bool: is each robot's centre over the target?"""
        return shapely.contains_xy(self.target, positions[:, 0], positions[:, 1])

    def probe_at(self, x: float, y: float) -> Callable[[np.ndarray], bool]:
        """A probe for a robot at (x, y): ``probe(offset)`` tells if floor at +offset is target."""
        target, limit = self.target, self.probe_range

        def probe(offset: np.ndarray) -> bool:
            ox, oy = float(offset[0]), float(offset[1])
            if ox * ox + oy * oy > limit * limit * (1 + 1e-9):
                raise ValueError(f"probe offset {(ox, oy)} is beyond the probe range {limit}")
            return bool(shapely.contains_xy(target, x + ox, y + oy))

        return probe


NEIGHBOURHOOD_CHUNK = 2048
"""Robots per chunk of the neighbourhood pass (see NeighbourSearch.neighbourhoods)."""


class NeighbourSearch:
    """A k-d tree over all robot centres, built once per tick (scipy's cKDTree).

    Args:
        positions: (N, 2) robot centres at the start of the tick.
    """

    def __init__(self, positions: np.ndarray):
        self.positions = positions
        self.tree = cKDTree(positions)

    def neighbours(self, robots: np.ndarray, radius: float | np.ndarray) -> list[np.ndarray]:
        """For each robot index in ``robots``: indices of the others within ``radius``.

        ``radius`` is one value or one per robot. Each array is sorted by distance (ties by
        index), the robot itself excluded.
        """
        if len(robots) == 0:
            return []
        pos = self.positions
        lists = self.tree.query_ball_point(pos[robots], radius, return_sorted=True)
        out = []
        for i, lst in zip(robots.tolist(), lists, strict=True):
            idx = np.asarray(lst, dtype=np.intp)
            idx = idx[idx != i]
            d2 = ((pos[idx] - pos[i]) ** 2).sum(axis=1)
            out.append(idx[np.argsort(d2, kind="stable")])
        return out

    def neighbourhoods(self, robots: np.ndarray, radius: float | np.ndarray,
                       perturb: Callable[[np.ndarray], np.ndarray] | None = None
                       ) -> tuple[list[np.ndarray], list[np.ndarray], list[np.ndarray]]:
        """Like :meth:`neighbours`, with each robot's relative view, in one vectorised pass.

        Returns three lists aligned with ``robots``: neighbour indices (sorted by distance,
        ties by index, self excluded), their offsets (k, 2) relative to the robot and their
        distances (k,), in units. The same values as :meth:`neighbours` + :func:`relative_view`.
        ``perturb`` (sensing noise) maps all true offsets (P, 2) to sensed ones before sorting,
        so neighbours come sorted by sensed distance.

        Robots are taken ``NEIGHBOURHOOD_CHUNK`` at a time, which bounds the temporary arrays
        (a robot of a 10,000-robot formation listening at R_c = 15 has ~800 neighbours); the
        result is the same to the bit, ``perturb`` included (it is called on the chunks'
        offsets in order, and a numpy Generator's draws do not depend on how they are split).
        """
        radii = np.broadcast_to(np.asarray(radius, dtype=float), (len(robots),))
        views: tuple[list[np.ndarray], list[np.ndarray], list[np.ndarray]] = ([], [], [])
        for a in range(0, len(robots), NEIGHBOURHOOD_CHUNK):
            chunk = slice(a, a + NEIGHBOURHOOD_CHUNK)
            for out, part in zip(views, self._neighbourhood_chunk(robots[chunk], radii[chunk],
                                                                  perturb), strict=True):
                out.extend(part)
        return views

    def _neighbourhood_chunk(self, robots: np.ndarray, radii: np.ndarray,
                             perturb: Callable[[np.ndarray], np.ndarray] | None
                             ) -> tuple[list[np.ndarray], list[np.ndarray], list[np.ndarray]]:
        pos = self.positions
        lists = self.tree.query_ball_point(pos[robots], radii, return_sorted=True)
        counts = np.fromiter(map(len, lists), dtype=np.intp, count=len(lists))
        flat = np.fromiter(itertools.chain.from_iterable(lists), dtype=np.intp,
                           count=int(counts.sum()))
        del lists
        segment = np.repeat(np.arange(len(robots)), counts)
        src = robots[segment]
        keep = flat != src
        flat, src, segment = flat[keep], src[keep], segment[keep]
        offsets = pos[flat] - pos[src]
        if perturb is not None:
            offsets = perturb(offsets)
        d2 = offsets[:, 0] ** 2 + offsets[:, 1] ** 2
        order = by_segment_then_distance(segment, d2)
        flat, offsets = flat[order], offsets[order]
        distances = np.hypot(offsets[:, 0], offsets[:, 1])
        bounds = split_bounds(np.bincount(segment, minlength=len(robots)))
        return ([flat[a:b] for a, b in bounds], [offsets[a:b] for a, b in bounds],
                [distances[a:b] for a, b in bounds])

    def near_any(self, points: np.ndarray, radius: float) -> np.ndarray:
        """Sorted unique indices of robots within ``radius`` of any of ``points`` (M, 2)."""
        if len(points) == 0:
            return np.zeros(0, dtype=np.intp)
        lists = self.tree.query_ball_point(points, radius)
        if len(lists) == 0:
            return np.zeros(0, dtype=np.intp)
        return np.unique(np.concatenate([np.asarray(x, dtype=np.intp) for x in lists]))

    def pairs(self, radius: float) -> np.ndarray:
        """(P, 2) unique index pairs i < j closer than ``radius``."""
        return self.tree.query_pairs(radius, output_type="ndarray")


def by_segment_then_distance(segment: np.ndarray, d2: np.ndarray) -> np.ndarray:
    """The order that sorts entries by segment, then squared distance, then position.

    ``np.lexsort((position, d2, segment))`` in two stable passes: by d2, then by segment (a
    radix sort on 16-bit keys), several times faster. Entries come from ``query_ball_point``
    with sorted indices, so position order is index order: ties go to the smaller index.
    """
    if len(segment) and segment[-1] >= np.iinfo(np.int16).max:
        return np.lexsort((np.arange(len(d2)), d2, segment))
    by_distance = np.argsort(d2, kind="stable")
    return by_distance[np.argsort(segment.astype(np.int16)[by_distance], kind="stable")]


def split_bounds(counts: np.ndarray) -> list[tuple[int, int]]:
    """(start, end) of consecutive segments of the given lengths (faster than np.split)."""
    ends = np.cumsum(counts).tolist()
    return list(zip([0, *ends[:-1]], ends, strict=True))


def relative_view(positions: np.ndarray, i: int, idx: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Offsets (k, 2) of robots ``idx`` relative to robot ``i`` and their distances (k,)."""
    offsets = positions[idx] - positions[i]
    return offsets, np.hypot(offsets[:, 0], offsets[:, 1])
