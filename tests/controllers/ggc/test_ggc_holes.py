"""Hole filling (rules/holes.py) on hand-made neighbourhoods: arrived robots find holes inside
the structure and pass news of them on; movers go and fill them."""

import math

import numpy as np
import pytest

from controllers.ggc.rules.holes import HOLE_AGE, HOLE_HOPS, HOLE_PATH, HOLE_PERIOD, NO_HOLE
from controllers.ggc.rules.rulesets import HOLES, YIELD
from controllers.ggc.statuses import ARRIVE, COVERAGE
from tests.ggc_bot import Bot


def ring(spacing: float, first_id: int = 10, skip: tuple = ()) -> list:
    """Six arrived robots round me, ``spacing`` away, at 0, 60, ... 300 degrees."""
    rows = []
    for k in range(6):
        if k in skip:
            continue
        a = math.radians(60 * k)
        rows.append(((spacing * math.cos(a), spacing * math.sin(a)), first_id + k, 1, ARRIVE))
    return rows


def on_target(offset) -> bool:
    return True


def arrived_bot(ruleset: str = "yield-holes") -> Bot:
    return Bot(status=ARRIVE, ruleset=ruleset)


def mover(ruleset: str = "yield-holes", walked: float = HOLE_PATH) -> Bot:
    """A mover that has walked ``walked`` units since it left its formation."""
    bot = Bot(ruleset=ruleset)
    bot.me["path"] = walked
    return bot


def test_an_arrived_robot_inside_a_lattice_too_wide_reports_the_hole_between_three():
    tight = arrived_bot()
    actions = tight.step(ring(6.0), on_target=True, probe=on_target)
    assert tight.me["hole"] == NO_HOLE  # spacing 6: every triangle's centre is within r = 4
    assert actions.sleep[0] and actions.wake_tick[0] == tight.tick - 1 + HOLE_PERIOD
    wide = arrived_bot()
    wide.step(ring(8.0), on_target=True, probe=on_target, tick=100)
    assert wide.me["hole"] == NO_HOLE  # seen, not reported yet: it may still be filled
    wide.step(ring(8.0), on_target=True, probe=on_target, tick=100 + HOLE_AGE - 1)
    assert wide.me["hole"] == NO_HOLE
    wide.step(ring(8.0), on_target=True, probe=on_target, tick=100 + HOLE_AGE)
    assert wide.me["hole"] == 0  # the same hole for HOLE_AGE ticks: sealed in
    # the circumcentre of (me, two neighbours 8 apart at 60 degrees): 8 / sqrt(3) away
    assert math.hypot(wide.me["hole_x"], wide.me["hole_y"]) == pytest.approx(8 / math.sqrt(3))
    assert wide.swarm.rules.flags & HOLES


EDGE = ring(8.0, skip=(3, 4))  # arrived robots at 0, 60, 120 and 300 degrees: open at 210


def test_a_robot_on_the_structures_edge_that_movers_come_by_reports_no_hole():
    edge = arrived_bot()
    passing = ((-7.0, -3.0), 30, 2, COVERAGE)
    for tick in range(100, 101 + HOLE_AGE, HOLE_PERIOD):
        rows = EDGE + [passing] if tick == 100 + HOLE_AGE // 2 else EDGE
        edge.step(rows, on_target=True, probe=on_target, tick=tick)
    assert edge.me["hole"] == NO_HOLE  # a mover came by half-way: seen afresh since
    assert edge.me["seen_since"] == 100 + HOLE_AGE // 2 + HOLE_PERIOD


def test_a_quiet_edge_reports_the_open_floor_beyond_it_as_a_hole():
    """A large hole sealed inside the structure: its rim robots see a wide gap, on the
    target, and no mover ever comes by. The spot is d_cover out along the gap's middle."""
    edge = arrived_bot()
    for tick in (100, 100 + HOLE_AGE):
        edge.step(EDGE, on_target=True, probe=on_target, tick=tick)
    assert edge.me["hole"] == 0
    d = edge.swarm.params.d_cover
    assert edge.me["hole_x"] == pytest.approx(d * math.cos(math.radians(210)))
    assert edge.me["hole_y"] == pytest.approx(d * math.sin(math.radians(210)))


def test_an_edge_along_the_targets_boundary_reports_no_hole():
    boundary = arrived_bot()
    for tick in (100, 100 + HOLE_AGE):
        boundary.step(EDGE, on_target=True, probe=lambda offset: False, tick=tick)
    assert boundary.me["hole"] == NO_HOLE and boundary.me["seen_since"] == -1


def test_a_hole_whose_way_leaves_the_target_is_no_hole():
    """A triangle across a concave corner of the target has its centre off the target: the
    probe toward it finds no target floor."""
    corner = arrived_bot()
    for tick in (100, 100 + HOLE_AGE):
        corner.step(ring(8.0), on_target=True, probe=lambda offset: False, tick=tick)
    assert corner.me["hole"] == NO_HOLE


