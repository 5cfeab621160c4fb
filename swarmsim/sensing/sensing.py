"""Local sensing: one whole-swarm neighbour search per tick, sliced into per-robot views.

A robot senses the robots within its controller's sensing range: their positions relative to
its own (world-aligned frame), distances, and what they broadcast last tick. It also has a floor
sensor (is the floor under me part of the target?) and a short-range floor probe. Nothing here
gives a controller a global position.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import NamedTuple

import numpy as np
from scipy.spatial import cKDTree
from shapely.geometry import Polygon

from swarmsim.sensing import floortest
from swarmsim.sensing.cellsearch import cell_views


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
        self._edges = floortest.polygon_edges(target)
        self.probe_range = float(probe_range)

    def on_target(self, positions: np.ndarray) -> np.ndarray:
        """(N,) bool: is each robot's centre over the target (its interior)?"""
        return floortest.contains(positions[:, 0], positions[:, 1], self._edges)

    def on_target_after(self, on_target: np.ndarray, positions: np.ndarray,
                        before: np.ndarray) -> np.ndarray:
        """:meth:`on_target` at ``positions`` (N, 2), given its answers ``on_target`` at
        ``before``: asked again only for robots that moved (a robot where it was reads the
        same floor)."""
        return floortest.refresh(on_target, positions, before, self._edges)

    def edge_distance(self, positions: np.ndarray) -> np.ndarray:
        """(N,) each of ``positions`` (N, 2)'s distance to the target's nearest edge (its
        outline or a hole's), units: how near a robot there is to where its floor reading
        changes."""
        at = np.ascontiguousarray(positions, dtype=np.float64)
        return floortest.edge_distance(at[:, 0], at[:, 1], self._edges)

    def probes(self, at: np.ndarray) -> Callable[[np.ndarray, np.ndarray], np.ndarray]:
        """Many robots' probes in one query, for robots at ``at`` (R, 2), units:
        ``probes(at)(ks, offsets)`` is (M,) bool, entry j the floor at robot ``ks[j]``'s
        position plus ``offsets[j]`` (each within the probe range)."""
        limit2 = self.probe_range * self.probe_range * (1 + 1e-9)
        at = np.ascontiguousarray(at, dtype=np.float64)

        def probe_many(ks: np.ndarray, offsets: np.ndarray) -> np.ndarray:
            offsets = np.ascontiguousarray(offsets, dtype=np.float64).reshape(-1, 2)
            ks = np.ascontiguousarray(ks, dtype=np.intp)
            found, beyond = floortest.probe(at, ks, offsets, limit2, self._edges)
            if beyond >= 0:
                raise ValueError(f"probe offset {tuple(offsets[beyond].tolist())} is beyond "
                                 f"the probe range {self.probe_range}")
            return found

        return probe_many

    def probe_at(self, x: float, y: float) -> FloorProbe:
        """A probe for a robot at (x, y): ``probe(offset)`` tells if floor at +offset is target."""
        return FloorProbe(self._edges, self.probe_range, x, y)


class FloorProbe:
    """One robot's floor probe for one tick: is the floor at its position plus an offset part
    of the target? (A Perception's ``probe``.)

    Args:
        edges: the target's edges (floortest.polygon_edges).
        limit: the probe's reach, units.
        x, y: the robot's position, units (held privately: a controller may only ask).
    """

    __slots__ = ("_edges", "_limit", "_x", "_y")  # private: the controller only asks

    def __init__(self, edges: np.ndarray, limit: float, x: float, y: float):
        self._edges, self._limit, self._x, self._y = edges, limit, x, y

    def __call__(self, offset: np.ndarray) -> bool:
        """Is the floor at +``offset`` (2,), units, target?"""
        ox, oy = float(offset[0]), float(offset[1])
        if self._beyond(ox, oy):
            raise self._too_far(ox, oy)
        return bool(floortest.inside(self._x + ox, self._y + oy, self._edges))

    def many(self, offsets: np.ndarray) -> np.ndarray:
        """(k,) bool: the same for each row of ``offsets`` (k, 2), units, in one query."""
        ox, oy = offsets[:, 0], offsets[:, 1]
        beyond = self._beyond(ox, oy)
        if beyond.any():
            first = offsets[np.argmax(beyond)]
            raise self._too_far(float(first[0]), float(first[1]))
        return floortest.contains(self._x + ox, self._y + oy, self._edges)

    def _beyond(self, ox: float | np.ndarray, oy: float | np.ndarray) -> bool | np.ndarray:
        """Whether offset (ox, oy), units (floats or arrays), is past the probe's reach."""
        return ox * ox + oy * oy > self._limit * self._limit * (1 + 1e-9)

    def _too_far(self, ox: float, oy: float) -> ValueError:
        return ValueError(f"probe offset {(ox, oy)} is beyond the probe range {self._limit}")


