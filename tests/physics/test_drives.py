"""Steering drives on the pymunk bodies (issue 69): a diff robot turns before it moves, a robot
pushed off-centre turns (a holonomic one does not), parking with spin sleeps as it should."""

import numpy as np
import pymunk
import pytest

from swarmsim.physics.physics import Physics, PhysicsConfig
from swarmsim.robots.drives import DiffDrive
from tests.conftest import square_world

AXLE = 0.2  # PhysicsConfig().axle_offset


def drive_tick(physics: Physics, drive: DiffDrive, wish: np.ndarray) -> tuple[np.ndarray, ...]:
    """One tick as the engine runs a steering drive; (commanded drive-point velocity,
    positions, headings) after it."""
    physics.read()
    lin, spin = drive.motion(wish, None, physics.headings(), np.ones(len(wish), dtype=bool))
    physics.command_motion(lin, spin)
    physics.step()
    return lin, physics.read()[0], physics.headings()


def axle_point(physics: Physics, i: int = 0) -> np.ndarray:
    return np.array(physics._robots[i].local_to_world((-AXLE, 0.0)))


@pytest.mark.parametrize("sleep", [False, True])
def test_a_diff_robot_commanded_sideways_turns_before_it_moves(sleep):
    cfg = PhysicsConfig(drive="diff", physics_sleep=sleep)
    physics = Physics(square_world(), np.array([[20.0, 20.0]]), cfg, angles=np.zeros(1))
    drive = DiffDrive(cfg, 0, 1)
    wish = np.array([[0.0, 0.1]])  # sideways: the robot faces +x
    start_axle = axle_point(physics)
    heading, turning_ticks = np.zeros(1), 0
    while heading[0] < np.pi / 2 - 0.2:  # the wish more than 90 degrees off the axle's way
        before = heading[0]
        lin, _, heading = drive_tick(physics, drive, wish)
        if abs(np.pi / 2 - before) >= np.pi / 2:
            assert np.hypot(*lin[0]) < 1e-9  # turning only: the wheels do not drive it on
            assert np.hypot(*(axle_point(physics) - start_axle)) < 0.01  # about its axle
            turning_ticks += 1
        assert heading[0] > before  # toward the wish, every tick
        assert turning_ticks < 20
    assert turning_ticks >= 1
    for _ in range(15):
        _, before_pos, _ = drive_tick(physics, drive, wish)
    _, after, heading = drive_tick(physics, drive, wish)
    step = after[0] - before_pos[0]
    assert step[1] >= 0.09 and abs(step[0]) < 0.01  # along +y at about full speed
    assert abs(heading[0] - np.pi / 2) < 0.01


def pushed_turn(drive: str) -> float:
    """How far (rad) a robot commanded still turns while a kinematic disc slides past it,
    its path 0.3 from the robot's centre, for 120 ticks."""
    cfg = PhysicsConfig(drive=drive, physics_sleep=False)
    holonomic = drive == "holonomic"
    physics = Physics(square_world(), np.array([[20.0, 20.0]]), cfg,
                      angles=None if holonomic else np.zeros(1))
    pusher = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
    pusher.position, pusher.velocity = (17.0, 20.3), (0.05, 0.0)
    disc = pymunk.Circle(pusher, 0.4)
    disc.friction = cfg.friction
    physics.space.add(pusher, disc)
    physics._index_rows()  # the pusher is a new body row
    before = physics.headings()[0]
    for _ in range(120):
        physics.read()
        if holonomic:
            physics.command(np.zeros((1, 2)))
        else:
            physics.headings()
            physics.command_motion(np.zeros((1, 2)), np.zeros(1))
        physics.step()
    assert physics.read()[0][0, 1] < 19.9  # it was pushed aside in both cases
    return abs(physics.headings()[0] - before)


def test_a_robot_pushed_off_centre_turns_with_a_steering_drive_only():
    assert pushed_turn("diff") > 0.3  # held at its axle, behind the centre: a lever
    assert pushed_turn("kilobot") > 0.3
    assert pushed_turn("holonomic") < 1e-3  # held at its centre, gripped against spinning


def test_parking_with_spin_moves_robots_as_staying_awake_does():
    """Two robots drive, turn, stop (parked, asleep), then drive again: the same motion with
    physics_sleep on and off. Exactly the same until they wake; then to 1e-5 (measured 9e-6):
    waking puts a robot's two joints back into pymunk's constraint list in another order, and
    with an axle offset its pivot and gear both act on the spin (a holonomic robot's gear has
    nothing to do, so its runs agree exactly)."""
    wishes = ([[0.1, 0.0], [0.0, 0.1]] * 1, [[0.0, -0.1], [-0.1, 0.0]], [[0.0, 0.0]] * 2,
              [[0.07, 0.07], [0.1, 0.0]])
    schedule = [np.array(wishes[k]) for k in (0,) * 10 + (1,) * 15 + (2,) * 10 + (3,) * 15]
    runs = {}
    for sleep in (False, True):
        cfg = PhysicsConfig(drive="diff", physics_sleep=sleep)
        physics = Physics(square_world(), np.array([[15.0, 15.0], [25.0, 25.0]]), cfg,
                          angles=np.array([0.3, -2.0]))
        drive = DiffDrive(cfg, 0, 2)
        track, slept = [], False
        for wish in schedule:
            _, positions, headings = drive_tick(physics, drive, wish)
            track.append(np.column_stack([positions, headings]))
            slept |= bool(physics.bodies_asleep().all())
        runs[sleep] = np.array(track)
        assert slept == sleep
    np.testing.assert_array_equal(runs[True][:35], runs[False][:35])  # until they wake
    np.testing.assert_allclose(runs[True], runs[False], atol=1e-4)
    moved = runs[True][-1, :, :2] - runs[True][35, :, :2]
    assert np.all(np.hypot(moved[:, 0], moved[:, 1]) > 0.5)  # woken and driving again
