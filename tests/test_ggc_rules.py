"""GGC's inter-group rules on hand-made perceptions (no simulation): which robots a mover
follows and which movers make it Stop."""

import dataclasses

import numpy as np
import pytest

from controllers.ggc import GGCParams
from controllers.ggc.robot import (
    ARRIVE,
    COVERAGE,
    DETECTION,
    MESSAGE_FIELDS,
    STOP,
    SURPLUS,
    GGCRobot,
)
from swarmsim.controller import Perception, RobotSetup, message_dtype


def robot(groups: int = 3, **params) -> GGCRobot:
    setup = RobotSetup(5, leader=False, group=1, groups=groups)
    return GGCRobot(setup, GGCParams(**params), np.random.default_rng(0))


def perception(rows: list[tuple[tuple[float, float], int, int, int]]) -> Perception:
    """rows: (offset, id, group, status), nearest first."""
    messages = np.zeros(len(rows), dtype=message_dtype(MESSAGE_FIELDS))
    offsets = np.array([r[0] for r in rows], dtype=float)
    for k, (_, rid, group, status) in enumerate(rows):
        messages[k]["id"], messages[k]["group"], messages[k]["status"] = rid, group, status
        messages[k]["moving"] = status == COVERAGE
    return Perception(tick=10, offsets=offsets, distances=np.hypot(*offsets.T),
                      messages=messages, on_target=False, probe=lambda offset: False,
                      beacon=None, moved=np.zeros(2))


NEIGHBOURS = [((1.0, 0.0), 7, 2, DETECTION),   # another group's formation
              ((2.0, 0.0), 8, 1, DETECTION),   # my group's formation
              ((3.0, 0.0), 9, 3, ARRIVE)]      # another group's arrived robot


def test_with_follow_other_formations_movers_follow_every_formation():
    r = robot(follow_other_formations=True)  # the paper's rule
    assert r.edge_robots(perception(NEIGHBOURS)).tolist() == [True, True, True]


def test_by_default_other_groups_formations_are_not_edges():
    r = robot()
    assert r.edge_robots(perception(NEIGHBOURS)).tolist() == [False, True, True]
    # one group: the option changes nothing
    one = robot(groups=1, follow_other_formations=False)
    assert one.edge_robots(perception(NEIGHBOURS)).tolist() == [True, True, True]


def test_another_groups_mover_with_priority_makes_a_mover_stop():
    behind = perception([((-2.0, 0.0), 9, 2, COVERAGE)])
    lower_id = perception([((2.0, 0.0), 3, 2, COVERAGE)])
    r = robot()
    r.heading = np.array([1.0, 0.0])
    assert r.other_group_mover(behind)            # the paper's rule: anywhere within d_cover
    assert not r.other_group_mover(lower_id)      # ids break the symmetry
    ahead_only = robot(stop_ahead_only=True)
    ahead_only.heading = np.array([1.0, 0.0])
    assert not ahead_only.other_group_mover(behind)
    assert ahead_only.other_group_mover(perception([((2.0, 0.5), 9, 2, COVERAGE)]))


def _yielder_view(enclosed: list[bool], with_leader: bool) -> Perception:
    """A wedged rim robot: waiting robots of its group on one side (one row of a formation),
    and, with_leader, an arrived robot on the other side closing the ring."""
    rows = [((1.0, 0.0), 7, 1, DETECTION), ((0.5, 0.87), 8, 1, DETECTION),
            ((-0.5, 0.87), 9, 1, DETECTION), ((-1.0, 0.0), 10, 1, DETECTION)]
    if with_leader:
        rows.append(((0.0, -1.0), 1, 1, ARRIVE))
    p = perception(rows)
    p.messages["enclosed"][:4] = enclosed
    return p


