"""GGC from a scattered start: leader selection, grouping, aggregation, groups covering."""

import itertools
from collections import Counter

import numpy as np
import pytest

from controllers.ggc import GGC, GGCParams
from controllers.ggc.statuses import (
    APPROACH,
    ARRIVE,
    COVERAGE,
    DETECTION,
    FORMED,
    GATHERING,
    INITIAL,
    STOP,
    SURPLUS,
)
from swarmsim import Simulation
from swarmsim.world.world import world_from_dict
from tests.conftest import small_world
from tests.ggc_bot import Bot, ggc_state

SELECTION = (GGCParams().h_max + 1) * GGCParams().T_settle
"""Ticks of leader selection (Algorithm 3) with the default parameters."""


def scattered(world, robots, groups, seed, **settings):
    return Simulation(world, controller="ggc", robots=robots, groups=groups, seed=seed,
                      max_ticks=20000, settings={"start": "random", **settings})


def leader_spread(sim):
    """Sum of pairwise distances between the current leaders (units)."""
    pos = sim.positions[ggc_state(sim)["leader"]]
    return sum(float(np.hypot(*(a - b))) for a, b in itertools.combinations(pos, 2))


def wide_band():
    """A long spawn band (so that leaders have room to spread) below a small target."""
    return world_from_dict({
        "name": "band",
        "target": {"outline": [[0, 0], [60, 0], [60, 20], [0, 20]]},
        "spawn": [{"outline": [[-20, -30], [80, -30], [80, -12], [-20, -12]]}],
        "beacon": {"position": [30, 10]},
    })


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_grouping_gives_k_non_empty_groups_of_every_robot(seed):
    sim = scattered(wide_band(), robots=120, groups=3, seed=seed)
    for _ in range(SELECTION + 60):
        sim.step()
    state = ggc_state(sim)
    assert sorted(state["group"][state["leader"]].tolist()) == [1, 2, 3]
    sizes = Counter(state["group"].tolist())
    assert set(sizes) == {1, 2, 3}, sizes  # every robot has a group, none is empty
    # sizes follow the leaders' nearness cells: not equal, but no group starves or dominates
    assert min(sizes.values()) >= 8 and max(sizes.values()) <= 0.6 * 120, sizes
    # the summary's grouping figures (GatherTicks): grouped after leader selection, in time
    summary = sim.swarm.summarize()
    assert SELECTION <= summary["grouped_tick"] < sim.tick, summary
    formed = (state["visited"] >> FORMED & 1).astype(bool)
    assert summary["formed_robots"] == formed.sum() > 0
    assert summary["formed_tick"] is not None and summary["formed_tick"] < sim.tick


def test_gather_ticks_note_each_robots_first_group_and_formation():
    from controllers.ggc.swarm import GatherTicks

    state = np.zeros(3, dtype=[("group", "i2"), ("visited", "u2")])
    ticks = GatherTicks.new(3)
    state["group"][0] = 1
    ticks.mark(state, np.arange(3), 5)
    state["group"][1], state["visited"][1] = 2, 1 << FORMED
    ticks.mark(state, np.arange(3), 9)
    assert ticks.summary(np.ones(3, bool)) == {"grouped_tick": None, "formed_robots": 1,
                                               "formed_tick": 9}
    state["group"][2] = 1
    ticks.mark(state, np.array([2]), 12)  # only robot 2 decided this tick
    assert ticks.grouped.tolist() == [5, 9, 12]
    assert ticks.summary(np.array([True, False, True]))["grouped_tick"] == 12


def test_formations_report_no_grouping_figures():
    sim = Simulation(small_world(), controller="ggc", robots=30, groups=2, seed=0)
    assert "grouped_tick" not in sim.swarm.summarize() and sim.swarm.gather is None


@pytest.mark.slow
def test_leaders_end_farther_apart_than_they_started():
    before, after = [], []
    for seed in range(4):
        sim = scattered(wide_band(), robots=120, groups=3, seed=seed)
        before.append(leader_spread(sim))
        for _ in range(SELECTION):
            sim.step()
        after.append(leader_spread(sim))
        assert after[-1] >= before[-1] - 1.0, (seed, before[-1], after[-1])
    assert np.mean(after) > 1.2 * np.mean(before), (before, after)


@pytest.fixture(scope="module")
def two_group_run():
    sim = scattered(small_world(), robots=60, groups=2, seed=0)
    statuses_seen = set()

    def watch(s):
        if s.tick % 20 == 0:
            statuses_seen.update(ggc_state(s)["status"].tolist())

    return sim, sim.run(on_tick=watch), statuses_seen


