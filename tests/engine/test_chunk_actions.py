"""A chunk's actions as columns (swarmsim.controller.ChunkActions): the same as the Actions."""

import hashlib

import numpy as np
import pytest

from controllers.dispersion import DispersionRobot
from swarmsim import Simulation
from swarmsim.controller import Action, ChunkActions
from tests.bad_controllers import PutSwarm

ACTIONS = [Action((1.0, -2.0), message=(7, 1)), Action(),
           Action(sleep=True, wake_range=2.0, listen=3.0, wake_on_motion=False, wake_tick=9),
           Action((0.5, 0.0), sleep=True, listen=4.0)]


def test_columns_of_actions_hold_each_field_in_its_row():
    columns = ChunkActions.of(ACTIONS)
    assert columns.velocities.tolist() == [[1.0, -2.0], [0.0, 0.0], [0.0, 0.0], [0.5, 0.0]]
    assert np.isnan(columns.listen[:2]).all() and columns.listen[2:].tolist() == [3.0, 4.0]
    assert columns.messages == {0: (7, 1)}
    assert columns.sleepers == {2: ACTIONS[2], 3: ACTIONS[3]}


def test_columns_put_row_by_row_equal_the_columns_of_the_list():
    put = ChunkActions.empty(len(ACTIONS))
    for k in (3, 0, 2, 1):  # any order
        put.put(k, ACTIONS[k])
    of = ChunkActions.of(ACTIONS)
    assert put.velocities.tobytes() == of.velocities.tobytes()
    assert put.listen.tobytes() == of.listen.tobytes()
    assert put.messages == of.messages and put.sleepers == of.sleepers


class ColumnsDispersion(DispersionRobot):
    """Dispersion as a batch controller: a chunk's robots decided into columns (each robot's
    step, put), the path of a batch controller's ChunkActions."""

    @classmethod
    def create_swarm(cls, setups, params, rngs) -> PutSwarm:
        return PutSwarm.of(DispersionRobot, setups, params, rngs)


def run_hash(controller: str) -> tuple[str, int]:
    """Every position and broadcast of a run hashed, and the robot-ticks spent asleep."""
    sim = Simulation("K", controller=controller, robots=150, seed=3, max_ticks=600)
    digest, asleep = hashlib.sha256(), 0
    for _ in range(600):
        sim.step()
        digest.update(sim.positions.tobytes())
        digest.update(sim.messages.tobytes())
        digest.update(sim.listen.tobytes())
        asleep += int(sim.asleep.sum())
    return digest.hexdigest(), asleep


@pytest.mark.slow
def test_a_run_decided_through_columns_is_the_run_decided_robot_by_robot():
    """Velocities, broadcasts, listening ranges and sleep all go through the columns."""
    by_columns, asleep = run_hash("tests.engine.test_chunk_actions:ColumnsDispersion")
    assert asleep > 500  # the run exercised sleep
    assert by_columns == run_hash("dispersion")[0]
