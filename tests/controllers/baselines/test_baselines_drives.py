"""Every shipped controller runs under every steering drive (issue 69): controllers wish
velocities and the drive decides what the robot does, so a baseline needs no change. A short
run on tiny must move the robots, cover some of the target and keep every body finite."""

import numpy as np
import pytest

from swarmsim import Simulation
from swarmsim.registry import available_controllers

TICKS = 300


@pytest.mark.parametrize("drive", ["diff", "kilobot"])
@pytest.mark.parametrize("controller", sorted(available_controllers()))
def test_every_controller_runs_under_a_steering_drive(controller: str, drive: str) -> None:
    sim = Simulation("tiny", controller=controller, seed=1, max_ticks=TICKS,
                     settings={"drive": drive, "stop_on_complete": False})
    start = sim.positions.copy()
    result = sim.run()
    assert sim.tick == TICKS
    assert np.isfinite(sim.positions).all() and np.isfinite(sim.physics.headings()).all()
    moved = np.hypot(*(sim.positions - start).T)
    assert moved.max() > 3.0, f"{controller} under {drive}: nobody got anywhere"
    assert result.summary["total_distance"] > 0
