"""Shared test helpers: small worlds built in memory."""

from __future__ import annotations

import os

import pytest

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
os.environ.setdefault("SDL_AUDIODRIVER", "dummy")

from swarmsim.world.world import World, world_from_dict


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """Mark GGC's tests ``ggc`` (``-m ggc``, ``-m "not ggc"``): those of a test_ggc*.py file
    or of a folder tests/controllers/ggc/. ``slow`` is marked where each test is written."""
    for item in items:
        path = item.path
        if path.name.startswith("test_ggc") or path.parent.parts[-2:] == ("controllers", "ggc"):
            item.add_marker(pytest.mark.ggc)


def square_world(size: float = 40.0, spawn: float = 20.0, gap: float = 10.0,
                 beacon: bool = True, margin: float = 10.0) -> World:
    """A square target [0, size]^2 with a spawn square below it."""
    data = {
        "name": "square",
        "target": {"outline": [[0, 0], [size, 0], [size, size], [0, size]]},
        "spawn": [{"outline": [[0, -gap - spawn], [spawn, -gap - spawn], [spawn, -gap],
                               [0, -gap]]}],
        "arena": {"margin": margin},
    }
    if beacon:
        data["beacon"] = {"position": [size / 2, size / 2]}
    return world_from_dict(data)


def small_world(width: float = 30.0, height: float = 24.0) -> World:
    """A small rectangular target with a spawn band below it and a beacon inside."""
    return world_from_dict({
        "name": "small",
        "target": {"outline": [[0, 0], [width, 0], [width, height], [0, height]]},
        "spawn": [{"outline": [[-5, -30], [width + 5, -30], [width + 5, -12], [-5, -12]]}],
        "beacon": {"position": [width / 2, height / 2]},
        "arena": {"margin": 15.0},
    })


@pytest.fixture
def square() -> World:
    return square_world()
