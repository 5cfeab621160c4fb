"""How tests compare two runs' ends (a restored run with the run that saved, say): one tuple
that is equal only if the runs ended identically."""

from __future__ import annotations

import pickle

from swarmsim import Simulation
from swarmsim.engine.sim import TIMING_FIELDS


def untimed(summary: dict) -> dict:
    """``summary`` without the fields that time the run (they differ between equal runs)."""
    return {k: v for k, v in summary.items() if k not in TIMING_FIELDS}


def outcome(sim: Simulation) -> tuple:
    """Run ``sim`` to its end; everything its end is compared by: summary (untimed), series,
    robots.csv rows, positions and broadcasts as bytes, engine sleep, controller state."""
    result = sim.run()
    swarm = sim.swarm
    if hasattr(swarm, "state"):
        state = swarm.state.tobytes()
    elif hasattr(swarm, "rows"):  # a batch swarm's state columns (Kilobot's, CVT's)
        state = b"".join(column.tobytes() for column in swarm.rows)
    else:
        state = pickle.dumps([vars(robot) for robot in swarm.robots])
    for values in getattr(swarm, "per_group", ()):  # GGC's per-group arrays
        state += values.tobytes()
    return (sim.tick, untimed(result.summary), result.timeseries, result.robots,
            sim.positions.tobytes(), sim.messages.tobytes(), sim.asleep.tobytes(), state)
