"""GGC's failure mode no_gradient (paper Section 5, Figure 10): a robot that cannot obtain its
neighbours' gradient has an infinite one, sets off to cover first, and covers normally."""

from __future__ import annotations

import numpy as np

from controllers.common.gradient import INF_GRADIENT
from controllers.ggc import GGC, GGCParams
from controllers.ggc.statuses import ARRIVE, COVERAGE, DETECTION, INITIAL
from controllers.ggc.swarm import GGCSwarm
from swarmsim import Simulation
from swarmsim.controller import FailingSwarm, RobotSetup

GRADIENT_FAILURES = {"failures": 5, "failure_phase": "gradient", "failure_mode": "no_gradient"}


def test_ggc_declares_no_gradient_and_its_swarm_can_fail_robots():
    assert "no_gradient" in GGC.FAILURE_MODES
    swarm = GGC.create_swarm([RobotSetup(i) for i in range(2)], GGCParams(),
                             [np.random.default_rng(i) for i in range(2)])
    assert isinstance(swarm, FailingSwarm)


def test_a_lost_gradient_is_infinite_and_a_leaders_is_kept():
    setups = [RobotSetup(0, leader=True), *(RobotSetup(i) for i in range(1, 5))]
    swarm = GGCSwarm(setups, GGCParams(), [np.random.default_rng(i) for i in range(5)])
    s = swarm.state
    s["status"][[0, 1, 2, 3, 4]] = [ARRIVE, INITIAL, DETECTION, COVERAGE, DETECTION]
    s["gradient"][1:] = [2, 3, 4, 5]
    swarm.fail(np.arange(5), "no_gradient")
    assert s["gradient"][0] == 0 and s["status"][0] == ARRIVE and not s["no_gradient"][0]
    assert (s["gradient"][1:] == INF_GRADIENT).all()
    assert s["status"][1] == DETECTION and s["cmd"][1] == 0  # stops travelling, waits
    assert s["no_gradient"][[1, 2]].all()  # takes no gradient from its formation
    assert s["status"][3] == COVERAGE and not s["no_gradient"][3]  # takes one as it moves


def test_robots_that_lose_their_gradient_cover_first_and_settle():
    """tiny, seed 1: the failed robots wait in Detection with an infinite gradient, leave
    before every other robot of the formation, walk, take up a gradient from the structure,
    and the run completes with every robot working ("Failed" is nobody's status)."""
    sim = Simulation("tiny", seed=1, max_ticks=4000, settings=GRADIENT_FAILURES)
    injector = sim.hooks[0]
    first_movers: set[int] = set()
    walked, driven = np.zeros(sim.n), np.zeros(sim.n, dtype=bool)
    before = sim.positions.copy()
    while sim.stop_reason is None:
        sim.advance()
        walked += np.linalg.norm(sim.positions - before, axis=1)
        driven |= np.abs(sim.velocities).max(axis=1) > 0  # told to move
        before = sim.positions.copy()
        if injector.fired_tick == sim.tick:
            failed = injector.robots
            walked[:], driven[:] = 0.0, False
            assert (sim.swarm.state["gradient"][failed] == INF_GRADIENT).all()
            assert (sim.swarm.state["status"][failed] == DETECTION).all()
        if injector.fired_tick is not None and not first_movers:
            first_movers = set(np.flatnonzero(sim.swarm.state["status"] == COVERAGE).tolist())
    summary = sim.result().summary
    assert summary["stop_reason"] == "complete"
    assert summary["failed_robots"] == 5 and "Failed" not in summary["status_counts"]
    assert first_movers and first_movers <= set(failed.tolist())
    assert (sim.swarm.state["visited"][failed] & (1 << COVERAGE)).all()  # each one covered
    assert driven[failed].all() and walked[failed].sum() > 50.0  # not dead bodies (one may
    # be wedged against its formation soon after it sets off, as any mover may)
    assert (sim.swarm.state["gradient"][failed] < INF_GRADIENT).all()  # one taken up again
    assert not sim.failed.any()


def test_sleeping_changes_nothing_when_gradients_are_lost():
    """A robot that loses its gradient while asleep (at tick 250 most robots wait, asleep, in
    their formation) is woken to act on it: the run is the run without sleeping."""
    def run(allow_sleep):
        sim = Simulation("tiny", seed=1, max_ticks=700,
                         settings={**GRADIENT_FAILURES, "failure_phase": "tick",
                                   "failure_tick": 250, "allow_sleep": allow_sleep})
        res = sim.run()
        fewest_awake = min(r["awake"] for r in res.timeseries[1:])
        return sim.positions, sim.messages, fewest_awake

    (pa, ma, fewest), (pb, mb, _) = run(True), run(False)
    assert np.array_equal(pa, pb) and np.array_equal(ma, mb)
    assert fewest < len(pa) // 2  # robots really slept
