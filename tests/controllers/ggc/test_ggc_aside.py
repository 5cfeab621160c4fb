"""Formations that meet another group's: they halt beside a formation that reached the
target (flag BESIDE, the default "yield-holes"), or turn aside (rules/aside.py, the
experimental rule set "yield-holes-aside") and slide along its robots, instead of pushing
through (as under "yield-holes-push", the default without BESIDE)."""

import numpy as np
import pytest
from scipy.spatial import cKDTree

from controllers.ggc.statuses import ARRIVE, CMD_TRAVEL, COVERAGE, DETECTION, INITIAL
from swarmsim import Simulation
from swarmsim.world.world import world_from_dict
from tests.ggc_bot import Bot

V = 0.1
"""The formation's speed, units per tick (GGCParams.v)."""
ASIDE = "yield-holes-aside"
PUSH = "yield-holes-push"
"""The default rules without BESIDE: formations push into each other."""
BESIDE = "yield-holes"
"""The default rule set, with BESIDE."""


def _follower(ruleset: str = ASIDE) -> Bot:
    """A robot of group 1 in Initial, one hop from its leader."""
    return Bot(groups=3, status=INITIAL, ruleset=ruleset)


def _travel(bot: Bot, others, **fields) -> int:
    """One tick copying its parent's travel straight up, beside ``others`` (``fields``: their
    broadcasts' columns, the parent's first); the side it says."""
    parent = ((0.0, -1.0), 0, 1, INITIAL)
    rows = [parent, *others]
    bot.step(rows, gradient=[0] + [0] * len(others), cmd=CMD_TRAVEL, travel_x=0.0, travel_y=V,
             **fields)
    return int(bot.me["blocked"])


def test_a_robot_says_to_turn_away_from_another_groups_robot_ahead():
    assert _travel(_follower(), [((-0.4, 1.0), 7, 2, DETECTION)]) == -1  # ahead, left: right
    assert _travel(_follower(), [((0.4, 1.0), 7, 2, DETECTION)]) == 1    # ahead, right: left
    assert _travel(_follower(), [((1.2, 0.3), 7, 2, DETECTION)]) == 0    # beside: no turn
    assert _travel(_follower(), [((0.0, 1.2), 7, 1, DETECTION)]) == 0    # my group: no turn


def test_the_default_rules_and_one_group_never_turn():
    for ruleset in (BESIDE, PUSH, "paper"):
        assert _travel(_follower(ruleset), [((0.0, 1.0), 7, 2, DETECTION)]) == 0
    lone = Bot(groups=1, status=INITIAL, ruleset=ASIDE)
    lone.step([((0.0, -1.0), 0, 1, INITIAL), ((0.2, 1.0), 7, 1, DETECTION)],
              gradient=[0, 0], cmd=CMD_TRAVEL, travel_x=0.0, travel_y=V)
    assert lone.me["blocked"] == 0


def test_the_word_runs_inward_to_the_leader_which_turns_and_then_heads_on():
    leader = Bot(groups=3, status=INITIAL, leader=True, ruleset=ASIDE)
    child = ((0.0, 1.0), 9, 1, INITIAL)  # one hop out (gradient 1), says turn left
    d = leader.step([child], beacon_deg=90.0, gradient=1, blocked=1)
    assert np.allclose(d.velocities[0], [-V, 0.0])
    d = leader.step([child], beacon_deg=90.0, gradient=1, blocked=-1)
    assert np.allclose(d.velocities[0], [V, 0.0])
    d = leader.step([child], beacon_deg=90.0, gradient=1, blocked=0)
    assert np.allclose(d.velocities[0], [0.0, V])  # nobody says so: toward the beacon
    # a robot nearer the leader than me (gradient 0 < mine 1) is not heard
    mid = _follower()
    _travel(mid, [])
    assert mid.me["gradient"] == 1
    mid.step([((0.0, -1.0), 0, 1, INITIAL), ((1.0, 0.0), 3, 1, INITIAL)],
             gradient=[0, 0], cmd=CMD_TRAVEL, travel_x=0.0, travel_y=V, blocked=[0, 1])
    assert mid.me["blocked"] == 0
    mid.step([((0.0, -1.0), 0, 1, INITIAL), ((1.0, 0.0), 3, 1, INITIAL)],
             gradient=[0, 2], cmd=CMD_TRAVEL, travel_x=0.0, travel_y=V, blocked=[0, 1])
    assert mid.me["blocked"] == 1


