"""The stuck metric: a robot that presses against something and does not get anywhere."""

from __future__ import annotations

from dataclasses import dataclass
from types import SimpleNamespace
from typing import ClassVar

import numpy as np

from swarmsim import Simulation
from swarmsim.controller import Action, Perception, RobotSetup
from swarmsim.metrics.part import Observation
from swarmsim.metrics.stuck import AGAINST_ROBOTS, AGAINST_WALL, STUCK_WINDOW, StuckPart
from tests.conftest import square_world


@dataclass(frozen=True)
class WalkerParams:
    """Attributes:
        heading: walk this way, radians (world frame), at full speed, every tick.
    """

    heading: float = 0.0


class Walker:
    """Walks one way at full speed, whatever is in its way."""

    name = "walker"
    Params = WalkerParams
    STATUSES = ("Walking",)
    MESSAGE_FIELDS: ClassVar[list] = []

    @classmethod
    def sensing_range(cls, params: WalkerParams) -> float:
        return 5.0

    def __init__(self, setup: RobotSetup, params: WalkerParams, rng: np.random.Generator):
        self.id = setup.robot_id
        self.velocity = (0.1 * np.cos(params.heading), 0.1 * np.sin(params.heading))

    def step(self, perception: Perception) -> Action:
        return Action(self.velocity, (self.id, 0, True))


WALKER = "tests.metrics.test_stuck:Walker"


def walk(heading: float, ticks: int) -> Simulation:
    """One robot of the square world (spawn 10 to 30 below the target, arena margin 10)
    walking ``heading`` for ``ticks`` ticks."""
    sim = Simulation(square_world(), controller=WALKER, robots=1, seed=0, max_ticks=ticks,
                     settings={"heading": heading, "stop_on_complete": False,
                               "stall_ticks": 10_000})
    sim.run()
    return sim


def test_a_robot_driven_into_a_wall_is_stuck_against_the_wall():
    sim = walk(-np.pi / 2, 400)  # down: the arena's wall is at most 30 units below it
    s = sim.summary()
    assert (s["stuck_robots"], s["stuck_robots_wall"], s["stuck_robots_robots"]) == (1, 1, 0)
    stuck_ticks = [row["stuck"] for row in sim.metrics.rows]
    assert stuck_ticks[-1] == 1 and stuck_ticks[0] == 0
    # it reached the wall within 300 ticks and is stuck from STUCK_WINDOW ticks later on
    assert 400 - 300 - STUCK_WINDOW <= s["stuck_robot_ticks"] < 400 - STUCK_WINDOW


def test_a_free_robot_is_not_stuck():
    sim = walk(np.pi / 2, 300)  # up, into the open target: touches nothing
    s = sim.summary()
    assert (s["stuck_robots"], s["stuck_robot_ticks"]) == (0, 0)
    assert all(row["stuck"] == 0 for row in sim.metrics.rows)


def observe(part: StuckPart, tick: int, at: float, commanded: float, touching: bool,
            wall: bool) -> None:
    part.contacts.state = SimpleNamespace(in_contact=np.array([touching]),
                                          on_wall=np.array([wall and touching]))
    part.observe(Observation(tick, np.array([[at, 0.0]]), np.zeros(1, bool), np.zeros(1), 1,
                             np.array([[commanded, 0.0]]), np.zeros(1, bool)))


def test_stuck_needs_a_whole_window_of_pressing_without_getting_anywhere():
    part = StuckPart(1, SimpleNamespace(state=None), v_max=0.1)
    observe(part, 0, 0.0, 0.0, touching=True, wall=False)  # the start: nothing commanded yet
    for tick in range(1, STUCK_WINDOW):  # pressing against a robot, not moving: not yet
        observe(part, tick, 0.0, 0.1, touching=True, wall=False)
        assert part.stuck_now == 0
    observe(part, STUCK_WINDOW, 0.0, 0.1, touching=True, wall=False)
    assert part.stuck_now == 1 and part.against[0] == AGAINST_ROBOTS
    observe(part, STUCK_WINDOW + 1, 0.0, 0.0, touching=True, wall=False)  # told to stop
    assert part.stuck_now == 0


def test_a_robot_sliding_along_a_wall_is_not_stuck():
    part = StuckPart(1, SimpleNamespace(state=None), v_max=0.1)
    for tick in range(3 * STUCK_WINDOW):  # presses on, at a tenth of full speed
        observe(part, tick, 0.01 * tick, 0.1, touching=True, wall=True)
        assert part.stuck_now == 0
    assert part.stuck_robot_ticks == 0 and not part.ever_wall[0]


def test_one_wall_touch_makes_it_stuck_against_the_wall_for_a_window():
    part = StuckPart(1, SimpleNamespace(state=None), v_max=0.1)
    touch = 2 * STUCK_WINDOW
    against = []
    for tick in range(1, 4 * STUCK_WINDOW):  # pressing, not moving; one wall touch
        observe(part, tick, 0.0, 0.1, touching=True, wall=tick == touch)
        against.append(int(part.against[0]))
    assert against[:STUCK_WINDOW - 1] == [0] * (STUCK_WINDOW - 1)
    expect = [AGAINST_WALL if touch <= tick < touch + STUCK_WINDOW else AGAINST_ROBOTS
              for tick in range(STUCK_WINDOW, 4 * STUCK_WINDOW)]
    assert against[STUCK_WINDOW - 1:] == expect
    assert part.ever_wall[0] and part.ever_robots[0]
    assert part.stuck_robot_ticks == len(expect)
