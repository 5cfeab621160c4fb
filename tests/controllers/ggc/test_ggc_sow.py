"""SOW (rules/sow.py): a formation walks on across the target and its rearmost robots settle
where it leaves them, about d_cover apart, while the rest travel on."""

import numpy as np
import pytest

from controllers.ggc.statuses import ARRIVE, CMD_TRAVEL, INITIAL
from swarmsim import Simulation
from tests.conftest import small_world
from tests.ggc_bot import Bot

SOW = "sow"
AHEAD = ((0.0, 1.0), 2, 1, INITIAL)
"""My gradient parent, one unit ahead along my travel vector (+y)."""


def sows(ruleset: str, rows, on_target: bool = True) -> bool:
    """Does a travelling robot (id 5, group 1, heading +y) with these neighbours settle?"""
    bot = Bot(groups=3, status=INITIAL, ruleset=ruleset)
    bot.me["cmd"], bot.me["travel_x"], bot.me["travel_y"] = CMD_TRAVEL, 0.0, 0.1
    bot.me["gradient"] = 4
    bot.step(rows, on_target=on_target, probe=lambda offset: True,
             gradient=[3] + [4] * (len(rows) - 1), cmd=CMD_TRAVEL, travel_y=0.1)
    return int(bot.me["status"]) == ARRIVE


@pytest.mark.parametrize(("rows", "on_target", "expected"), [
    ([AHEAD], True, True),                                        # the rear, on the target
    ([AHEAD], False, False),                                      # the rear, off the target
    ([AHEAD, ((0.5, -1.0), 3, 1, INITIAL)], True, False),         # a robot of mine behind me
    ([AHEAD, ((3.0, -4.0), 3, 1, INITIAL)], True, False),         # behind me, within d_cover
    ([AHEAD, ((4.0, 0.0), 9, 1, INITIAL)], True, False),          # level, larger id
    ([AHEAD, ((4.0, 0.0), 3, 1, INITIAL)], True, True),           # level, smaller id
    ([AHEAD, ((0.0, -7.0), 3, 1, INITIAL)], True, True),          # behind, beyond d_cover
    ([AHEAD, ((4.0, -3.0), 7, 2, ARRIVE)], True, False),          # a settled robot near
    ([AHEAD, ((5.0, -3.0), 7, 2, ARRIVE)], True, True),           # settled, d_cover away
])
def test_the_rearmost_robot_on_the_target_settles_where_it_stands(rows, on_target, expected):
    assert sows(SOW, rows, on_target) == expected
    assert not sows("yield-holes", rows, on_target)  # the default never settles in Initial


def test_a_formation_sows_robots_while_it_travels_and_they_stand_apart():
    world = small_world(width=40.0, height=40.0)
    sim = Simulation(world, controller="ggc", robots=60, groups=1, seed=3, max_ticks=700,
                     settings={"ruleset": SOW})
    state = sim.swarm.state
    sown_in_travel = 0
    while sim.advance() is None:
        status = state["status"]
        if np.any(status == INITIAL):
            sown_in_travel = int(np.sum(status == ARRIVE))
    settled = sim.positions[state["status"] == ARRIVE]
    assert sown_in_travel >= 3, sown_in_travel
    d = np.hypot(*(settled[:, None, :] - settled[None, :, :]).transpose(2, 0, 1))
    d[np.diag_indices_from(d)] = np.inf
    rules = Bot(groups=1, ruleset=SOW).swarm.rules
    assert d.min() >= rules.d_cover - rules.arrive_tolerance - 0.3, d.min()


@pytest.mark.parametrize(("ruleset", "floor_ahead", "halts"), [
    ("yield-holes", True, True),   # the default halts where the front touches the target
    (SOW, True, False),            # sow walks on across the target
    (SOW, False, True),            # ... until the floor ahead leaves it
])
def test_the_sowing_leader_walks_on_until_its_front_reaches_the_far_edge(ruleset, floor_ahead,
                                                                         halts):
    bot = Bot(groups=3, status=INITIAL, leader=True, ruleset=ruleset)
    bot.me["cmd"], bot.me["travel_x"], bot.me["travel_y"] = CMD_TRAVEL, 0.0, 0.1
    bot.step([((0.0, -1.0), 6, 1, INITIAL)], on_target=True,
             probe=lambda offset: floor_ahead, beacon_deg=90.0)
    assert (int(bot.me["status"]) == ARRIVE) == halts


def test_sow_acts_with_one_group_so_the_run_is_its_own():
    from controllers.ggc import GGCParams
    from controllers.ggc.rules.rulesets import SOW as SOW_FLAG
    from controllers.ggc.swarm import acting_flags, same_run_ruleset

    for groups in (1, 3):
        params = GGCParams(ruleset=SOW)
        assert acting_flags(params, groups) & SOW_FLAG
        assert same_run_ruleset(params, groups) == SOW
