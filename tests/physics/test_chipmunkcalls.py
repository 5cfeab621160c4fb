"""Chipmunk's body functions called from compiled code do what pymunk's own calls do."""

import platform
import sys

import numpy as np
import pymunk
import pytest

from swarmsim import Simulation
from swarmsim.physics import chipmunkcalls

KNOWN_ABI = sys.platform != "win32" and platform.machine().lower() in {"x86_64", "aarch64"}


@pytest.mark.skipif(not KNOWN_ABI, reason="the two-double cpVect convention is not assumed here")
def test_the_compiled_calls_are_used_where_the_convention_is_known():
    assert chipmunkcalls.body_calls() is not None


@pytest.mark.skipif(not KNOWN_ABI, reason="the two-double cpVect convention is not assumed here")
def test_compiled_calls_set_velocity_and_type_on_the_bodies_named():
    calls = chipmunkcalls.body_calls()
    space = pymunk.Space()
    robots = [pymunk.Body(1, 1) for _ in range(3)]
    controls = [pymunk.Body(body_type=pymunk.Body.KINEMATIC) for _ in range(3)]
    space.add(*robots, *controls)
    robot_at = np.array([chipmunkcalls.address(b) for b in robots], dtype=np.uintp)
    control_at = np.array([chipmunkcalls.address(b) for b in controls], dtype=np.uintp)
    v = np.array([[0.5, -0.25], [3.0, 4.0], [-1e-3, 7.5]])
    none = np.zeros(0, dtype=np.int64)
    chipmunkcalls.command(calls, robot_at, control_at, none, np.array([1]), np.array([0, 2]),
                          v)
    assert tuple(controls[0].velocity) == (0.5, -0.25)
    assert tuple(controls[2].velocity) == (-1e-3, 7.5)
    assert controls[1].body_type == pymunk.Body.STATIC
    assert tuple(controls[1].velocity) == (0.0, 0.0)
    chipmunkcalls.command(calls, robot_at, control_at, np.array([1]), none, np.array([1]), v)
    assert controls[1].body_type == pymunk.Body.KINEMATIC
    assert tuple(controls[1].velocity) == (3.0, 4.0)


def end_state(monkeypatch: pytest.MonkeyPatch, compiled: bool) -> bytes:
    if not compiled:
        monkeypatch.setattr(chipmunkcalls, "body_calls", lambda: None)
    sim = Simulation("tiny", seed=3, max_ticks=300)
    for _ in range(300):
        sim.step()
    assert sim.physics.parked.any()  # robots parked and unparked on the way
    return sim.positions.tobytes() + sim.messages.tobytes()


@pytest.mark.slow
def test_a_run_is_the_same_with_compiled_calls_and_with_pymunks(monkeypatch):
    assert end_state(monkeypatch, True) == end_state(monkeypatch, False)


@pytest.mark.skipif(not KNOWN_ABI, reason="the two-double cpVect convention is not assumed here")
def test_calls_the_compiler_cannot_build_fall_back_to_pymunks_with_a_warning(monkeypatch):
    def cannot_build(calls):
        raise RuntimeError("LLVM IR parsing error\nmore")

    monkeypatch.setattr(chipmunkcalls, "_works", cannot_build)
    chipmunkcalls.body_calls.cache_clear()
    try:
        with pytest.warns(RuntimeWarning, match=r"\(RuntimeError: LLVM IR parsing error\); pymunk"):
            assert chipmunkcalls.body_calls() is None
    finally:
        chipmunkcalls.body_calls.cache_clear()


def steered_end_state(monkeypatch: pytest.MonkeyPatch, compiled: bool) -> bytes:
    if not compiled:
        monkeypatch.setattr(chipmunkcalls, "body_calls", lambda: None)
    sim = Simulation("tiny", seed=3, max_ticks=200, settings={"drive": "kilobot"})
    assert (sim.physics._parking._set_spin is not None) == (compiled and KNOWN_ABI)
    for _ in range(200):
        sim.step()
    assert sim.physics.parked.any()  # robots parked and unparked on the way
    return sim.positions.tobytes() + sim.physics.headings().tobytes() + sim.messages.tobytes()


def test_a_steered_run_is_the_same_with_compiled_spin_calls_and_with_pymunks(monkeypatch):
    assert steered_end_state(monkeypatch, True) == steered_end_state(monkeypatch, False)
