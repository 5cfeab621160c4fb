"""The drive laws (swarmsim/robots/drives.py) on numbers alone, the kilobot's calibration
streams, and what the engine tells each robot about its drive."""

import dataclasses
import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import pytest

from swarmsim import Simulation
from swarmsim.controller import Action, Perception, RobotSetup
from swarmsim.errors import ConfigError
from swarmsim.physics.physics import PhysicsConfig
from swarmsim.robots.drives import DiffDrive, KilobotDrive, make_drive
from tests.conftest import square_world

DIFF = PhysicsConfig(drive="diff")
V = 0.1
W = DIFF.wheel_speed  # a wheel's top speed
ONE = np.ones(1, dtype=bool)


def motions(drive, wishes, heading=0.0, wheels=False):
    """The drive's (lin, spin) of one robot for each wish (or wheel pair) in turn."""
    out = []
    for w in wishes:
        given = np.array([w], dtype=float)
        lin, spin = drive.motion(None if wheels else given, given if wheels else None,
                                 np.array([heading]), ONE)
        out.append((lin[0].copy(), float(spin[0])))
    return out


def test_wheels_speed_up_by_at_most_wheel_accel_a_tick_and_brake_at_once():
    drive = DiffDrive(DIFF, 0, 1)
    (l1, s1), (l2, _), (l3, _), (l4, s4) = motions(drive, [(V, 0)] * 3 + [(0, 0)])
    assert l1[0] == pytest.approx(DIFF.wheel_accel) and s1 == 0  # straight ahead
    assert l2[0] == pytest.approx(2 * DIFF.wheel_accel) == pytest.approx(V)
    assert l3[0] == pytest.approx(V)
    assert np.all(l4 == 0) and s4 == 0  # a robot told to stop stops the same tick
    np.testing.assert_array_equal(drive.wheels, 0)


def test_a_wish_behind_is_driven_backward_with_reverse_and_turned_to_without():
    back = [(-V, 0.0)] * 6  # the wheels reach their top speed within wheel_accel
    lin, spin = motions(DiffDrive(DIFF, 0, 1), back)[-1]
    assert lin[0] == pytest.approx(-V) and spin == pytest.approx(0)
    lin, spin = motions(DiffDrive(PhysicsConfig(drive="diff", reverse=False), 0, 1), back)[-1]
    assert np.hypot(*lin) < 1e-12 and abs(spin) == pytest.approx(2 * W / DIFF.wheel_base)


def test_wheel_commands_drive_straight_or_turn_in_place():
    drive = DiffDrive(DIFF, 0, 1)
    lin, spin = motions(drive, [(V, V)] * 2, heading=0.5, wheels=True)[-1]
    np.testing.assert_allclose(lin, V * np.array([math.cos(0.5), math.sin(0.5)]))
    assert spin == 0
    drive = DiffDrive(DIFF, 0, 1)
    lin, spin = motions(drive, [(-V, V)] * 2, wheels=True)[-1]
    assert np.hypot(*lin) == 0 and spin == pytest.approx(2 * V / DIFF.wheel_base)
    drive = DiffDrive(DIFF, 0, 1)  # too fast: both wheels scaled down together
    lin, spin = motions(drive, [(2 * W, 4 * W)] * 6, wheels=True)[-1]
    np.testing.assert_allclose(drive.wheels[0], [W / 2, W])


def test_a_failed_robot_stands_still_and_loses_its_wheel_speeds():
    drive = DiffDrive(DIFF, 0, 2)
    wish, heading = np.tile([V, 0.0], (2, 1)), np.zeros(2)
    drive.motion(wish, None, heading, np.ones(2, dtype=bool))
    lin, spin = drive.motion(wish, None, heading, np.array([True, False]))
    assert np.all(lin[1] == 0) and spin[1] == 0 and np.all(drive.wheels[1] == 0)
    assert np.hypot(*lin[0]) > 0


KILO = PhysicsConfig(drive="kilobot")


