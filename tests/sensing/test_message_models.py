"""Sensing and communication models beyond the uniform ones: message success that falls with
distance (message_model = "logistic") and a floor sensor that misreads near the target's edge
(floor_edge_band, floor_edge_misread). See swarmsim/robots/imperfections.py."""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import pytest

from swarmsim import ConfigError, Simulation
from swarmsim.cli import main
from swarmsim.controller import NO_SENDER, Action, Perception, RobotSetup
from swarmsim.robots.imperfections import Imperfections, NoiseLevels, logistic_success
from tests.conftest import square_world
from tests.errlines import one_error_line

LOGISTIC = {"message_model": "logistic", "message_range50": 6.0, "message_falloff": 1.5}


def measured_success(levels: NoiseLevels, distance: float, draws: int, seed: int = 3) -> float:
    """Share of ``draws`` messages across ``distance`` units that arrive."""
    lost = Imperfections(levels, seed).lost(draws, np.full(draws, distance))
    return 1.0 - float(np.mean(lost))


def test_the_logistic_profile_is_the_formula():
    d = np.array([0.0, 4.5, 6.0, 7.5, 60.0])
    expected = 1.0 / (1.0 + np.exp((d - 6.0) / 1.5))
    assert np.allclose(logistic_success(d, 6.0, 1.5), expected, rtol=0, atol=1e-15)
    assert logistic_success(np.array([6.0]), 6.0, 1.5)[0] == 0.5
    assert logistic_success(np.array([1e6]), 6.0, 1.5)[0] == 0.0  # no overflow warning


@pytest.mark.parametrize("distance", [2.0, 5.0, 6.0, 8.0, 11.0])
def test_logistic_success_measured_over_many_draws_matches_the_formula(distance):
    levels = NoiseLevels(**LOGISTIC)
    draws = 200_000
    p = float(logistic_success(np.array([distance]), 6.0, 1.5)[0])
    sd = np.sqrt(p * (1 - p) / draws)
    # the seed is fixed: the measured share is one number, 5 sd is a margin, not a gamble
    assert abs(measured_success(levels, distance, draws) - p) <= 5 * sd + 1e-9


def test_message_loss_on_top_of_the_logistic_model_multiplies_success():
    levels = NoiseLevels(message_loss=0.25, **LOGISTIC)
    draws = 200_000
    p = 0.75 * float(logistic_success(np.array([5.0]), 6.0, 1.5)[0])
    assert abs(measured_success(levels, 5.0, draws) - p) <= 5 * np.sqrt(p * (1 - p) / draws)


def test_the_logistic_model_needs_each_messages_distance():
    with pytest.raises(ValueError, match="distance"):
        Imperfections(NoiseLevels(**LOGISTIC), 0).lost(3)


@dataclass(frozen=True)
class HearerParams:
    """Attributes:
        reach: sensing range, units.
        walk_ticks: walk toward the beacon for this many ticks first.
    """

    reach: float = 14.0
    walk_ticks: int = 0


class Hearer:
    """Walks toward the beacon for ``walk_ticks`` ticks, then stands still and notes its floor
    readings and, per sensed neighbour, its distance and whether it was heard."""

    name = "hearer"
    Params = HearerParams
    STATUSES = ("Standing",)
    MESSAGE_FIELDS: ClassVar[list] = []

    @classmethod
    def sensing_range(cls, params: HearerParams) -> float:
        return params.reach

    def __init__(self, setup: RobotSetup, params: HearerParams, rng: np.random.Generator):
        self.id = setup.robot_id
        self.walk_ticks = params.walk_ticks
        self.pairs: list[tuple[float, bool]] = []
        self.floor: list[bool] = []

    def step(self, perception: Perception) -> Action:
        if perception.tick < self.walk_ticks:
            v = 0.1 * perception.beacon
            return Action((float(v[0]), float(v[1])), (self.id, 0, True))
        self.floor.append(bool(perception.on_target))
        if perception.tick >= 1:  # broadcasts arrive one tick after they are sent
            heard = perception.messages["id"] != NO_SENDER
            self.pairs.extend(zip(perception.distances.tolist(), heard.tolist(), strict=True))
        return Action((0.0, 0.0), (self.id, 0, True))


HEARER = "tests.sensing.test_message_models:Hearer"


def stand(world=None, ticks: int = 30, robots: int = 40, **settings) -> Simulation:
    sim = Simulation(world or square_world(), controller=HEARER, robots=robots, seed=4,
                     max_ticks=ticks, settings={"stop_on_complete": False, **settings})
    sim.run()
    return sim


