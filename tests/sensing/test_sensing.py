"""The k-d tree neighbour search must agree with the pymunk point-query reference."""

import numpy as np
import pytest

from swarmsim.physics.physics import Physics
from swarmsim.sensing.sensing import FloorSensor, NeighbourSearch
from swarmsim.world.spawn import random_layout
from tests.conftest import square_world


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("radius", [1.5, 4.0, 9.0])
def test_kdtree_matches_pymunk_queries(seed, radius):
    world = square_world(spawn=30)
    pos = random_layout(world, 300, 1.0, np.random.default_rng(seed))
    physics = Physics(world, pos)
    search = NeighbourSearch(physics.read()[0])
    robots = np.arange(len(pos))
    fast = search.neighbours(robots, radius)
    total = 0
    for i in robots:
        ref = physics.neighbours_by_query(int(i), radius)
        assert sorted(fast[i].tolist()) == ref.tolist(), f"robot {i}"
        total += len(ref)
    assert total > 0


def test_neighbours_sorted_by_distance_without_self():
    pos = np.array([[0.0, 0.0], [3.0, 0.0], [1.0, 0.0], [0.0, 2.0], [50.0, 50.0]])
    nb = NeighbourSearch(pos).neighbours(np.array([0]), 5.0)[0]
    assert nb.tolist() == [2, 3, 1]


def test_floor_probe_and_range():
    world = square_world()
    floor = FloorSensor(world.target, probe_range=2.0)
    assert floor.on_target(np.array([[1.0, 1.0], [-1.0, 1.0]])).tolist() == [True, False]
    probe = floor.probe_at(0.5, 5.0)
    assert probe(np.array([0.4, 0.0]))
    assert not probe(np.array([-1.0, 0.0]))
    with pytest.raises(ValueError, match="probe range"):
        probe(np.array([3.0, 0.0]))


def test_neighbourhoods_match_neighbours_and_relative_view():
    from swarmsim.sensing.sensing import relative_view

    rng = np.random.default_rng(3)
    pos = rng.uniform(0, 20, (200, 2))
    pos[5] = pos[6] + [1.0, 0.0]  # ties in distance are broken by index
    pos[7] = pos[6] - [1.0, 0.0]
    search = NeighbourSearch(pos)
    robots = np.array([6, 0, 199, 42])
    radii = np.array([3.0, 0.01, 5.0, 8.0])
    idx, offsets, dists = search.neighbourhoods(robots, radii)
    for k, i in enumerate(robots):
        expected = search.neighbours(np.array([i]), radii[k])[0]
        np.testing.assert_array_equal(idx[k], expected)
        off, d = relative_view(pos, int(i), expected)
        np.testing.assert_array_equal(offsets[k], off)
        np.testing.assert_array_equal(dists[k], d)
    assert len(idx[1]) == 0 and offsets[1].shape == (0, 2)


def test_segment_then_distance_order_equals_lexsort_on_a_lattice_full_of_ties():
    from swarmsim.sensing.sensing import by_segment_then_distance

    rng = np.random.default_rng(4)
    rows, cols = np.meshgrid(np.arange(30), np.arange(30), indexing="ij")
    pos = np.stack([cols + 0.5 * (rows % 2), rows * np.sqrt(3) / 2], axis=-1).reshape(-1, 2)
    robots = rng.permutation(len(pos))[:300]
    idx, _, dists = NeighbourSearch(pos).neighbourhoods(robots, 3.0)
    search = NeighbourSearch(pos)
    for k, i in enumerate(robots):  # nearest first; equal distances by index
        np.testing.assert_array_equal(idx[k], search.neighbours(np.array([i]), 3.0)[0])
        assert np.all(np.diff(dists[k]) >= -1e-12)
    segment = np.repeat(np.arange(50), 40)
    d2 = rng.integers(0, 5, len(segment)).astype(float)  # many exact ties
    np.testing.assert_array_equal(by_segment_then_distance(segment, d2),
                                  np.lexsort((np.arange(len(d2)), d2, segment)))
    d2 = rng.random(len(segment)) * 225.0  # every bit of the doubles counts
    d2[::3] = np.nextafter(d2[1::3][: len(d2[::3])], np.inf)  # one ulp from a neighbour's
    d2[::17] = 0.0
    np.testing.assert_array_equal(by_segment_then_distance(segment, d2),
                                  np.lexsort((np.arange(len(d2)), d2, segment)))
    big = np.arange(70_000)  # too many segments for 16-bit keys: the lexsort path
    d2 = rng.random(len(big))
    np.testing.assert_array_equal(by_segment_then_distance(big, d2),
                                  np.lexsort((np.arange(len(d2)), d2, big)))



