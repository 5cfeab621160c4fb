"""CVT decided a chunk at a time (controllers/cvt/swarm.py, issue 72) makes the very runs CVT
made one robot at a time (controllers/cvt/robot.py, the code it was ported from): the same
positions every tick, broadcasts, sleep and summary, to the bit. Its pieces give the per-robot
code's numbers: Python's hypot (controllers/common/pyhypot.py) and the local maps as arrays
(controllers/common/mapbatch.py).
"""

from __future__ import annotations

import hashlib

import numpy as np
import pytest
from shapely.geometry import Polygon

from controllers.common.localmap import LocalMap
from controllers.common.mapbatch import MapRows, lattice_values
from controllers.cvt import CVT
from controllers.cvt.robot import CVTRobot
from swarmsim import Simulation
from swarmsim.controller import make_perception
from swarmsim.engine.sim import TIMING_FIELDS
from swarmsim.sensing.sensing import FloorSensor
from tests.restorecheck import restored_goes_on, run_for

RUNS = {
    # name: (world, seed, ticks, settings)
    "tiny seed 1": ("tiny", 1, 500, {}),
    "tiny seed 0 small cells": ("tiny", 0, 300, {"cell_radius": 4.0, "map_cell": 0.5}),
    "tiny seed 2 noisy": ("tiny", 2, 300, {"distance_noise": 0.05, "bearing_noise": 0.05,
                                           "message_loss": 0.1}),
}

SLEEPING = ("tiny seed 1",)
"""The runs whose robots rest and sleep (on tiny, from about tick 400)."""

GOLDEN = {
    "tiny seed 1": "2c25808594e21e85",
}
"""Digests (:func:`run_digest`) of runs of the per-robot CVT at 2807bdb, before the port."""


def run_digest(controller: object, world: str, seed: int, ticks: int,
               settings: dict) -> tuple[str, dict]:
    """sha256 (16 hex digits) of a run's positions every tick, then its broadcasts and floor
    bits; and its summary without the fields that time it or name the controller as given."""
    sim = Simulation(world, controller=controller, seed=seed, max_ticks=ticks,
                     settings={"stop_on_complete": False, **settings})
    digest = hashlib.sha256()
    for _ in range(ticks):
        sim.step()
        digest.update(sim.positions.tobytes())
    digest.update(sim.messages.tobytes())
    digest.update(sim.on_target.tobytes())
    summary = {k: v for k, v in sim.result().summary.items() if k not in (*TIMING_FIELDS, "controller")}
    return digest.hexdigest()[:16], summary


@pytest.mark.parametrize("case", sorted(RUNS))
def test_the_batch_cvt_makes_the_per_robot_runs(case):
    """The same run, sleeping robots and decisions counted included."""
    batch, per_robot = run_digest(CVT, *RUNS[case]), run_digest(CVTRobot, *RUNS[case])
    assert batch == per_robot
    if case in GOLDEN:
        assert batch[0] == GOLDEN[case]
    summary = batch[1]
    slept = summary["decisions"] < summary["robots"] * RUNS[case][2]
    assert slept == (case in SLEEPING)
    assert summary["total_distance"] > 0


def test_chunks_change_nothing(monkeypatch):
    """Robots decided 7 at a time (K decides its 603 in one chunk): the same run."""
    whole = run_digest(CVT, *RUNS["tiny seed 2 noisy"])
    monkeypatch.setattr("swarmsim.engine.sim.DECIDE_CHUNK", 7)
    assert run_digest(CVT, *RUNS["tiny seed 2 noisy"]) == whole


def test_a_restored_cvt_run_goes_on_as_the_run(tmp_path):
    """The swarm's arrays (maps, discs, statuses) are all of a checkpoint needs of CVT."""
    run = run_for("cvt", seed=1, ticks=200, max_ticks=400)
    restored = restored_goes_on(run, tmp_path, 150)
    assert run.swarm.rows.status.tobytes() == restored.swarm.rows.status.tobytes()


def test_map_rows_remember_what_local_maps_remember():
    """Robots wandering over an L-shaped floor, far enough to move their windows many times:
    the windows, their origins and the lookups are LocalMap's, each robot's probes asked in
    one query per tick."""
    floor = FloorSensor(Polygon([(0, 0), (40, 0), (40, 12), (12, 12), (12, 40), (0, 40)]), 6.0)
    rng = np.random.default_rng(8)
    robots, radius, cell = 5, 5.0, 0.7
    at = rng.uniform(2, 10, size=(robots, 2))
    maps = MapRows(robots, radius, cell)
    local = [LocalMap(radius, cell) for _ in range(robots)]
    rows = np.array([3, 0, 4], dtype=np.int64)  # a chunk of three, out of order
    asked = []
    for _ in range(120):
        moved = rng.normal(size=(robots, 2)) * 0.6
        at += moved
        probes = floor.probes(at[rows])

        def probe_many(ks, offsets, probes=probes):
            asked.append(len(ks))
            return probes(ks, offsets)

        maps.sense(rows, moved[rows], probe_many)
        for k, i in enumerate(rows.tolist()):
            lm = local[i]
            lm.move(moved[i])
            perception = make_perception(0, np.zeros((0, 2)), np.zeros(0), np.zeros(0), True,
                                         floor.probe_at(*at[i]), None, moved[i])
            lm.sense(perception)
            assert np.array_equal(maps.grid[i], lm._grid)
            assert np.array_equal(maps.origin[i], lm._origin)
            assert maps.odo[i].tobytes() == lm.odo.tobytes()
            offsets = rng.uniform(-1, 1, size=(30, 2))
            scale = rng.uniform(0.5, 1.2) * radius  # some points beyond the radius
            want = lm.lookup(perception, offsets * scale)
            got = np.zeros(len(offsets), dtype=np.int8)
            assert lattice_values(maps.odo[i], maps.origin[i], maps.grid[i], cell,
                                  maps.radius2, offsets, scale, got) == -1
            assert np.array_equal(got == 1, want)
    assert (maps.grid[[1, 2]] == -1).all()  # robots outside the chunk never sensed
    values = np.full(2, 7, dtype=np.int8)
    far = np.array([[radius + 2 * cell, 0.0], [0.0, 0.0]])  # beyond the radius, then within
    assert lattice_values(maps.odo[1], maps.origin[1], maps.grid[1], cell, maps.radius2, far,
                          1.0, values) == 1  # robot 1 never sensed: its own point is unknown
    assert values[0] == 0
    assert sum(asked) > 0 and len(asked) > 10