def test_in_a_run_messages_arrive_as_the_logistic_model_says():
    sim = stand(**LOGISTIC)
    pairs = np.array([p for c in sim.controllers for p in c.pairs])
    d, heard = pairs[:, 0], pairs[:, 1].astype(bool)
    p = logistic_success(d, 6.0, 1.5)  # no sensing noise: sensed distances are the true ones
    assert len(d) > 5000 and d.min() < 3 and d.max() > 10
    # the heard count against its expectation, within 5 sd (a fixed seed: one number)
    assert abs(heard.sum() - p.sum()) <= 5 * np.sqrt((p * (1 - p)).sum())
    assert heard[d < 3].mean() > 0.85 and heard[d > 10].mean() < 0.1
    assert stand().controllers[0].pairs and all(  # the uniform default loses nothing
        h for c in stand().controllers for _, h in c.pairs)


WALK = 250
"""Ticks the Hearers walk from the spawn square toward the beacon: enough for some to stand
well inside the target, some near its edge, some still off it."""


def walked(band: float, rate: float) -> tuple[Simulation, np.ndarray]:
    """A run whose robots walk onto the target, then stand 60 ticks reading the floor; and
    each robot's distance to the target's edge where it stands, units."""
    sim = stand(ticks=WALK + 60, walk_ticks=WALK, floor_edge_band=band,
                floor_edge_misread=rate)
    return sim, sim.floor.edge_distance(sim.positions)


def test_a_robot_far_inside_the_target_always_reads_its_floor_right():
    band = 2.0
    sim, edge = walked(band, 0.3)
    inside = (edge > band + 0.5) & sim.on_target  # 0.5: room for a push while standing
    assert inside.sum() >= 5
    for k in np.flatnonzero(inside):
        assert sim.controllers[k].floor == [True] * 60


def test_near_the_edge_floor_readings_flip_at_about_the_set_rate():
    imp = Imperfections(NoiseLevels(floor_edge_band=1.0, floor_edge_misread=0.2), seed=7)
    on = np.arange(100_000) % 3 == 0
    edge = np.where(np.arange(100_000) % 2 == 0, 0.5, 1.5)  # even robots within the band
    read = imp.read_floor(on, lambda: edge)
    flipped = read != on
    assert not flipped[1::2].any()  # outside the band: exact
    share, sd = flipped[::2].mean(), np.sqrt(0.2 * 0.8 / 50_000)
    assert abs(share - 0.2) <= 5 * sd
    off = Imperfections(NoiseLevels(), seed=7)
    assert off.read_floor(on, lambda: pytest.fail("asked for edge distances")) is on


def test_in_a_run_robots_near_the_edge_misread_at_about_the_set_rate():
    band, rate = 2.0, 0.3
    sim, edge = walked(band, rate)
    truth = sim.on_target
    near = np.flatnonzero(edge < band - 0.5)
    wrong = [r != truth[k] for k in near for r in sim.controllers[k].floor]
    share, sd = np.mean(wrong), np.sqrt(rate * (1 - rate) / len(wrong))
    assert len(wrong) >= 180 and abs(share - rate) <= 5 * sd


def test_edge_distance_is_the_distance_to_the_nearest_edge_of_outline_or_hole():
    world = square_world(size=40.0)
    sim = Simulation(world, controller=HEARER, robots=2, seed=0, max_ticks=1)
    at = np.array([[20.0, 20.0], [1.0, 30.0], [-2.0, 5.0], [45.0, 45.0]])
    assert np.allclose(sim.floor.edge_distance(at), [20.0, 1.0, 2.0, np.hypot(5, 5)])


# ----------------------------------------------------------------------------- defaults
def fingerprint(**settings) -> str:
    """A short GGC run on tiny: its positions, broadcasts and floor readings, hashed."""
    sim = Simulation("tiny", controller="ggc", groups=2, seed=1, max_ticks=200,
                     settings={"stop_on_complete": False, **settings})
    for _ in range(200):
        sim.step()
    blob = sim.positions.tobytes() + sim.messages.tobytes() + sim.on_target.tobytes()
    return hashlib.sha256(blob).hexdigest()[:16]


NOISY = {"distance_noise": 0.05, "bearing_noise": 0.05, "message_loss": 0.1,
         "speed_noise": 0.05}