@pytest.mark.parametrize("segments", [50, 70_000])  # 16-bit radix passes; lexsort beyond
def test_segment_then_distance_breaks_ties_by_a_given_order(segments):
    """Entries in no order (as the dual-tree pass returns them), ties broken by ``order``."""
    from swarmsim.sensing.sensing import by_segment_then_distance

    rng = np.random.default_rng(segments)
    n = 3 * segments
    segment = rng.integers(0, segments, n)
    segment[-1] = segments - 1
    d2 = rng.integers(0, 4, n).astype(float)  # many exact ties
    neighbour = rng.permutation(n)
    by_neighbour = np.argsort(neighbour, kind="stable")
    want = np.lexsort((neighbour, d2, segment))
    np.testing.assert_array_equal(by_segment_then_distance(segment, d2, by_neighbour), want)
    np.testing.assert_array_equal(by_segment_then_distance(segment, d2),
                                  np.lexsort((np.arange(n), d2, segment)))

def test_neighbourhoods_in_chunks_equal_one_pass_noise_included(monkeypatch):
    from swarmsim.sensing import sensing

    rng = np.random.default_rng(5)
    rows, cols = np.meshgrid(np.arange(40), np.arange(40), indexing="ij")
    pos = np.stack([cols + 0.5 * (rows % 2), rows * np.sqrt(3) / 2], axis=-1).reshape(-1, 2)
    robots = rng.permutation(len(pos))[:500]
    radii = rng.uniform(0.5, 6.0, len(robots))
    search = NeighbourSearch(pos)

    def noisy(seed):  # sensing noise draws from one Generator, in order
        gen = np.random.default_rng(seed)
        return lambda off: off * (1 + 0.05 * gen.standard_normal(off.shape))

    monkeypatch.setattr(sensing, "NEIGHBOURHOOD_CHUNK", 10**9)
    whole = search.neighbourhoods(robots, radii, perturb=noisy(1))
    monkeypatch.setattr(sensing, "NEIGHBOURHOOD_CHUNK", 7)
    chunked = search.neighbourhoods(robots, radii, perturb=noisy(1))
    assert sum(len(x) for x in whole[0]) > 10_000
    for a, b in zip(whole, chunked, strict=True):
        assert len(a) == len(b) == len(robots)
        for x, y in zip(a, b, strict=True):
            np.testing.assert_array_equal(x, y)
    scalar = search.neighbourhoods(robots, 3.0)  # one radius for all, also chunked
    np.testing.assert_array_equal(scalar[0][3], search.neighbours(robots[3:4], 3.0)[0])


@pytest.mark.parametrize("spread", [1e9, 2.0])  # one pass at the largest radius; per radius
def test_neighbourhoods_keep_exactly_the_robots_within_each_robots_own_radius(spread,
                                                                             monkeypatch):
    """Mixed radii (dual-tree passes, then each robot's own radius) on robots at the radius,
    one ulp inside and one ulp outside it: the same sets as query_ball_point."""
    from scipy.spatial import cKDTree

    from swarmsim.sensing import sensing

    monkeypatch.setattr(sensing, "RADIUS_SPREAD", spread)

    rng = np.random.default_rng(8)
    centres = rng.uniform(0, 100, (40, 2))
    radii = rng.choice([1.5, 6.0, 12.0, 15.0], len(centres))
    ring = []
    for c, r in zip(centres, radii, strict=True):
        for angle in rng.uniform(0, 2 * np.pi, 6):
            for dist in (np.nextafter(r, 0), r, np.nextafter(r, np.inf)):
                ring.append(c + dist * np.array([np.cos(angle), np.sin(angle)]))
    pos = np.vstack([centres, ring, rng.uniform(0, 100, (300, 2))])
    robots = np.arange(len(centres))
    idx, _, _ = NeighbourSearch(pos).neighbourhoods(robots, radii)
    reference = cKDTree(pos).query_ball_point(pos[robots], radii)
    for k, i in enumerate(robots):
        assert sorted(idx[k].tolist()) == sorted(set(reference[k]) - {int(i)}), f"robot {i}"
    assert sum(map(len, idx)) > 6 * len(centres)


def test_pairs_near_equals_query_ball_point_self_included():
    from scipy.spatial import cKDTree

    rng = np.random.default_rng(9)
    pos = rng.uniform(0, 40, (400, 2))
    pos[1] = pos[0] + [2.5, 0.0]  # exactly at the radius
    robots = np.array([0, 5, 17, 399])
    k, near = NeighbourSearch(pos).pairs_near(robots, 2.5)
    src = robots[k]
    reference = cKDTree(pos).query_ball_point(pos[robots], 2.5)
    for i, expected in zip(robots, reference, strict=True):
        assert sorted(near[src == i].tolist()) == sorted(expected)
    assert 1 in near[src == 0] and 0 in near[src == 0]
    empty = NeighbourSearch(pos).pairs_near(np.zeros(0, dtype=np.intp), 2.5)
    assert len(empty[0]) == len(empty[1]) == 0


