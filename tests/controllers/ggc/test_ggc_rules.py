"""GGC's rules on hand-made neighbourhoods (no simulation): one robot decided by the run's
driver (tests/ggc_bot.py), or one rule called alone on a view."""

import math

import numpy as np
import pytest

from controllers.ggc import GGCParams
from controllers.ggc.rules.coverage import edge_rows, valley
from controllers.ggc.rules.cross import CROSS_MAX, CROSS_PATH
from controllers.ggc.rules.deadlock import may_arrive_when_stuck, wedged
from controllers.ggc.rules.detection import (
    BY_WAITING,
    NOT_BLOCKED,
    blocked,
    nobody_to_yield_to,
)
from controllers.ggc.rules.holes import HOLE_PATH
from controllers.ggc.rules.intergroup import stops
from controllers.ggc.statuses import (
    ARRIVE,
    CMD_HALT,
    CMD_TRAVEL,
    COVERAGE,
    DETECTION,
    INITIAL,
    STOP,
    SURPLUS,
)
from tests.ggc_bot import Bot, view

NEIGHBOURS = [((1.0, 0.0), 7, 2, DETECTION),   # another group's formation
              ((2.0, 0.0), 8, 1, DETECTION),   # my group's formation
              ((3.0, 0.0), 9, 3, ARRIVE)]      # another group's arrived robot


@pytest.mark.slow
def test_other_groups_formations_are_not_edges():
    bot = Bot()
    assert edge_rows(view(NEIGHBOURS), bot.me, bot.swarm.rules) == (1, 2)
    one = Bot(groups=1)  # one group: every stationary robot is an edge
    assert edge_rows(view(NEIGHBOURS, groups=1), one.me, one.swarm.rules) == (0, 1)


@pytest.mark.slow
def test_another_groups_mover_with_priority_makes_a_mover_stop():
    bot = Bot(ruleset="paper")
    sense = None  # the paper's rule reads no sensor
    behind = view([((-2.0, 0.0), 9, 2, COVERAGE)])
    lower_id = view([((2.0, 0.0), 3, 2, COVERAGE)])
    far = view([((6.5, 0.0), 9, 2, COVERAGE)])
    mine = view([((2.0, 0.0), 9, 1, COVERAGE)])
    assert stops(behind, bot.me, sense, bot.swarm.rules)       # anywhere within d_cover
    assert not stops(lower_id, bot.me, sense, bot.swarm.rules)  # ids break the symmetry
    assert not stops(far, bot.me, sense, bot.swarm.rules)
    assert not stops(mine, bot.me, sense, bot.swarm.rules)
    one = Bot(groups=1, ruleset="paper")
    assert not stops(view([((-2.0, 0.0), 9, 2, COVERAGE)], groups=1), one.me, sense,
                     one.swarm.rules)


@pytest.mark.slow
def test_a_mover_stops_for_another_groups_mover_and_resumes_when_it_has_gone():
    bot = Bot(ruleset="paper")
    rows = [((2.0, 0.5), 9, 2, COVERAGE), ((6.0, 0.0), 8, 1, ARRIVE)]
    bot.step(rows)
    assert bot.me["status"] == STOP and bot.me["collision_stops"] == 1
    bot.step(rows)
    assert bot.me["status"] == STOP
    bot.step(rows[1:])
    assert bot.me["status"] == COVERAGE


@pytest.mark.slow
@pytest.mark.parametrize("ruleset", ["yield", "yield-holes"])
def test_under_the_yield_rule_sets_another_groups_mover_parks_no_one(ruleset):
    """The YIELD flag: no Stop between groups; a larger-id mover close ahead of any group is
    given way to (coverage.give_way), one behind is not."""
    rows = [((2.0, 0.5), 9, 2, COVERAGE), ((6.0, 0.0), 8, 1, ARRIVE)]
    paper, yielding = Bot(ruleset="paper"), Bot(ruleset=ruleset)
    assert stops(view(rows), yielding.me, None, yielding.swarm.rules) is False
    assert stops(view(rows), paper.me, None, paper.swarm.rules)
    yielding.step(rows)
    assert yielding.me["status"] == COVERAGE and yielding.me["collision_stops"] == 0
    behind = [((-2.0, 0.5), 9, 2, COVERAGE), ((6.0, 0.0), 8, 1, ARRIVE)]
    assert np.hypot(*yielding.step(behind).velocities[0]) > 0  # nobody ahead: it moves on