@pytest.mark.slow
def test_small_two_group_world_from_a_scattered_start_is_covered(two_group_run):
    sim, res, seen = two_group_run
    s = res.summary
    assert s["stop_reason"] == "complete" and s["coverage"] >= 0.99, s
    assert s["max_overlap"] < 0.05 * 0.4
    # every robot went through aggregation into a formation, then travelled and covered
    assert {FORMED, INITIAL, ARRIVE} <= seen and seen & set(GATHERING)
    visited = ggc_state(sim)["visited"].astype(int)
    formed = (visited >> FORMED & 1).sum()
    assert formed >= 0.9 * len(visited)


@pytest.mark.slow
def test_under_yield_holes_two_groups_meeting_head_on_park_no_one():
    """The default rule set on the corridor: no Stop between groups, yet no deadlock."""
    from swarmsim.world.world import load_world

    sim = Simulation(load_world("corridor"), controller="ggc", robots=60, groups=2, seed=0,
                     max_ticks=20000)
    s = sim.run().summary
    assert sim.swarm.params.ruleset == "yield-holes"
    assert s["stop_reason"] in ("complete", "plateau") and s["coverage"] >= 0.96, s
    assert s["collision_stops"] == 0 and s["deadlocks_open"] == 0, s


@pytest.mark.slow
def test_two_groups_meeting_head_on_resolve_without_deadlock():
    """The corridor world: two formations enter a band from its two ends and meet (the
    paper's rule set: Section 4.3's Stop between groups)."""
    from swarmsim.world.world import load_world

    sim = Simulation(load_world("corridor"), controller="ggc", robots=60, groups=2, seed=0,
                     max_ticks=20000, settings={"ruleset": "paper"})
    s = sim.run().summary
    assert s["stop_reason"] in ("complete", "plateau"), s  # never stalled or out of ticks
    # One robot's coverage disc is 4 % of this small band, and a hole where the groups meet
    # is part of one: seeds 0-4 end at 0.967 / 0.977 / 0.990 / 0.974 / 0.975 by the plateau.
    assert s["coverage"] >= 0.96, s
    assert s["collision_stops"] > 0  # the groups did meet (Section 4.3 stops happened) ...
    state = ggc_state(sim)
    assert not (state["status"] == STOP).any()  # ... and every stop was lifted
    assert s["deadlocks_open"] == 0, s  # no deadlock left unreleased
    arrived = [(sim.positions[i], state["group"][i]) for i in range(len(state))
               if state["status"][i] == ARRIVE and sim.on_target[i]]
    pairs = [np.hypot(*(a - b)) for (a, g), (b, h) in itertools.combinations(arrived, 2)
             if g != h]
    assert min(pairs) <= 1.5 * 6.0  # the junction is filled: the groups' robots are neighbours


def test_too_many_groups_is_a_clear_error():
    """One past swarmsim.limits.MAX_GROUPS is refused naming the key, the bound and the
    value; the bound itself is a run GGC takes."""
    from swarmsim import ConfigError
    from swarmsim.limits import MAX_GROUPS

    one_more = MAX_GROUPS + 1
    with pytest.raises(ConfigError, match=rf"key 'groups': must be at most {MAX_GROUPS:,} "
                                          rf"\(groups in one run\), got {one_more}$"):
        Simulation.check(small_world(), controller="ggc", robots=one_more, groups=one_more)
    config, _ = Simulation.check(small_world(), controller="ggc", robots=MAX_GROUPS,
                                 groups=MAX_GROUPS, settings={"start": "random"})
    assert config.groups == MAX_GROUPS == GGC.max_groups


def test_twenty_groups_from_a_scattered_start_select_leaders_gather_and_leave():
    """More groups than the 16 a run once had: 20 leaders, every robot grouped and heard of
    every leader (per-group values sized by the run), formations formed, then departing."""
    sim = scattered(wide_band(), robots=200, groups=20, seed=0)
    assert sim.swarm.per_group.ldist.shape == (200, 20) and sim.messages["ldist"].shape[1] == 20
    for _ in range(800):
        sim.step()
    state = ggc_state(sim)
    assert sorted(state["group"][state["leader"]].tolist()) == list(range(1, 21))
    assert (state["group"] > 0).all()
    assert (sim.swarm.per_group.ldist < 1e9).all()  # every robot knows a way to each leader
    formed = (state["visited"] >> FORMED & 1).astype(bool)
    assert set(state["group"][formed].tolist()) == set(range(1, 21))
    assert formed.sum() >= 0.9 * len(state)
    left = np.isin(state["status"], [INITIAL, DETECTION, COVERAGE, ARRIVE])
    assert left.sum() >= 0.9 * len(state)  # the formations set off for the target