def test_a_yielding_rim_robot_stops_yielding_when_everyone_around_it_yields():
    r = robot(groups=1, d_cover=2.0)
    r.status, r.yield_count = DETECTION, 4
    assert r.nobody_to_yield_to(_yielder_view([True, True, True, True], with_leader=False))
    r.detection(_yielder_view([True, True, True, True], with_leader=False))
    assert r.yield_count == 0 and r.status == DETECTION  # it waits one tick, then takes turns
    # a waiting neighbour that may still leave first: keep yielding
    assert not r.nobody_to_yield_to(_yielder_view([True, False, True, True], with_leader=False))
    # closed in by the formation's leader (inside the formation): keep yielding
    assert not r.nobody_to_yield_to(_yielder_view([True, True, True, True], with_leader=True))


def test_yield_release_is_off_above_its_d_cover_bound():
    r = robot(groups=1, d_cover=6.0)  # default bound 4: d_cover 6 runs unchanged
    r.status, r.yield_count = DETECTION, 4
    r.detection(_yielder_view([True, True, True, True], with_leader=False))
    assert r.yield_count == 4


def test_a_stuck_mover_beside_its_formation_rejoins_it_at_small_d_cover_or_with_groups():
    beside = perception([((1.2, 0.0), 7, 1, DETECTION), ((0.0, 1.1), 9, 1, ARRIVE)])
    assert robot(groups=1, d_cover=2.0).wedged(beside)       # a formation neighbour: rejoin
    assert not robot(groups=1, d_cover=6.0).wedged(beside)   # d_cover 6: only when touching
    touching = perception([((0.85, 0.0), 7, 1, DETECTION)])
    assert robot(groups=1, d_cover=6.0).wedged(touching)
    assert robot(groups=3, d_cover=6.0).wedged(beside)       # with groups: at any d_cover
    other_group = perception([((1.2, 0.0), 7, 2, DETECTION)])
    assert not robot(groups=3, d_cover=6.0).wedged(other_group)  # only my own formation


def test_a_deadlocked_mover_arrives_where_it_is_when_a_robot_nearby_has_stopped():
    """Algorithm 5, line 5: deadlock on the target and a Stop robot near: Arrive."""
    close = [((2.0, 0.0), 8, 1, ARRIVE), ((4.0, 0.0), 9, 2, STOP)]
    no_stop = [((2.0, 0.0), 8, 1, ARRIVE), ((4.0, 0.0), 9, 2, COVERAGE)]
    assert robot().may_arrive_when_stuck(perception(close), 0)
    assert not robot().may_arrive_when_stuck(perception(no_stop), 0)
    # the earlier rule: only at covering distance from the nearest stationary robot
    spaced = robot(spaced_deadlock_arrive=True)
    assert not spaced.may_arrive_when_stuck(perception(close), 0)
    far = [((6.0, 0.0), 8, 1, ARRIVE), ((7.0, 0.0), 9, 2, STOP)]
    assert spaced.may_arrive_when_stuck(perception(far), 0)
    # one group: anywhere
    assert robot(groups=1).may_arrive_when_stuck(perception(no_stop), 0)



def test_with_groups_a_robot_in_stop_does_not_hold_its_formation_back():
    """Algorithm 7 waits for neighbours of larger gradient; with groups, one in Stop (Section
    4.3) has left already, and may wait there for another group's mover for good."""
    from controllers.ggc.batch import BLOCKED_BY_WAITING, NOT_BLOCKED

    p = perception([((3.0, 0.0), 9, 1, STOP)])
    p.messages["gradient"][0] = 7
    for groups, expected in ((3, NOT_BLOCKED), (1, BLOCKED_BY_WAITING)):
        r = robot(groups=groups)
        r.status, r.grad = DETECTION, 5
        assert r.blocked(p) == expected, groups


def lap_view(rows, on_target: bool = False, free_outward: bool = False,
             moved: tuple[float, float] = (0.1, 0.0),
             beacon_deg: float | None = None) -> Perception:
    """A mover's view for the surplus rule: ``free_outward`` says what the floor probe finds
    (target floor beyond the robot, away from the structure, or not)."""
    p = perception(rows)
    return Perception(tick=p.tick, offsets=p.offsets, distances=p.distances,
                      messages=p.messages, on_target=on_target,
                      probe=lambda offset: free_outward, moved=np.array(moved),
                      beacon=None if beacon_deg is None else
                      np.array([np.cos(np.radians(beacon_deg)), np.sin(np.radians(beacon_deg))]))