def _yielder_view(enclosed: list[bool], with_leader: bool):
    """A wedged rim robot: waiting robots of its group on one side (one row of a formation),
    and, with_leader, an arrived robot on the other side closing the ring."""
    rows = [((1.0, 0.0), 7, 1, DETECTION), ((0.5, 0.87), 8, 1, DETECTION),
            ((-0.5, 0.87), 9, 1, DETECTION), ((-1.0, 0.0), 10, 1, DETECTION)]
    if with_leader:
        rows.append(((0.0, -1.0), 1, 1, ARRIVE))
    return rows, {"enclosed": enclosed + [False] * with_leader}


def test_a_yielding_rim_robot_stops_yielding_when_everyone_around_it_yields():
    bot = Bot(groups=1, d_cover=2.0, status=DETECTION)
    bot.me["yield_count"] = 4
    P = bot.swarm.rules
    rows, fields = _yielder_view([True, True, True, True], with_leader=False)
    assert nobody_to_yield_to(view(rows, 1, **fields), P)
    bot.step(rows, **fields)
    assert bot.me["yield_count"] == 0 and bot.me["status"] == DETECTION  # waits, then turns
    rows, fields = _yielder_view([True, False, True, True], with_leader=False)
    assert not nobody_to_yield_to(view(rows, 1, **fields), P)  # one may still leave first
    rows, fields = _yielder_view([True, True, True, True], with_leader=True)
    assert not nobody_to_yield_to(view(rows, 1, **fields), P)  # inside the formation


def test_yield_release_is_off_above_its_d_cover_bound():
    bot = Bot(groups=1, d_cover=6.0, status=DETECTION)  # default bound 4
    bot.me["yield_count"] = 4
    rows, fields = _yielder_view([True, True, True, True], with_leader=False)
    bot.step(rows, **fields)
    assert bot.me["yield_count"] == 4


@pytest.mark.slow
def test_a_stuck_mover_beside_its_formation_rejoins_it_at_small_d_cover_or_with_groups():
    def is_wedged(rows, groups, d_cover):
        bot = Bot(groups=groups, d_cover=d_cover)
        return wedged(view(rows, groups), bot.me, bot.swarm.rules)

    beside = [((1.2, 0.0), 7, 1, DETECTION), ((0.0, 1.1), 9, 1, ARRIVE)]
    assert is_wedged(beside, 1, 2.0)            # a formation neighbour: rejoin
    assert not is_wedged(beside, 1, 6.0)        # d_cover 6: only when touching
    assert is_wedged([((0.85, 0.0), 7, 1, DETECTION)], 1, 6.0)
    assert is_wedged(beside, 3, 6.0)            # with groups: at any d_cover
    assert not is_wedged([((1.2, 0.0), 7, 2, DETECTION)], 3, 6.0)  # only my own formation


@pytest.mark.slow
def test_a_mover_jammed_against_another_formation_beside_its_own_waits_with_its_own():
    """L-hole seed 1: two formations side by side, a mover of each pressed into the other's;
    each formation waited for its own mover, and nothing moved (a stall at 0.692)."""
    jammed = [((0.8, 0.0), 7, 2, DETECTION), ((-4.5, 0.0), 8, 1, DETECTION)]

    def is_wedged(rows, ruleset):
        bot = Bot(groups=3, ruleset=ruleset)
        return wedged(view(rows, 3), bot.me, bot.swarm.rules)

    assert is_wedged(jammed, "yield-holes")
    assert not is_wedged(jammed, "paper")  # the paper's rules as they were
    assert not is_wedged(jammed[:1], "yield-holes")  # my formation is not beside me: go on