def test_twenty_formations_travel_to_the_target():
    """20 groups from the formation start: every formation moves off, robots arrive."""
    sim = Simulation(wide_band(), controller="ggc", robots=200, groups=20, seed=0,
                     max_ticks=5000)
    group = ggc_state(sim)["group"].copy()
    start = sim.positions.copy()
    for _ in range(400):
        sim.step()
    moved = np.hypot(*(sim.positions - start).T)
    assert min(np.median(moved[group == g]) for g in range(1, 21)) > 5.0
    assert (ggc_state(sim)["status"] == ARRIVE).sum() >= 10 and sim.on_target.sum() >= 10


@pytest.mark.parametrize("groups", [1, 3])
def test_broadcasts_carry_one_leader_distance_per_group(groups):
    """A run's message rows and per-group arrays hold the scattered start's per-group fields
    for its own groups only, and leaders' distance fields still spread."""
    sim = scattered(wide_band(), robots=60, groups=groups, seed=0)
    assert sim.messages["ldist"].shape == (60, groups)
    assert sim.messages["lepoch"].shape == (60, groups)
    assert [a.shape for a in sim.swarm.per_group] == [(60, groups)] * 2
    for _ in range(30):
        sim.step()
    heard_of_last_leader = sim.messages["ldist"][:, groups - 1] < 1e9
    assert heard_of_last_leader.sum() > 10


def test_formations_broadcast_no_leader_distances():
    """Formations never read the scattered start's per-group fields: their rows hold none
    (every row a robot hears is copied each tick)."""
    sim = Simulation(small_world(), controller="ggc", robots=60, groups=3, seed=0)
    assert sim.messages["ldist"].shape == (60, 0) and sim.messages["lepoch"].shape == (60, 0)
    assert [a.shape for a in sim.swarm.per_group] == [(60, 0)] * 2  # nor do their robots
    assert sim.dtype.itemsize <= 48


def test_a_robot_not_formed_in_time_covers_on_its_own():
    """aggregation_timeout: a robot of a group still gathering that long after leader selection
    covers on its own (Detection, then Coverage); it does not stop for good as Surplus."""
    params = GGCParams()
    bot = Bot(groups=3, robot_id=7, group=2, scattered=True, status=APPROACH)
    d = bot.step([], beacon_deg=0.0, tick=SELECTION + params.aggregation_timeout + 1)
    assert bot.me["visited"] >> DETECTION & 1
    assert bot.me["status"] in (DETECTION, COVERAGE)
    assert bot.me["status"] != SURPLUS and bot.me["surplus"] == 0
    assert np.hypot(*d.velocities[0]) > 0  # nobody to wait for: it heads for the beacon


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_every_group_keeps_a_leader_when_two_leaders_pick_the_same_robot(seed):
    """Leaders hand over on the same tick and may pick the same robot, which takes over one
    group only: the other leader must stay (5 groups on tiny lost a group on most seeds)."""
    sim = scattered("tiny", robots=40, groups=5, seed=seed)
    for _ in range(SELECTION + 1):
        sim.step()
    state = ggc_state(sim)
    assert sorted(state["group"][state["leader"]].tolist()) == [1, 2, 3, 4, 5]


def test_a_robot_cut_off_from_the_swarm_covers_on_its_own_after_the_timeout(monkeypatch):
    from swarmsim.world import spawn

    layout = spawn.random_layout

    def one_far_away(world, n, spacing, rng, **options):
        out = layout(world, n, spacing, rng, **options)
        out[0] = (-8.0, 0.0)  # over R_c = 15 from every spawn point: hears nobody
        return out

    monkeypatch.setattr(spawn, "random_layout", one_far_away)
    sim = scattered("tiny", robots=40, groups=1, seed=0, aggregation_timeout=300)
    start = sim.positions[0].copy()
    for _ in range(SELECTION + 300 + 1 + 100):
        sim.step()
    robot = ggc_state(sim)[0]
    assert robot["visited"] >> DETECTION & 1 and robot["status"] in (COVERAGE, ARRIVE)
    assert np.hypot(*(sim.positions[0] - start)) > 5  # on its way to the beacon


@pytest.mark.slow
def test_where_the_target_is_full_every_robot_of_every_group_ends_standing():
    """d_cover 8 on the corridor holds 23 of 60 robots: the default's surplus movers of both
    groups stop (SURPLUS flag), so the run ends stalled, not on the plateau rule."""
    from swarmsim.world.world import load_world

    sim = Simulation(load_world("corridor"), controller="ggc", robots=60, groups=2, seed=0,
                     d_cover=8, max_ticks=30000)
    s = sim.run().summary
    assert s["stop_reason"] == "stalled" and "Coverage" not in s["status_counts"], s
    assert s["surplus_stops"] > 0 and s["robots_placed"] >= 20 and s["coverage"] >= 0.74, s
