"""A run saved to a checkpoint and restored goes on as the run itself (the batch
controllers' tests: tests/controllers/baselines/test_*_swarm.py)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from swarmsim import Simulation


def run_for(controller: str, seed: int, ticks: int, max_ticks: int,
            robots: int | None = None) -> Simulation:
    """A run of ``controller`` on tiny, ``ticks`` ticks in (it does not stop on completion)."""
    run = Simulation("tiny", controller=controller, seed=seed, robots=robots,
                     max_ticks=max_ticks, settings={"stop_on_complete": False})
    for _ in range(ticks):
        run.advance()
    return run


def restored_goes_on(run: Simulation, folder: Path, ticks: int) -> Simulation:
    """Save ``run``, restore it, advance both ``ticks`` ticks asserting the same positions
    every tick and the same broadcasts at the end; the restored run."""
    run.save(folder / "run.ckpt")
    restored = Simulation.restore(folder / "run.ckpt")
    for _ in range(ticks):
        run.advance()
        restored.advance()
        assert np.array_equal(run.positions, restored.positions)
    assert run.messages.tobytes() == restored.messages.tobytes()
    return restored
