"""Dispersion decided a chunk at a time (controllers/dispersion/swarm.py, issue 72) makes the
very runs dispersion made one robot at a time (controllers/dispersion/robot.py, the code it
was ported from): the same positions every tick, broadcasts, sleep and summary, to the bit.
"""

from __future__ import annotations

import numpy as np
import pytest

from controllers.dispersion import Dispersion, DispersionParams, DispersionRobot
from controllers.dispersion.swarm import DispersionSwarm
from swarmsim.controller import (
    DecideBatch,
    NeighbourBatch,
    Perception,
    RobotSetup,
    message_dtype,
    silent_message,
)
from tests.restorecheck import restored_goes_on, run_for
from tests.runhash import run_digest

NOISY = {"distance_noise": 0.05, "bearing_noise": 0.05, "speed_noise": 0.05,
         "message_loss": 0.1}

RUNS = {
    # name: (world, seed, ticks, settings)
    "tiny seed 1": ("tiny", 1, 600, {}),
    "tiny seed 2 noisy": ("tiny", 2, 300, NOISY),
}

GOLDEN = {
    "tiny seed 1": "e906d9c75abd6c80",
}
"""Digests (tests/runhash.py run_digest) of runs of the per-robot dispersion at 87b9045,
before the port."""


@pytest.mark.parametrize("case", sorted(RUNS))
def test_the_batch_dispersion_makes_the_per_robot_runs(case):
    """The same run, sleeping robots and decisions counted included."""
    batch, per_robot = run_digest(Dispersion, *RUNS[case]), run_digest(DispersionRobot,
                                                                       *RUNS[case])
    assert batch == per_robot
    if case in GOLDEN:
        assert batch[0] == GOLDEN[case]
    assert batch[2] > 0  # robots slept
    assert batch[1]["total_distance"] > 0


def test_small_chunks_change_nothing(monkeypatch):
    """Robots decided 7 at a time (tiny's 40 are one chunk): the per-robot run."""
    per_robot = run_digest(DispersionRobot, *RUNS["tiny seed 2 noisy"])
    monkeypatch.setattr("swarmsim.engine.sim.DECIDE_CHUNK", 7)
    assert run_digest(Dispersion, *RUNS["tiny seed 2 noisy"]) == per_robot


def test_a_restored_dispersion_run_goes_on_as_the_run(tmp_path):
    """Dispersion keeps no state of its own: a checkpoint goes on as the run."""
    run = run_for("dispersion", seed=1, ticks=150, max_ticks=300)
    restored_goes_on(run, tmp_path, 100)


def test_the_swarm_decides_a_hand_made_chunk_as_each_robot_steps():
    """Robots on and off the target, near and far from their one neighbour, on a half-plane
    of target floor that one's step would leave, probed one by one (a batch without
    probe_many) in a world without a beacon: the swarm's velocities, sleep and broadcasts
    are each robot's own step's."""
    params = DispersionParams()
    offsets = np.array([[3.0, 0.5], [-4.0, 2.0], [0.0, 7.0], [5.5, -0.5], [0.2, -0.1],
                        [-3.0, 0.0]])
    on_target = np.array([True, True, True, True, True, False])
    n = len(offsets)
    dtype = message_dtype(Dispersion.MESSAGE_FIELDS)
    messages = np.array([silent_message(dtype)] * n, dtype=dtype)
    distances = np.hypot(offsets[:, 0], offsets[:, 1])
    moved = np.zeros((n, 2))
    probe = lambda offset: bool(offset[0] < 0.5)  # the floor: x < 0.5

    def perceive(k):
        return Perception(0, offsets[k:k + 1], distances[k:k + 1], messages[k:k + 1],
                          bool(on_target[k]), probe, None, moved[k])

    batch = DecideBatch(0, NeighbourBatch(messages, distances, np.arange(n + 1)), offsets,
                        on_target, moved, None, lambda k: probe, perceive)
    robots = np.array([4, 0, 5, 3, 1, 2])
    chunk = DispersionSwarm([RobotSetup(i) for i in range(n)], params).decide(robots, batch)
    for k, i in enumerate(robots.tolist()):
        action = DispersionRobot(RobotSetup(i), params, np.random.default_rng(0)).step(
            perceive(k))
        assert tuple(chunk.velocities[k]) == action.velocity
        assert chunk.sleep[k] == action.sleep
        assert chunk.broadcast[k].tolist() == np.array(
            [action.message], dtype=chunk.broadcast.dtype)[0].tolist()
    assert chunk.sleep.any() and not chunk.sleep.all()
    assert chunk.velocities[chunk.sleep].tolist() == [[0.0, 0.0]] * int(chunk.sleep.sum())
