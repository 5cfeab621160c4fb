"""Movers confined without a place give up (rules/confined.py): the rule alone on a hand-made
robot, and a scene whose movers have no place they can reach."""

import pytest

from controllers.ggc.statuses import ARRIVE, COVERAGE, DETECTION, SURPLUS
from swarmsim import Simulation
from swarmsim.world.world import world_from_dict
from tests.ggc_bot import Bot

EDGE = [((2.0, 0.0), 40, 1, ARRIVE)]
"""One arrived robot, d_cover 2 away: a mover beside it follows its edge."""


def _search(bot: Bot, ticks: int, moved=(0.0, 0.0), on_target: bool = False,
            rows=EDGE) -> None:
    """Decide ``ticks`` ticks beside ``rows``, the odometry adding ``moved`` each tick."""
    for _ in range(ticks):
        if bot.me["status"] != COVERAGE:
            return
        bot.step(rows, moved=moved, on_target=on_target, beacon_deg=90.0)


def _bot(groups: int = 1) -> Bot:
    """A mover at d_cover 2 that gives up after 75 ticks (confined_ticks 50 at d_cover 1, in
    proportion to d_safe + d_cover) within 12 units (confined_reach 6 d_cover)."""
    return Bot(groups=groups, d_cover=2.0, confined_ticks=50.0)


def test_a_mover_that_stays_within_reach_for_confined_ticks_gives_up():
    bot = _bot()
    _search(bot, 74)
    assert bot.me["status"] == COVERAGE and bot.me["roam_ticks"] == 74
    _search(bot, 1)
    assert bot.me["status"] == SURPLUS and bot.me["surplus"] == 1
    on = _bot(groups=3)
    _search(on, 75, on_target=True)
    assert on.me["status"] == ARRIVE  # on the target it stops where it is, covering it


def test_getting_beyond_the_reach_starts_the_count_again():
    bot = _bot()
    _search(bot, 40, moved=(0.25, 0.0))  # 10 units from where the count started
    assert bot.me["roam_ticks"] == 40
    _search(bot, 30, moved=(0.25, 0.0))  # beyond 12 units 10 ticks on: counted afresh
    assert bot.me["status"] == COVERAGE and 10 < bot.me["roam_ticks"] < 30


def test_the_structure_growing_near_me_starts_the_count_again():
    """Early on, movers jam while the structure still grows round them: no give-up then."""
    bot = _bot()
    _search(bot, 60)
    grown = EDGE + [((-2.0, 1.0), 41, 1, ARRIVE)]  # a robot arrived near me
    _search(bot, 1, rows=grown)
    assert bot.me["roam_ticks"] == 1 and bot.me["roam_seen"] == 2
    _search(bot, 60, rows=EDGE)  # one of them out of hearing again: no news
    assert bot.me["status"] == COVERAGE and bot.me["roam_ticks"] == 61
    _search(bot, 14, rows=EDGE)
    assert bot.me["status"] == SURPLUS


def test_a_mover_that_walks_past_confined_walk_gives_up():
    """Walking on, the mover leaves its reach again and again, so the count of ticks never
    ends; the walk since it left its formation does: 5 * d_cover * max(d_cover, 2) = 20 units
    at d_cover 2, here 80 ticks of 0.25 units."""
    bot = Bot(groups=1, d_cover=2.0, confined_ticks=50.0, confined_walk=5.0)
    _search(bot, 80, moved=(0.25, 0.0))
    assert bot.me["status"] == COVERAGE and bot.me["path"] == pytest.approx(20.0)
    assert bot.me["roam_ticks"] < 75  # the count alone would not end the walk
    _search(bot, 1, moved=(0.25, 0.0))
    assert bot.me["status"] == SURPLUS
    paper = Bot(groups=1, d_cover=2.0, confined_walk=5.0, ruleset="paper")
    _search(paper, 200, moved=(0.25, 0.0))
    assert paper.me["status"] == COVERAGE  # the paper's rules walk on


@pytest.mark.parametrize("settings", [{"d_cover": 6.0}, {"d_cover": 2.0, "ruleset": "paper"},
                                      {"d_cover": 2.0, "ruleset": "yield"}])
def test_no_give_up_at_d_cover_6_or_without_the_surplus_flag(settings):
    bot = Bot(groups=1, confined_ticks=50.0, **settings)
    _search(bot, 400)
    assert bot.me["status"] != SURPLUS and bot.me["surplus"] == 0
    assert bot.me["roam_ticks"] == 0


def _walled_off_world():
    """A 16 x 6 target whose right half lies inside a closed ring of walls: the movers fill
    the left half, and the right half stays uncovered, so the run cannot complete."""
    bar = [[17, 27], [18, 27], [18, 39], [17, 39]]
    return world_from_dict({
        "name": "walled-off",
        "target": {"outline": [[10, 30], [26, 30], [26, 36], [10, 36]]},
        "spawn": [{"outline": [[6, 8], [26, 8], [26, 16], [6, 16]]}],
        "obstacles": [{"outline": bar},
                      {"outline": [[17, 38], [30, 38], [30, 39], [17, 39]]},
                      {"outline": [[17, 27], [30, 27], [30, 28], [17, 28]]},
                      {"outline": [[29, 27], [30, 27], [30, 39], [29, 39]]}],
        "beacon": {"position": [13.5, 33.0]},
        "arena": {"margin": 10.0},
    })


@pytest.mark.slow
def test_movers_with_no_place_they_can_reach_end_standing():
    """d_cover 2: the reachable half holds fewer than the 30 robots; the surplus lap does not
    apply at this d_cover, so without the rule the other movers walk on to the tick limit
    (confined_ticks 10^9). confined_ticks shortened so that the test runs in seconds."""
    sim = Simulation(_walled_off_world(), controller="ggc", robots=30, groups=1, seed=0,
                     d_cover=2.0, max_ticks=12000, settings={"confined_ticks": 1000.0})
    s = sim.run().summary
    assert s["stop_reason"] == "stalled", s
    assert set(s["status_counts"]) <= {"Arrive", "Surplus"}, s
    assert s["surplus_stops"] > 0 and s["robots_placed"] >= 20, s


def test_the_count_pauses_while_my_group_still_has_robots_waiting():
    """Beside my formation, while it still sends robots out, a slow search is no reason to
    give up; once none is left waiting the count goes on."""
    bot = _bot()
    waiting = EDGE + [((0.0, -3.0), 42, 1, DETECTION)]  # one of my group, still to be sent
    _search(bot, 200, rows=waiting)
    assert bot.me["status"] == COVERAGE and bot.me["roam_ticks"] == 0
    _search(bot, 75)
    assert bot.me["status"] == SURPLUS
