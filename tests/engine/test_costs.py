"""summary.json's cost fields (swarmsim/engine/costs.py): decisions, broadcasts heard per
robot-tick, bytes and fields per broadcast, controller time per robot-tick."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from swarmsim import Simulation
from swarmsim.controller import (
    NO_SENDER,
    Action,
    Perception,
    RobotSetup,
    get_controller,
    message_dtype,
    run_message_fields,
)
from swarmsim.engine.sim import TIMING_FIELDS

COST_KEYS = ("decisions", "messages_heard_per_robot_tick", "message_bytes", "message_fields",
             "controller_ms_per_robot_tick")


@dataclass(frozen=True)
class NoParams:
    """No parameters."""


class Listener:
    """Stands still, broadcasts from its second decision on, and counts what it hears itself
    (neighbours' rows with a sender)."""

    name = "listener-test"
    Params = NoParams
    STATUSES = ("Still",)

    @classmethod
    def sensing_range(cls, params: NoParams) -> float:
        return 6.0

    def __init__(self, setup: RobotSetup, params: NoParams, rng: np.random.Generator):
        self.heard = 0
        self.decided = 0

    def step(self, perception: Perception) -> Action:
        self.heard += int(np.count_nonzero(perception.messages["id"] != NO_SENDER))
        self.decided += 1
        return Action((0.0, 0.0), {"status": 0} if self.decided > 1 else None)


def test_ggc_costs_count_its_decisions_and_its_message_dtype():
    """GGC (a batch controller): every cost field is there; decisions are the robot-ticks of
    awake robots (sleepers do not decide); bytes and fields per broadcast are the run's
    message dtype's, built from the class's declared fields."""
    awake = []
    sim = Simulation("tiny", controller="ggc", seed=0, max_ticks=60)
    summary = sim.run(on_tick=lambda s: awake.append(s.awake_count)).summary
    assert set(COST_KEYS) <= set(summary)
    assert summary["decisions"] == sum(awake) < sim.n * summary["ticks"]  # some slept
    assert summary["messages_heard_per_robot_tick"] > 1  # a formation: neighbours in range
    fields = run_message_fields(get_controller("ggc"), sim.config.groups, scattered=False)
    dtype = message_dtype(fields)
    assert summary["message_bytes"] == dtype.itemsize == sim.dtype.itemsize
    assert summary["message_fields"] == len(dtype.names) == 3 + len(fields)
    assert isinstance(summary["controller_ms_per_robot_tick"], float)
    assert "controller_ms_per_robot_tick" in TIMING_FIELDS


def _fail_two_at_tick_8(sim: Simulation) -> None:
    if sim.tick == 8:
        sim.fail(np.array([0, 1]))


def test_heard_broadcasts_are_those_the_controllers_perceive_with_a_sender():
    """Per-robot controllers, with lost messages, two robots failing and a first tick of
    silence: the engine's count is what the robots themselves heard (rows with a sender),
    over their decisions."""
    sim = Simulation("tiny", controller=Listener, seed=1, max_ticks=20,
                     settings={"message_loss": 0.3})
    summary = sim.run(on_tick=_fail_two_at_tick_8).summary
    robots = sim.controllers
    heard = sum(r.heard for r in robots)
    decided = sum(r.decided for r in robots)
    assert heard > 0
    assert summary["decisions"] == decided == sim.n * summary["ticks"] - 2 * 12
    assert sim.costs.heard == heard
    assert summary["messages_heard_per_robot_tick"] == round(heard / decided, 4)
    assert summary["message_bytes"] == 6 and summary["message_fields"] == 3


def test_a_lone_robot_hears_nothing():
    sim = Simulation("tiny", controller="dispersion", robots=1, seed=0, max_ticks=10)
    summary = sim.run().summary
    assert summary["decisions"] == 10
    assert summary["messages_heard_per_robot_tick"] == 0


def test_cost_fields_before_any_decision_are_none():
    summary = Simulation("tiny", controller="dispersion", seed=0, max_ticks=5).summary()
    assert summary["decisions"] == 0
    assert summary["messages_heard_per_robot_tick"] is None
    assert summary["controller_ms_per_robot_tick"] is None