def test_a_deadlocked_mover_arrives_where_it_is_when_a_robot_nearby_has_stopped():
    """Algorithm 5, line 5: deadlock on the target and a Stop robot near: Arrive."""
    close = [((2.0, 0.0), 8, 1, ARRIVE), ((4.0, 0.0), 9, 2, STOP)]
    no_stop = [((2.0, 0.0), 8, 1, ARRIVE), ((4.0, 0.0), 9, 2, COVERAGE)]
    P3, P1 = Bot().swarm.rules, Bot(groups=1).swarm.rules
    assert may_arrive_when_stuck(view(close), P3)
    assert not may_arrive_when_stuck(view(no_stop), P3)
    assert may_arrive_when_stuck(view(no_stop, groups=1), P1)  # one group: anywhere
    # through the driver: stuck on the target beside a robot in Stop
    bot = Bot()
    bot.me["progress_tick"] = 0
    bot.step(close, on_target=True, probe=lambda offset: True, moved=(0.0, 0.0), tick=100)
    assert bot.me["status"] == ARRIVE and bot.me["deadlocks"] == 1


def test_with_groups_a_robot_in_stop_does_not_hold_its_formation_back():
    """Algorithm 7 waits for neighbours of larger gradient; with groups, one in Stop (Section
    4.3) has left already, and may wait there for another group's mover for good."""
    rows = [((3.0, 0.0), 9, 1, STOP)]
    for groups, expected in ((3, NOT_BLOCKED), (1, BY_WAITING)):
        bot = Bot(groups=groups, status=DETECTION)
        bot.me["gradient"] = 5
        assert blocked(view(rows, groups, gradient=7), bot.me, bot.swarm.rules) == expected


ARRIVED_ONLY = [((6.0, 0.0), 40, 1, ARRIVE)]            # away: no waiting robot heard
BACK_HOME = [((6.0, 0.0), 8, 1, DETECTION)]             # beside my group's formation


def mover(**params) -> Bot:
    return Bot(groups=1, d_cover=8.0, **params)


def test_a_mover_back_at_its_formation_after_a_lap_past_no_free_floor_is_surplus():
    bot = mover()
    bot.step(ARRIVED_ONLY)                              # out of hearing of the formation
    assert bot.me["away"] and bot.me["status"] == COVERAGE
    d = bot.step(BACK_HOME)
    assert bot.me["status"] == SURPLUS and d.broadcast["status"][0] == SURPLUS
    assert bot.me["surplus"] == 1 and d.velocities[0].tolist() == [0.0, 0.0]


def test_a_lap_past_free_target_floor_goes_round_again():
    bot = mover()
    for _ in range(30):  # 3 units on the target with target floor outward: a frontier
        bot.step(ARRIVED_ONLY, on_target=True, probe=lambda offset: True)
    assert bot.me["frontier"] > bot.swarm.params.surplus_frontier
    bot.step(BACK_HOME)
    assert bot.me["status"] == COVERAGE and not bot.me["away"] and bot.me["frontier"] == 0.0


def test_a_mover_that_never_left_its_formations_hearing_is_not_surplus():
    bot = mover()
    bot.step(BACK_HOME)
    assert bot.me["status"] == COVERAGE and bot.me["surplus"] == 0


def test_after_turning_round_only_the_next_whole_lap_counts():
    bot = mover()
    bot.step(ARRIVED_ONLY)
    bot.me["lap_whole"], bot.me["away"] = False, False  # as turning round at a dead end does
    bot.step(ARRIVED_ONLY)  # retracing its way, out of hearing again
    bot.step(BACK_HOME)
    assert bot.me["status"] == COVERAGE and bot.me["lap_whole"]  # home early: a whole lap
    bot.step(ARRIVED_ONLY)
    bot.step(BACK_HOME)
    assert bot.me["status"] == SURPLUS