NEIGHBOURHOOD_CHUNK = 2048
"""Robots per chunk of the neighbourhood pass (see NeighbourSearch.neighbourhoods)."""

RADIUS_SPREAD = 2.0
"""Robots whose listening radii differ by more than this factor are searched in separate
passes (see NeighbourSearch._pairs_within)."""


class FlatViews(NamedTuple):
    """Several robots' neighbourhood views in flat arrays (:meth:`NeighbourSearch.
    neighbourhoods_flat`): robot k owns ``counts[k]`` rows, right after robot k-1's."""

    neighbours: np.ndarray
    """(P,) neighbour indices, each robot's nearest first (ties by index)."""
    offsets: np.ndarray
    """(P, 2) the neighbours' positions relative to the robot, units."""
    distances: np.ndarray
    """(P,) their distances, units."""
    counts: np.ndarray
    """(R,) rows per robot."""


class NeighbourSearch:
    """All robot centres at the start of a tick, searched for neighbours.

    A tick's views and wake pairs come from a compiled cell-grid pass (swarmsim.sensing.cellsearch);
    the other queries from a k-d tree (scipy's cKDTree), built when first needed. Both give
    the same views to the bit (tests/sensing/test_sensing.py).

    Args:
        positions: (N, 2) robot centres at the start of the tick.
        compiled: False takes the k-d tree for everything (the reference path).
    """

    def __init__(self, positions: np.ndarray, compiled: bool = True):
        self.positions = positions
        self.compiled = compiled

    @functools.cached_property
    def tree(self) -> cKDTree:
        """The k-d tree over all centres (built on first use)."""
        return cKDTree(self.positions)

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
        so neighbours come sorted by sensed distance. (:meth:`neighbourhoods_flat` gives the
        same views as flat arrays.)
        """
        views = self.neighbourhoods_flat(robots, radius, perturb)
        bounds = split_bounds(views.counts)
        return ([views.neighbours[a:b] for a, b in bounds],
                [views.offsets[a:b] for a, b in bounds],
                [views.distances[a:b] for a, b in bounds])

    def neighbourhoods_flat(self, robots: np.ndarray, radius: float | np.ndarray,
                            perturb: Callable[[np.ndarray], np.ndarray] | None = None
                            ) -> FlatViews:
        """:meth:`neighbourhoods` as flat arrays: robot k's rows follow robot k-1's.

        Robots are taken ``NEIGHBOURHOOD_CHUNK`` at a time, which bounds the temporary arrays
        (a robot of a 10,000-robot formation listening at R_c = 15 has ~800 neighbours); the
        result is the same to the bit, ``perturb`` included (it is called on the chunks'
        offsets in order, and a numpy Generator's draws do not depend on how they are split).
        """
        radii = as_radii(radius, len(robots))
        parts = [self._neighbourhood_chunk(robots[a:a + NEIGHBOURHOOD_CHUNK],
                                           radii[a:a + NEIGHBOURHOOD_CHUNK], perturb)
                 for a in range(0, len(robots), NEIGHBOURHOOD_CHUNK)]
        if len(parts) == 1:
            return parts[0]
        if not parts:
            return FlatViews(np.zeros(0, dtype=np.intp), np.zeros((0, 2)), np.zeros(0),
                             np.zeros(0, dtype=np.intp))
        return FlatViews(*(np.concatenate(field) for field in zip(*parts, strict=True)))

    def _neighbourhood_chunk(self, robots: np.ndarray, radii: np.ndarray,
                             perturb: Callable[[np.ndarray], np.ndarray] | None) -> FlatViews:
        if perturb is None and self.compiled:  # ~4x faster, the same views
            flat, offsets, d2, counts = cell_views(self.positions, robots, radii)
            return FlatViews(flat, offsets, np.sqrt(d2), counts)
        segment, flat, offsets, d2 = self._pairs_within(robots, radii)
        order = stable_radix_order(flat.astype(np.uint64), index_bits(len(self.positions)))
        if perturb is not None:  # the noise is drawn in (segment, neighbour) order
            order = stable_radix_order(segment.astype(np.uint64), index_bits(len(robots)), order)
            segment, flat = segment[order], flat[order]
            offsets = perturb(rows(offsets, order))
            d2 = offsets[:, 0] ** 2 + offsets[:, 1] ** 2
            order = None  # ties: as they now come, by neighbour
        # one sort by (segment, distance, neighbour): a total order, so the same views as
        # sorting by (segment, neighbour) first
        order = by_segment_then_distance(segment, d2, order)
        flat, offsets = flat[order], rows(offsets, order)
        distances = distances_of(offsets)
        return FlatViews(flat, offsets, distances, np.bincount(segment, minlength=len(robots)))

    def _pairs_within(self, robots: np.ndarray, radii: np.ndarray
                      ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(segment, neighbour, offset, squared distance) of every other robot within the
        radius of ``robots[segment]``, in no particular order; offsets (P, 2) are the
        neighbours' positions relative to that robot, units (squared distances: units^2).

        The path of sensing noise and of ``compiled`` False: pairs from :meth:`pairs_near`
        (the cell grid, or with ``compiled`` False dual-tree passes: scipy's
        sparse_distance_matrix, arrays all the way), then each robot's own radius on the same
        squared distances the search compares. One pass at the largest radius while the radii are
        within RADIUS_SPREAD of each other, else one pass per distinct radius, so that a few
        robots listening far do not make every robot's query that wide.
        """
        pos = self.positions
        if len(robots) == 0:
            return (np.zeros(0, dtype=np.intp), np.zeros(0, dtype=np.intp), np.zeros((0, 2)),
                    np.zeros(0))
        if radii.max() <= RADIUS_SPREAD * radii.min():
            passes = [np.arange(len(robots))]
        else:
            passes = [np.flatnonzero(radii == r) for r in np.unique(radii)]
        found = [self.pairs_near(robots[members], float(radii[members].max()))
                 for members in passes]
        segment = np.concatenate([members[k] for members, (k, _) in zip(passes, found,
                                                                         strict=True)])
        flat = np.concatenate([near for _, near in found])
        src = robots[segment]
        offsets = rows(pos, flat) - rows(pos, src)
        d2 = offsets[:, 0] ** 2 + offsets[:, 1] ** 2
        keep = (d2 <= radii[segment] ** 2) & (flat != src)
        return segment[keep], flat[keep], offsets[keep], d2[keep]

    def pairs_near(self, robots: np.ndarray, radius: float) -> tuple[np.ndarray, np.ndarray]:
        """Pairs (k, other): robot ``other`` is within ``radius`` (units) of ``robots[k]``;
        each robot is paired with itself too; unordered. The compiled cell-grid pass, or with
        ``compiled`` False one dual-tree pass (scipy's sparse_distance_matrix)."""
        if len(robots) == 0:
            return np.zeros(0, dtype=np.intp), np.zeros(0, dtype=np.intp)
        if self.compiled:
            radii = np.full(len(robots), float(radius))
            near, _, _, counts = cell_views(self.positions, robots, radii, ordered=False)
            k = np.repeat(np.arange(len(robots)), counts)
            mine = np.arange(len(robots))  # each robot is paired with itself too
            return np.concatenate((k, mine)), np.concatenate((near, robots.astype(np.intp)))
        pairs = cKDTree(self.positions[robots]).sparse_distance_matrix(
            self.tree, float(radius), output_type="ndarray")
        return pairs["i"].astype(np.intp), pairs["j"].astype(np.intp)

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


def as_radii(radius: float | np.ndarray, n: int) -> np.ndarray:
    """(n,) float64 radii (units): ``radius`` itself when it already is that (the tick's
    listening ranges), else broadcast (numpy's broadcast_to costs microseconds a call)."""
    if isinstance(radius, np.ndarray) and radius.dtype == np.float64 and radius.shape == (n,):
        return radius
    return np.broadcast_to(np.asarray(radius, dtype=float), (n,))


def stable_radix_order(keys: np.ndarray, bits: int, order: np.ndarray | None = None
                       ) -> np.ndarray:
    """Stable sort of ``keys[order]`` (unsigned 64-bit) on their lowest ``bits`` bits.

    LSD radix sort, 16 bits a pass (numpy's stable argsort is a radix sort on 16-bit keys).
    Returns the indices into ``keys``; ``order`` (default: 0..n-1) breaks ties.
    """
    order = np.arange(len(keys)) if order is None else order
    for shift in range(0, bits, 16):
        digit = (keys[order] >> np.uint64(shift)).astype(np.uint16)  # wraps: the low 16 bits
        order = order[np.argsort(digit, kind="stable")]
    return order


def index_bits(n: int) -> int:
    """Bits that hold every index below ``n`` in whole 16-bit radix passes (16 or 32)."""
    return 16 if n <= 1 << 16 else 32


def by_segment_then_distance(segment: np.ndarray, d2: np.ndarray,
                             order: np.ndarray | None = None) -> np.ndarray:
    """The order that sorts entries by segment, then squared distance, then ``order``.

    ``order`` (default: the entries as they come) is the order of the entries that decides
    ties. ``np.lexsort((rank in order, d2, segment))`` as five stable 16-bit radix passes,
    2-3x faster than a stable sort of the floats: four on the bits of ``d2`` (non-negative
    doubles sort like their bit patterns read as unsigned integers), then one on the segment.
    """
    if len(segment) and int(segment.max()) >= 1 << 16:
        rank = np.arange(len(d2))
        if order is not None:
            rank = np.empty_like(rank)
            rank[order] = np.arange(len(d2))
        return np.lexsort((rank, d2, segment))
    order = stable_radix_order(np.ascontiguousarray(d2, dtype=np.float64).view(np.uint64), 64,
                               order)
    return stable_radix_order(segment.astype(np.uint64), 16, order)


def rows(a: np.ndarray, index: np.ndarray) -> np.ndarray:
    """``a[index]`` for a 2-D array and an integer index: the same rows, ~10x faster (numpy
    2.x gathers whole rows with ``take`` far faster than with fancy indexing)."""
    return np.take(a, index, axis=0)


def split_bounds(counts: np.ndarray) -> list[tuple[int, int]]:
    """(start, end) of consecutive segments of the given lengths (faster than np.split)."""
    ends = np.cumsum(counts).tolist()
    return list(zip([0, *ends[:-1]], ends, strict=True))


def relative_view(positions: np.ndarray, i: int, idx: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Offsets (k, 2) of robots ``idx`` relative to robot ``i`` and their distances (k,)."""
    offsets = positions[idx] - positions[i]
    return offsets, distances_of(offsets)


def distances_of(offsets: np.ndarray) -> np.ndarray:
    """(k,) the lengths of ``offsets`` (k, 2), units: sqrt(x*x + y*y), correctly rounded from
    the squared distance the neighbour search compares (not libm's slower ``hypot``, which
    differs from it by at most an ulp)."""
    return np.sqrt(offsets[:, 0] * offsets[:, 0] + offsets[:, 1] * offsets[:, 1])