ARRIVED_ONLY = [((6.0, 0.0), 40, 1, ARRIVE)]            # away: no waiting robot heard
BACK_HOME = [((6.0, 0.0), 8, 1, DETECTION)]             # beside my group's formation


def mover(**params) -> GGCRobot:
    r = robot(groups=1, d_cover=8.0, **params)
    r.set_status(COVERAGE)
    return r


def test_a_mover_back_at_its_formation_after_a_lap_past_no_free_floor_is_surplus():
    r = mover()
    r.coverage(lap_view(ARRIVED_ONLY))                  # out of hearing of the formation
    assert r.away and r.status == COVERAGE
    action = r.coverage(lap_view(BACK_HOME))
    assert r.status == SURPLUS and action.message[1] == SURPLUS and r.surplus == 1
    assert action.velocity == (0.0, 0.0)


def test_a_lap_past_free_target_floor_goes_round_again():
    r = mover()
    for _ in range(30):  # 3 units on the target with target floor outward: a frontier
        r.coverage(lap_view(ARRIVED_ONLY, on_target=True, free_outward=True))
    assert r.frontier > r.p.surplus_frontier
    r.coverage(lap_view(BACK_HOME))
    assert r.status == COVERAGE and not r.away and r.frontier == 0.0


def test_a_mover_that_never_left_its_formations_hearing_is_not_surplus():
    r = mover()
    r.coverage(lap_view(BACK_HOME))
    assert r.status == COVERAGE and r.surplus == 0


def test_after_turning_round_only_the_next_whole_lap_counts():
    r = mover()
    r.coverage(lap_view(ARRIVED_ONLY))
    r.restart_lap(whole=False)  # what a mover does when it turns round at a dead end
    r.coverage(lap_view(ARRIVED_ONLY))  # retracing its way, out of hearing again
    r.coverage(lap_view(BACK_HOME))
    assert r.status == COVERAGE and r.lap_whole  # home early: now a whole lap starts
    r.coverage(lap_view(ARRIVED_ONLY))
    r.coverage(lap_view(BACK_HOME))
    assert r.status == SURPLUS


def test_the_news_spreads_through_my_group_only():
    r = mover()
    r.coverage(lap_view([((8.0, 0.0), 9, 1, SURPLUS)]))
    assert r.status == SURPLUS                        # a mover reaching a Surplus robot
    other = mover()
    other.coverage(lap_view([((8.0, 0.0), 9, 2, SURPLUS)]))
    assert other.status == COVERAGE                   # another group's: just an edge
    waiting = robot(groups=1, d_cover=8.0)
    waiting.set_status(DETECTION)
    waiting.detection(lap_view([((1.0, 0.0), 9, 1, SURPLUS)]))
    assert waiting.status == SURPLUS                  # the formation stays where it is
    waiting3 = robot(groups=1, d_cover=8.0)
    waiting3.set_status(DETECTION)
    waiting3.detection(lap_view([((1.0, 0.0), 9, 2, SURPLUS)]))
    assert waiting3.status != SURPLUS


def test_the_surplus_rule_is_off_when_disabled_at_small_d_cover_or_with_groups():
    for r in (mover(surplus_stop=False), robot(groups=1, d_cover=4.0),
              robot(groups=3, d_cover=8.0)):
        r.set_status(COVERAGE)
        r.coverage(lap_view(ARRIVED_ONLY))
        r.coverage(lap_view(BACK_HOME))
        assert r.status == COVERAGE and r.surplus == 0


def test_movers_off_the_target_that_hear_a_surplus_robot_of_their_group_stop():
    heard = [((3.0, 0.0), 40, 1, ARRIVE), ((12.0, 0.0), 9, 1, SURPLUS)]
    r = mover()
    r.coverage(lap_view(heard))
    assert r.status == SURPLUS
    on_target = mover()  # on the target a place may be near: carry on
    on_target.coverage(lap_view(heard, on_target=True))
    assert on_target.status == COVERAGE
    no_spread = mover(surplus_spread=False)
    no_spread.coverage(lap_view(heard))
    assert no_spread.status == COVERAGE


