"""GGC robots keep their edge-following and Stop state in rows of one EdgeBook per run: each
robot's properties read and write its own row, with the types plain attributes had."""

import numpy as np

from controllers.ggc import GGC, GGCParams
from controllers.ggc.book import EdgeBook
from swarmsim.controller import NO_SENDER, RobotSetup


def make_robots(n: int = 5) -> list[GGC]:
    setups = [RobotSetup(i, group=1 + i % 2, groups=2) for i in range(n)]
    rngs = [np.random.default_rng(i) for i in range(n)]
    return GGC.create_robots(setups, GGCParams(), rngs)


def test_a_runs_robots_share_one_book_a_row_each():
    robots = make_robots()
    assert all(r.book is robots[0].book for r in robots)
    assert [r.row for r in robots] == list(range(5))
    assert len(robots[0].book.heading) == 5


def test_each_robot_reads_and_writes_its_own_row_only():
    a, b = make_robots()[2:4]
    a.heading = np.array([0.6, 0.8])
    a.odometer += np.array([1.0, 2.0])  # in place, as step() does
    a.odometer += np.array([1.0, 2.0])
    a.sense, a.circling_id, a.circled, a.last_bearing = -1.0, 9, 1.5, 0.25
    a.progress_tick, a.pass_until, a.stop_since, a.resume_tick = 10, 11, 12, 13
    assert a.heading.tolist() == [0.6, 0.8] and a.odometer.tolist() == [2.0, 4.0]
    assert (a.sense, a.circling_id, a.circled, a.last_bearing) == (-1.0, 9, 1.5, 0.25)
    assert (a.progress_tick, a.pass_until, a.stop_since, a.resume_tick) == (10, 11, 12, 13)
    assert b.heading.tolist() == [0.0, 0.0] and b.odometer.tolist() == [0.0, 0.0]
    assert (b.circling_id, b.circled, b.last_bearing) == (NO_SENDER, 0.0, None)
    assert (b.progress_tick, b.pass_until, b.stop_since, b.resume_tick) == (0, 0, 0, 0)
    a.odometer[:] = 0.0  # a sample restarts it
    assert a.odometer.tolist() == [0.0, 0.0]
    a.last_bearing = None
    assert a.last_bearing is None


def test_properties_give_the_types_attributes_had():
    robot = make_robots()[0]
    robot.sense, robot.circling_id, robot.progress_tick = -1.0, 4, 7
    assert type(robot.sense) is float and type(robot.circled) is float
    assert type(robot.circling_id) is int and type(robot.progress_tick) is int
    assert robot.heading.shape == (2,) and robot.heading.dtype == float


def test_a_robot_made_on_its_own_has_a_book_of_one_row():
    robot = GGC(RobotSetup(7, groups=1), GGCParams(), np.random.default_rng(0))
    assert isinstance(robot.book, EdgeBook) and robot.row == 0
    assert len(robot.book.sense) == 1 and robot.sense == GGCParams().orbit