def _random_views_case(rng: np.random.Generator, trial: int):
    """Positions, robots and radii with the awkward cases: lattice ties, coincident robots,
    radius 0, repeated robots, views longer than the insertion sort's limit."""
    n = int(rng.integers(1, 400))
    pos = rng.uniform(0, rng.uniform(1, 60), size=(n, 2))
    if trial % 3 == 0:
        pos = np.round(pos * 2) / 2  # many equal distances
    if trial % 5 == 0:
        pos[: n // 4] = pos[0]  # robots on top of each other
    robots = rng.choice(n, size=int(rng.integers(1, n + 1)), replace=bool(trial % 2))
    if trial % 4:
        radii = rng.choice([0.0, 0.5, 1.0, 3.0, 12.0, 40.0], size=len(robots))
    else:
        radii = np.full(len(robots), 2.0)
    return pos, robots, radii


def test_compiled_views_equal_the_kdtree_views_to_the_bit():
    rng = np.random.default_rng(11)
    longest = 0
    for trial in range(120):
        pos, robots, radii = _random_views_case(rng, trial)
        fast = NeighbourSearch(pos).neighbourhoods_flat(robots, radii)
        ref = NeighbourSearch(pos, compiled=False).neighbourhoods_flat(robots, radii)
        for field in ("neighbours", "offsets", "distances", "counts"):
            a, b = getattr(fast, field), getattr(ref, field)
            assert a.shape == b.shape and np.array_equal(a, b), (trial, field)
        longest = max(longest, int(ref.counts.max()))
    assert longest > 64  # long views were sorted too


def test_compiled_views_on_a_lattice_full_of_exact_ties():
    """Integer lattice: whole rings of neighbours at the same squared distance, which the
    compiled sort's buckets must leave in index order, as the k-d tree path does."""
    xs, ys = np.meshgrid(np.arange(30.0), np.arange(30.0))
    pos = np.column_stack((xs.ravel(), ys.ravel()))[np.random.default_rng(3).permutation(900)]
    robots = np.arange(0, 900, 7)
    for radius in (1.0, 2.0, 5.0, 9.0):
        fast = NeighbourSearch(pos).neighbourhoods_flat(robots, radius)
        ref = NeighbourSearch(pos, compiled=False).neighbourhoods_flat(robots, radius)
        assert np.array_equal(fast.neighbours, ref.neighbours), radius
        assert np.array_equal(fast.offsets, ref.offsets), radius
    assert fast.counts.max() > 200  # views of a few hundred rows, mostly ties


def test_compiled_views_over_a_wide_sparse_swarm():
    """A tiny radius over a wide swarm: the grid gets coarser cells, the views stay equal."""
    rng = np.random.default_rng(4)
    pos = rng.uniform(0, 1e5, (3000, 2))
    pos[1] = pos[0] + [0.05, 0.0]
    robots = np.arange(3000)
    fast = NeighbourSearch(pos).neighbourhoods_flat(robots, 0.1)
    ref = NeighbourSearch(pos, compiled=False).neighbourhoods_flat(robots, 0.1)
    assert np.array_equal(fast.neighbours, ref.neighbours)
    assert np.array_equal(fast.counts, ref.counts) and fast.neighbours[:2].tolist() == [1, 0]


def test_compiled_pairs_near_equal_the_kdtree_pairs():
    rng = np.random.default_rng(5)
    for trial in range(40):
        pos, robots, radii = _random_views_case(rng, trial)
        radius = float(radii[0])
        pairs = [NeighbourSearch(pos, compiled=c).pairs_near(robots, radius)
                 for c in (True, False)]
        fast, ref = ({(int(k), int(j)) for k, j in zip(*p, strict=True)} for p in pairs)
        assert fast == ref and len(pairs[0][0]) == len(pairs[1][0]), trial


def test_compiled_views_compile_once_whatever_arrays_callers_pass():
    """Read-only, broadcast, strided or int32 inputs take the one compiled signature, so a
    run never compiles inside its clock (Simulation warms the kernels up before)."""
    from swarmsim.sensing import cellsearch

    rng = np.random.default_rng(2)
    pos = rng.uniform(0, 20, (300, 4))[:, ::2]  # strided
    pos.flags.writeable = False
    robots = np.arange(0, 300, 3, dtype=np.int32)
    radii = np.broadcast_to(3.0, robots.shape)  # read-only, stride 0
    cellsearch.warm_up()
    fast = cellsearch.cell_views(pos, robots, radii)
    ref = NeighbourSearch(np.ascontiguousarray(pos), compiled=False).neighbourhoods_flat(
        robots.astype(np.intp), 3.0)
    assert np.array_equal(fast[0], ref.neighbours) and np.array_equal(fast[1], ref.offsets)
    assert len(cellsearch._views.signatures) == 1


def test_cell_views_refuse_positions_that_are_not_finite():
    from swarmsim.sensing.cellsearch import cell_views

    robots, radii = np.arange(3, dtype=np.int64), np.full(3, 5.0)
    for bad in (np.nan, np.inf, -np.inf):
        positions = np.zeros((3, 2))
        positions[2, 1] = bad
        with pytest.raises(ValueError, match="must be finite"):
            cell_views(positions, robots, radii)
    flat, _, _, counts = cell_views(np.zeros((3, 2)), robots, radii)
    assert counts.tolist() == [2, 2, 2] and len(flat) == 6
