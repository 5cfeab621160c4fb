"""Shared test helpers: small worlds built in memory."""

from __future__ import annotations

import os

import pytest

os.environ.setdefault("SDL_VIDEODRIVER", "dummy")
os.environ.setdefault("SDL_AUDIODRIVER", "dummy")

from swarmsim.world import World, world_from_dict


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


@pytest.fixture
def square() -> World:
    return square_world()
