"""TRAINS (rules/trains.py): formations release their robots as trains, a train gap apart
instead of d_cover, and never into each other."""

import numpy as np
import pytest

from controllers.ggc.rules.detection import BY_MOVER, BY_WAITING, NOT_BLOCKED, blocked
from controllers.ggc.rules.trains import train_gap
from controllers.ggc.statuses import COVERAGE, DETECTION
from swarmsim import Simulation
from tests.conftest import small_world
from tests.ggc_bot import Bot, view

TRAINS = "yield-holes-trains"
INWARD = ((-1.0, 0.0), 3, 1, DETECTION)
"""A waiting robot of my formation on my left: my way out (orbit sense +1) is +y."""


@pytest.mark.parametrize(("other", "default", "trains"), [
    (((1.0, 3.5), 9, 1, COVERAGE), BY_MOVER, NOT_BLOCKED),      # mover ahead, past the gap
    (((0.5, 2.0), 9, 1, COVERAGE), BY_MOVER, BY_MOVER),         # mover ahead, within it
    (((1.0, -3.5), 9, 1, COVERAGE), BY_MOVER, BY_MOVER),        # mover behind: may walk in
    (((0.0, 4.0), 9, 1, DETECTION), BY_WAITING, NOT_BLOCKED),   # outranks me, leaves ahead
    (((0.0, 2.0), 9, 1, DETECTION), BY_WAITING, BY_WAITING),    # outranks me, too close
    (((0.0, -4.0), 9, 1, DETECTION), BY_WAITING, BY_WAITING),   # outranks me, behind
])
def test_a_waiting_robot_leaves_a_train_gap_behind_the_robot_ahead(other, default, trains):
    rows = [INWARD, other]
    for ruleset, expected in (("yield-holes", default), (TRAINS, trains)):
        bot = Bot(groups=1, status=DETECTION, ruleset=ruleset)
        bot.me["gradient"] = 5
        got = blocked(view(rows, 1, gradient=[4, 6]), bot.me, bot.swarm.rules)
        assert got == expected, (ruleset, other)


def departures(ruleset: str, ticks: int) -> list[float]:
    """Each departure (Detection -> Coverage) of a 60-robot formation on the small world in
    ``ticks`` ticks: the distance from the robot that left to the nearest other mover."""
    sim = Simulation(small_world(), controller="ggc", robots=60, groups=1, seed=3,
                     max_ticks=ticks, settings={"ruleset": ruleset})
    status = sim.swarm.state["status"].copy()
    nearest: list[float] = []
    while sim.advance() is None:
        now = sim.swarm.state["status"]
        movers = np.flatnonzero(now == COVERAGE)
        for i in np.flatnonzero((status == DETECTION) & (now == COVERAGE)):
            others = movers[movers != i]
            d = np.hypot(*(sim.positions[others] - sim.positions[i]).T)
            nearest.append(float(d.min()) if len(d) else np.inf)
        status[:] = now
    return nearest


def test_trains_leave_closer_together_than_d_cover_and_never_into_each_other():
    ticks = 900
    default, trains = departures("yield-holes", ticks), departures(TRAINS, ticks)
    bot = Bot(groups=1, ruleset=TRAINS)
    gap, d_cover = train_gap(bot.swarm.rules), bot.swarm.rules.d_cover
    assert len(trains) > len(default) >= 5, (len(trains), len(default))
    assert min(trains) >= gap - 2 * bot.swarm.rules.v, min(trains)  # never into each other
    close = [d for d in trains if d < 0.8 * d_cover]  # behind the robot ahead, not d_cover
    assert len(close) >= len(trains) // 4, sorted(trains)


def test_trains_act_with_one_group_so_the_run_is_its_own():
    from controllers.ggc import GGCParams
    from controllers.ggc.rules.rulesets import TRAINS as TRAINS_FLAG
    from controllers.ggc.swarm import acting_flags, same_run_ruleset

    for groups in (1, 3):
        params = GGCParams(ruleset=TRAINS)
        assert acting_flags(params, groups) & TRAINS_FLAG
        assert same_run_ruleset(params, groups) == TRAINS
