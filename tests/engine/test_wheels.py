"""Controllers that command wheels (COMMANDS = "wheels"), and the odometry they steer by."""

from dataclasses import dataclass

import numpy as np
import pytest

from swarmsim import Simulation
from swarmsim.controller import Action, Perception
from swarmsim.errors import ConfigError
from swarmsim.physics.physics import PhysicsConfig
from tests.conftest import square_world


@dataclass(frozen=True)
class WheelParams:
    """Attributes:
        left, right: the wheel speeds every robot commands every tick, units/tick.
    """

    left: float = 0.1
    right: float = 0.1


class FixedWheels:
    """Every robot turns its wheels at the same (left, right) speeds, every tick."""

    name = "fixed-wheels"
    Params = WheelParams
    STATUSES = ("Driving",)
    COMMANDS = "wheels"

    @classmethod
    def sensing_range(cls, params) -> float:
        return 2.0

    def __init__(self, setup, params: WheelParams, rng):
        self.wheels = (params.left, params.right)

    def step(self, perception: Perception) -> Action:
        return Action(self.wheels, {"status": 0, "moving": True})


def drive(left: float, right: float, ticks: int = 30, **settings) -> tuple[np.ndarray, ...]:
    """(start positions, end positions, body angles at each tick (ticks + 1, N)) of 3 robots
    turning their wheels at (left, right) under a diff drive."""
    sim = Simulation(square_world(), controller=FixedWheels, robots=3, max_ticks=ticks + 1,
                     settings={"drive": "diff", "left": left, "right": right, **settings})
    start, angles = sim.positions.copy(), [sim.physics.headings()]
    for _ in range(ticks):
        sim.step()
        angles.append(sim.physics.headings())
    return start, sim.positions, np.array(angles)


def test_a_wheel_controller_is_refused_with_a_holonomic_drive():
    with pytest.raises(ConfigError, match="controller '.*FixedWheels' commands wheels") as no:
        Simulation.check(square_world(), controller=FixedWheels, robots=3)
    assert no.value.key == "drive"
    Simulation.check(square_world(), controller=FixedWheels, robots=3,
                     settings={"drive": "kilobot"})


def test_equal_wheels_drive_straight_ahead():
    v = 0.1
    start, end, angles = drive(v, v)
    np.testing.assert_allclose(angles, angles[0][None, :].repeat(len(angles), 0), atol=1e-9)
    heading = np.column_stack([np.cos(angles[0]), np.sin(angles[0])])
    travel = end - start
    along = np.sum(travel * heading, axis=1)
    assert np.all(along > 30 * v - 0.1)  # full speed but the first (accelerating) tick
    across = travel - along[:, None] * heading
    assert np.abs(across).max() < 1e-6


def test_opposite_wheels_turn_in_place():
    v = 0.1
    start, end, angles = drive(-v, v)
    turned = angles[-1] - angles[0]
    assert np.all(turned > 30 * 2 * v / 0.6 * 0.8)  # about 0.33 rad a tick, after spin-up
    assert np.abs(end - start).max() <= 2 * 0.2 + 1e-6  # the centre swings round the axle


def test_wheel_speeds_are_clamped_to_the_drive_s_top_speed():
    start, end, _ = drive(5.0, 5.0, ticks=10)
    top = PhysicsConfig().wheel_speed
    start_top, end_top, _ = drive(top, top, ticks=10)
    np.testing.assert_allclose(end - start, end_top - start_top, atol=1e-9)


def test_odometry_reports_each_tick_s_turn():
    turns = []

    class Spinner(FixedWheels):
        def step(self, perception: Perception) -> Action:
            turns.append(perception.turned)
            return super().step(perception)

    sim = Simulation(square_world(), controller=Spinner, robots=1, max_ticks=20,
                     settings={"drive": "diff", "left": -0.1, "right": 0.1})
    angles = [sim.physics.headings()[0]]
    for _ in range(10):
        sim.step()
        angles.append(sim.physics.headings()[0])
    assert turns[0] == 0.0
    np.testing.assert_allclose(turns[1:], np.diff(angles)[:9], atol=1e-12)


def test_the_wheel_walker_example_brings_robots_to_the_target():
    for drive_name in ("diff", "kilobot"):
        sim = Simulation("tiny", controller="examples.wheel_walker:WheelWalker", robots=10,
                         seed=1, max_ticks=600, settings={"drive": drive_name})
        assert sim.run().summary["robots_on_target"] >= 9


def test_a_controller_commanding_something_else_is_refused():
    class Legs(FixedWheels):
        COMMANDS = "legs"

    with pytest.raises(ConfigError, match="COMMANDS must be one of velocity, wheels") as no:
        Simulation.check(square_world(), controller=Legs, robots=3,
                         settings={"drive": "diff"})
    assert no.value.key == "controller"
