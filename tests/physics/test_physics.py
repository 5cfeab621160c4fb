"""Disc robots collide for real, stay in the arena, and barely overlap when pushed."""

import numpy as np
import pytest

from swarmsim.physics.physics import Physics, PhysicsConfig
from swarmsim.world.spawn import hex_offsets
from tests.conftest import square_world


def drive(physics: Physics, velocity_fn, ticks: int) -> float:
    worst = 0.0
    for _ in range(ticks):
        pos, _ = physics.read()
        physics.command(velocity_fn(pos))
        physics.step()
        worst = max(worst, physics.contact_state().max_overlap)
    return worst


def test_unobstructed_robot_tracks_command():
    physics = Physics(square_world(), np.array([[5.0, 5.0]]))
    drive(physics, lambda p: np.array([[0.1, 0.0]]), 100)
    pos, vel = physics.read()
    assert abs(pos[0, 0] - 15.0) < 0.15  # one tick of drive lag
    assert abs(vel[0, 0] - 0.1) < 1e-6


@pytest.mark.slow
def test_pushed_crowd_overlap_below_5_percent_of_radius():
    cfg = PhysicsConfig()
    pos = hex_offsets(200, 1.0) + np.array([20.0, 20.0])
    physics = Physics(square_world(), pos, cfg)

    def to_centre(p):
        d = np.array([20.0, 20.0]) - p
        n = np.maximum(np.hypot(*d.T), 1e-9)[:, None]
        return d / n * 0.1

    worst = drive(physics, to_centre, 300)
    assert physics.contacts.robot_robot > 0
    assert 0 < worst < 0.05 * cfg.radius


@pytest.mark.slow
def test_robots_never_leave_the_arena():
    world = square_world()
    pos = hex_offsets(50, 1.0) + np.array([20.0, 20.0])
    physics = Physics(world, pos)
    drive(physics, lambda p: np.tile([0.1, 0.07], (len(p), 1)), 1500)
    p, _ = physics.read()
    xmin, ymin, xmax, ymax = world.arena
    assert (p[:, 0] > xmin).all() and (p[:, 0] < xmax).all()
    assert (p[:, 1] > ymin).all() and (p[:, 1] < ymax).all()
    assert physics.contacts.robot_wall > 0
    assert physics.contacts.per_robot_wall.sum() == physics.contacts.robot_wall
    touching = physics.contact_state().in_contact
    assert touching.any()


def test_obstacles_block_robots():
    from swarmsim.world.world import world_from_dict

    world = world_from_dict({
        "name": "wall", "target": {"outline": [[0, 0], [40, 0], [40, 40], [0, 40]]},
        "spawn": [{"outline": [[0, -20], [10, -20], [10, -10], [0, -10]]}],
        "obstacles": [{"outline": [[20, 0], [22, 0], [22, 40], [20, 40]]}]})
    physics = Physics(world, np.array([[10.0, 20.0]]))
    drive(physics, lambda p: np.array([[0.1, 0.0]]), 300)
    assert physics.read()[0][0, 0] < 20.0


@pytest.mark.parametrize("mode,passes", [("ghost", True), ("rigid", False)])
def test_ghost_robots_pass_through_rigid_do_not(mode, passes):
    physics = Physics(square_world(), np.array([[10.0, 10.0], [14.0, 10.0]]),
                      PhysicsConfig(mode=mode))
    drive(physics, lambda p: np.array([[0.1, 0.0], [-0.1, 0.0]]), 60)
    pos, _ = physics.read()
    assert (pos[0, 0] > pos[1, 0]) == passes
    assert (physics.contacts.robot_robot > 0) == (not passes)


def test_bad_physics_config():
    with pytest.raises(ValueError, match="radius"):
        PhysicsConfig(radius=-1)
    with pytest.raises(ValueError, match="mode"):
        PhysicsConfig(mode="soft")


def test_infinite_spin_traction_locks_rotation_without_a_gear_joint():
    """spin_traction = inf: robots never turn and each has one joint (the drive), not two;
    the drive still moves them and they still collide."""
    pos = np.array([[10.0, 10.0], [12.0, 10.3]])  # the second is hit off-centre

    def head_on(p):
        return np.array([[0.1, 0.0], [-0.1, 0.0]])

    spinning = Physics(square_world(), pos)
    locked = Physics(square_world(), pos, PhysicsConfig(spin_traction=float("inf")))
    assert len(spinning.space.constraints) == 4 and len(locked.space.constraints) == 2
    for physics in (spinning, locked):
        drive(physics, head_on, 40)
    assert locked.contacts.robot_robot > 0
    assert all(b.angle == 0.0 and b.angular_velocity == 0.0 for b in locked._robots)
    assert any(b.angle != 0.0 for b in spinning._robots)  # the default's robots do turn
    pos_after, vel = locked.read()
    assert np.isfinite(vel).all()
    assert pos_after[0, 0] - pos[0, 0] > 0.5  # the drive still moves it (0.1 a tick, 40 ticks)