def test_the_news_spreads_through_my_group_only():
    bot = mover()
    bot.step([((8.0, 0.0), 9, 1, SURPLUS)])
    assert bot.me["status"] == SURPLUS                  # a mover reaching a Surplus robot
    other = mover()
    other.step([((8.0, 0.0), 9, 2, SURPLUS)])
    assert other.me["status"] == COVERAGE               # another group's: just an edge
    waiting = mover(status=DETECTION)
    waiting.step([((1.0, 0.0), 9, 1, SURPLUS)])
    assert waiting.me["status"] == SURPLUS              # the formation stays where it is
    waiting2 = mover(status=DETECTION)
    waiting2.step([((1.0, 0.0), 9, 2, SURPLUS)])
    assert waiting2.me["status"] != SURPLUS


def test_the_surplus_rule_is_off_when_disabled_at_small_d_cover_or_where_groups_fill_holes():
    for bot in (mover(surplus_stop=False), Bot(groups=1, d_cover=4.0),
                Bot(groups=3, d_cover=8.0, ruleset="paper"),
                Bot(groups=3, d_cover=8.0, ruleset="yield"),
                Bot(groups=3, d_cover=6.0)):  # holes filled here: movers go on to them
        bot.step(ARRIVED_ONLY)
        bot.step(BACK_HOME)
        assert bot.me["status"] == COVERAGE and bot.me["surplus"] == 0


def test_with_groups_a_whole_turn_past_no_free_floor_is_surplus():
    around = Bot(groups=3, d_cover=8.0)  # formation long gone: no waiting robot heard
    for deg in range(0, 381, 20):
        around.step(ARRIVED_ONLY, beacon_deg=deg)
    assert around.me["status"] == SURPLUS and around.me["surplus"] == 1
    short = Bot(groups=3, d_cover=8.0)  # 340 degrees: not yet round
    for deg in range(0, 341, 20):
        short.step(ARRIVED_ONLY, beacon_deg=deg)
    assert short.me["status"] == COVERAGE
    past_floor = Bot(groups=3, d_cover=8.0)  # free target floor passed on the way: again
    for deg in range(0, 381, 5):  # 3 units of it in the first 150 degrees
        past_floor.step(ARRIVED_ONLY, beacon_deg=deg, on_target=deg < 150,
                        probe=lambda offset: True)
    assert past_floor.me["status"] == COVERAGE
    assert math.radians(250) < abs(past_floor.me["winding"]) < math.radians(300)


def test_with_groups_the_news_of_a_full_target_spreads_to_every_group():
    heard = [((3.0, 0.0), 40, 1, ARRIVE), ((12.0, 0.0), 9, 2, SURPLUS)]
    bot = Bot(groups=3, d_cover=8.0)
    bot.step(heard)
    assert bot.me["status"] == SURPLUS
    paper = Bot(groups=3, d_cover=8.0, ruleset="paper")
    paper.step(heard)
    assert paper.me["status"] == COVERAGE


def test_movers_off_the_target_that_hear_a_surplus_robot_of_their_group_stop():
    heard = [((3.0, 0.0), 40, 1, ARRIVE), ((12.0, 0.0), 9, 1, SURPLUS)]
    bot = mover()
    bot.step(heard)
    assert bot.me["status"] == SURPLUS
    on_target = mover()  # on the target a place may be near: carry on
    on_target.step(heard, on_target=True, probe=lambda offset: True)
    assert on_target.me["status"] == COVERAGE
    no_spread = mover(surplus_spread=False)
    no_spread.step(heard)
    assert no_spread.me["status"] == COVERAGE


