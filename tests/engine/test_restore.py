"""Snapshot and restore (swarmsim/engine/checkpoint.py): a run saved at a tick and the run
restored from the file, here or in another process, end identically (summary, time series,
robots.csv, positions, broadcasts, controller state), physics sleep on; and files that are not
checkpoints of this code, or runs that cannot be saved, are refused with one line."""

from __future__ import annotations

import os
import pickle
import subprocess
import sys
import threading
from pathlib import Path

import numpy as np
import pytest

from swarmsim import Simulation
from swarmsim.engine import checkpoint
from swarmsim.engine.hooks import Hook
from swarmsim.errors import ConfigError
from swarmsim.world.world import world_from_dict
from tests.run_outcome import outcome as _outcome

ROOT = Path(__file__).resolve().parents[2]
CROWDER = "tests.resume_bots:Crowder"  # a user's per-robot controller (module:Class)
RUNS = {  # controller -> robots, tick to save at, max_ticks (ggc, kilobot: robots asleep then)
    "ggc": (40, 300, 450),
    "kilobot": (20, 400, 550),
    CROWDER: (20, 250, 400),
}


def _sim(controller: str) -> Simulation:
    robots, _, max_ticks = RUNS[controller]
    return Simulation("tiny", controller=controller, seed=3, robots=robots, max_ticks=max_ticks)


def _saved(controller: str, path: Path) -> Simulation:
    """The run of ``controller`` advanced to its save tick and saved to ``path``."""
    sim = _sim(controller)
    for _ in range(RUNS[controller][1]):
        sim.advance()
    sim.save(path)
    return sim


@pytest.mark.parametrize("controller", list(RUNS))
def test_a_restored_run_ends_as_the_run_that_saved(tmp_path, controller):
    path = tmp_path / "run.ckpt"
    first = _saved(controller, path)
    rest = Simulation.restore(path)
    assert rest.tick == first.tick == RUNS[controller][1]
    assert np.array_equal(rest.physics.bodies_asleep(), first.physics.bodies_asleep())
    if controller != CROWDER:  # its robots are pushed too often to sleep in pymunk
        assert first.physics.bodies_asleep().any()  # sleeping bodies are restored asleep
    assert first.velocities.any()  # and robots are moving: the rest of the run is real
    assert _outcome(rest) == _outcome(first)


def test_a_run_without_physics_sleep_restores_too(tmp_path):
    path = tmp_path / "run.ckpt"
    sim = Simulation("tiny", controller=CROWDER, seed=3, robots=20, max_ticks=300,
                     settings={"physics_sleep": False})
    for _ in range(150):
        sim.advance()
    sim.save(path)
    assert _outcome(Simulation.restore(path)) == _outcome(sim)


def test_a_scattered_start_of_twenty_groups_restores_mid_gathering(tmp_path):
    """GGC's per-group arrays (one column per group, beside the state rows) are saved and
    restored: a scattered start of 20 groups saved while its robots gather."""
    world = world_from_dict({
        "name": "band", "target": {"outline": [[0, 0], [60, 0], [60, 20], [0, 20]]},
        "spawn": [{"outline": [[-20, -30], [80, -30], [80, -12], [-20, -12]]}],
        "beacon": {"position": [30, 10]}})
    sim = Simulation(world, controller="ggc", robots=200, groups=20, seed=1, max_ticks=450,
                     settings={"start": "random"})
    for _ in range(300):
        sim.advance()
    path = tmp_path / "run.ckpt"
    sim.save(path)
    rest = Simulation.restore(path)
    saved = [a.copy() for a in sim.swarm.per_group]
    assert rest.swarm.per_group.ldist.shape == (200, 20)
    assert all(np.array_equal(a, b) for a, b in zip(rest.swarm.per_group, saved, strict=True))
    assert _outcome(rest) == _outcome(sim)
    assert not np.array_equal(rest.swarm.per_group.lepoch, saved[1])  # they went on changing


_RESTORE_ELSEWHERE = """
import pickle, sys
sys.path.insert(0, {root!r})
from swarmsim import Simulation
from tests.engine.test_restore import _outcome
sys.stdout.buffer.write(pickle.dumps(_outcome(Simulation.restore({path!r}))))
"""


@pytest.mark.slow
@pytest.mark.parametrize("controller", ["ggc", CROWDER])
def test_a_run_restored_in_another_process_ends_as_the_run_that_saved(tmp_path, controller):
    """Another process with another string hash seed (set and dict orders of str keys)."""
    path = tmp_path / "run.ckpt"
    first = _saved(controller, path)
    env = {**os.environ, "PYTHONHASHSEED": "12345"}
    out = subprocess.run([sys.executable, "-c", _RESTORE_ELSEWHERE.format(root=str(ROOT),
                                                                            path=str(path))],
                         env=env, cwd=ROOT, capture_output=True, check=True).stdout
    assert pickle.loads(out) == _outcome(first)


