"""DASH decided a chunk at a time (controllers/dash/swarm.py, issue 72) makes the very runs
DASH made one robot at a time (controllers/dash/robot.py, the code it was ported from): the
same positions every tick, broadcasts, listening, sleep and summary, to the bit.
"""

from __future__ import annotations

import numpy as np
import pytest

from controllers.dash import Dash, DashParams, DashRobot
from controllers.dash.swarm import DashSwarm
from swarmsim import Simulation
from swarmsim.controller import (
    DecideBatch,
    NeighbourBatch,
    Perception,
    RobotSetup,
    message_dtype,
)
from tests.restorecheck import restored_goes_on, run_for
from tests.runhash import run_digest

NOISY = {"distance_noise": 0.05, "bearing_noise": 0.05, "speed_noise": 0.05,
         "message_loss": 0.1}

RUNS = {
    # name: (world, seed, ticks, settings)
    "tiny seed 1": ("tiny", 1, 500, {}),
    "tiny seed 2 noisy": ("tiny", 2, 300, NOISY),
    "tiny seed 3 fast spacing": ("tiny", 3, 400, {"adapt_rate": 0.05, "crowd": 2}),
}

GOLDEN = {
    "tiny seed 1": "71b95dd5c8cdf376",
    "tiny seed 2 noisy": "e64a8df2535b0218",
}
"""Digests (tests/runhash.py run_digest) of runs of the per-robot DASH at 87b9045, before the
port."""


@pytest.mark.parametrize("case", sorted(RUNS))
def test_the_batch_dash_makes_the_per_robot_runs(case):
    """The same run, sleeping robots and decisions counted included."""
    batch, per_robot = run_digest(Dash, *RUNS[case]), run_digest(DashRobot, *RUNS[case])
    assert batch == per_robot
    if case in GOLDEN:
        assert batch[0] == GOLDEN[case]
    assert batch[2] > 0  # robots slept
    assert batch[1]["total_distance"] > 0


def test_small_chunks_change_nothing(monkeypatch):
    """Robots decided 7 at a time (tiny's 40 are one chunk): the per-robot run."""
    per_robot = run_digest(DashRobot, *RUNS["tiny seed 2 noisy"])
    monkeypatch.setattr("swarmsim.engine.sim.DECIDE_CHUNK", 7)
    assert run_digest(Dash, *RUNS["tiny seed 2 noisy"]) == per_robot


def test_a_restored_dash_run_goes_on_as_the_run(tmp_path):
    """The swarm's arrays (levels, spacings, statuses) are all a checkpoint needs of DASH."""
    run = run_for("dash", seed=1, ticks=200, max_ticks=400)
    restored = restored_goes_on(run, tmp_path, 150)
    assert run.swarm.s.tobytes() == restored.swarm.s.tobytes()
    assert (run.swarm.level > 0).any()  # the spacings had grown


def test_the_swarm_decides_a_hand_made_chunk_as_each_robot_steps():
    """Robots on and off the target hearing peers that are crowded, far, seeking or silent,
    on a half-plane of target floor that some steps would leave, probed one by one (a
    batch without probe_many), over a few ticks (their spacings carry over): the swarm's
    velocities, listening, sleep and broadcasts are each robot's own step's."""
    params = DashParams(adapt_rate=0.3, crowd=2)
    dtype = message_dtype(Dash.MESSAGE_FIELDS)
    heard = [  # per robot: (offset x, offset y, sender, status, spacing)
        [(1.0, 0.2, 7, 1, 2.0), (-1.2, 0.4, 8, 1, 2.6), (0.3, 1.5, 9, 0, 2.0)],
        [(4.0, 1.0, 7, 2, 3.5)],
        [(-8.5, 0.5, 7, 1, 5.0), (0.6, -0.2, -1, -1, 0.0)],
        [],
        [(0.8, 0.1, 7, 1, 2.0)],
    ]
    on_target = np.array([True, True, True, True, False])
    n = len(heard)
    rows = [row for robot in heard for row in robot]
    offsets = np.array([row[:2] for row in rows], dtype=np.float64).reshape(-1, 2)
    distances = np.hypot(offsets[:, 0], offsets[:, 1])
    messages = np.array([(s, st, False, sp) for _, _, s, st, sp in rows], dtype=dtype)
    starts = np.cumsum([0] + [len(robot) for robot in heard])
    moved = np.zeros((n, 2))
    beacons = np.tile([0.0, 1.0], (n, 1))
    probe = lambda offset: bool(offset[0] < 0.5)  # the floor: x < 0.5

    def perceive(k):
        a, b = starts[k], starts[k + 1]
        return Perception(0, offsets[a:b], distances[a:b], messages[a:b], bool(on_target[k]),
                          probe, beacons[k], moved[k])

    batch = DecideBatch(0, NeighbourBatch(messages, distances, starts), offsets, on_target,
                        moved, beacons, lambda k: probe, perceive)
    robots = np.array([3, 0, 4, 1, 2])
    swarm = DashSwarm([RobotSetup(i) for i in range(n)], params)
    each = [DashRobot(RobotSetup(i), params, np.random.default_rng(0)) for i in robots.tolist()]
    for _ in range(4):
        chunk = swarm.decide(robots, batch)
        for k, robot in enumerate(each):
            action = robot.step(perceive(k))
            assert tuple(chunk.velocities[k]) == action.velocity
            assert chunk.sleep[k] == action.sleep and chunk.listen[k] == action.listen
            assert chunk.broadcast[k].tolist() == np.array(
                [action.message], dtype=chunk.broadcast.dtype)[0].tolist()
    assert chunk.sleep.any() and not chunk.sleep.all()
    assert len(set(swarm.s.tolist())) > 2  # spacings grew, shrank or held


def test_a_run_compiles_no_chunk_kernel_after_its_warm_up():
    """Dash.warm_up compiles the chunk kernel for the very types a run passes: the run adds
    no signature (numba would compile for seconds mid-run)."""
    from controllers.dash import chunk

    sim = Simulation("tiny", controller="dash", seed=0, max_ticks=60)  # warms up
    before = list(chunk.wished.signatures)
    sim.run()
    assert list(chunk.wished.signatures) == before
    assert before