def test_a_lap_counts_only_if_it_went_round_the_beacon():
    # into a bay of the structure's edge and back out beside the formation: the bearing to
    # the beacon swung by 90 degrees and back, so the lap did not go round the structure
    bay = mover()
    for deg in [*range(0, 91, 10), *range(90, -1, -10)]:
        bay.coverage(lap_view(ARRIVED_ONLY, beacon_deg=deg))
    bay.coverage(lap_view(BACK_HOME, beacon_deg=0))
    assert bay.status == COVERAGE and bay.surplus == 0 and not bay.away
    # all the way round (bearing turned 300 degrees, past surplus_winding = 270)
    lap = mover()
    for deg in range(0, 301, 20):
        lap.coverage(lap_view(ARRIVED_ONLY, beacon_deg=deg))
    assert abs(np.degrees(lap.winding) - 300) < 1e-6
    lap.coverage(lap_view(BACK_HOME, beacon_deg=300))
    assert lap.status == SURPLUS


def _travel_then_leave(r: GGCRobot, vx: float, vy: float) -> None:
    """Drive ``r`` through its formation's travel (its parent broadcasts TRAVEL (vx, vy), then
    HALT) and on into Coverage."""
    from controllers.ggc.robot import CMD_HALT, CMD_TRAVEL, INITIAL

    for cmd in (CMD_TRAVEL, CMD_HALT):
        p = perception([((1.0, 0.0), 0, r.group, INITIAL)])   # my gradient parent: the leader
        p.messages["gradient"], p.messages["cmd"] = 0, cmd
        p.messages["vx"], p.messages["vy"] = vx, vy
        r.initial(p)
    assert r.status == DETECTION
    r.start_coverage(perception([((1.0, 0.0), 0, r.group, ARRIVE)]))


def test_each_group_orbits_away_from_the_beacon_side_it_came_from():
    senses = {}
    for vx in (0.05, -0.05):
        r = robot(groups=3)
        _travel_then_leave(r, vx, 0.087)             # up toward the beacon, from its left/right
        senses[vx] = r.sense
    assert senses == {0.05: -1, -0.05: 1}          # came from the left: clockwise, heads left
    r = robot(groups=3)
    _travel_then_leave(r, 0.05, -0.087)             # from above-left: counter-clockwise
    assert r.sense == 1


def test_group_orbit_same_alternate_and_one_group_keep_their_rules():
    for groups, rule, group, expected in [(1, "away", 1, 1), (3, "same", 1, 1),
                                          (3, "alternate", 1, 1), (3, "alternate", 2, -1)]:
        r = robot(groups=groups, group_orbit=rule)
        r.group = group
        _travel_then_leave(r, 0.05, 0.087)
        assert r.sense == expected, (groups, rule, group)


def test_group_orbit_must_be_a_known_rule():
    with pytest.raises(ValueError, match="group_orbit"):
        GGCParams(group_orbit="left")


def test_with_stop_on_target_only_a_mover_off_the_target_does_not_stop_for_other_groups():
    rows = [((2.0, 0.5), 9, 2, COVERAGE), ((6.0, 0.0), 8, 1, ARRIVE)]
    for flag, expected in ((False, STOP), (True, COVERAGE)):
        r = robot(stop_on_target_only=flag)
        r.status = COVERAGE
        r.coverage(perception(rows))  # off the target (perception's floor sensor says so)
        assert r.status == expected, flag


def test_after_stop_patience_ticks_in_stop_a_robot_goes_on_and_passes_for_T_s():
    view = perception([((2.0, 0.5), 9, 2, COVERAGE), ((6.0, 0.0), 8, 1, ARRIVE)])

    def at(tick: int) -> Perception:
        return dataclasses.replace(view, tick=tick)

    r = robot(stop_patience=300, T_s=100)
    r.status = COVERAGE
    r.coverage(at(10))
    assert r.status == STOP  # Section 4.3: another group's mover with priority
    r.stopped(at(309))
    assert r.status == STOP  # still there, and patience not yet used up
    r.stopped(at(310))
    assert r.status == COVERAGE  # waited stop_patience ticks: goes on
    r.coverage(at(409))
    assert r.status == COVERAGE  # and passes that mover for T_s ticks
    r.coverage(at(410))
    assert r.status == STOP
    patient = robot()  # the default (0): waits as long as the mover is there
    patient.status = COVERAGE
    patient.coverage(at(10))
    patient.stopped(at(100_000))
    assert patient.status == STOP