def test_a_lap_counts_only_if_it_went_round_the_beacon():
    bay = mover()  # into a bay and back out: the bearing swung 90 degrees and back
    for deg in [*range(0, 91, 10), *range(90, -1, -10)]:
        bay.step(ARRIVED_ONLY, beacon_deg=deg)
    bay.step(BACK_HOME, beacon_deg=0)
    assert bay.me["status"] == COVERAGE and bay.me["surplus"] == 0 and not bay.me["away"]
    lap = mover()  # all the way round: 300 degrees, past surplus_winding = 270
    for deg in range(0, 301, 20):
        lap.step(ARRIVED_ONLY, beacon_deg=deg)
    assert abs(np.degrees(lap.me["winding"]) - 300) < 1e-6
    lap.step(BACK_HOME, beacon_deg=300)
    assert lap.me["status"] == SURPLUS


def _travel_then_leave(bot: Bot, vx: float, vy: float) -> None:
    """Drive ``bot`` through its formation's travel (its parent broadcasts TRAVEL (vx, vy),
    then HALT) and on into Coverage."""
    bot.me["status"] = INITIAL
    group = int(bot.me["group"])
    for cmd in (CMD_TRAVEL, CMD_HALT):
        bot.step([((1.0, 0.0), 0, group, INITIAL)], gradient=0, cmd=cmd, travel_x=vx, travel_y=vy)
    assert bot.me["status"] == DETECTION
    bot.step([((8.0, 0.0), 0, group, ARRIVE)])
    assert bot.me["status"] == COVERAGE


def test_a_formation_robot_copies_its_parents_travel_and_halts_with_it():
    bot = Bot(groups=1, status=INITIAL)
    d = bot.step([((1.0, 0.0), 0, 1, INITIAL), ((2.0, 0.0), 3, 1, INITIAL)],
                 gradient=[0, 1], cmd=CMD_TRAVEL, travel_x=0.05, travel_y=0.08)
    assert bot.me["gradient"] == 1 and d.velocities[0].tolist() == [np.float32(0.05),
                                                                np.float32(0.08)]
    d = bot.step([((1.0, 0.0), 0, 1, INITIAL)], gradient=0, cmd=CMD_HALT)
    assert bot.me["status"] == DETECTION and d.velocities[0].tolist() == [0.0, 0.0]


def test_each_group_orbits_away_from_the_beacon_side_it_came_from():
    senses = {}
    for vx in (0.05, -0.05):
        bot = Bot(groups=3)
        _travel_then_leave(bot, vx, 0.087)             # up toward the beacon
        senses[vx] = bot.me["sense"]
    assert senses == {0.05: -1, -0.05: 1}
    bot = Bot(groups=3)
    _travel_then_leave(bot, 0.05, -0.087)               # from above-left
    assert bot.me["sense"] == 1
    one = Bot(groups=1)
    _travel_then_leave(one, 0.05, 0.087)                # one group: the orbit parameter
    assert one.me["sense"] == 1


def test_deadlock_episodes_open_at_a_detection_and_close_on_progress_or_settling():
    bot = Bot()
    T = bot.swarm.params.T_r
    here = [((6.0, 0.0), 40, 1, ARRIVE), ((6.0, 3.0), 41, 1, ARRIVE)]

    def sample(moved: float, tick: int) -> None:
        bot.me["odo_x"], bot.me["odo_y"] = moved, 0.0
        bot.me["circ_id"] = -1  # no full circle
        bot.step(here, moved=(0.0, 0.0), tick=tick)

    sample(0.0, T)
    bot.me["status"] = COVERAGE
    sample(0.5, 2 * T)                                      # two detections, one episode
    assert (bot.me["deadlocks"], bot.me["episodes"], bot.me["in_deadlock"]) == (2, 1, True)
    bot.me["status"] = COVERAGE
    sample(5.0, 3 * T)
    assert not bot.me["in_deadlock"] and bot.swarm.summarize()["deadlocks_released"] == 1
    sample(0.0, 4 * T)
    assert bot.me["episodes"] == 2 and bot.me["in_deadlock"]
    bot.me["status"] = COVERAGE
    bot.step(here, on_target=True, probe=lambda offset: False)  # arrives: the episode ends
    assert bot.me["status"] == ARRIVE and not bot.me["in_deadlock"]
    assert bot.swarm.summarize()["deadlocks_released"] == 2


