"""Kilobot's robots as arrays (KilobotSwarm, compiled chunks) make the very runs of the
per-robot controller (KilobotRobot), to the bit: positions every tick, broadcasts, floor
readings, the summary and the sleep decisions.

GOLDEN holds the hashes of the per-robot controller's runs, recorded at 87b9045 (before
the swarm existed), as tests/runhash.py fingerprints a run: a change of the
algorithm, of its float order or of when a robot sleeps changes them.
"""

from __future__ import annotations

import numpy as np
import pytest

from controllers.kilobot import Kilobot, KilobotRobot
from swarmsim import Simulation
from tests.restorecheck import restored_goes_on, run_for
from tests.runhash import run_hash, run_trace

NOISY = {"distance_noise": 0.05, "bearing_noise": 0.05, "speed_noise": 0.05,
         "message_loss": 0.1}
GOLDEN = {  # tiny seed 3 (40 robots), 800 ticks: run_hash of the per-robot controller at 87b9045
    "plain": ({}, "d501545cfd9c689b"),  # robots peel off from tick ~350; 4 have joined by 800
    "lossy": ({"message_loss": 0.1, "distance_noise": 0.05}, "d19fc1c22c427dbf"),
}


@pytest.mark.parametrize("name", sorted(GOLDEN))
def test_swarm_runs_hash_as_the_per_robot_controller_did(name):
    settings, golden = GOLDEN[name]
    assert run_hash("tiny", Kilobot, 3, 800, settings) == golden



@pytest.mark.parametrize("settings", [{}, NOISY, {"d_cover": 4.0, "orbit": 1}],
                         ids=["plain", "noisy", "other orbit"])
def test_swarm_and_per_robot_controller_make_the_same_run(settings, monkeypatch):
    """The same run, tick for tick, with the same summary (decisions: the same robots slept
    at the same ticks; status counts), the swarm deciding 7 robots at a time."""
    per_robot = run_trace(KilobotRobot, settings, 800, robots=20)
    monkeypatch.setattr("swarmsim.engine.sim.DECIDE_CHUNK", 7)
    (pa, sa, ma, suma, ta), (pb, sb, mb, sumb, tb) = run_trace(Kilobot, settings, 800, robots=20), per_robot
    assert np.array_equal(pa, pb) and np.array_equal(sa, sb)
    assert ma == mb and ta == tb
    assert suma == sumb
    assert sa.any() and not sa.all()  # robots slept, and not all of them
    counts = suma["status_counts"]
    assert counts.get("Joined", 0) > 1 and len(counts) > 1  # robots moved, and joined


def test_a_restored_run_goes_on_as_the_run(tmp_path):
    """The swarm's arrays are all a checkpoint needs: saved while robots edge-follow."""
    run = run_for("kilobot", seed=3, ticks=400, max_ticks=800, robots=20)
    assert run.messages["moving"].any()  # robots edge-follow: circling, odometry, traps
    restored = restored_goes_on(run, tmp_path, 200)
    for a, b in zip(run.swarm.rows, restored.swarm.rows, strict=True):
        assert np.array_equal(a, b)


def test_a_run_compiles_no_chunk_kernel_after_its_warm_up():
    """Kilobot.warm_up compiles the chunk kernels for the very types a run passes: the run
    adds no signature (numba would compile for seconds mid-run)."""
    from controllers.kilobot import chunk

    kernels = (chunk.probe_questions, chunk.decide_chunk)
    sim = Simulation("tiny", controller="kilobot", seed=0, robots=20, max_ticks=60)
    before = [list(k.signatures) for k in kernels]
    sim.run()
    assert [list(k.signatures) for k in kernels] == before
    assert all(before)