def test_saving_is_an_event_in_the_run(tmp_path):
    """The run that saved goes on from the state loaded back from its file, not from its
    own Space: the same run never saved ends differently (the Space loaded from pymunk's
    pickle does not step bit for bit like the original), and the restore ends as the run
    that saved. Were the re-seat skipped, the run that saved would end as the unsaved one,
    and not as its restore."""
    path = tmp_path / "run.ckpt"
    first = _saved(CROWDER, path)
    never_saved = _sim(CROWDER)
    ended = _outcome(first)
    assert _outcome(never_saved) != ended
    assert _outcome(Simulation.restore(path)) == ended


def test_a_run_saved_at_tick_0_or_after_its_end_restores(tmp_path):
    start, end = tmp_path / "start.ckpt", tmp_path / "end.ckpt"
    sim = _sim("kilobot")
    sim.save(start)
    outcome = _outcome(sim)
    assert _outcome(Simulation.restore(start)) == outcome
    sim.save(end)
    done = Simulation.restore(end)
    assert done.stop_reason == sim.stop_reason == "max_ticks"
    assert _outcome(done) == outcome  # run() of an ended run steps no more


def _refused(path: Path) -> str:
    with pytest.raises(ConfigError) as caught:
        Simulation.restore(path)
    message = str(caught.value)
    assert str(path) in message and "\n" not in message
    return message


def test_files_that_are_not_checkpoints_of_this_code_are_refused(tmp_path, monkeypatch):
    path = tmp_path / "run.ckpt"
    _saved("kilobot", path)
    data = path.read_bytes()
    other = tmp_path / "other.ckpt"
    other.write_bytes(b"hello\n")
    assert "not a swarmsim checkpoint" in _refused(other)
    other.write_bytes(data[:-100])
    assert "truncated" in _refused(other)
    flipped = bytearray(data)
    flipped[-50] ^= 0xFF
    other.write_bytes(bytes(flipped))
    assert "digest" in _refused(other)
    this_format = f'"format": {checkpoint.FORMAT}'.encode()
    assert this_format in data
    other.write_bytes(data.replace(this_format, b'"format": 9', 1))
    assert "format 9" in _refused(other)
    assert "cannot read" in _refused(tmp_path / "missing.ckpt")
    monkeypatch.setattr(checkpoint, "code_version", lambda: "9.9.9")
    assert "restore it with the code that wrote it" in _refused(path)


class _Counter(Hook):
    """A user's loop hook."""


class _Locked:
    """A per-robot controller holding what pickle cannot take (a lock)."""

    def __init__(self, setup, params, rng):
        self.lock = threading.Lock()


def test_runs_that_cannot_be_saved_are_refused_and_nothing_is_written(tmp_path):
    path = tmp_path / "run.ckpt"
    sim = _sim(CROWDER)  # a per-robot controller: one object per robot
    sim.hooks.append(_Counter())
    with pytest.raises(ConfigError, match=r"user's loop hook \(_Counter\)"):
        sim.save(path)
    sim.hooks.pop()
    sim.swarm.robots[3].extra = _Locked(None, None, None)
    with pytest.raises(ConfigError, match=r"sim\.swarm\.robots\[3\]\.extra.*lock"):
        sim.save(path)
    assert list(tmp_path.iterdir()) == []  # nothing half-written, no temporary file


def test_a_checkpoint_is_replaced_atomically(tmp_path):
    path = tmp_path / "run.ckpt"
    sim = _sim("kilobot")
    sim.save(path)
    sim.advance()
    sim.save(path)
    assert checkpoint.read_header(path)["tick"] == 1
    assert [p.name for p in tmp_path.iterdir()] == ["run.ckpt"]


@pytest.mark.parametrize("drive", ["diff", "kilobot"])
@pytest.mark.parametrize("sleep", [True, False])
def test_a_run_with_a_steering_drive_restores_too(tmp_path, drive, sleep):
    """The body angles, the drive's wheel speeds and random streams, the spins written to
    parked robots' control bodies and the odometry are all saved."""
    path = tmp_path / "run.ckpt"
    sim = Simulation("tiny", seed=3, robots=40, max_ticks=450,
                     settings={"drive": drive, "physics_sleep": sleep})
    for _ in range(300):
        sim.advance()
    sim.save(path)
    rest = Simulation.restore(path)
    np.testing.assert_array_equal(rest.physics.headings(), sim.physics.headings())
    assert _outcome(rest) == _outcome(sim)
