"""Mean-shift's robots as arrays (MeanShiftSwarm, compiled chunks) make the very runs of the
per-robot controller (MeanShiftRobot), to the bit: positions every tick, broadcasts, floor
readings, the summary and the sleep decisions.

GOLDEN holds the hashes of the per-robot controller's runs, recorded at 2807bdb (before
the swarm existed), as tests/runhash.py fingerprints a run: a change of the
algorithm, of its float order or of when a robot sleeps changes them.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numba import njit

from controllers.common.pyhypot import py_hypot as hypot
from controllers.meanshift import MeanShift, MeanShiftParams, MeanShiftRobot
from controllers.meanshift.swarm import MeanShiftSwarm
from swarmsim import Simulation
from swarmsim.controller import (
    DecideBatch,
    NeighbourBatch,
    Perception,
    RobotSetup,
    message_dtype,
    silent_message,
)
from tests.restorecheck import restored_goes_on, run_for
from tests.runhash import run_hash, run_trace

GOLDEN = {  # (world, seed, ticks): run_hash of the per-robot controller at 2807bdb
    ("tiny", 0, 520): "1cc88ffd1ea2e8f8",  # its robots start to sleep at about tick 450
    ("K", 1, 200): "36f42def81341a2b",
}


@pytest.mark.parametrize("world, seed, ticks", sorted(GOLDEN))
def test_swarm_runs_hash_as_the_per_robot_controller_did(world, seed, ticks):
    assert run_hash(world, MeanShift, seed, ticks, {}) == GOLDEN[world, seed, ticks]


NOISY = {"distance_noise": 0.05, "bearing_noise": 0.05, "speed_noise": 0.05,
         "message_loss": 0.1}



@pytest.mark.parametrize("settings", [
    {}, NOISY, {"map_cell": 0.7, "r_occupied": 2.5, "r_sense": 8.0}],
    ids=["plain", "noisy", "other lattice"])
def test_swarm_and_per_robot_controller_make_the_same_run(settings, monkeypatch):
    """The same run, tick for tick, with the same summary (decisions: the same robots slept
    at the same ticks), the swarm deciding 7 robots at a time (tiny's 40 are one chunk)."""
    per_robot = run_trace(MeanShiftRobot, settings, 480)
    monkeypatch.setattr("swarmsim.engine.sim.DECIDE_CHUNK", 7)
    (pa, sa, ma, suma, ta), (pb, sb, mb, sumb, tb) = run_trace(MeanShift, settings, 480), per_robot
    assert np.array_equal(pa, pb) and np.array_equal(sa, sb)
    assert ma == mb and ta == tb
    assert suma == sumb
    assert sa.any() and not sa.all()  # robots slept, and not all of them


def test_a_restored_run_goes_on_as_the_run(tmp_path):
    """The swarm's arrays (odometry, velocities, statuses, maps) are all a checkpoint needs."""
    run = run_for("meanshift", seed=1, ticks=150, max_ticks=400)
    restored = restored_goes_on(run, tmp_path, 100)
    assert np.array_equal(run.swarm.maps.grid, restored.swarm.maps.grid)


def _batch(offsets, on_target, moved, probe):
    """A hand-made chunk of robots that each hear one silent neighbour."""
    n = len(offsets)
    dtype = message_dtype(MeanShift.MESSAGE_FIELDS)
    messages = np.array([silent_message(dtype)] * n, dtype=dtype)
    distances = np.hypot(offsets[:, 0], offsets[:, 1])
    starts = np.arange(n + 1, dtype=np.int64)

    def perceive(k):
        return Perception(0, offsets[k:k + 1], distances[k:k + 1], messages[k:k + 1],
                          bool(on_target[k]), probe, np.array([0.0, 1.0]), moved[k])

    return DecideBatch(0, NeighbourBatch(messages, distances, starts), offsets, on_target,
                       moved, np.tile([0.0, 1.0], (n, 1)), lambda k: probe, perceive,
                       None), perceive


def test_swarm_decides_a_hand_made_chunk_as_each_robot_steps():
    """Robots on and off a half-plane of target floor, probed one by one (a batch without
    probe_many): the swarm's velocities and broadcasts are each robot's own step's."""
    params = MeanShiftParams()
    offsets = np.array([[3.0, 0.5], [-4.0, 2.0], [0.0, 7.0], [5.5, -5.5]])
    on_target = np.array([True, False, True, False])
    moved = np.array([[0.05, 0.0], [0.0, -0.1], [0.0, 0.0], [0.03, 0.04]])
    probe = lambda offset: bool(offset[1] > -2.5)  # the floor: y > -2.5
    batch, perceive = _batch(offsets, on_target, moved, probe)
    swarm = MeanShiftSwarm([RobotSetup(i) for i in range(4)], params)
    robots = [MeanShiftRobot(RobotSetup(i), params, np.random.default_rng(0)) for i in range(4)]
    for _ in range(3):  # a few ticks: the maps and velocities carry over
        chunk = swarm.decide(np.arange(4), batch)
        for k, robot in enumerate(robots):
            action = robot.step(perceive(k))
            assert tuple(chunk.velocities[k]) == action.velocity
            assert chunk.sleep[k] == action.sleep
            assert tuple(chunk.broadcast[k].tolist()[1:]) == tuple(
                np.array([action.message], dtype=chunk.broadcast.dtype)[0].tolist()[1:])
    assert np.abs(chunk.velocities).sum() > 0  # they moved


def _crowded_batch(rng, robots, map_cell):
    """A hand-made chunk of ``robots`` robots, each hearing up to 30 neighbours (some
    moving, some silent) within 13 units, on a wavy floor: many sensed target points are
    occupied. Returns the batch, each robot's Perception, and the floor probe."""
    params = MeanShiftParams(map_cell=map_cell)
    counts = rng.integers(0, 31, size=robots)
    starts = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    radius = 13.0 * np.sqrt(rng.random(starts[-1]))
    angle = rng.uniform(-np.pi, np.pi, starts[-1])
    offsets = np.column_stack([radius * np.cos(angle), radius * np.sin(angle)])
    distances = np.hypot(offsets[:, 0], offsets[:, 1])
    dtype = message_dtype(MeanShift.MESSAGE_FIELDS)
    messages = np.array([silent_message(dtype)] * starts[-1], dtype=dtype)
    heard = rng.random(starts[-1]) < 0.7
    messages["id"][heard] = rng.integers(0, 100, size=heard.sum())
    messages["vx"][heard] = rng.normal(0, 0.05, size=heard.sum())
    messages["vy"][heard] = rng.normal(0, 0.05, size=heard.sum())
    on_target = rng.random(robots) < 0.5
    moved = rng.normal(0, 0.06, size=(robots, 2))
    probe = lambda offset: bool(np.sin(offset[0] / 3) + np.cos(offset[1] / 4) > -0.4)

    def perceive(k):
        s, e = starts[k], starts[k + 1]
        return Perception(0, offsets[s:e], distances[s:e], messages[s:e], bool(on_target[k]),
                          probe, np.array([0.6, 0.8]), moved[k])

    batch = DecideBatch(0, NeighbourBatch(messages, distances, starts), offsets, on_target,
                        moved, np.tile([0.6, 0.8], (robots, 1)), lambda k: probe, perceive,
                        None)
    return params, batch, perceive


@pytest.mark.parametrize("map_cell", [1.0, 0.3], ids=["one word a row", "two words a row"])
def test_swarm_decides_crowded_robots_as_each_robot_steps(map_cell):
    """Robots among up to 30 neighbours (the marking of occupied points: a stencil row in
    one word of bits, and, at map_cell 0.3, 71 cells in two): the swarm's velocities and
    sleep decisions are each robot's own step's, tick after tick."""
    rng = np.random.default_rng(72)
    params, batch, perceive = _crowded_batch(rng, 8, map_cell)
    swarm = MeanShiftSwarm([RobotSetup(i) for i in range(8)], params)
    robots = [MeanShiftRobot(RobotSetup(i), params, np.random.default_rng(0)) for i in range(8)]
    for _ in range(3):
        chunk = swarm.decide(np.arange(8), batch)
        for k, robot in enumerate(robots):
            action = robot.step(perceive(k))
            assert tuple(chunk.velocities[k]) == action.velocity
            assert chunk.sleep[k] == action.sleep
    alone = MeanShiftRobot(RobotSetup(0), params, np.random.default_rng(0))
    crowd = perceive(int(np.argmax(np.diff(batch.neighbours.starts))))
    points, target = alone.map.sense(crowd)
    no_one = Perception(0, np.zeros((0, 2)), np.zeros(0), crowd.messages[:0], crowd.on_target,
                        crowd.probe, crowd.beacon, crowd.moved)
    # the neighbours occupy target points: the command is not the one without them
    assert not np.array_equal(alone.exploring(crowd, points, target),
                              alone.exploring(no_one, points, target))


@njit
def _compiled_hypots(xy):
    out = np.empty(len(xy))
    for i in range(len(xy)):
        out[i] = hypot(xy[i, 0], xy[i, 1])
    return out


@njit
def _libm_hypots(xy):
    out = np.empty(len(xy))
    for i in range(len(xy)):
        out[i] = math.hypot(xy[i, 0], xy[i, 1])
    return out


def test_compiled_hypot_is_pythons_to_the_bit():
    """Random pairs over many scales, zeros and ties; numba's own math.hypot (the C
    library's) differs on some of the same pairs, so the test tells the two apart."""
    rng = np.random.default_rng(11)
    xy = rng.normal(size=(200_000, 2)) * 10.0 ** rng.integers(-6, 6, size=(200_000, 1))
    xy[:100, 1] = 0.0
    xy[100:200, 1] = xy[100:200, 0]
    xy[200:210] = 0.0
    python = np.array([math.hypot(x, y) for x, y in xy.tolist()])
    assert np.array_equal(_compiled_hypots(xy), python)
    assert not np.array_equal(_libm_hypots(xy), python)
    special = np.array([(0.0, 0.0), (-3.0, 4.0), (5e-320, 1e-321), (1e308, 1e308), (0.0, -2.5),
                        (math.inf, math.nan)])
    assert np.array_equal(_compiled_hypots(special),
                          np.array([math.hypot(x, y) for x, y in special.tolist()]))


def test_a_run_compiles_no_chunk_kernel_after_its_warm_up():
    """MeanShift.warm_up compiles the map and chunk kernels for the very types a run passes:
    the run adds no signature (numba would compile for seconds mid-run)."""
    from controllers.common import mapbatch
    from controllers.meanshift import chunk

    kernels = (mapbatch.advance, mapbatch.store, chunk.decide_chunk)
    sim = Simulation("tiny", controller="meanshift", seed=0, max_ticks=60)  # warms up
    before = [list(k.signatures) for k in kernels]
    sim.run()
    assert [list(k.signatures) for k in kernels] == before
    assert all(before)
