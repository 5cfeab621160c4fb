"""Parked robots sleep in pymunk (physics_sleep): the same collisions, reads and contacts.

One test per pitfall of swarmsim/physics/bodysleep.py: sleepers are still pushed (and wake), reads map
rows by body id, contacts of sleepers are kept, an unparked sleeper moves, runs repeat.
"""

import hashlib

import numpy as np
import pytest

from swarmsim import Simulation
from swarmsim.physics import chipmunkcalls
from swarmsim.physics.bodysleep import IdTable
from swarmsim.physics.physics import Physics, PhysicsConfig
from swarmsim.world.spawn import hex_offsets
from tests.conftest import square_world

SLEEP = PhysicsConfig(physics_sleep=True)
AWAKE = PhysicsConfig(physics_sleep=False)


def tick(physics: Physics, velocities: np.ndarray) -> np.ndarray:
    """One tick as the engine runs it; the positions after it."""
    physics.read()
    physics.command(velocities)
    physics.step()
    return physics.read()[0]


def true_asleep(physics: Physics) -> np.ndarray:
    return np.array([b.is_sleeping for b in physics._robots])


def test_sleep_is_on_by_default_and_can_be_switched_off():
    assert PhysicsConfig().physics_sleep
    pos = np.array([[10.0, 10.0], [20.0, 10.0]])
    for cfg, sleeps in ((SLEEP, True), (AWAKE, False)):
        physics = Physics(square_world(), pos, cfg)
        for _ in range(10):
            tick(physics, np.zeros((2, 2)))
        assert physics.bodies_asleep().all() == sleeps
        assert true_asleep(physics).all() == sleeps
        assert physics.parked.all() == sleeps


def test_bad_sleep_time_is_refused():
    with pytest.raises(ValueError, match="physics_sleep_time"):
        PhysicsConfig(physics_sleep_time=0.0)


def push(cfg: PhysicsConfig) -> tuple[np.ndarray, list[bool]]:
    """Robot 0 parks and sleeps; robot 1 then drives into it for 60 ticks."""
    physics = Physics(square_world(), np.array([[10.0, 10.0], [14.0, 10.0]]), cfg)
    for _ in range(10):
        tick(physics, np.zeros((2, 2)))
    slept = [bool(physics.bodies_asleep()[0])]
    for _ in range(60):
        tick(physics, np.array([[0.0, 0.0], [-0.1, 0.0]]))
        slept.append(bool(physics.bodies_asleep()[0]))
    return physics.read()[0], slept


def test_a_sleeping_robot_pushed_by_a_mover_moves_and_wakes():
    pos_on, slept = push(SLEEP)
    pos_off, _ = push(AWAKE)
    assert slept[0]  # it was asleep before the push
    assert not all(slept[1:])  # the push woke it
    assert pos_on[0, 0] < 10.0 - 1.0  # pushed a unit or more
    np.testing.assert_allclose(pos_on, pos_off, atol=0.02)  # as far as when never asleep


@pytest.mark.parametrize("compiled", [True, False], ids=["chipmunk calls", "pymunk.batch"])
def test_reads_are_right_while_robots_sleep_and_wake(monkeypatch, compiled):
    if not compiled:  # pymunk.batch's rows, matched to robots by body id
        monkeypatch.setattr(chipmunkcalls, "body_calls", lambda: None)
    pos = hex_offsets(40, 3.0) + np.array([20.0, 20.0])
    physics = Physics(square_world(), pos, SLEEP)
    rng = np.random.default_rng(3)
    most_asleep, orders = 0, set()
    for t in range(150):
        v = np.zeros((40, 2))
        movers = rng.choice(40, size=4, replace=False) if t % 25 < 10 else []
        v[movers] = rng.normal(0.0, 0.1, (len(movers), 2))
        physics.read()
        physics.command(v)
        physics.step()
        got_pos, got_vel = physics.read()
        assert np.array_equal(got_pos, [tuple(b.position) for b in physics._robots])
        assert np.array_equal(got_vel, [tuple(b.velocity) for b in physics._robots])
        asleep = physics.bodies_asleep()
        assert np.array_equal(asleep, true_asleep(physics))
        most_asleep = max(most_asleep, int(asleep.sum()))
        orders.add(physics._rows.robot_rows.tobytes())
    assert most_asleep > 30  # many slept...
    if not compiled:
        assert len(orders) > 10  # ...and pymunk's rows were reordered many times


def test_commanding_movers_leaves_the_sleepers_asleep():
    physics = Physics(square_world(), hex_offsets(10, 3.0) + np.array([20.0, 20.0]), SLEEP)
    for _ in range(10):
        tick(physics, np.zeros((10, 2)))
    assert true_asleep(physics).all()
    v = np.zeros((10, 2))
    v[0] = [0.1, 0.0]
    physics.read()
    physics.command(v)  # a batch write would wake (or skip) every sleeper
    assert true_asleep(physics).tolist() == [False] + [True] * 9
    physics.step()
    assert physics.bodies_asleep().tolist() == [False] + [True] * 9