def test_on_the_target_a_robot_in_stop_waits_whatever_its_stop_patience():
    view = dataclasses.replace(perception([((2.0, 0.5), 9, 2, COVERAGE)]), on_target=True,
                               probe=lambda offset: True)
    r = robot(stop_patience=300, T_s=100)
    r.status = STOP
    r.stop_since = 10
    r.stopped(dataclasses.replace(view, tick=5000))
    assert r.status == STOP  # the mover is still there: on the target, the paper's rule
    r.stopped(dataclasses.replace(view, tick=5001, on_target=False))
    assert r.status == COVERAGE  # off the target the same wait has used up its patience


def test_stop_patience_counts_from_a_deadlock_stop_too():
    view = perception([((2.0, 0.5), 9, 2, COVERAGE)])
    r = robot(stop_patience=300, T_s=100)
    r.status = COVERAGE
    r.deadlock_stop(dataclasses.replace(view, tick=1000))
    r.stopped(dataclasses.replace(view, tick=1100))  # T_s is over, the mover is still there
    assert r.status == STOP
    r.stopped(dataclasses.replace(view, tick=1300))
    assert r.status == COVERAGE


def test_stop_patience_must_not_be_negative():
    with pytest.raises(ValueError, match="stop_patience"):
        GGCParams(stop_patience=-1)


def test_deadlock_episodes_open_at_a_detection_and_close_on_progress_or_settling():
    r = robot()
    r.set_status(COVERAGE)
    view = lap_view(ARRIVED_ONLY)

    def sample(moved: float, tick: int) -> bool:
        r.odometer[:] = (moved, 0.0)
        return r.stuck(Perception(tick=tick, offsets=view.offsets, distances=view.distances,
                                  messages=view.messages, on_target=False, probe=view.probe,
                                  beacon=None, moved=np.zeros(2)))

    T = r.p.T_r
    assert sample(0.0, T) and sample(0.5, 2 * T)            # two detections, one episode
    assert (r.deadlocks, r.deadlock_episodes, r.in_deadlock) == (2, 1, True)
    assert not sample(5.0, 3 * T) and r.deadlocks_released == 1 and not r.in_deadlock
    assert sample(0.0, 4 * T) and r.deadlock_episodes == 2  # a new episode ...
    r.set_status(ARRIVE)                                     # ... ends when it settles
    assert r.deadlocks_released == 2 and not r.in_deadlock


def _beside_other_groups_robots(second: bool) -> Perception:
    """On the target at d_cover from another group's arrived robot (gradients not comparable:
    my gradient is far larger than its); ``second``: a second arrived robot of that group
    within d_cover + arrive_tolerance, so that stopping here closes a triangle."""
    rows = [((6.0, 0.0), 8, 2, ARRIVE)] + ([((3.0, 5.5), 9, 2, ARRIVE)] if second else [])
    p = perception(rows)
    p.messages["gradient"] = 3
    return dataclasses.replace(p, on_target=True, probe=lambda offset: True)


def test_junction_stop_decides_rule_b_beside_another_groups_arrived_robot():
    expected = {"always": (True, True), "lattice": (False, True), "never": (False, False)}
    for rule, (alone, triangle) in expected.items():
        r = robot(junction_stop=rule)
        r.grad = 40
        assert r.should_arrive(_beside_other_groups_robots(False), 0) == alone, rule
        assert r.should_arrive(_beside_other_groups_robots(True), 0) == triangle, rule
    own = robot(junction_stop="lattice")  # my own group's robots: the gradient rule as before
    own.grad = 2
    p = _beside_other_groups_robots(False)
    p.messages["group"] = 1
    assert own.should_arrive(p, 0)


def test_junction_stop_must_be_a_known_rule():
    with pytest.raises(ValueError, match="junction_stop"):
        GGCParams(junction_stop="sometimes")