def test_news_of_a_hole_is_passed_on_unless_i_see_it_covered():
    relay = arrived_bot()
    rows = ring(6.0)
    relay.step(rows, on_target=True, hole=[0, NO_HOLE, 3, NO_HOLE, NO_HOLE, NO_HOLE],
               hole_x=[2.0, 0, 0, 0, 0, 0], hole_y=[5.0, 0, 0, 0, 0, 0])
    assert relay.me["hole"] == 1  # a neighbour at (6, 0) has a hole at (2, 5) from it
    assert (relay.me["hole_x"], relay.me["hole_y"]) == pytest.approx((8.0, 5.0))
    covered = arrived_bot()
    covered.step(rows + [((8.0, 4.0), 30, 1, ARRIVE)], on_target=True,
                 hole=[0, NO_HOLE, NO_HOLE, NO_HOLE, NO_HOLE, NO_HOLE, NO_HOLE],
                 hole_x=[2.0, 0, 0, 0, 0, 0, 0], hole_y=[5.0, 0, 0, 0, 0, 0, 0])
    assert covered.me["hole"] == NO_HOLE  # a robot 1 unit from that hole covers it
    far = arrived_bot()
    far.step(rows, on_target=True, hole=[HOLE_HOPS] + [NO_HOLE] * 5)
    assert far.me["hole"] == NO_HOLE  # news travels HOLE_HOPS hops at most


WALL = [((3.0, 3.0), 20, 1, ARRIVE), ((3.0, -3.0), 21, 1, ARRIVE)]
# news of a hole at (8, 0)
HOLE_AT_8_0 = {"hole": [2, NO_HOLE], "hole_x": [5.0, 0.0], "hole_y": [-3.0, 0.0]}


def heads_for_8_0(v) -> bool:
    return v[0] > 0 and abs(v[1]) < 1e-9


def test_a_mover_that_hears_of_a_hole_goes_for_it_and_arrives_on_it():
    bot = mover()
    assert heads_for_8_0(bot.step(WALL, on_target=True, **HOLE_AT_8_0).velocities[0])
    assert bot.me["status"] == COVERAGE
    near = [((2.6, 3.0), 20, 1, ARRIVE), ((0.0, -3.0), 21, 1, ARRIVE)]
    bot.step(near, on_target=True, hole=[0, NO_HOLE], hole_x=[-2.3, 0.0], hole_y=[-3.0, 0.0])
    assert bot.me["status"] == ARRIVE  # 0.3 from the hole


def test_a_mover_fresh_from_its_formation_keeps_to_the_edge():
    fresh = mover(walked=HOLE_PATH - 1)
    v = fresh.step(WALL, on_target=True, **HOLE_AT_8_0).velocities[0]
    assert np.hypot(*v) > 0 and not heads_for_8_0(v)


def test_only_the_mover_nearest_to_a_hole_goes_for_it_and_a_stuck_one_rests_from_holes():
    bot = mover()
    rows = [((3.0, 3.0), 20, 1, ARRIVE), ((6.0, 0.5), 30, 2, COVERAGE)]
    fields = {"hole": [0, NO_HOLE], "hole_x": [5.0, 0.0], "hole_y": [-3.0, 0.0]}  # at (8, 0)
    v = bot.step(rows, on_target=True, **fields).velocities[0]
    assert not heads_for_8_0(v)  # the mover at (6, 0.5) is nearer: not mine
    alone = mover()
    alone.me["progress_tick"] = 0
    # no progress over T_r ticks
    alone.step(rows[:1], on_target=True, tick=500, hole=[0], hole_x=[5.0], hole_y=[-3.0])
    assert alone.me["hole_rest"] > 500


def test_a_mover_arrives_short_of_a_hole_its_probe_finds_off_the_target():
    bot = mover()
    rows = [((3.0, 3.0), 20, 1, ARRIVE)]
    bot.step(rows, on_target=True, probe=lambda offset: False,
             hole=[0], hole_x=[-1.5], hole_y=[-3.0])  # the hole 1.5 units ahead, off the target
    assert bot.me["status"] == ARRIVE
    outside = mover()
    outside.step(rows, on_target=False, probe=lambda offset: False, tick=300,
                 hole=[0], hole_x=[-1.5], hole_y=[-3.0])  # off the target myself: not mine to fill
    assert outside.me["status"] == COVERAGE and outside.me["hole_rest"] > 300


@pytest.mark.parametrize("ruleset", ["paper", "yield"])
def test_without_hole_filling_arrived_robots_sleep_for_good_and_movers_follow_the_edge(ruleset):
    bot = arrived_bot(ruleset)
    bot.step(ring(8.0), on_target=True, probe=on_target, tick=100)
    actions = bot.step(ring(8.0), on_target=True, probe=on_target, tick=100 + HOLE_AGE)
    assert bot.me["hole"] == NO_HOLE and actions.sleep[0] and actions.wake_tick[0] == -1
    v = mover(ruleset).step(WALL, on_target=True, **HOLE_AT_8_0).velocities[0]
    assert np.hypot(*v) > 0 and not heads_for_8_0(v)


def test_holes_are_filled_only_where_the_lattice_covers():
    """At d_cover 8 a lattice leaves holes by design (8 > r sqrt(3)): nobody reports them."""
    assert Bot(ruleset="yield-holes").swarm.rules.flags & HOLES
    wide = Bot(ruleset="yield-holes", d_cover=8.0)
    assert not wide.swarm.rules.flags & HOLES and wide.swarm.rules.flags & YIELD