def test_a_halted_leader_says_nothing():
    leader = Bot(groups=3, status=INITIAL, leader=True, ruleset=ASIDE)
    leader.step([((0.0, 1.0), 9, 1, INITIAL)], beacon_deg=90.0, gradient=1, blocked=1,
                on_target=True)
    assert leader.me["status"] == ARRIVE and leader.me["blocked"] == 0


def _queue() -> dict:
    """A spawn strip narrow enough that two formations stand one behind the other, below a
    wide target: the one behind meets the one ahead on its way."""
    return {"name": "queue", "target": {"outline": [[-12, 30], [20, 30], [20, 40], [-12, 40]]},
            "spawn": [{"outline": [[0, 0], [8, 0], [8, 22], [0, 22]]}],
            "beacon": {"position": [4, 36]}, "arena": {"margin": 10.0}}


def _touching_when_halted(ruleset: str, seed: int) -> tuple[int, int]:
    """(pairs of robots of two groups touching, pairs of one group touching) once no robot is
    in Initial: a formation pushed by another packs until its robots touch."""
    sim = Simulation(world_from_dict(_queue()), controller="ggc", robots=60, groups=2,
                     seed=seed, d_cover=6.0, settings={"ruleset": ruleset})
    group = sim.start_groups
    for _ in range(1000):
        sim.step()
        if sim.tick > 1 and not np.any(sim.messages["status"] == INITIAL):
            break
    assert not np.any(sim.messages["status"] == INITIAL), f"{ruleset}: robots left in Initial"
    pairs = cKDTree(sim.positions).query_pairs(2 * sim.physics_config.radius + 0.01,
                                                output_type="ndarray")
    mixed = group[pairs[:, 0]] != group[pairs[:, 1]]
    return int(np.count_nonzero(mixed)), int(np.count_nonzero(~mixed))


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 3])
def test_the_formation_behind_goes_round_the_one_ahead_instead_of_through_it(seed):
    """Seed 3 sheds two robots at the rim, which count each other's gradients up: they start
    alone (LOST_HOPS) instead of travelling on for ever."""
    mixed, same = _touching_when_halted(ASIDE, seed)
    assert mixed <= 5 and same <= 30
    mixed, same = _touching_when_halted(PUSH, seed)
    assert mixed >= 10 and same >= 50  # pushed through: both formations packed


def test_a_formation_halts_beside_another_groups_formation_that_reached_the_target():
    halted = ((0.0, 1.2), 7, 2, DETECTION)  # another group's, waiting in its formation
    for ruleset, expected in ((BESIDE, True), (PUSH, False), ("paper", False)):
        bot = _follower(ruleset)
        _travel(bot, [halted], touch=[False, True])
        assert bool(bot.me["touch"]) is expected, ruleset
    bot = _follower(BESIDE)  # its formation has not reached the target: travel on
    _travel(bot, [halted], touch=[False, False])
    assert not bot.me["touch"]
    bot = _follower(BESIDE)  # a mover that came from such a formation is not one
    _travel(bot, [((0.0, 1.2), 7, 2, COVERAGE)], touch=[False, True])
    assert not bot.me["touch"]
    leader = Bot(groups=3, status=INITIAL, leader=True, ruleset=BESIDE)
    d = leader.step([halted], beacon_deg=90.0, touch=True)
    assert leader.me["status"] == ARRIVE and np.allclose(d.velocities[0], [0.0, 0.0])


def test_the_formation_behind_halts_behind_the_one_ahead():
    mixed, same = _touching_when_halted(BESIDE, 0)
    assert mixed <= 5 and same <= 5