def _outside_beside_an_arrived_robot() -> Perception:
    """Off the target, d_cover from an arrived robot of my group, target floor toward it:
    the strip between the structure and the boundary is uncovered."""
    return dataclasses.replace(perception([((6.0, 0.0), 8, 1, ARRIVE)]),
                               probe=lambda offset: True)


def test_boundary_fill_steps_in_with_one_group_by_default_and_as_told_with_groups():
    expected = {("one-group", 1): True, ("one-group", 3): False, ("always", 3): True,
                ("never", 1): False, (True, 3): True, ("false", 1): False}
    for (rule, groups), steps_in in expected.items():
        r = robot(groups=groups, boundary_fill=rule)
        r.set_status(COVERAGE)
        action = r.coverage(_outside_beside_an_arrived_robot())
        assert r.stepping_in == steps_in, (rule, groups)
        if steps_in:  # straight toward the arrived robot
            assert action.velocity[0] > 0 and action.velocity[1] == 0


def test_boundary_fill_must_be_a_known_rule():
    assert GGCParams(boundary_fill=False).boundary_fill == "never"  # it was a bool
    with pytest.raises(ValueError, match="boundary_fill must be one of one-group"):
        GGCParams(boundary_fill="sometimes")


def _valley_with_numpy(r, p, a, b):
    """valley_follow as it was written on numpy 2-vectors (the reference)."""
    from controllers.ggc.geometry import unit

    ra, rb = p.offsets[a] / p.distances[a], p.offsets[b] / p.distances[b]
    if ra @ rb >= 0:
        return None
    axis = unit(ra - rb)
    along = np.array([axis[1], -axis[0]])
    reference = r.heading if np.any(r.heading) else np.array([ra[1], -ra[0]]) * r.sense
    if along @ reference < 0:
        along = -along
    centring = max(-1.0, min(1.0, (p.distances[a] - p.distances[b]) * r.p.radial_gain))
    return unit(along + 0.5 * centring * axis) * r.p.v


def test_valley_following_in_floats_matches_numpy_to_the_bit():
    rng = np.random.default_rng(3)
    r = robot()
    checked = 0
    for _ in range(300):
        offsets = rng.normal(size=(2, 2)) * 4
        p = perception([(tuple(o), 8 + k, 1, ARRIVE) for k, o in enumerate(offsets)])
        r.heading = rng.normal(size=2) if rng.random() < 0.7 else np.zeros(2)
        r.sense = 1 if rng.random() < 0.5 else -1
        got, want = r.valley_follow(p, 0, 1), _valley_with_numpy(r, p, 0, 1)
        assert (got is None) == (want is None)
        if want is not None:
            assert got.tobytes() == want.tobytes()
            checked += 1
    assert checked > 100  # robots on opposite sides: the valley case itself was compared


def test_a_mover_stuck_in_a_closed_valley_turns_round_when_it_goes_again():
    """A robot leaving an uneven formation from a corner of two touching formation robots
    follows the 'valley' between them by its heading, which pointed into the corner. At the
    dead end it flipped only its orbit sense, which a valley ignores: rejoining and leaving
    again it pushed into the same corner for good, and two such robots took turns at it
    while the rest of the formation waited (K, 1 group, scattered start, seed 4: 229 robots
    never left). Rejoining, it now turns its heading round too."""
    corner = perception([((0.01, -0.8), 7, 1, DETECTION), ((0.8, 0.02), 8, 1, DETECTION)])
    into = np.array([0.7, -0.7])  # toward the corner between the two
    r = robot(groups=1)
    r.start_coverage(corner)
    r.heading = into.copy()
    assert r.coverage(corner).velocity @ into > 0  # the heading leads it into the corner
    r.odometer[:] = 0.0
    at_dead_end = dataclasses.replace(corner, tick=corner.tick + r.p.T_r)
    r.coverage(at_dead_end)
    assert r.status == DETECTION and r.yield_count == 2  # wedged: it waits its turn again
    r.start_coverage(at_dead_end)
    assert r.coverage(at_dead_end).velocity @ into < 0  # and then leaves the other way
