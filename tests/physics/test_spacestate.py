"""A Physics pickled (a checkpoint's physics: swarmsim/physics/spacestate.py) loads as a Space
made again that holds the saved state: every body's motion, the cached contacts, which
robots are parked and asleep; and every load of the same bytes steps alike."""

import math
import pickle

import numpy as np
import pymunk
import pytest

from swarmsim.physics.physics import Physics, PhysicsConfig
from swarmsim.physics.spacestate import read_space
from swarmsim.world.spawn import hex_offsets
from tests.conftest import square_world

N = 30
PUSHERS, STOPPERS = 4, 8  # robots 0-3 push into the crowd, 4-7 push then stop; the others
# are parked from the start (zero command)


def _run(config: PhysicsConfig, ticks: int = 120) -> Physics:
    """A crowd, packed tight (robots touch), into which a few robots push."""
    physics = Physics(square_world(), hex_offsets(N, 0.82) + np.array([20.0, 20.0]), config)
    v = np.zeros((N, 2))
    v[:PUSHERS] = (0.05, 0.02)
    for t in range(ticks):
        v[PUSHERS:STOPPERS] = (-0.03, 0.04) if t < ticks // 2 else (0.0, 0.0)
        physics.read()
        physics.command(v)
        physics.step()
    return physics


def _contacts(physics: Physics) -> list:
    """The cached contacts, order and handler side (``swapped``: set again when a contact is
    cached) aside."""
    arbiters = read_space(physics.space, []).arbiters
    return sorted(a[:8] + a[9:] for a in arbiters)


def _step(physics: Physics, ticks: int) -> bytes:
    v = np.zeros((N, 2))
    v[:3] = (-0.04, 0.01)
    for _ in range(ticks):
        physics.read()
        physics.command(v)
        physics.step()
    return physics.read()[0].tobytes()


@pytest.mark.parametrize("config", [PhysicsConfig(physics_sleep=True),
                                    PhysicsConfig(physics_sleep=False),
                                    PhysicsConfig(spin_traction=math.inf)],
                         ids=["physics sleep", "no physics sleep", "robots never turn"])
def test_a_loaded_physics_holds_the_saved_state(config):
    first = _run(config)
    sleep = config.physics_sleep
    bodies = first._robots + first._controls
    data = pickle.dumps(first)
    loaded = pickle.loads(data)
    saved, got = read_space(first.space, bodies), read_space(loaded.space,
                                                            loaded._robots + loaded._controls)
    assert np.array_equal(got.bodies, saved.bodies)
    assert (got.stamp, got.time_step) == (saved.stamp, saved.time_step)
    assert _contacts(first) and _contacts(loaded) == _contacts(first)
    pairs = [arbiter[:2] for arbiter in saved.arbiters]  # in an order that is the same in
    assert pairs == sorted(pairs)  # every process (not the cache's: by memory address)
    assert np.array_equal(loaded.parked, first.parked)
    assert np.array_equal(loaded.bodies_asleep(), first.bodies_asleep())
    assert [b.body_type for b in loaded._controls] == [b.body_type for b in first._controls]
    if sleep:
        assert first.parked.any() and first.bodies_asleep().any()
        assert pymunk.Body.STATIC in {b.body_type for b in loaded._controls}
    assert np.array_equal(loaded.contacts.per_robot, first.contacts.per_robot)
    assert _step(loaded, 60) == _step(pickle.loads(data), 60)  # every load steps alike
