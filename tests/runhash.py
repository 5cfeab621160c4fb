"""A run's fingerprint for golden tests: the sha256 of its positions at every tick, then its
broadcasts and floor readings at the end (tests/engine/test_holonomic_golden.py,
tests/controllers/baselines/test_meanshift_swarm.py)."""

from __future__ import annotations

import hashlib

from swarmsim import Simulation


def run_hash(world: str, controller: str | type, seed: int, ticks: int, settings: dict) -> str:
    """sha256 (first 16 hex digits) of positions every tick, then broadcasts and floor bits."""
    sim = Simulation(world, controller=controller, seed=seed, max_ticks=ticks,
                     settings={"stop_on_complete": False, **settings})
    digest = hashlib.sha256()
    for _ in range(ticks):
        sim.step()
        digest.update(sim.positions.tobytes())
    digest.update(sim.messages.tobytes())
    digest.update(sim.on_target.tobytes())
    return digest.hexdigest()[:16]
