"""A run's fingerprint for golden tests: the sha256 of its positions at every tick, then its
broadcasts and floor readings at the end (tests/engine/test_holonomic_golden.py,
tests/controllers/baselines/test_meanshift_swarm.py), and its summary (run_digest); a
run's trace to compare two controllers by (run_trace)."""

from __future__ import annotations

import hashlib

import numpy as np

from swarmsim import Simulation
from swarmsim.engine.costs import TIMING_FIELDS
from swarmsim.engine.sim import TIMING_FIELDS as RUN_TIMING_FIELDS


def run_hash(world: str, controller: str | type, seed: int, ticks: int, settings: dict) -> str:
    """sha256 (first 16 hex digits) of positions every tick, then broadcasts and floor bits."""
    return _run(world, controller, seed, ticks, settings)[0]


def run_digest(controller: str | type, world: str, seed: int, ticks: int,
               settings: dict) -> tuple[str, dict, int]:
    """:func:`run_hash` of a run; its summary without the fields that time it or name the
    controller as given (a batch controller and its per-robot reference are two classes);
    and the robot-ticks it ended asleep."""
    digest, sim, asleep = _run(world, controller, seed, ticks, settings)
    summary = {k: v for k, v in sim.result().summary.items()
               if k not in (*TIMING_FIELDS, "controller")}
    return digest, summary, asleep


def _run(world: str, controller: str | type, seed: int, ticks: int,
         settings: dict) -> tuple[str, Simulation, int]:
    """The run's fingerprint (16 hex digits), the Simulation ``ticks`` ticks on, and the
    robot-ticks it ended asleep."""
    sim = Simulation(world, controller=controller, seed=seed, max_ticks=ticks,
                     settings={"stop_on_complete": False, **settings})
    digest, asleep = hashlib.sha256(), 0
    for _ in range(ticks):
        sim.step()
        digest.update(sim.positions.tobytes())
        asleep += int(sim.asleep.sum())
    digest.update(sim.messages.tobytes())
    digest.update(sim.on_target.tobytes())
    return digest.hexdigest()[:16], sim, asleep


def run_trace(controller: type, settings: dict, ticks: int, robots: int | None = None
              ) -> tuple:
    """tiny seed 3, ``ticks`` ticks: positions and sleepers every tick, the broadcasts at the
    end, the summary (but its timings and the controller's name, the class's module path) and
    the time series; two controllers that make the same run give equal traces."""
    sim = Simulation("tiny", controller=controller, seed=3, robots=robots, max_ticks=ticks,
                     settings={"stop_on_complete": False, **settings})
    positions, asleep = [], []
    res = sim.run(on_tick=lambda s: (positions.append(s.positions.copy()),
                                     asleep.append(s.asleep.copy())))
    summary = {k: v for k, v in res.summary.items()
               if k not in RUN_TIMING_FIELDS and k != "controller"}
    return (np.array(positions), np.array(asleep), sim.messages.tobytes(), summary,
            res.timeseries)