def test_kilobot_bias_is_the_same_for_the_same_seed_and_differs_between_robots():
    a, b, c = KilobotDrive(KILO, 7, 50), KilobotDrive(KILO, 7, 50), KilobotDrive(KILO, 8, 50)
    for name in ("fwd_factor", "turn_factor", "curve"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
        assert len(np.unique(getattr(a, name))) == 50  # every robot its own
        assert not np.array_equal(getattr(a, name), getattr(c, name))
    np.testing.assert_array_equal(a.start_headings(), b.start_headings())
    assert np.all(a.fwd_factor >= 0.2) and abs(a.fwd_factor.std() - KILO.kilobot_bias) < 0.05
    # a robot's calibration depends on the seed and its index, not on how many robots run
    np.testing.assert_array_equal(KilobotDrive(KILO, 7, 60).fwd_factor[:50], a.fwd_factor)


def test_kilobot_bias_does_not_depend_on_the_noise_settings():
    def factors(**settings):
        sim = Simulation(square_world(), controller="dispersion", robots=6, max_ticks=5,
                         settings={"drive": "kilobot", **settings})
        return sim.drive.fwd_factor, sim.drive.turn_factor, sim.physics.headings()

    for quiet, noisy in zip(factors(), factors(speed_noise=0.05, message_loss=0.2),
                            strict=True):
        np.testing.assert_array_equal(quiet, noisy)


def test_a_kilobot_turns_in_place_until_aligned_then_goes_forward():
    cfg = PhysicsConfig(drive="kilobot", kilobot_stick=0, kilobot_slip=0)
    drive = KilobotDrive(cfg, 0, 1)
    (lin, spin), = motions(drive, [(0.0, V)])  # 90 degrees to the left
    assert np.hypot(*lin) == 0 and spin == pytest.approx(cfg.kilobot_turn
                                                           * drive.turn_factor[0])
    fast = KilobotDrive(dataclasses.replace(cfg, kilobot_turn=1.0), 0, 1)
    (lin, spin), = motions(fast, [(0.0, V)], heading=math.pi / 2 - 0.4)  # never past it
    assert np.hypot(*lin) == 0 and spin == pytest.approx(0.4)
    (lin, spin), = motions(drive, [(0.0, V)], heading=math.pi / 2 - 0.2)  # aligned enough
    assert lin[1] > 0 and np.hypot(*lin) == pytest.approx(V * drive.fwd_factor[0])
    assert spin == drive.curve[0]
    (lin, spin), = motions(drive, [(-V, 0.0)])  # never backward: it turns round
    assert np.hypot(*lin) == 0 and abs(spin) > 0
    assert drive.reverse is False


def test_kilobot_motors_read_as_on_or_off():
    cfg = PhysicsConfig(drive="kilobot", kilobot_stick=0, kilobot_slip=0)
    drive = KilobotDrive(cfg, 0, 1)
    rate = cfg.kilobot_turn * drive.turn_factor[0]
    (ahead, _), (left, s_left), (right, s_right), (off, s_off) = motions(
        drive, [(0.01, 0.05), (0.1, 0.0), (0.0, 0.1), (0.0, -0.1)], wheels=True)
    assert ahead[0] == pytest.approx(cfg.kilobot_speed * drive.fwd_factor[0])
    assert np.all(left == 0) and s_left == pytest.approx(-rate)  # left motor: turns right
    assert np.all(right == 0) and s_right == pytest.approx(rate)
    assert np.all(off == 0) and s_off == 0


def test_kilobot_stick_slip_is_drawn_from_its_own_stream():
    drive, again = KilobotDrive(KILO, 3, 2000), KilobotDrive(KILO, 3, 2000)
    wish, heading = np.tile([V, 0.0], (2000, 1)), np.zeros(2000)
    active = np.ones(2000, dtype=bool)
    lin, _ = drive.motion(wish, None, heading, active)
    np.testing.assert_array_equal(lin, again.motion(wish, None, heading, active)[0])
    stuck = np.mean(lin[:, 0] == 0)
    assert abs(stuck - KILO.kilobot_stick) < 0.03
    scale = lin[lin[:, 0] > 0, 0] / (V * drive.fwd_factor[lin[:, 0] > 0])
    assert abs(scale.std() - KILO.kilobot_slip) < 0.03
    later, _ = drive.motion(wish, None, heading, active)
    assert not np.array_equal(later, lin)  # a new draw each tick


@dataclass(frozen=True)
class _NoParams:
    """No parameters."""


class SetupRecorder:
    """Stands still; keeps the RobotSetup each robot was given (class-wide)."""

    name = "setup-recorder"
    Params = _NoParams
    STATUSES = ("Standing",)
    SETTLED_STATUSES = ("Standing",)
    seen: ClassVar[list[RobotSetup]] = []

    @classmethod
    def sensing_range(cls, params) -> float:
        return 2.0

    def __init__(self, setup: RobotSetup, params, rng: np.random.Generator):
        SetupRecorder.seen.append(setup)

    def step(self, perception: Perception) -> Action:
        return Action((0.0, 0.0), {"status": 0, "moving": False})


@pytest.mark.parametrize("drive, rate, reverse", [
    ("holonomic", lambda d: math.inf, True),
    ("diff", lambda d: 2 * d.wheel_speed / d.wheel_base, True),
    ("kilobot", lambda d: 0.325 * d.turn_factor, False),
])
def test_each_robot_is_told_its_drives_turn_rate_and_whether_it_reverses(drive, rate, reverse):
    SetupRecorder.seen = []
    sim = Simulation(square_world(), controller=SetupRecorder, robots=5, max_ticks=2,
                     settings={"drive": drive})
    rates = np.array([s.turn_rate for s in SetupRecorder.seen])
    np.testing.assert_allclose(rates, np.broadcast_to(rate(sim.drive), 5))
    assert all(s.reverse is reverse for s in SetupRecorder.seen)
    sim.run()


def test_make_drive_builds_the_named_drive():
    assert not make_drive(PhysicsConfig(), 0, 3).has_heading
    assert isinstance(make_drive(DIFF, 0, 3), DiffDrive)
    assert isinstance(make_drive(KILO, 0, 3), KilobotDrive)


@pytest.mark.parametrize("settings, key", [
    ({"drive": "wheelbarrow"}, "drive"),
    ({"drive": "diff", "spin_traction": math.inf}, "drive"),
    ({"drive": "diff", "wheel_base": -0.5}, "wheel_base"),
    ({"drive": "diff", "wheel_accel": 0}, "wheel_accel"),
    ({"drive": "diff", "axle_offset": 0.5}, "axle_offset"),
    ({"drive": "kilobot", "kilobot_stick": 1.0}, "kilobot_stick"),
    ({"drive": "kilobot", "kilobot_slip": -0.1}, "kilobot_slip"),
])
def test_bad_drive_settings_are_refused_naming_the_key(settings, key):
    with pytest.raises(ConfigError) as refused:
        Simulation.check(square_world(), controller="dispersion", robots=3, settings=settings)
    assert refused.value.key == key
    assert "\n" not in str(refused.value)
