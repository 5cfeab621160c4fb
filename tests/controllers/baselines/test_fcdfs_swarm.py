"""FCDFS's robots as arrays (FCDFSSwarm, compiled chunks) make the very runs of the
per-robot controller (FCDFSRobot), to the bit: positions every tick, broadcasts, floor
readings, the summary and the sleep decisions.

GOLDEN holds the hashes of the per-robot controller's runs, recorded at 87b9045 (before
the swarm existed), as tests/runhash.py fingerprints a run: a change of the
algorithm, of its float order, of its probes or of when a robot sleeps changes them.
"""

from __future__ import annotations

import numpy as np
import pytest

from controllers.fcdfs import FCDFS, FCDFSRobot
from swarmsim import Simulation
from swarmsim.controller import (
    DecideBatch,
    NeighbourBatch,
    RobotSetup,
    make_perception,
    message_dtype,
)
from tests.restorecheck import restored_goes_on, run_for
from tests.runhash import run_hash, run_trace

NOISY = {"distance_noise": 0.05, "bearing_noise": 0.05, "speed_noise": 0.05,
         "message_loss": 0.1}
GOLDEN = {  # tiny seed 3 (40 robots), 800 ticks: run_hash of the per-robot controller at 87b9045
    "plain": ({}, "63f775562e286c77"),
    "lossy": ({"message_loss": 0.1, "distance_noise": 0.05}, "9997c64b3780d97d"),
}


@pytest.mark.parametrize("name", sorted(GOLDEN))
def test_swarm_runs_hash_as_the_per_robot_controller_did(name):
    settings, golden = GOLDEN[name]
    assert run_hash("tiny", FCDFS, 3, 800, settings) == golden



@pytest.mark.parametrize("settings", [{}, NOISY, {"turn": 1, "cell": 5.0}],
                         ids=["plain", "noisy", "other turn and lattice"])
def test_swarm_and_per_robot_controller_make_the_same_run(settings, monkeypatch):
    """The same run, tick for tick, with the same summary (decisions: the same robots slept
    at the same ticks; status counts), the swarm deciding 7 robots at a time."""
    per_robot = run_trace(FCDFSRobot, settings, 800, robots=20)
    monkeypatch.setattr("swarmsim.engine.sim.DECIDE_CHUNK", 7)
    (pa, sa, ma, suma, ta), (pb, sb, mb, sumb, tb) = run_trace(FCDFS, settings, 800, robots=20), per_robot
    assert np.array_equal(pa, pb) and np.array_equal(sa, sb)
    assert ma == mb and ta == tb
    assert suma == sumb
    assert sa.any() and not sa.all()  # robots slept, and not all of them
    counts = suma["status_counts"]
    assert counts.get("Settled", 0) >= 2 and counts.get("Door") == 1  # robots entered


def test_a_restored_run_goes_on_as_the_run(tmp_path):
    """The swarm's arrays are all a checkpoint needs: saved while robots enter the lattice."""
    run = run_for("fcdfs", seed=3, ticks=500, max_ticks=800, robots=20)
    assert run.swarm.rows.has_goal.any()  # robots are on their way between cells
    restored = restored_goes_on(run, tmp_path, 200)
    for a, b in zip(run.swarm.rows, restored.swarm.rows, strict=True):
        assert np.array_equal(a, b)


def test_a_run_compiles_no_chunk_kernel_after_its_warm_up():
    """FCDFS.warm_up compiles the chunk kernel for the very types a run passes: the run
    adds no signature (numba would compile for seconds mid-run)."""
    from controllers.fcdfs import chunk

    sim = Simulation("tiny", controller="fcdfs", seed=0, robots=20, max_ticks=60)
    before = list(chunk.decide_chunk.signatures)
    sim.run()
    assert list(chunk.decide_chunk.signatures) == before
    assert before


def _load(swarm, robot):
    """Swarm row 0 set to ``robot``'s state (FCDFSRobot's attributes)."""
    r = swarm.rows
    r.status[0], r.grad[0], r.cmd[0], r.door[0] = robot.status, robot.grad, robot.cmd, robot.door
    r.pdir[0], r.touch[0], r.hops[0], r.waited[0] = robot.pdir, robot.touch, robot.hops, robot.waited
    r.travel[0], r.pos[0], r.cell[0] = robot.travel, robot.pos, robot.cell
    r.has_goal[0] = robot.goal is not None
    r.goal[0] = robot.goal if robot.goal is not None else (0, 0)
    r.hist_n[0] = min(len(robot.history), 2)
    for h, cell in enumerate(robot.history[::-1][:2]):
        r.hist[0, h] = cell
    r.stepping[0], r.stepped[0] = robot.stepping, robot.stepped


