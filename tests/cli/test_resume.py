"""``swarmsim run --checkpoint-every N`` and ``swarmsim run --resume DIR``: a run killed with
SIGKILL at a random tick and resumed writes the outputs the same command never killed writes
(summary.json but its timing fields, timeseries.csv and robots.csv byte for byte, coverage.npz
and trajectories.npz array for array), for GGC, a baseline and a user's per-robot controller,
physics sleep on; and the options' misuses are refused with one line."""

from __future__ import annotations

import json
import os
import random
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from swarmsim.cli import main
from swarmsim.engine import checkpoint
from swarmsim.engine.sim import TIMING_FIELDS

ROOT = Path(__file__).resolve().parents[2]
EVERY = 100  # --checkpoint-every
RUNS = {  # long enough that a kill a second after the first checkpoint falls mid-run
    "ggc": ["tiny", "--robots", "40", "--max-ticks", "1500"],
    "kilobot": ["tiny", "--controller", "kilobot", "--robots", "20", "--max-ticks", "1500"],
    "user": ["tiny", "--controller", "tests.resume_bots:Crowder", "--robots", "20",
             "--max-ticks", "1200", "--trajectories", "25"],
}


def _swarmsim(args: list[str], hash_seed: str) -> subprocess.Popen:
    env = {**os.environ, "PYTHONHASHSEED": hash_seed, "SDL_VIDEODRIVER": "dummy",
           "MPLBACKEND": "Agg"}
    return subprocess.Popen([sys.executable, "-m", "swarmsim", "run", *args, "--quiet"],
                            cwd=ROOT, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)


def _finished(proc: subprocess.Popen) -> None:
    _, err = proc.communicate(timeout=600)
    assert proc.returncode == 0, err


def _kill_after_a_checkpoint(proc: subprocess.Popen, saved: Path) -> None:
    """SIGKILL ``proc`` at a random moment after its first checkpoint ``saved`` exists."""
    deadline = time.monotonic() + 300  # the first run in a checkout loads or compiles kernels
    while not saved.exists():
        assert proc.poll() is None, proc.communicate()[1]
        assert time.monotonic() < deadline, "no checkpoint written"
        time.sleep(0.02)
    time.sleep(random.uniform(0.0, 1.0))
    assert proc.poll() is None, "the run ended before it was killed: make it longer"
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()


def _summary(folder: Path) -> dict:
    summary = json.loads((folder / "summary.json").read_text())
    return {k: v for k, v in summary.items() if k not in TIMING_FIELDS}


def _same_arrays(a: Path, b: Path) -> bool:
    with np.load(a) as x, np.load(b) as y:
        return sorted(x) == sorted(y) and all(np.array_equal(x[k], y[k]) for k in x)


@pytest.mark.slow
@pytest.mark.parametrize("run", list(RUNS))
def test_a_run_killed_and_resumed_is_the_run_never_killed(tmp_path, run):
    whole, cut = tmp_path / "whole", tmp_path / "cut"
    options = [*RUNS[run], "--checkpoint-every", str(EVERY)]
    never_killed = _swarmsim([*options, "--out", str(whole)], "1")
    killed = _swarmsim([*options, "--out", str(cut)], "2")
    _kill_after_a_checkpoint(killed, cut / checkpoint.FILE_NAME)
    _finished(never_killed)
    killed_at = checkpoint.read_header(cut / checkpoint.FILE_NAME)["tick"]
    assert killed_at % EVERY == 0 and killed_at > 0
    assert not (cut / "summary.json").exists()
    _finished(_swarmsim(["--resume", str(cut)], "3"))

    assert _summary(cut) == _summary(whole), f"killed after the checkpoint of tick {killed_at}"
    assert _summary(cut)["ticks"] > killed_at
    for name in ("timeseries.csv", "robots.csv"):
        assert (cut / name).read_bytes() == (whole / name).read_bytes(), name
    names = ["coverage.npz", *(["trajectories.npz"] if "--trajectories" in options else [])]
    for name in names:
        assert _same_arrays(cut / name, whole / name), name
    for folder in (whole, cut):  # a run that ended removed its checkpoint (and temporaries)
        assert sorted(p.name for p in folder.iterdir()) == sorted(p.name for p in
                                                                  whole.iterdir())
        assert not list(folder.glob(f"*{checkpoint.FILE_NAME}*"))


def _error(argv: list[str], capsys: pytest.CaptureFixture) -> str:
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("swarmsim: error: ") and err.count("\n") == 1
    return err


def test_misused_checkpoint_options_are_refused(tmp_path, capsys):
    assert "needs --out" in _error(["run", "tiny", "--checkpoint-every", "10"], capsys)
    assert "swarmsim replay" in _error(["run", "tiny", "--checkpoint-every", "10", "--out",
                                        str(tmp_path / "a"), "--video",
                                        str(tmp_path / "a.mp4")], capsys)
    assert ">= 1" in _error(["run", "tiny", "--checkpoint-every", "0", "--out",
                             str(tmp_path / "a")], capsys)
    assert "give the WORLD" in _error(["run"], capsys)
    assert not (tmp_path / "a").exists()


def test_resume_says_what_it_cannot_resume(tmp_path, capsys):
    assert "no checkpoint in" in _error(["run", "--resume", str(tmp_path)], capsys)
    ended = tmp_path / "ended"
    assert main(["run", "tiny", "--robots", "5", "--max-ticks", "30", "--quiet", "--out",
                 str(ended), "--checkpoint-every", "10"]) == 0
    assert not (ended / checkpoint.FILE_NAME).exists()
    assert "has ended" in _error(["run", "--resume", str(ended)], capsys)
    assert "got --robots too" in _error(["run", "--resume", str(ended), "--robots", "4"],
                                        capsys)
    assert "got world too" in _error(["run", "tiny", "--resume", str(ended)], capsys)
    assert "got --width too" in _error(["run", "--resume", str(ended), "--width", "400"],
                                       capsys)


def test_a_new_run_removes_an_earlier_runs_checkpoint(tmp_path, capsys):
    """A checkpoint left by a killed run is not this run's: it must not be resumed later."""
    folder = tmp_path / "out"
    folder.mkdir()
    stale = folder / checkpoint.FILE_NAME
    stale.write_bytes(b"an earlier run's")
    half_written = folder / f".{checkpoint.FILE_NAME}.abc123.tmp"  # a kill during a write
    half_written.write_bytes(b"half")
    assert main(["run", "tiny", "--robots", "5", "--max-ticks", "30", "--quiet", "--out",
                 str(folder)]) == 0
    assert not stale.exists() and not half_written.exists()


def test_an_interrupted_run_says_how_to_resume(tmp_path, capsys):
    folder = tmp_path / "out"
    argv = ["run", "tiny", "--controller", "tests.resume_bots:Interrupted", "--robots", "5",
            "--quiet", "--out", str(folder)]
    assert main([*argv, "--checkpoint-every", "10"]) == 130
    err = capsys.readouterr().err
    assert f"'swarmsim run --resume {folder}' continues the run" in err
    assert err.count("\n") == 1
    assert checkpoint.read_header(folder / checkpoint.FILE_NAME)["tick"] == 20
    assert main([*argv, "--checkpoint-every", "50"]) == 130  # before its first checkpoint
    assert "--resume" not in capsys.readouterr().err
