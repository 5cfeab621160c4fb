"""Imperfect robots (noise, message loss, sensing limit) and the collision instruments."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import pytest

from swarmsim import ConfigError, Simulation
from swarmsim.controller import NO_SENDER, Action, Perception, RobotSetup
from swarmsim.engine.sim import TIMING_FIELDS
from swarmsim.metrics import SettledWatch
from swarmsim.physics.physics import Physics, PhysicsConfig
from swarmsim.robots.imperfections import Imperfections, NoiseLevels
from tests.conftest import square_world


@dataclass(frozen=True)
class ListenerParams:
    """Attributes:
        reach: sensing range, units.
    """

    reach: float = 8.0


class Listener:
    """Walks toward the beacon and remembers what it sensed and heard (a test probe)."""

    name = "listener"
    Params = ListenerParams
    STATUSES = ("Walking",)
    MESSAGE_FIELDS: ClassVar[list] = []

    @classmethod
    def sensing_range(cls, params: ListenerParams) -> float:
        return params.reach

    def __init__(self, setup: RobotSetup, params: ListenerParams, rng: np.random.Generator):
        self.id = setup.robot_id
        self.heard_ids: list[int] = []
        self.distances: list[float] = []
        self.sorted_ok = True

    def step(self, perception: Perception) -> Action:
        if perception.tick >= 1:  # broadcasts arrive one tick after they are sent
            self.heard_ids.extend(perception.messages["id"].tolist())
        self.distances.extend(perception.distances.tolist())
        self.sorted_ok &= bool(np.all(np.diff(perception.distances) >= 0))
        v = 0.1 * perception.beacon
        return Action((float(v[0]), float(v[1])), (self.id, 0, True))


LISTENER = "tests.robots.test_imperfections:Listener"


def listen(ticks: int = 40, **settings) -> Simulation:
    sim = Simulation(square_world(), controller=LISTENER, robots=40, seed=5, max_ticks=ticks,
                     settings={"stop_on_complete": False, **settings})
    sim.run()
    return sim


def test_message_loss_of_one_leaves_robots_without_messages():
    heard = [i for c in listen(message_loss=1.0).controllers for i in c.heard_ids]
    assert heard and set(heard) == {NO_SENDER}  # neighbours sensed, never heard


def test_partial_message_loss_drops_about_that_share():
    heard = np.array([i for c in listen(message_loss=0.3).controllers for i in c.heard_ids])
    lost = float(np.mean(heard == NO_SENDER))
    assert 0.25 < lost < 0.35
    ideal = [i for c in listen().controllers for i in c.heard_ids]
    assert NO_SENDER not in ideal


def test_sensing_limit_caps_what_robots_sense():
    far = max(d for c in listen().controllers for d in c.distances)
    assert far > 5.0
    near = max(d for c in listen(sensing_limit=3.0).controllers for d in c.distances)
    assert near <= 3.0


def test_sensing_noise_changes_distances_and_keeps_them_sorted():
    ideal = listen(ticks=1)
    noisy = listen(ticks=1, distance_noise=0.2, bearing_noise=0.1)
    a = sorted(d for c in ideal.controllers for d in c.distances)
    b = sorted(d for c in noisy.controllers for d in c.distances)
    assert len(a) == len(b) and a != b
    assert all(c.sorted_ok for c in noisy.controllers)


def run_ggc(**settings) -> dict:
    sim = Simulation(square_world(size=24), controller="ggc", robots=40, groups=1, seed=2,
                     max_ticks=900, settings=settings)
    summary = sim.run().summary
    for key in TIMING_FIELDS:
        summary.pop(key)
    return summary


@pytest.mark.slow
def test_noise_changes_results_only_when_set():
    ideal = run_ggc()
    zeros = run_ggc(speed_noise=0.0, heading_noise=0.0, distance_noise=0.0, bearing_noise=0.0,
                    message_loss=0.0, sensing_limit=0.0)
    assert zeros == ideal
    for key, value in [("speed_noise", 0.1), ("heading_noise", 0.1), ("distance_noise", 0.05),
                       ("bearing_noise", 0.05), ("message_loss", 0.1)]:
        noisy = run_ggc(**{key: value})
        assert noisy != ideal, key
        assert noisy == run_ggc(**{key: value}), f"{key}: same seed, same noisy run"


def test_actuation_noise_leaves_still_robots_still():
    imp = Imperfections(NoiseLevels(speed_noise=0.2, heading_noise=0.3), seed=1)
    v = np.zeros((1000, 2))
    v[::2] = (0.1, 0.0)
    out = imp.actuate(v)
    assert np.all(out[1::2] == 0)
    speed = np.hypot(*out[::2].T)
    assert abs(speed.mean() - 0.1) < 0.005 and 0.015 < speed.std() < 0.025
    heading = np.arctan2(out[::2, 1], out[::2, 0])
    assert 0.25 < heading.std() < 0.35


@pytest.mark.parametrize("key,value", [("speed_noise", -0.1), ("message_loss", 1.5),
                                       ("sensing_limit", -2.0), ("displaced_threshold", 0.0)])
def test_bad_imperfection_settings_name_the_key(key, value):
    with pytest.raises(ConfigError, match=key):
        Simulation(square_world(), controller="dispersion", robots=5, settings={key: value})


@pytest.mark.parametrize("mode", ["rigid", "ghost"])
def test_a_settled_robot_pushed_out_of_place_is_counted(mode):
    """Robot 0 has settled (status Arrive); robot 1 drives straight through its place."""
    physics = Physics(square_world(), np.array([[10.0, 10.0], [7.0, 10.0]]),
                      PhysicsConfig(mode=mode))
    watch = SettledWatch(2, codes=(3,), threshold=0.1)
    messages = np.zeros(2, dtype=[("status", "i1"), ("moving", "?")])
    messages[0], messages[1] = (3, False), (2, True)
    for _ in range(80):
        physics.read()
        physics.command(np.array([[0.0, 0.0], [0.1, 0.0]]))
        physics.step()
        watch.observe(physics.read()[0], messages)
    pushed = watch.ever_displaced.tolist()
    assert pushed == ([True, False] if mode == "rigid" else [False, False])
    assert physics.contacts.per_robot.tolist() == ([1, 1] if mode == "rigid" else [0, 0])


def test_run_summary_and_robot_table_report_contacts():
    sim = Simulation(square_world(size=12, spawn=20), controller="ggc", robots=60, groups=2,
                     seed=2, max_ticks=600)
    result = sim.run()
    s = result.summary
    assert s["mode"] == "rigid" and s["collisions_robot_robot"] > 0
    assert len(result.robots) == 60
    per_robot = sum(r["contacts_robot"] for r in result.robots)
    assert per_robot == 2 * s["collisions_robot_robot"]  # each contact has two robots
    assert s["robots_touched"] == sum(r["contacts_robot"] > 0 for r in result.robots)
    assert 0 < s["mean_overlap"] <= s["max_overlap"]
    assert s["peak_contact_impulse"] > 0
    assert {"contact_impulse", "settled_displaced"} <= set(result.timeseries[-1])


def test_wheel_noise_scales_each_turning_wheel_and_leaves_still_robots_still():
    wheels = np.array([[0.1, 0.1], [0.0, 0.0], [-0.1, 0.1]])
    assert Imperfections(NoiseLevels(heading_noise=0.3), seed=1).actuate_wheels(wheels) is wheels
    noisy = Imperfections(NoiseLevels(speed_noise=0.2), seed=1).actuate_wheels(wheels)
    again = Imperfections(NoiseLevels(speed_noise=0.2), seed=1).actuate_wheels(wheels)
    np.testing.assert_array_equal(noisy, again)  # one seed, one draw
    np.testing.assert_array_equal(noisy[1], 0.0)  # a still robot draws nothing, moves nothing
    scale = noisy[[0, 2]] / wheels[[0, 2]]
    assert np.all(scale >= 0) and len(np.unique(scale)) == 4  # a draw per wheel