def _random_robot(rng, params):
    """An FCDFS robot queued or moving on the lattice, in a random state."""
    from controllers.fcdfs.params import MOVING, QUEUE

    robot = FCDFSRobot(RobotSetup(5), params, rng)
    robot.status = MOVING if rng.random() < 0.7 else QUEUE
    robot.door, robot.pdir = int(rng.choice([0, 7, -1])), int(rng.integers(4))
    robot.hops = int(rng.choice([3, 2**31 - 1]))
    robot.cell = tuple(int(c) for c in rng.integers(-2, 3, 2))
    robot.history = [tuple(int(c) for c in rng.integers(-2, 3, 2))
                     for _ in range(int(rng.integers(4)))]
    robot.goal = (None if rng.random() < 0.5
                  else tuple(int(c) for c in rng.integers(-2, 3, 2)))
    robot.pos = np.array(robot.cell, dtype=float) * params.spacing + rng.normal(0, 0.5, 2)
    robot.waited = int(rng.integers(params.patience))
    return robot


def _random_neighbours(rng, dtype):
    """Up to 7 heard (or silent) neighbours within 12 units, nearest first."""
    from controllers.fcdfs.params import DOOR, MOVING, QUEUE, SETTLED

    n = int(rng.integers(8))
    offsets = rng.uniform(-8, 8, (n, 2))
    distances = np.hypot(offsets[:, 0], offsets[:, 1])
    order = np.argsort(distances)
    offsets, distances = offsets[order], distances[order]
    messages = np.zeros(n, dtype=dtype)
    messages["id"] = rng.choice([-1, 0, 3, 7, 9, 11], n)
    messages["status"] = rng.choice([QUEUE, DOOR, MOVING, SETTLED], n)
    messages["moving"] = rng.random(n) < 0.3
    messages["door"] = rng.choice([0, 7], n)
    messages["hops"] = rng.choice([1, 2, 5, 2**31 - 1], n)
    messages["ci"], messages["cj"] = rng.integers(-2, 3, n), rng.integers(-2, 3, n)
    return offsets, distances, messages


def test_swarm_decides_random_robots_as_each_robot_steps():
    """Queued and moving robots in random states, among random neighbours, on a box of
    floor probed one by one (a batch without probe_many): the swarm's action,
    broadcast and new state are the robot's own step's. Runs reach few of FCDFS's corners
    (dead ends, a turn at the entry cell, patience); random states reach them all."""
    from controllers.fcdfs import FCDFSParams
    from controllers.fcdfs.swarm import FCDFSSwarm

    params = FCDFSParams()
    dtype = message_dtype(FCDFS.MESSAGE_FIELDS)
    rng = np.random.default_rng(4)
    outcomes = set()
    for _ in range(400):
        robot = _random_robot(rng, params)
        swarm = FCDFSSwarm([RobotSetup(5)], params)
        _load(swarm, robot)
        offsets, distances, messages = _random_neighbours(rng, dtype)
        low, high = rng.uniform(-10, -2, 2), rng.uniform(2, 10, 2)

        def probe(offset, low=low, high=high):  # the floor: a box around the robot
            return bool((low < offset).all() and (offset < high).all())

        moved = rng.normal(0, 0.05, 2)
        perception = make_perception(7, offsets, distances, messages, bool(rng.random() < 0.5),
                                     probe, None, moved)
        batch = DecideBatch(7, NeighbourBatch(messages, distances,
                                              np.array([0, len(messages)])),
                            offsets, np.array([perception.on_target]), moved[None, :], None,
                            lambda k, f=probe: f, lambda k, p=perception: p, None)
        chunk = swarm.decide(np.array([0]), batch)
        action = robot.step(perception)
        assert tuple(chunk.velocities[0]) == action.velocity
        assert bool(chunk.sleep[0]) == action.sleep
        expected = np.array([action.message], dtype=dtype)[0].tolist()[1:]
        assert chunk.broadcast[0].tolist()[1:] == expected
        mirror = FCDFSSwarm([RobotSetup(5)], params)
        _load(mirror, robot)
        rows = swarm.rows
        if not rows.has_goal[0]:
            rows.goal[0] = 0  # a goal of None: what the row holds then is never read
        rows.hist[0, rows.hist_n[0]:] = 0  # nor is history it has not got
        for name, a, b in zip(rows._fields, rows, mirror.rows, strict=True):
            assert np.array_equal(a, b), name
        outcomes.add((robot.status, action.sleep, bool(np.any(action.velocity))))
    assert len(outcomes) >= 5  # settled, waited, went, queued asleep, made way...