def _beside_other_groups_robots(second: bool):
    """On the target at d_cover from another group's arrived robot; ``second``: a second
    arrived robot of that group within d_cover + arrive_tolerance (a triangle closes)."""
    return [((6.0, 0.0), 8, 2, ARRIVE)] + ([((3.0, 5.5), 9, 2, ARRIVE)] if second else [])


def test_rule_b_beside_another_groups_arrived_robot_needs_a_triangle():
    for second, arrives in ((False, False), (True, True)):
        bot = Bot()
        bot.me["gradient"] = 40
        bot.step(_beside_other_groups_robots(second), on_target=True,
                 probe=lambda offset: True, gradient=3)
        assert (bot.me["status"] == ARRIVE) == arrives, second
    own = Bot()  # my own group's robot: the gradient rule
    own.me["gradient"] = 2
    own.step([((6.0, 0.0), 8, 1, ARRIVE)], on_target=True, probe=lambda offset: True,
             gradient=3)
    assert own.me["status"] == ARRIVE


def test_boundary_fill_steps_in_with_one_group_or_late_with_groups_under_holes():
    for groups, ruleset, walked, steps_in in ((1, "paper", 0.0, True),
                                              (3, "yield-holes", 0.0, False),
                                              (3, "yield-holes", HOLE_PATH, True),
                                              (3, "paper", HOLE_PATH, False)):
        bot = Bot(groups=groups, ruleset=ruleset)
        bot.me["path"] = walked
        d = bot.step([((6.0, 0.0), 8, 1, ARRIVE)], probe=lambda offset: True)
        assert bool(bot.me["stepping"]) == steps_in, (groups, ruleset, walked)
        if steps_in:  # straight toward the arrived robot
            assert d.velocities[0, 0] > 0 and d.velocities[0, 1] == 0


def test_valley_following_goes_along_the_valley_the_way_it_was_heading():
    bot = Bot()
    P = bot.swarm.rules
    between = view([((0.0, 2.0), 8, 1, ARRIVE), ((0.0, -3.0), 9, 1, ARRIVE)])
    bot.me["head_x"], bot.me["head_y"] = -1.0, 0.1
    ok, vx, vy = valley(between, bot.me, 0, 1, P)
    assert ok and vx < 0 and math.isclose(math.hypot(vx, vy), P.v)
    assert vy < 0  # centring: toward the middle, away from the nearer robot above
    same_side = view([((0.0, 2.0), 8, 1, ARRIVE), ((1.0, 3.0), 9, 1, ARRIVE)])
    assert not valley(same_side, bot.me, 0, 1, P)[0]


def test_a_mover_stuck_in_a_closed_valley_turns_round_when_it_goes_again():
    """A robot leaving an uneven formation from a corner of two touching formation robots
    follows the valley between them by its heading. Rejoining at the dead end, it turns its
    heading round too, so that it leaves the other way (K, 1 group, scattered, seed 4)."""
    corner = [((0.01, -0.8), 7, 1, DETECTION), ((0.8, 0.02), 8, 1, DETECTION)]
    into = np.array([0.7, -0.7])  # toward the corner between the two
    bot = Bot(groups=1)
    bot.me["head_x"], bot.me["head_y"] = into
    bot.me["progress_tick"] = bot.tick
    assert bot.step(corner).velocities[0] @ into > 0  # the heading leads into the corner
    bot.me["odo_x"] = bot.me["odo_y"] = 0.0
    bot.step(corner, moved=(0.0, 0.0), tick=bot.tick + bot.swarm.params.T_r)
    assert bot.me["status"] == DETECTION and bot.me["yield_count"] == 2  # waits its turn
    bot.me["status"] = COVERAGE
    assert bot.step(corner).velocities[0] @ into < 0  # and then leaves the other way