def resting_crowd(cfg: PhysicsConfig) -> dict:
    """A crowd driven into a corner for 150 ticks, then parked there, touching, 250 ticks."""
    pos = hex_offsets(60, 1.0)
    physics = Physics(square_world(), pos, cfg)
    robot_ticks, worst, slept_touching = 0, 0.0, 0
    for t in range(400):
        p, _ = physics.read()
        d = np.array([-8.0, -8.0]) - p
        v = d / np.maximum(np.hypot(*d.T), 1e-9)[:, None] * 0.1 * (t < 150)
        physics.command(v)
        physics.step()
        c = physics.contact_state()
        robot_ticks += int(c.in_contact.sum())
        worst = max(worst, c.max_overlap)
        slept_touching = max(slept_touching, int((physics.bodies_asleep() & c.in_contact).sum()))
    return {"begins": physics.contacts.robot_robot, "walls": physics.contacts.robot_wall,
            "robot_ticks": robot_ticks, "max_overlap": worst, "slept_touching": slept_touching}


def test_contacts_of_sleepers_are_kept_in_a_resting_crowd():
    on, off = resting_crowd(SLEEP), resting_crowd(AWAKE)
    assert on["slept_touching"] > 30  # sleepers in contact: their contacts had to be kept
    assert off["slept_touching"] == 0
    assert on["robot_ticks"] == pytest.approx(off["robot_ticks"], rel=0.005)
    assert on["begins"] == pytest.approx(off["begins"], abs=2)
    assert on["walls"] == pytest.approx(off["walls"], abs=2)
    assert on["max_overlap"] == pytest.approx(off["max_overlap"], abs=0.001)


def plough(cfg: PhysicsConfig) -> tuple[int, int, float]:
    """A line of parked robots that a mover ploughs through, steering back to its lane 0.2
    beside their centres, shoving each aside: (robots displaced by more than 0.1, contacts
    begun, largest overlap)."""
    line = np.array([[5.0 + 2.0 * k, 20.0] for k in range(11)])
    physics = Physics(square_world(), np.vstack([line, [[2.0, 20.2]]]), cfg)
    worst = 0.0
    for t in range(350):
        p, _ = physics.read()
        v = np.zeros((12, 2))
        if t >= 20:
            v[11] = [0.1, np.clip(20.2 - p[11, 1], -0.05, 0.05)]
        physics.command(v)
        physics.step()
        worst = max(worst, physics.contact_state().max_overlap)
    moved = np.hypot(*(physics.read()[0][:11] - line).T)
    return int((moved > 0.1).sum()), physics.contacts.robot_robot, worst


def test_parked_robots_are_shoved_alike_asleep_or_awake():
    displaced, begins, worst = plough(SLEEP)
    assert displaced >= 8
    assert (displaced, begins) == plough(AWAKE)[:2]
    assert worst == pytest.approx(plough(AWAKE)[2], abs=0.001)


def unpark(cfg: PhysicsConfig) -> tuple[float, bool]:
    physics = Physics(square_world(), np.array([[10.0, 10.0]]), cfg)
    for _ in range(10):
        tick(physics, np.zeros((1, 2)))
    was_asleep = bool(physics.bodies_asleep()[0])
    for _ in range(20):
        p = tick(physics, np.array([[0.1, 0.0]]))
    return float(p[0, 0] - 10.0), was_asleep


def test_an_unparked_sleeping_robot_moves():
    moved, was_asleep = unpark(SLEEP)
    moved_off, _ = unpark(AWAKE)
    assert was_asleep
    assert moved > 1.8  # 20 ticks at 0.1, less one tick of drive lag
    assert moved == pytest.approx(moved_off, abs=1e-9)


def run_digest(settings: dict) -> tuple[str, int]:
    sim = Simulation("tiny", seed=0, max_ticks=400, settings=settings)
    slept = 0
    for _ in range(400):
        sim.step()
        slept = max(slept, int(sim.physics.bodies_asleep().sum()))
    state = sim.positions.tobytes() + sim.messages.tobytes()
    return hashlib.sha256(state).hexdigest(), slept


@pytest.mark.slow
def test_runs_with_sleeping_repeat_exactly():
    first, slept = run_digest({"physics_sleep": True})
    again, _ = run_digest({"physics_sleep": True})
    assert slept > 0
    assert first == again


def test_id_table_finds_every_id_and_only_those():
    rng = np.random.default_rng(0)
    ids = np.unique(rng.integers(1, 1 << 44, 3000)).astype(np.uintp) * 16
    table = IdTable(ids.tolist(), range(len(ids)))
    order = rng.permutation(len(ids))
    assert np.array_equal(table.lookup(ids[order]), order)
    assert (table.lookup(ids[:50] + 8) == -1).all()
    full = IdTable([16, 32], [0, 1])  # then every slot taken by another key: probing stops
    full._keys[:], full._used[:], full._codes[:] = 99, True, 7
    assert (full.lookup(np.array([16, 5], dtype=np.uintp)) == -1).all()
