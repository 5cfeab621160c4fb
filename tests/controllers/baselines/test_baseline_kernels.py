"""The compiled kernels of the map-reading baselines (mean-shift, CVT) give the very numbers of
the numpy formulas they replaced, so their runs did not change to the bit."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from shapely.geometry import box

from controllers.common.localmap import probe_all
from controllers.common.mapbatch import MapRows
from controllers.common.mapkernel import lattice_values, window_within
from controllers.common.npsum import pairwise_sum
from controllers.common.push import push_away
from controllers.cvt import CVTParams
from controllers.cvt.kernel import owned
from controllers.cvt.robot import CVTRobot
from controllers.dash.kernel import spacing_view
from controllers.meanshift.kernel import explore, interact
from swarmsim.controller import NO_SENDER, RobotSetup
from swarmsim.sensing.sensing import FloorSensor


def test_pairwise_sum_is_numpys_sum_to_the_bit():
    """Sizes round numpy's block of 128 and its halving, nested calls and the stack beyond
    them (a plain running sum differs)."""
    rng = np.random.default_rng(3)
    for n in [*range(300), 511, 512, 513, 1031, 2047, 2048, 2049, 2100, 4099, 9000]:
        a = rng.random(n) * 10 ** rng.uniform(-3, 3)
        assert pairwise_sum(a, 0, n) == a.sum()
    a = rng.random(1000)
    assert pairwise_sum(a, 100, 700) == a[100:800].sum()
    for n in (0, 5, 77, 300):  # float32 sums in float32, as numpy's do
        b = rng.random(n).astype(np.float32)
        assert pairwise_sum(b, 0, n) == b.sum()
    assert b.sum() != b.astype(float).sum()  # float32 arithmetic shows
    running = 0.0
    for x in a:
        running += x
    assert running != a.sum()  # the test can tell the two sums apart


def test_cell_ownership_is_the_numpy_formulas_to_the_bit():
    """CVT's compiled ownership keeps exactly the points the table of squared distances kept,
    ties on the bisector (which stay the robot's) and no neighbours at all included."""
    rng = np.random.default_rng(7)
    for _ in range(200):
        q = rng.normal(size=(int(rng.integers(1, 300)), 2)) * 7
        others = rng.normal(size=(int(rng.integers(0, 25)), 2)) * 9
        if len(others):
            plain = (q * q).sum(1) <= ((q[:, None, :] - others) ** 2).sum(2).min(1)
        else:
            plain = np.ones(len(q), dtype=bool)
        assert np.array_equal(owned(q, others), plain)
    on_grid = np.array([(x, y) for x in range(-4, 5) for y in range(-4, 5)], dtype=float)
    neighbours = np.array([[2.0, 0.0], [0.0, -4.0], [3.0, 3.0]])
    ties = (on_grid * on_grid).sum(1) == ((on_grid[:, None] - neighbours) ** 2).sum(2).min(1)
    assert ties.sum() >= 9  # e.g. (1, y): as near the robot as the neighbour at (2, 0)
    plain = (on_grid * on_grid).sum(1) <= ((on_grid[:, None] - neighbours) ** 2).sum(2).min(1)
    assert np.array_equal(owned(on_grid, neighbours), plain)
    assert not owned(on_grid, neighbours).all()


def numpy_explore(points, target, offsets, distances, r_sense, r_occupied, kf, ke):
    """Mean-shift's exploring command as it was written in numpy."""
    q = points[target]
    if len(q) == 0:
        return np.zeros(2)
    d = np.sqrt((q * q).sum(axis=1))
    w = 0.5 * (1.0 + np.cos(np.pi * np.minimum(d / r_sense, 1.0)))
    out = np.zeros(2)
    if w.sum() > 0:
        out += kf * (w[:, None] * q).sum(axis=0) / w.sum()
    near = distances <= r_sense + r_occupied
    free = None
    if near.any():
        d2 = ((q[:, None, :] - offsets[near][None, :, :]) ** 2).sum(axis=2).min(axis=1)
        free = d2 > r_occupied ** 2
    wf, qf = (w, q) if free is None else (w[free], q[free])
    if wf.sum() > 0:
        out += ke * (wf[:, None] * qf).sum(axis=0) / wf.sum()
    return out


def numpy_interact(offsets, distances, messages, velocity, d_cover, r_sense, ka, kc):
    """Mean-shift's interaction command as it was written in numpy."""
    out = np.zeros(2)
    close = distances < d_cover
    if close.any():
        d = np.maximum(distances[close], 1e-6)
        push = (d_cover - d) / d
        out -= ka * (offsets[close] / d[:, None] * push[:, None]).sum(0)
    heard = (distances <= r_sense) & (messages["id"] != NO_SENDER)
    if heard.any() and kc > 0:
        vj = np.column_stack([messages["vx"][heard], messages["vy"][heard]])
        out -= kc * (velocity - vj.astype(float)).mean(axis=0)
    return out


def random_neighbourhood(rng):
    """Offsets, distances and broadcasts of 0-40 neighbours (a few silent, a few at 0)."""
    k = int(rng.integers(0, 40))
    offsets = rng.normal(size=(k, 2)) * 6
    if k > 2:
        offsets[0] = 0.0
    distances = np.hypot(offsets[:, 0], offsets[:, 1])
    messages = np.zeros(k, dtype=[("id", "i4"), ("status", "i1"), ("vx", "f4"), ("vy", "f4")])
    messages["id"] = np.where(rng.random(k) < 0.2, NO_SENDER, np.arange(k))
    messages["vx"], messages["vy"] = rng.normal(size=(2, k)) * 0.05
    return offsets, distances, messages


def test_mean_shift_kernels_match_the_numpy_formulas_to_the_bit():
    rng = np.random.default_rng(11)
    for _ in range(300):
        points = rng.normal(size=(int(rng.integers(0, 400)), 2)) * 6
        target = rng.random(len(points)) < rng.random()
        offsets, distances, messages = random_neighbourhood(rng)
        args = (10.0, 3.0, 0.025, 0.075)
        got = explore(points, target, offsets, distances, *args)
        assert got.tobytes() == numpy_explore(points, target, offsets, distances,
                                              *args).tobytes()
        velocity = rng.normal(size=2) * 0.05
        got = interact(offsets, distances, messages["id"], messages["vx"], messages["vy"],
                       velocity, 6.0, 10.0, 0.5, 1.0, NO_SENDER)
        want = numpy_interact(offsets, distances, messages, velocity, 6.0, 10.0, 0.5, 1.0)
        assert got.tobytes() == want.tobytes()


def test_dash_kernels_match_the_numpy_formulas_to_the_bit():
    rng = np.random.default_rng(13)
    for _ in range(300):
        offsets, distances, messages = random_neighbourhood(rng)
        status = rng.integers(-1, 3, size=len(distances)).astype(np.int8)
        spacing = rng.uniform(1, 6, size=len(distances)).astype(np.float32)
        peers = ((distances <= 9.0) & (messages["id"] != NO_SENDER) & (status != 0)
                 & (status >= 0))
        mean, close = spacing_view(distances, messages["id"], status, spacing, 9.0, 4.5,
                                   NO_SENDER, 0)
        if peers.any():
            assert mean == float(spacing[peers].mean())
        else:
            assert np.isnan(mean)
        assert close == int((distances < 4.5).sum())
        radius = rng.uniform(0.5, 8)
        near = distances < radius
        want = np.zeros(2)
        if near.any():
            d = np.maximum(distances[near], 1e-6)
            want = -0.05 * (offsets[near] * ((radius - d) / d)[:, None]).sum(axis=0)
        assert push_away(offsets, distances, radius, 0.05).tobytes() == want.tobytes()


def test_map_window_matches_the_numpy_selection():
    rng = np.random.default_rng(5)
    for _ in range(100):
        points = rng.integers(-12, 13, size=(625, 2)) * rng.uniform(0.25, 1.5)
        odo = rng.normal(size=2) * 3
        values = rng.integers(-1, 2, size=len(points)).astype(np.int8)
        radius = rng.uniform(0.5, 10)
        offsets, known, unknown, unknown_at = window_within(points, odo, radius * radius,
                                                            values)
        plain = points - odo
        keep = np.flatnonzero((plain * plain).sum(axis=1) <= radius * radius)
        assert offsets.tobytes() == plain[keep].tobytes()
        assert np.array_equal(known, values[keep])
        assert np.array_equal(unknown, keep[values[keep] < 0])
        assert np.array_equal(keep[unknown_at], unknown)


def test_lattice_values_match_the_numpy_lookup():
    """The lookup's lattice indices, window cells, values and points to probe, against the
    numpy formulas it replaced; offsets that leave the window and repeat a point included."""
    rng = np.random.default_rng(9)
    cell, size = 1.0, 31
    for _ in range(100):
        odo = rng.normal(size=2) * 4
        offsets = rng.uniform(-9, 9, size=(int(rng.integers(1, 200)), 2))
        offsets[-1] = offsets[0] + 0.01  # most likely the same lattice point
        origin = np.floor(odo / cell).astype(np.int64) - 12
        grid = rng.integers(-1, 2, size=(size, size)).astype(np.int8)
        values, local, unknown, points = lattice_values(odo, offsets, cell, origin, grid, 36.0)
        idx = np.floor((odo + offsets) / cell + 0.5).astype(np.int64)
        want_local = idx - origin
        ok = ((want_local >= 0) & (want_local < size)).all(axis=1)
        want = np.zeros(len(offsets), dtype=np.int8)
        want[ok] = grid[want_local[ok, 0], want_local[ok, 1]]
        near = np.array([(q := i * cell - odo) @ q <= 36.0 for i in idx])
        assert np.array_equal(local, want_local) and np.array_equal(values, want)
        assert np.array_equal(unknown, np.flatnonzero(ok & (want < 0) & near))
        assert points.tobytes() == (idx[unknown] * cell - odo).tobytes()


def test_floor_probe_many_answers_as_one_by_one():
    sensor = FloorSensor(box(0, 0, 10, 5), probe_range=6.0)
    probe = sensor.probe_at(2.0, 2.5)
    offsets = np.random.default_rng(2).uniform(-4, 4, size=(200, 2))
    one_by_one = np.array([probe(o) for o in offsets])
    assert np.array_equal(probe.many(offsets), one_by_one)
    assert np.array_equal(probe_all(lambda o: probe(o), offsets), one_by_one)  # no .many
    assert 0 < one_by_one.sum() < len(offsets)
    with pytest.raises(ValueError, match="beyond the probe range"):
        probe.many(np.array([[1.0, 0.0], [7.0, 0.0]]))
    at = np.array([2.0, 2.5]) + offsets
    assert np.array_equal(one_by_one, shapely.contains_xy(sensor.target, at[:, 0], at[:, 1]))


def test_a_still_cvt_robot_sleeps_once_its_sampling_disc_settles():
    """Asleep, a robot must answer as it would awake, so a still CVT robot sleeps only when
    its next cell is sampled in the same disc: a change within one grid step keeps the old
    disc; a larger one keeps it awake; two discs in turn count as settled."""
    robot = CVTRobot(RobotSetup(0), CVTParams(), np.random.default_rng(0))
    step = 3.5 / 7  # one grid step of a disc of radius 3.5
    robot.extent, robot.heard = 3.5 + 0.9 * step, 7.0 + 1.8 * step  # as cell() may leave it
    assert robot.settle_disc((3.5, 7.0))
    assert (robot.extent, robot.heard) == (3.5, 7.0)  # kept the disc it sampled in
    robot.extent, robot.heard = 3.5 + 1.2 * step, 7.0 + 2.4 * step
    assert not robot.settle_disc((3.5, 7.0))  # grown by more than a step: sample anew
    assert (robot.extent, robot.heard) == (3.5 + 1.2 * step, 7.0 + 2.4 * step)
    robot.extent, robot.heard = 3.5, 7.0  # ... and back: a cycle of two discs
    assert robot.settle_disc((3.5 + 1.2 * step, 7.0 + 2.4 * step))
    assert (robot.extent, robot.heard) == (3.5 + 1.2 * step, 7.0 + 2.4 * step)


def test_formation_kernels_match_the_numpy_formulas():
    """Kilobot's (and FCDFS's) neighbour tests, compiled, against the numpy they replaced."""
    from controllers.common import formationkernel as fk
    from controllers.common.gradient import INF_GRADIENT
    from controllers.kilobot import MESSAGE_FIELDS, TRAVEL, WAIT
    from swarmsim.controller import message_dtype

    rng = np.random.default_rng(11)
    dtype = message_dtype(MESSAGE_FIELDS)
    hits = {"low": 0, "parent": 0, "blocked": 0}
    for _ in range(400):
        k = int(rng.integers(0, 30))
        m = np.zeros(k, dtype=dtype)
        m["id"] = np.where(rng.random(k) < 0.15, NO_SENDER, rng.integers(0, 50, k))
        m["moving"] = rng.random(k) < 0.4
        m["status"] = rng.integers(0, 5, k)
        m["gradient"] = np.where(rng.random(k) < 0.2, INF_GRADIENT, rng.integers(0, 6, k))
        m.flags.writeable = False
        dist = np.sort(rng.uniform(0, 12, k))
        reach, grad, me = rng.uniform(0, 12), int(rng.integers(0, 6)), int(rng.integers(0, 50))
        heard = m["id"] != NO_SENDER
        ok = (dist <= reach) & ~m["moving"] & heard & (m["gradient"] < INF_GRADIENT)
        low = fk.lowest_gradient(dist, m, reach, NO_SENDER, INF_GRADIENT)
        assert low == (int(m["gradient"][ok].min()) if ok.any() else -1)
        parent = (dist <= reach) & ~m["moving"] & heard & (m["gradient"] == grad)
        first = fk.first_parent(dist, m, reach, grad, NO_SENDER)
        assert first == (int(np.flatnonzero(parent)[0]) if parent.any() else -1)
        quiet, start = rng.uniform(0, 12), rng.uniform(0, 12)
        near = (dist <= start) & heard & ((m["status"] == WAIT) | (m["status"] == TRAVEL))
        outranks = (m["gradient"] > grad) | ((m["gradient"] == grad) & (m["id"] > me))
        expected = ((dist <= quiet) & m["moving"] & heard).any() or (near & outranks).any()
        answer = fk.blocked(dist, m, quiet, start, grad, me, NO_SENDER, WAIT, TRAVEL)
        assert answer == expected
        hits["low"] += low >= 0
        hits["parent"] += first >= 0
        hits["blocked"] += bool(answer)
    assert all(40 < v < 360 for v in hits.values()), hits  # each test answered both ways


@pytest.mark.parametrize("radius, cell", [(10.0, 1.0), (5.0, 0.7), (2.0, 0.5)])
def test_map_rows_search_the_rim_for_the_points_the_whole_stencil_gives(radius, cell):
    """Robots walking in small steps (and now and then a long one) over a random floor: the
    points a chunk asks, searched on the rim after a robot's first sensing, are those the
    whole stencil's search asks, in the same order, to the bit; and the maps stay the same."""
    rng = np.random.default_rng(21)
    robots = 40
    rim_maps, full_maps = MapRows(robots, radius, cell), MapRows(robots, radius, cell)
    assert len(rim_maps.rim) < (2 * rim_maps.reach + 1) ** 2 / 2
    rows = rng.permutation(robots)[:30].astype(np.int64)
    small = asked_any = 0
    for tick in range(300):
        moved = rng.normal(size=(len(rows), 2)) * (0.12 * cell if tick % 9 else 2 * cell)
        small += int((np.hypot(moved[:, 0], moved[:, 1]) <= rim_maps.step).sum())
        asked = []
        for maps in (rim_maps, full_maps):
            if maps is full_maps:
                maps.sensed[:] = False  # the whole stencil every time
            asked.append((np.zeros(0, dtype=np.int64), np.zeros((0, 2))))  # none asked

            def probe_many(ks, offsets, maps=maps, asked=asked):
                asked[-1] = (ks.copy(), offsets.copy())
                return np.sin(3 * (maps.odo[rows[ks], 0] + offsets[:, 0])) > np.cos(
                    2 * (maps.odo[rows[ks], 1] + offsets[:, 1]))

            maps.sense(rows, moved, probe_many)
        (ks_rim, at_rim), (ks_full, at_full) = asked
        asked_any += len(ks_rim) > 0
        assert np.array_equal(ks_rim, ks_full) and at_rim.tobytes() == at_full.tobytes()
        assert np.array_equal(rim_maps.grid, full_maps.grid)
        assert np.array_equal(rim_maps.origin, full_maps.origin)
    assert small > 5000  # most steps searched the rim
    assert asked_any > 200  # most ticks asked points