def test_a_lone_mover_wanders_toward_the_beacon_and_stops_where_the_floor_ends():
    bot = Bot(groups=1)
    d = bot.step([], beacon_deg=90.0)
    assert np.allclose(d.velocities[0], [0.0, 0.1])
    bot.step([], on_target=True, probe=lambda offset: False, beacon_deg=90.0)
    assert bot.me["status"] == ARRIVE


@pytest.mark.parametrize("bad", ["left", "", "PAPER"])
def test_ruleset_must_be_a_known_rule_set(bad):
    with pytest.raises(ValueError, match="ruleset must be one of yield-holes, paper"):
        GGCParams(ruleset=bad)


def _far_walker(ruleset: str = "yield-holes-cross", walked: float = CROSS_PATH) -> Bot:
    bot = Bot(ruleset=ruleset)
    bot.me["path"] = walked
    return bot


EDGE_BESIDE = [((6.0, 0.0), 8, 1, ARRIVE), ((0.0, -9.0), 12, 1, DETECTION)]  # the structure's
# edge to my right, my formation behind me


def test_a_walled_in_mover_that_walked_far_off_the_target_crosses_toward_the_beacon():
    bot = _far_walker()
    d = bot.step(EDGE_BESIDE, beacon_deg=90.0)
    assert bot.me["crossing"] and np.allclose(d.velocities[0], [0.0, 0.1])
    for ruleset, walked in (("yield-holes", CROSS_PATH), ("yield-holes-cross", CROSS_PATH - 1)):
        bot = _far_walker(ruleset, walked)  # no crossing: follows the edge round the robot
        d = bot.step(EDGE_BESIDE, beacon_deg=90.0)
        assert not bot.me["crossing"] and abs(d.velocities[0, 0]) < 1e-9
        assert abs(d.velocities[0, 1]) == pytest.approx(0.1)
    bot = _far_walker()  # far from its formation: not walled in, follows the edge
    bot.step(EDGE_BESIDE[:1], beacon_deg=90.0)
    assert not bot.me["crossing"]


def test_a_crossing_passes_a_robot_close_ahead_on_the_side_away_from_it():
    bot = _far_walker()
    d = bot.step([((0.3, 1.5), 8, 1, ARRIVE), EDGE_BESIDE[1]], beacon_deg=90.0)
    assert d.velocities[0, 0] < 0 < d.velocities[0, 1]


def test_a_crossing_ends_on_the_target_with_open_floor_ahead_and_the_next_waits():
    bot = _far_walker()
    bot.step(EDGE_BESIDE, beacon_deg=90.0)
    behind = [((1.0, -6.0), 8, 1, ARRIVE)]
    bot.step([((0.0, 5.0), 9, 1, ARRIVE)], on_target=True, beacon_deg=90.0)
    assert bot.me["crossing"]  # the structure still ahead
    bot.step(behind, on_target=True, beacon_deg=90.0, probe=lambda offset: True)
    assert not bot.me["crossing"]
    assert bot.me["cross_after"] == pytest.approx(bot.me["path"] + CROSS_PATH)
    bot.me["path"] += CROSS_PATH / 2  # off the target again, not far enough yet
    bot.step(EDGE_BESIDE, beacon_deg=90.0)
    assert not bot.me["crossing"]


def test_a_crossing_ends_after_cross_max():
    bot = _far_walker()
    bot.step(EDGE_BESIDE, beacon_deg=90.0)
    bot.me["path"] += CROSS_MAX + 1
    bot.step(EDGE_BESIDE, beacon_deg=90.0)
    assert not bot.me["crossing"]


