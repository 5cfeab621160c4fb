"""failure_mode: the engine's "dead" body and the modes a controller declares (FAILURE_MODES)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import pytest

from swarmsim import ConfigError, Simulation
from swarmsim.controller import Action, FailingController, Perception, RobotSetup
from swarmsim.errors import ControllerError
from swarmsim.experiments.spec import run_id
from tests.conftest import square_world

FAILING = {"failures": 3, "failure_phase": "tick", "failure_tick": 20}


@dataclass(frozen=True)
class LimpParams:
    """Attributes:
        v: speed, units per tick.
    """

    v: float = 0.1


class Limper:
    """Heads for the beacon; a robot failed "limp" goes on at a tenth of the speed."""

    name = "limper"
    Params = LimpParams
    STATUSES = ("Moving", "Limping")
    FAILURE_MODES: ClassVar[dict[str, str]] = {"limp": "goes on at a tenth of its speed"}
    calls: ClassVar[list[tuple[int, str]]] = []

    @classmethod
    def sensing_range(cls, params: LimpParams) -> float:
        return 2.0

    def __init__(self, setup: RobotSetup, params: LimpParams, rng: np.random.Generator):
        self.id, self.v, self.limping = setup.robot_id, params.v, False

    def fail(self, mode: str) -> None:
        Limper.calls.append((self.id, mode))
        self.limping = True

    def step(self, perception: Perception) -> Action:
        v = (0.1 if self.limping else 1.0) * self.v
        b = perception.beacon if perception.beacon is not None else np.zeros(2)
        return Action((float(b[0] * v), float(b[1] * v)), {"status": int(self.limping),
                                                           "moving": True})


class NoFail(Limper):
    """Declares a failure mode but cannot simulate it (no fail)."""

    fail = None  # type: ignore[assignment]


def limper_run(**settings):
    Limper.calls.clear()
    sim = Simulation(square_world(), controller=Limper, robots=10, seed=1, max_ticks=40,
                     settings={"stop_on_complete": False, **settings})
    start = sim.positions.copy()
    sim.run()
    return sim, start


def test_a_per_robot_controller_simulates_its_own_failure_mode():
    """fail(mode) is called once on each failing robot's controller, at the failure tick;
    the robot keeps moving and broadcasting as its controller decides (not silenced)."""
    sim, start = limper_run(**FAILING, failure_mode="limp")
    injector = sim.hooks[0]
    failed = injector.robots.tolist()
    assert injector.fired_tick == 20 and len(failed) == 3
    assert sorted(Limper.calls) == [(i, "limp") for i in failed]
    assert not sim.failed.any() and sim.failed_in_mode[failed].all()
    assert sim.result().summary["failed_robots"] == 3
    assert (sim.messages["status"][failed] == 1).all()  # they broadcast as limping
    moved = np.linalg.norm(sim.positions - start, axis=1)
    others = np.setdiff1d(np.arange(10), failed)
    assert (moved[failed] > 0.3).all() and (moved[failed] < moved[others].min()).all()


def test_dead_stays_dead_and_is_the_run_without_the_setting():
    (dead, _), (unnamed, _) = limper_run(**FAILING, failure_mode="dead"), limper_run(**FAILING)
    assert np.array_equal(dead.positions, unnamed.positions)
    failed = dead.hooks[0].robots
    assert Limper.calls == [] and dead.failed[failed].all() and not dead.failed_in_mode.any()
    assert (dead.messages["id"][failed] == -1).all()  # silent
    assert np.abs(dead.velocities[failed]).max() == 0.0


@pytest.mark.parametrize(("controller", "settings", "message"), [
    ("ggc", {"failure_mode": "no_gradient"}, "is used only with failures > 0"),
    ("ggc", {**FAILING, "failure_mode": "no_gradiant"},
     ("'no_gradiant' is not a failure mode of controller 'ggc' (did you mean 'no_gradient'?); "
     "its modes: dead, no_gradient")),
    ("ggc", {**FAILING, "failure_mode": "zombie"},
     "'zombie' is not a failure mode of controller 'ggc'; its modes: dead, no_gradient"),
    ("dispersion", {**FAILING, "failure_mode": "no_gradient"},
     ("'no_gradient' is a failure mode of ggc, not of controller 'dispersion'; its only mode "
     "is 'dead'")),
    ("ggc", {**FAILING, "failure_mode": ""}, "must be a failure mode's name"),
])
def test_a_failure_mode_the_controller_does_not_simulate_is_refused(controller, settings,
                                                                     message):
    with pytest.raises(ConfigError, match="failure_mode") as refused:
        Simulation.check("tiny", controller=controller, settings=settings)
    assert message in str(refused.value) and "\n" not in str(refused.value)


def test_malformed_failure_mode_declarations_are_refused():
    with pytest.raises(ConfigError, match="has no fail\\(mode\\) method"):
        Simulation.check(square_world(), controller=NoFail, robots=5)
    dead = type("Dead", (Limper,), {"FAILURE_MODES": {"dead": "again"}})
    with pytest.raises(ConfigError, match="not 'dead', the engine's own"):
        Simulation.check(square_world(), controller=dead, robots=5)


class SwarmWithoutFail:
    """A batch controller that declares a failure mode but whose swarm cannot fail robots."""

    name = "swarm-without-fail"
    Params = LimpParams
    STATUSES = ("Moving",)
    FAILURE_MODES: ClassVar[dict[str, str]] = {"limp": "slower"}

    @classmethod
    def sensing_range(cls, params: LimpParams) -> float:
        return 2.0

    @classmethod
    def create_swarm(cls, setups, params, rngs):
        return _Deciding()


class _Deciding:
    def decide(self, robots, batch):
        return [Action() for _ in robots]

    def summarize(self, failed):
        return {}


def test_a_swarm_without_fail_is_refused_before_the_run():
    Simulation(square_world(), controller=SwarmWithoutFail, robots=5, max_ticks=2)  # fine
    with pytest.raises(ControllerError, match="without fail\\(robots, mode\\)"):
        Simulation(square_world(), controller=SwarmWithoutFail, robots=5, max_ticks=2,
                   settings={**FAILING, "failure_mode": "limp"})


def test_limper_is_a_failing_controller():
    assert isinstance(Limper(RobotSetup(0), LimpParams(), np.random.default_rng(0)),
                      FailingController)


def test_the_default_failure_mode_leaves_run_ids_as_they_were():
    """Ids recorded before failure_mode existed (at 7e0a063): naming "dead" keeps them; a
    mode of the controller's is another run."""
    paper = {"failures": 20, "failure_phase": "gradient", "d_cover": 6, "groups": 3}
    before = "a5cc6b4c3d1392e4"
    assert run_id("K", "ggc", paper, 0) == before
    assert run_id("K", "ggc", {**paper, "failure_mode": "dead"}, 0) == before
    assert run_id("K", "ggc", {**paper, "failure_mode": "no_gradient"}, 0) != before
    plain = {"d_cover": 6, "groups": 3}
    assert run_id("K", "ggc", plain, 0) == "0e251a12201974d0"
    assert run_id("K", "ggc", {**plain, "failure_mode": "dead"}, 0) == "0e251a12201974d0"
