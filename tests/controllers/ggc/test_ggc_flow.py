"""Walking through the structure (rules/flow.py, the THROUGH flag, rule set "flow"): movers
settle at the first free lattice site they meet, and walk through the structure to it."""

import math

import numpy as np
import pytest

from controllers.ggc.params import GGCParams
from controllers.ggc.rules.flow import SITE_REACHED
from controllers.ggc.rules.rulesets import RULESETS, THROUGH
from controllers.ggc.statuses import ARRIVE, COVERAGE
from controllers.ggc.swarm import acting_flags, same_run_ruleset
from swarmsim.engine.sim import Simulation
from tests.ggc_bot import Bot

HEIGHT = 6.0 * math.sqrt(3.0) / 2.0
"""A site's distance from the line through its two anchors, 6 apart (d_cover 6)."""


def anchors(site_x: float, site_y: float) -> list:
    """Two arrived robots (group 1), 6 apart, whose site below them is (site_x, site_y) from
    me; the site above them lies 2 HEIGHT farther up."""
    return [((site_x - 3.0, site_y + HEIGHT), 20, 1, ARRIVE),
            ((site_x + 3.0, site_y + HEIGHT), 21, 1, ARRIVE)]


def flow_mover() -> Bot:
    bot = Bot(ruleset="flow")
    bot.me["gradient"] = 50  # the anchors' gradient (0) is lower: rule (b) alone would stop me
    return bot


def test_flow_is_the_default_plus_through_and_acts_with_one_group():
    assert RULESETS["flow"] == RULESETS["yield-holes"] | THROUGH
    assert acting_flags(GGCParams(ruleset="flow"), 1) & THROUGH
    assert same_run_ruleset(GGCParams(ruleset="flow"), 1) == "flow"


def test_a_mover_on_the_target_heads_for_the_free_site_and_arrives_on_it():
    bot = flow_mover()
    v = bot.step(anchors(4.0, 0.0), on_target=True, probe=lambda offset: True).velocities[0]
    assert v[0] > 0 and abs(v[1]) < 0.5 * v[0]  # toward (4, 0)
    assert bot.me["status"] == COVERAGE
    bot.step(anchors(SITE_REACHED * 0.5, 0.0), on_target=True, probe=lambda offset: True)
    assert bot.me["status"] == ARRIVE
    assert bot.me["gradient"] == 1  # 1 + the lowest gradient of my group's arrived robots


def test_a_site_the_probe_finds_off_the_target_is_not_taken():
    bot = flow_mover()
    bot.step(anchors(1.5, 0.0), on_target=True, probe=lambda offset: False)
    assert bot.me["status"] == COVERAGE
    assert bot.me["ban_next"] == 1  # remembered, 1.5 ahead (carried by my odometry)
    assert math.hypot(bot.me["ban_x"][0] - 1.5, bot.me["ban_y"][0]) < 0.2
    bot.step(anchors(1.4, 0.0), on_target=True, probe=lambda offset: True, moved=(0.1, 0.0))
    assert bot.me["ban_next"] == 1  # the same site, 0.1 nearer: not asked again


def test_a_site_a_stationary_robot_crowds_is_not_free():
    crowded = [*anchors(SITE_REACHED * 0.5, 0.0), ((0.0, -5.0), 22, 2, ARRIVE)]
    bot = flow_mover()
    bot.step(crowded, on_target=True, probe=lambda offset: True)
    assert bot.me["status"] != ARRIVE


def test_without_the_flag_the_same_mover_does_not_stop_on_the_site():
    bot = Bot(ruleset="yield-holes")
    bot.me["gradient"] = 50
    bot.step(anchors(SITE_REACHED * 0.5, 0.0), on_target=True, probe=lambda offset: True)
    assert bot.me["status"] == COVERAGE


@pytest.mark.slow
def test_flow_completes_a_small_world():
    result = Simulation("tiny", controller="ggc", seed=0, max_ticks=6000,
                        settings={"ruleset": "flow"}).run()
    assert result.summary["coverage"] >= 0.99
    assert result.summary["completion_tick"] is not None
    assert np.isfinite(result.summary["total_distance"])