def test_with_groups_a_mover_walled_in_on_the_target_stops_there():
    around = [((7.0, 0.0), 40, 1, ARRIVE), ((-3.5, 6.06), 41, 2, ARRIVE),
              ((-3.5, -6.06), 42, 1, ARRIVE)]
    inside = Bot(groups=3, d_cover=8.0)
    inside.step(around, on_target=True, probe=lambda offset: True)
    assert inside.me["status"] == ARRIVE and inside.me["surplus"] == 1
    one_side = [((7.0, 0.0), 40, 1, ARRIVE), ((5.0, 5.0), 41, 2, ARRIVE),
                ((5.0, -5.0), 42, 1, ARRIVE)]
    edge = Bot(groups=3, d_cover=8.0)  # the structure's edge: free floor beyond
    edge.step(one_side, on_target=True, probe=lambda offset: True)
    assert edge.me["status"] == COVERAGE
    holes_filled = Bot(groups=3, d_cover=6.0)  # at d_cover 6 movers go on to fill holes
    holes_filled.step([((5.0, 0.0), 40, 1, ARRIVE), ((-2.5, 4.3), 41, 2, ARRIVE),
                       ((-2.5, -4.3), 42, 1, ARRIVE)], on_target=True,
                      probe=lambda offset: True)
    assert holes_filled.me["status"] == COVERAGE



def _orbit_lone_robot(bot: Bot, steps: int, on_target: bool = False):
    """Go round one arrived robot (id 40), 4 units away, 20 degrees a tick, the beacon
    straight up (+y); the last tick's actions."""
    for k in range(steps):
        angle = math.radians(20.0 * k)
        d = bot.step([((4.0 * math.cos(angle), 4.0 * math.sin(angle)), 40, 1, ARRIVE)],
                     on_target=on_target, beacon_deg=90.0)
    return d


def test_at_small_d_cover_a_mover_leaves_an_island_it_went_round_off_the_target():
    """A formation halts where its front touches the target: its leader, or the whole
    formation, may wait off it, and the last movers circled it for ever (K, 1 group,
    d_cover 2 and 4)."""
    bot = Bot(groups=1, d_cover=4.0)
    v = bot.swarm.params.v
    d = _orbit_lone_robot(bot, 18)  # not yet a whole turn: still going round
    assert not bot.me["leaving"] and d.velocities[0] @ [0.0, 1.0] < 0.99 * v
    d = _orbit_lone_robot(bot, 36)  # a whole turn, and the island is now behind me
    assert bot.me["leaving"] and np.allclose(d.velocities[0], [0.0, v])
    d = bot.step([((0.0, -3.0), 40, 1, ARRIVE)], beacon_deg=90.0)  # on for the beacon
    assert bot.me["leaving"] and np.allclose(d.velocities[0], [0.0, v])
    bot.step([((0.0, 3.0), 41, 1, ARRIVE), ((0.0, -5.0), 40, 1, ARRIVE)], beacon_deg=90.0)
    assert not bot.me["leaving"] and bot.me["turned"] == 0.0  # new ground ahead: its edge


def test_a_mover_pinned_on_its_way_off_an_island_follows_edges_again():
    bot = Bot(groups=1, d_cover=4.0)
    _orbit_lone_robot(bot, 36)
    assert bot.me["leaving"]
    bot.me["odo_x"] = bot.me["odo_y"] = 0.0
    T_r = bot.swarm.params.T_r
    bot.step([((0.0, -4.0), 40, 1, ARRIVE)], moved=(0.0, 0.0), beacon_deg=90.0,
             tick=int(bot.me["progress_tick"]) + T_r)  # no way on for T_r ticks
    assert not bot.me["leaving"] and bot.me["turned"] == 0.0


def test_target_floor_restarts_the_turn_and_d_cover_6_has_no_islands():
    on = Bot(groups=1, d_cover=4.0)
    _orbit_lone_robot(on, 36, on_target=True)
    assert on.me["turned"] == 0.0 and not on.me["leaving"]
    wide = Bot(groups=1, d_cover=6.0)
    _orbit_lone_robot(wide, 36)
    assert wide.me["turned"] == 0.0 and not wide.me["leaving"]
