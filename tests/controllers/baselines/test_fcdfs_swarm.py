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
from swarmsim.engine.sim import TIMING_FIELDS
from tests.runhash import run_hash

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


def _run(cls, settings, ticks=800):
    """tiny seed 3, 20 robots, 800 ticks: positions and sleepers every tick, the broadcasts
    at the end, the summary (but its timings and the controller's name) and the time series."""
    sim = Simulation("tiny", controller=cls, seed=3, robots=20, max_ticks=ticks,
                     settings={"stop_on_complete": False, **settings})
    positions, asleep = [], []
    res = sim.run(on_tick=lambda s: (positions.append(s.positions.copy()),
                                     asleep.append(s.asleep.copy())))
    summary = {k: v for k, v in res.summary.items()
               if k not in TIMING_FIELDS and k != "controller"}  # the class's module path
    return (np.array(positions), np.array(asleep), sim.messages.tobytes(), summary,
            res.timeseries)


@pytest.mark.parametrize("settings", [{}, NOISY, {"turn": 1, "cell": 5.0}],
                         ids=["plain", "noisy", "other turn and lattice"])
def test_swarm_and_per_robot_controller_make_the_same_run(settings, monkeypatch):
    """The same run, tick for tick, with the same summary (decisions: the same robots slept
    at the same ticks; status counts), the swarm deciding 7 robots at a time."""
    per_robot = _run(FCDFSRobot, settings)
    monkeypatch.setattr("swarmsim.engine.sim.DECIDE_CHUNK", 7)
    (pa, sa, ma, suma, ta), (pb, sb, mb, sumb, tb) = _run(FCDFS, settings), per_robot
    assert np.array_equal(pa, pb) and np.array_equal(sa, sb)
    assert ma == mb and ta == tb
    assert suma == sumb
    assert sa.any() and not sa.all()  # robots slept, and not all of them
    counts = suma["status_counts"]
    assert counts.get("Settled", 0) >= 2 and counts.get("Door") == 1  # robots entered


def test_a_restored_run_goes_on_as_the_run(tmp_path):
    """The swarm's arrays are all a checkpoint needs: saved while robots enter the lattice."""
    run = Simulation("tiny", controller="fcdfs", seed=3, robots=20, max_ticks=800,
                     settings={"stop_on_complete": False})
    for _ in range(500):
        run.advance()
    assert run.swarm.rows.has_goal.any()  # robots are on their way between cells
    run.save(tmp_path / "fc.ckpt")
    restored = Simulation.restore(tmp_path / "fc.ckpt")
    for _ in range(200):
        run.advance()
        restored.advance()
        assert np.array_equal(run.positions, restored.positions)
    assert run.messages.tobytes() == restored.messages.tobytes()
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
