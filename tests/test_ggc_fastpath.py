"""GGC's movers decided a chunk at a time (controllers/ggc/fastpath.py) change nothing."""

import hashlib
from collections import Counter

import numpy as np
import pytest

from controllers.ggc.book import EdgeBook
from controllers.ggc.robot import COVERAGE, DETECTION, INITIAL, STATUSES, STOP, GGCRobot
from swarmsim import Simulation
from swarmsim.sim import rows_to_array
from tests.test_ggc import small_world


def controller_state(sim: Simulation) -> list[dict]:
    """Every robot's controller state (its attributes and its row of the run's EdgeBook;
    arrays as bytes), to compare runs."""
    skip = {"rng", "p", "handlers", "pre", "pre_wait", "book"}
    return [{**{name: value.tobytes() if isinstance(value, np.ndarray) else value
                for name, value in vars(c).items() if name not in skip},
             **{name: getattr(c.book, name)[c.row].tobytes() for name in EdgeBook.__slots__}}
            for c in sim.swarm.robots]


def fingerprint_run(batch_decide: bool, robots: int = 120, groups: int = 3,
                    max_ticks: int = 3000, until_complete: bool = True
                    ) -> tuple[str, Simulation, Counter]:
    """A run's every position and broadcast, hashed tick by tick, and how many robot-ticks
    each status had."""
    sim = Simulation(small_world(40, 30), controller="ggc", robots=robots, groups=groups,
                     seed=1, max_ticks=max_ticks, settings={"batch_decide": batch_decide})
    digest, statuses = hashlib.sha256(), Counter()
    for _ in range(max_ticks):
        sim.step()
        digest.update(sim.positions.tobytes())
        digest.update(sim.messages.tobytes())
        statuses.update(STATUSES[c.status] for c in sim.swarm.robots)
        if until_complete and sim.metrics.completion_tick is not None:
            break
    return digest.hexdigest(), sim, statuses


@pytest.fixture(scope="module")
def both_ways():
    return fingerprint_run(True), fingerprint_run(False)


def test_batch_decide_changes_nothing_tick_by_tick(both_ways):
    (fast, sim, statuses), (slow, slow_sim, _) = both_ways
    assert fast == slow
    assert controller_state(sim) == controller_state(slow_sim)
    # the run exercised what the fast path decides: movers, Stops, a completed cover
    assert sim.metrics.completion_tick is not None
    assert statuses["Coverage"] > 20_000 and statuses["Stop"] > 20_000
    assert sum(c.collision_stops for c in sim.swarm.robots) > 100


@pytest.fixture
def stepped(monkeypatch) -> Counter:
    """Counts GGCRobot.step calls by the robot's status (the ticks the fast path left)."""
    calls = Counter()
    step = GGCRobot.step

    def counting(self, p):
        calls[self.status] += 1
        return step(self, p)

    monkeypatch.setattr(GGCRobot, "step", counting)
    return calls


def test_the_fast_path_decides_most_movers(stepped):
    """Travelling (Initial), Coverage, Stop and waiting (Detection) robots reach step() only
    for the rare cases."""
    _, _, statuses = fingerprint_run(True, max_ticks=1500)
    assert statuses["Coverage"] > 5_000
    assert stepped[COVERAGE] < 0.1 * statuses["Coverage"]
    assert stepped[STOP] < 0.2 * statuses["Stop"]
    assert statuses["Initial"] > 5_000 and stepped[INITIAL] < 0.1 * statuses["Initial"]
    assert stepped[DETECTION] < 0.2 * statuses["Detection"]


def test_one_group_with_the_surplus_lap_changes_nothing(stepped):
    """One group: the surplus lap and boundary fill are on. Run past completion until robots
    give up (Surplus): the same run both ways, and movers reach step() only rarely."""
    fast, sim, statuses = fingerprint_run(True, robots=80, groups=1, max_ticks=5000,
                                          until_complete=False)
    movers_stepped = stepped[COVERAGE]
    slow, slow_sim, _ = fingerprint_run(False, robots=80, groups=1, max_ticks=5000,
                                        until_complete=False)
    assert fast == slow
    assert controller_state(sim) == controller_state(slow_sim)
    assert sum(c.surplus for c in sim.swarm.robots) >= 10  # the lap ran to its end
    assert all(c.batch_coverage and c.surplus_rule for c in sim.swarm.robots)
    assert movers_stepped < 0.05 * statuses["Coverage"]


def test_repeated_broadcasts_are_the_robots_messages(monkeypatch):
    """The fast path sends no message when a robot's broadcast has not changed (the engine
    repeats its row): every row must still be what the robot's message() says, every tick."""
    repeated = Counter()
    apply = Simulation._apply

    def counting(self, awake, actions, *rest):
        sent = len(actions.messages)  # the fast path's actions come as columns
        repeated.update({True: len(awake) - sent, False: sent})
        return apply(self, awake, actions, *rest)

    monkeypatch.setattr(Simulation, "_apply", counting)
    sim = Simulation(small_world(40, 30), controller="ggc", robots=120, groups=3, seed=1,
                     max_ticks=1500)
    for _ in range(1500):
        sim.step()
        said = rows_to_array([c.message() for c in sim.swarm.robots], sim.dtype)
        assert said.tobytes() == sim.messages.tobytes(), f"tick {sim.tick}"
    assert repeated[True] > 0.3 * (repeated[True] + repeated[False])
