"""Nothing left behind: a run or a sweep that ends early (a refused option, a controller that
raises or returns NaN, Ctrl-C or SIGTERM, however busy the physics is) removes the folders it
made and keeps the ones that were there; a run folder holds one run and is locked while a run
writes into it."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pymunk
import pytest

from swarmsim import ConfigError
from swarmsim.cli import _terminate_as_interrupt, main
from swarmsim.engine.sim import Simulation
from swarmsim.experiments import run_sweep, spec_from_dict
from swarmsim.results import runfolder
from tests import early_end_bots
from tests.errlines import error_lines

REPO = Path(__file__).resolve().parents[2]
BOTS = "tests.early_end_bots"

ENDINGS = {
    "refused --color-by": ["--color-by", "no-such-field"],
    "controller raises": ["--controller", f"{BOTS}:RaisesInStep"],
    "NaN velocity": ["--controller", f"{BOTS}:NanVelocity"],
    "undeclared broadcast field": ["--controller", f"{BOTS}:UndeclaredField"],
    "interrupt": ["--controller", f"{BOTS}:Interrupted"],
}
"""Ways a run ends early: the options that make ``swarmsim run tiny`` end so."""

OUTPUTS = ["--out", "runs/a/out", "--video", "videos/v/run.mp4", "--snapshot", "shots/last.png",
           "--trajectories", "5"]
"""Where the run writes: three folders, two of them two levels deep."""


def _run_ending_early(argv: list[str]) -> None:
    """``swarmsim run tiny ARGV``, which must fail: exit status 2 or 130, or an exception."""
    try:
        status = main(["run", "tiny", "--quiet", "--max-ticks", "50", *argv])
    except Exception:  # noqa: BLE001  a controller's error may end as a traceback
        return
    assert status in (2, 130)


def _tree(root: Path) -> dict[str, str]:
    """Every file and folder under ``root``: relative path -> contents ('' for a folder)."""
    return {str(p.relative_to(root)): ("" if p.is_dir() else p.read_text(errors="replace"))
            for p in sorted(root.rglob("*"))}


@pytest.mark.parametrize("ending", list(ENDINGS))
def test_a_run_that_ends_early_leaves_no_folder_it_made(tmp_path, monkeypatch, ending):
    monkeypatch.chdir(tmp_path)
    _run_ending_early([*ENDINGS[ending], *OUTPUTS])
    assert list(tmp_path.iterdir()) == []


@pytest.mark.slow
@pytest.mark.parametrize("ending", list(ENDINGS))
def test_a_run_that_ends_early_keeps_the_folders_that_were_there(tmp_path, monkeypatch,
                                                                  ending):
    """The user's own files stay, and so do the files of the run made there before."""
    monkeypatch.chdir(tmp_path)
    assert main(["run", "tiny", "--quiet", "--max-ticks", "20", *OUTPUTS]) == 0
    for folder in ("runs/a/out", "videos/v", "shots", "runs"):
        (tmp_path / folder / "notes.txt").write_text("mine")
    before = _tree(tmp_path)
    _run_ending_early([*ENDINGS[ending], *OUTPUTS])
    assert _tree(tmp_path) == before


@pytest.mark.slow
def test_a_run_folder_holds_one_run(tmp_path, monkeypatch):
    """A re-run removes what the earlier run wrote and it does not (its trajectories, the
    temporary file of a killed write), and keeps the user's files."""
    monkeypatch.chdir(tmp_path)
    assert main(["run", "tiny", "--quiet", "--max-ticks", "20", "--out", "o",
                 "--trajectories", "5"]) == 0
    (tmp_path / "o" / "notes.txt").write_text("mine")
    (tmp_path / "o" / ".coverage.npz.k1ll3d.tmp").write_bytes(b"half")
    assert main(["run", "tiny", "--quiet", "--max-ticks", "30", "--out", "o"]) == 0
    assert sorted(p.name for p in (tmp_path / "o").iterdir()) == [
        "coverage.npz", "coverage.png", "notes.txt", "robots.csv", "summary.json",
        "timeseries.csv"]
    assert '"ticks": 30' in (tmp_path / "o" / "summary.json").read_text()