def test_runs_with_the_new_models_off_are_the_runs_before_them():
    """The hashes are those of the code before these models (3d60f50): with them off, a run
    draws nothing more from any stream, the uniform message loss included."""
    assert fingerprint() == BEFORE["defaults"]
    assert fingerprint(**NOISY) == BEFORE["noisy"]
    assert fingerprint(**NOISY, message_model="uniform", floor_edge_band=0.0,
                       floor_edge_misread=0.0) == BEFORE["noisy"]


BEFORE = {"defaults": "c87464da117ef7e5", "noisy": "38283493861bbeac"}


# ----------------------------------------------------------------------------- refusals
@pytest.mark.parametrize("settings, key, says", [
    ({"message_model": "radio"}, "message_model", "must be 'uniform' or 'logistic'"),
    ({"message_model": "logistic", "message_falloff": 1.0}, "message_range50",
     "must be positive with message_model 'logistic', got 0.0"),
    ({**LOGISTIC, "message_falloff": -1.0}, "message_falloff", "must be positive"),
    ({**LOGISTIC, "message_range50": float("nan")}, "message_range50", "must be a finite number"),
    ({"message_range50": 5.0}, "message_range50", "is used only with message_model 'logistic'"),
    ({"floor_edge_band": -1.0, "floor_edge_misread": 0.1}, "floor_edge_band", "must be >= 0"),
    ({"floor_edge_band": 1.0, "floor_edge_misread": 1.5}, "floor_edge_misread",
     r"must be in \[0, 1\]"),
    ({"floor_edge_band": 1.0}, "floor_edge_band", "1.0 does nothing while floor_edge_misread is 0"),
    ({"floor_edge_misread": 0.2}, "floor_edge_misread", "0.2 does nothing while floor_edge_band is 0"),
])
def test_bad_model_settings_are_refused_naming_the_key(settings, key, says):
    with pytest.raises(ConfigError, match=rf"key '{key}': {says}"):
        Simulation.check("tiny", settings=settings)


def test_the_command_line_refuses_a_logistic_model_without_its_range_in_one_line(tmp_path,
                                                                                  capsys):
    out = tmp_path / "run"
    assert main(["run", "tiny", "--quiet", "--out", str(out), "--set",
                 "message_model=logistic"]) == 2
    assert "key 'message_range50': must be positive" in one_error_line(capsys)
    assert not out.exists()


@pytest.mark.slow
def test_ggc_completes_tiny_with_logistic_messages_at_a_realistic_range():
    """GGC listens at R_c = 15: half its messages arrive from 10 units, few from 15."""
    sim = Simulation("tiny", controller="ggc", seed=0, max_ticks=6000,
                     settings={"message_model": "logistic", "message_range50": 10.0,
                               "message_falloff": 1.5})
    summary = sim.run().summary
    assert summary["completion_tick"] is not None and summary["coverage"] >= 0.99, summary


def test_the_new_draws_do_not_depend_on_decision_order_or_chunking(monkeypatch):
    """Message and floor draws are made in robot order, one chunk after the other: the order
    controllers are called in, and how many decide at once, change nothing."""
    import swarmsim.engine.sim as sim_module

    models = {**LOGISTIC, "floor_edge_band": 2.0, "floor_edge_misread": 0.3}

    def records(**extra) -> list:
        sim = stand(ticks=WALK + 20, walk_ticks=WALK, **models, **extra)
        return [(c.pairs, c.floor) for c in sim.controllers]

    reference = records()
    assert any(h is False for pairs, _ in reference for _, h in pairs)  # messages were lost
    assert any(len(set(floor)) > 1 for _, floor in reference)  # standing robots misread
    assert reference == records(decide_order="shuffled")
    monkeypatch.setattr(sim_module, "DECIDE_CHUNK", 7)
    assert reference == records()


def test_a_run_with_the_new_models_restores_to_the_same_end(tmp_path):
    """The message and floor streams are part of a checkpoint: the restored run draws on."""
    from tests.run_outcome import outcome as _outcome

    first = Simulation("tiny", controller="ggc", seed=3, max_ticks=350,
                       settings={**LOGISTIC, "floor_edge_band": 1.0, "floor_edge_misread": 0.2})
    for _ in range(200):
        first.advance()
    first.save(tmp_path / "run.ckpt")
    rest = Simulation.restore(tmp_path / "run.ckpt")
    assert _outcome(rest) == _outcome(first)