@pytest.mark.slow
@pytest.mark.parametrize("existed", [False, True], ids=["new folder", "existing folder"])
def test_writing_that_fails_leaves_no_half_run(tmp_path, monkeypatch, existed):
    """Writing the outputs fails half-way: none of the run's files stay (nor a folder made for
    them); the user's do."""
    import swarmsim.results.plots

    monkeypatch.chdir(tmp_path)
    if existed:
        assert main(["run", "tiny", "--quiet", "--max-ticks", "20", "--out", "o"]) == 0
        (tmp_path / "o" / "notes.txt").write_text("mine")

    def disk_full(*_args, **_kwargs):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(swarmsim.results.plots, "plot_timeseries", disk_full)
    with pytest.raises(OSError, match="No space"):
        main(["run", "tiny", "--quiet", "--max-ticks", "20", "--out", "o"])
    assert _tree(tmp_path) == ({"o": "", "o/notes.txt": "mine"} if existed else {})


# ------------------------------------------------------------------------------ the lock
@pytest.mark.parametrize("who", ["swarmsim run", "runfolder.locked"])
def test_a_folder_in_use_is_refused_naming_the_other_run(tmp_path, monkeypatch, capsys, who):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "o").mkdir()
    with runfolder.locked("o"):  # this process is the other run
        if who == "swarmsim run":
            assert main(["run", "tiny", "--quiet", "--out", "o"]) == 2
            lines = error_lines(capsys.readouterr().err)
            assert len(lines) == 1
            message = lines[0]
        else:
            with pytest.raises(ConfigError) as info, runfolder.locked("o"):
                pass
            message = str(info.value)
        assert "'o'" in message and f"pid {os.getpid()}" in message
    assert sorted(p.name for p in (tmp_path / "o").iterdir()) == []  # lock file removed


def test_a_lock_file_left_by_a_killed_run_does_not_hold_the_folder(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "o").mkdir()
    (tmp_path / "o" / runfolder.LOCK_FILE).write_text("pid 999999 on elsewhere\n")
    assert main(["run", "tiny", "--quiet", "--max-ticks", "10", "--out", "o"]) == 0
    assert (tmp_path / "o" / "summary.json").is_file()
    assert not (tmp_path / "o" / runfolder.LOCK_FILE).exists()


# ------------------------------------------------------------------- interrupts in pymunk
@pytest.mark.slow
@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_a_signal_inside_a_pymunk_callback_stops_the_run_at_the_end_of_the_tick(
        monkeypatch, signum):
    """Python API: the interrupt raised inside a collision callback (where cffi swallowed it)
    ends ``Simulation.run`` with KeyboardInterrupt once the tick is done. SIGTERM as the
    command line handles it (like Ctrl-C)."""
    sims: list[Simulation] = []
    at: list[int] = []

    def send_signal(arbiter, space, data):
        if not at:
            at.append(sims[0].tick)
            os.kill(os.getpid(), signum)

    on_collision = pymunk.Space.on_collision

    def on_collision_signalling(self, *types, begin=None, **kw):
        return on_collision(self, *types, begin=_then(begin, send_signal), **kw)

    monkeypatch.setattr(pymunk.Space, "on_collision", on_collision_signalling)
    sims.append(Simulation("tiny", controller=f"{BOTS}:Crowd", seed=1, max_ticks=100_000,
                           settings={"stop_on_complete": False}))
    with pytest.raises(KeyboardInterrupt), _terminate_as_interrupt():
        sims[0].run()
    assert at, "no contact began"
    assert sims[0].tick == at[0] + 1


def test_ctrl_c_outside_the_physics_raises_at_once_and_the_handlers_are_restored():
    """Python API: Ctrl-C anywhere else in the loop (here in on_tick) raises at once, as
    Python's own handler does; after the run the handlers are the ones before it."""
    sim = Simulation("tiny", controller=f"{BOTS}:Crowd", seed=1, max_ticks=100_000,
                     settings={"stop_on_complete": False})

    def ctrl_c_at_tick_5(sim):
        if sim.tick == 5:
            os.kill(os.getpid(), signal.SIGINT)
        assert sim.tick <= 5, "the interrupt was not raised at once"

    before = signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM)
    with pytest.raises(KeyboardInterrupt):
        sim.run(on_tick=ctrl_c_at_tick_5)
    assert sim.tick == 5
    assert (signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM)) == before
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def _then(first, second):
    """A pymunk callback that calls ``first``, then ``second``."""
    def both(arbiter, space, data):
        first(arbiter, space, data)
        second(arbiter, space, data)

    return both


@pytest.mark.slow
@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_a_signal_while_pymunk_is_busy_stops_swarmsim_run(tmp_path, signum):
    """``swarmsim run`` whose time goes into pymunk's collision callbacks (made slow by
    tests.slow_contacts): the signal arrives inside one; the run stops with status 130,
    "interrupted", no file and no folder."""
    marker = tmp_path / "inside-a-callback"
    env = {**os.environ, "PYTHONPATH": str(REPO), "SLOW_CONTACT_MARKER": str(marker),
           "SLOW_CONTACT_SECONDS": "0.2"}
    cmd = [sys.executable, "-m", "tests.slow_contacts", "run", "tiny", "--quiet",
           "--controller", f"{BOTS}:Crowd", "--out", "d/out", "--max-ticks", "10000000",
           "--set", "stop_on_complete=false", "--set", "plateau_ticks=10000000",
           "--set", "stall_ticks=10000000"]
    work = tmp_path / "work"
    work.mkdir()
    proc = subprocess.Popen(cmd, cwd=work, env=env, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 120
        while not marker.exists():
            assert proc.poll() is None and time.monotonic() < deadline, proc.stderr.read()
            time.sleep(0.05)
        proc.send_signal(signum)
        _, err = proc.communicate(timeout=60)
    finally:
        proc.kill()
    assert proc.returncode == 130, err
    assert err.strip().splitlines()[-1] == "swarmsim: interrupted"
    assert "Exception ignored" not in err
    assert list(work.iterdir()) == []


# ---------------------------------------------------------------------------- sweeps
@pytest.mark.parametrize("finished", [0, 1], ids=["in the first run", "after a run"])
@pytest.mark.parametrize("existed", [False, True], ids=["new folder", "existing folder"])
def test_an_interrupted_sweep_leaves_only_its_finished_runs(tmp_path, monkeypatch, finished,
                                                            existed):
    runs = spec_from_dict({"world": "tiny", "controller": "dispersion", "reps": 3,
                           "params": {"max_ticks": 30}}).runs()
    out = tmp_path / "sweep"
    if existed:
        out.mkdir()
        (out / "notes.txt").write_text("mine")
    step = Simulation.step

    def interrupted_in_run(sim):
        if sim.config.seed == finished and sim.tick == 10:
            raise KeyboardInterrupt
        step(sim)

    monkeypatch.setattr(Simulation, "step", interrupted_in_run)
    with pytest.raises(KeyboardInterrupt):
        run_sweep(runs, out, workers=1, progress=False)
    kept = sorted(str(p.relative_to(tmp_path)) for p in tmp_path.rglob("*")
                  if p.is_dir() or p.name == "notes.txt")
    done = [f"sweep/runs/{r.run_id}" for r in runs[:finished]]
    expected = (["sweep"] if existed or finished else []) + (["sweep/notes.txt"] if existed
                                                             else [])
    expected += (["sweep/runs"] if finished else []) + done
    assert kept == sorted(expected)
    assert all((tmp_path / d / "summary.json").is_file() for d in done)


def test_the_test_controllers_end_when_they_say():
    """The controllers above end runs at tick GO_FROM_TICK (not before: the run has begun)."""
    sim = Simulation("tiny", controller=f"{BOTS}:RaisesInStep", max_ticks=50)
    with pytest.raises(RuntimeError):
        sim.run()
    assert sim.tick == early_end_bots.GO_FROM_TICK
