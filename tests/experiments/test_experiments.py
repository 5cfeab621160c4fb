"""Sweeps (specs, resume, failures, executors), robot failures and the paper's figure registry."""

from __future__ import annotations

import contextlib
import json
import os
import socket
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from controllers.common.gradient import GRADIENT_FIELDS, INF_GRADIENT, SILENT
from controllers.ggc.rules.rulesets import DEFAULT_RULESET as DEFAULT
from swarmsim import ConfigError
from swarmsim.cli import main
from swarmsim.controller import Action, Perception, RobotSetup
from swarmsim.engine.faults import FaultInjector, FaultPlan
from swarmsim.engine.sim import TIMING_FIELDS, Simulation
from swarmsim.experiments import claims, load_spec, run_id, run_sweep, spec_from_dict
from swarmsim.experiments import reproduce as rp
from swarmsim.experiments.figures import failure_panels
from swarmsim.experiments.runner import Sweep, run_cost
from swarmsim.experiments.table import read_table

TINY = {"world": "tiny", "controller": "dispersion", "params": {"max_ticks": 30}}


def write_spec(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "spec.toml"
    path.write_text(text)
    return path


def no_wall(summary: dict) -> dict:
    return {k: v for k, v in summary.items() if k not in TIMING_FIELDS}


# ----------------------------------------------------------------------------- specs
def test_grid_is_the_cartesian_product_times_seeds():
    spec = spec_from_dict({**TINY, "reps": 2, "grid": {"d_cover": [4, 6], "robots": [20, 30]}})
    runs = spec.runs()
    assert len(runs) == 2 * 2 * 2
    assert [(r.settings["d_cover"], r.settings["robots"], r.seed) for r in runs[:4]] == [
        (4, 20, 0), (4, 20, 1), (4, 30, 0), (4, 30, 1)]
    assert all(r.settings["max_ticks"] == 30 for r in runs)
    assert len({r.run_id for r in runs}) == len(runs)
    again = spec_from_dict({**TINY, "reps": 2, "grid": {"d_cover": [4, 6], "robots": [20, 30]}})
    assert [r.run_id for r in again.runs()] == [r.run_id for r in runs]


def test_seeds_list_and_seed_base():
    assert [r.seed for r in spec_from_dict({**TINY, "seeds": [5, 9]}).runs()] == [5, 9]
    assert [r.seed for r in spec_from_dict({**TINY, "reps": 3, "seed_base": 10}).runs()] == [
        10, 11, 12]
    assert [r.seed for r in spec_from_dict(TINY).runs()] == [0]


def test_run_id_is_stable_and_ignores_inert_settings():
    a = run_id("K", "ggc", {"d_cover": 6, "groups": 3}, 0)
    assert a == run_id("K", "ggc", {"groups": 3, "d_cover": 6.0}, 0)
    assert a == run_id("K", "ggc", {"groups": 3, "d_cover": 6, "failures": 0,
                                    "failure_phase": "gradient"}, 0)
    assert a != run_id("K", "ggc", {"d_cover": 6, "groups": 3}, 1)
    assert a != run_id("K", "ggc", {"d_cover": 6, "groups": 3, "failures": 1}, 0)


@pytest.mark.parametrize("text, key, value", [
    ('world = "tiny"\nbogus = 3\n', "bogus", "3"),
    ('world = "tiny"\ncontroller = "dispersion"\nreps = 0\n', "reps", "0"),
    ('world = "tiny"\ncontroller = "dispersion"\nreps = "two"\n', "reps", "'two'"),
    ('world = "tiny"\ncontroller = "dispersion"\n[grid]\nd_cover = []\n', "grid.d_cover", "list"),
    ('world = "tiny"\ncontroller = "dispersion"\n[grid]\nd_cover = 5\n', "grid.d_cover", "5"),
    ('world = "tiny"\ncontroller = "dispersion"\n[grid]\n', "grid", "empty"),
    ('world = "tiny"\ncontroller = "dispersion"\n[grid]\nd_cover = [4, 4.0]\n', "grid.d_cover",
     "4"),
    ('world = "tiny"\ncontroller = "dispersion"\n[params]\nwarp = 9\n', "params.warp", "9"),
    ('world = "tiny"\ncontroller = "dispersion"\n[grid]\nd_cover = [1, "far"]\n',
     "grid.d_cover", "'far'"),
    ('world = "tiny"\ncontroller = "dispersion"\nseeds = [1, 1]\n', "seeds", "[1, 1]"),
    ('world = "tiny"\ncontroller = "dispersion"\nseeds = [1]\nreps = 2\n', "reps", "2"),
    ('world = "atlantis"\ncontroller = "dispersion"\n', "world", "atlantis"),
    ('world = "tiny"\ncontroller = "warpdrive"\n', "controller", "warpdrive"),
    ('controller = "dispersion"\n', "world", "missing"),
])
def test_spec_errors_name_file_key_and_value(tmp_path, text, key, value):
    path = write_spec(tmp_path, text)
    with pytest.raises(ConfigError) as err:
        load_spec(path)
    msg = str(err.value)
    assert str(path) in msg and f"key '{key}'" in msg and value in msg.replace(str(path), "")


def test_world_path_is_relative_to_the_spec(tmp_path, monkeypatch):
    from swarmsim.world.world import world_path

    (tmp_path / "worlds").mkdir()
    (tmp_path / "worlds" / "mine.toml").write_text(world_path("tiny").read_text())
    path = write_spec(tmp_path, 'world = "worlds/mine.toml"\ncontroller = "dispersion"\n'
                                "[params]\nmax_ticks = 5\n")
    monkeypatch.chdir(tmp_path.parent)
    runs = load_spec(path).runs()
    assert runs[0].world == "worlds/mine.toml" and Path(runs[0].world_ref).is_file()
    assert run_sweep(runs, tmp_path / "out", workers=1, progress=False).failed == 0


def test_cli_sweep_bad_spec_is_one_line_exit_2(tmp_path, capsys):
    path = write_spec(tmp_path, 'world = "tiny"\ncontroller = "dispersion"\nreps = -1\n')
    assert main(["sweep", str(path), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "reps" in err and "-1" in err


# ----------------------------------------------------------------------------- sweeps
@pytest.mark.slow
def test_interrupted_sweep_resumes_without_redoing_runs(tmp_path):
    runs = spec_from_dict({**TINY, "reps": 2, "grid": {"d_cover": [4, 5, 6]}}).runs()
    out = tmp_path / "out"
    finished = []

    def stop_after_two(run, status):
        finished.append(run.run_id)
        if len(finished) == 2:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run_sweep(runs, out, workers=1, progress=False, on_result=stop_after_two)
    assert sorted(p.parent.name for p in out.glob("runs/*/summary.json")) == sorted(finished)
    assert len(read_table(out / "results.csv")) == 2

    second = []
    report = run_sweep(runs, out, workers=1, progress=False,
                       on_result=lambda run, status: second.append(run.run_id))
    assert report.ran == 4 and report.skipped == 2 and report.failed == 0
    assert set(second).isdisjoint(finished) and len(second) == 4
    table = read_table(out / "results.csv")
    assert [r["run_id"] for r in table] == [r.run_id for r in runs]
    assert all(r["error"] == "" and float(r["coverage"]) >= 0 for r in table)
    assert {r["d_cover"] for r in table} == {"4", "5", "6"}
    third = run_sweep(runs, out, workers=1, progress=False)
    assert third.ran == 0 and third.skipped == 6


def test_a_table_before_any_run_finished_has_the_runs_columns(tmp_path):
    runs = spec_from_dict({**TINY, "grid": {"d_cover": [4, 6]}}).runs()

    def stop_at_once(run, status):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        Sweep(runs, tmp_path).run(workers=1, progress=False, on_result=stop_at_once)
    Sweep(runs, tmp_path / "empty").write_table()
    header = (tmp_path / "empty" / "results.csv").read_text().splitlines()
    assert header == ["run_id,world,controller,max_ticks,d_cover,seed,error"]
    text = (tmp_path / "results.csv").read_text().splitlines()
    assert text[0].startswith("run_id,world,controller,max_ticks,d_cover,seed,") and text[0].endswith(",error")
    assert len(text) == 2


@pytest.mark.slow
def test_failing_run_is_recorded_and_others_finish(tmp_path):
    # tiny's spawn band holds at most ~150 robots: 500 makes that run fail (a checked spec
    # refuses it before any run: see test_bad_input)
    runs = spec_from_dict({**TINY, "grid": {"robots": [20, 500, 25]}}, check=False).runs()
    out = tmp_path / "out"
    report = run_sweep(runs, out, workers=1, progress=False)
    assert report.ran == 3 and report.failed == 1
    table = {r["robots"]: r for r in read_table(out / "results.csv")}
    assert table["500"]["error"].startswith("ConfigError") and "500" in table["500"]["error"]
    assert table["20"]["error"] == "" and table["25"]["error"] == ""
    bad = out / "runs" / runs[1].run_id
    assert (bad / "error.txt").is_file() and not (bad / "summary.json").exists()
    assert "Traceback" in (bad / "error.txt").read_text()
    assert run_sweep(runs, out, workers=1, progress=False).ran == 0
    retry = run_sweep(runs, out, workers=1, progress=False, retry_failed=True)
    assert retry.ran == 1 and retry.failed == 1


def _claim_held_by(pid: int) -> str:
    return json.dumps({"host": socket.gethostname(), "pid": pid,
                       "process": claims._process_key(pid)})


@pytest.mark.slow
def test_runs_another_live_process_has_claimed_are_left_to_it(tmp_path):
    runs = spec_from_dict({**TINY, "grid": {"robots": [20, 25]}}).runs()
    out = tmp_path / "out"
    other = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(120)"])
    try:
        held = out / "runs" / runs[1].run_id
        held.mkdir(parents=True)
        (held / "claim.json").write_text(_claim_held_by(other.pid))
        report = run_sweep(runs, out, workers=1, progress=False)
        assert report.ran == 1 and report.busy == 1 and "claimed by another process" in report.line()
        assert report.line().startswith("2 runs: 1 done (1 run now, 0 already there), 0 failed")
        assert not (held / "summary.json").exists() and (held / "claim.json").is_file()
        assert (out / "runs" / runs[0].run_id / "summary.json").is_file()
    finally:
        other.kill()
        other.wait()
    again = run_sweep(runs, out, workers=1, progress=False)  # its process is gone: stale
    assert again.ran == 1 and again.busy == 0 and (held / "summary.json").is_file()
    assert not list(out.glob("runs/*/claim.json")) and not list(out.glob("runs/*/.claim*"))


@pytest.mark.slow
def test_two_processes_taking_over_one_stale_claim_do_not_both_win(tmp_path, monkeypatch):
    """While this process judges a stale claim, another process tries to take it over too:
    exactly one of them may win (the second used to delete the first one's fresh claim)."""
    run_dir = tmp_path / "runs" / "r1"
    run_dir.mkdir(parents=True)
    gone = subprocess.Popen([sys.executable, "-c", "pass"])
    gone.wait()
    (run_dir / "claim.json").write_text(_claim_held_by(gone.pid))  # stale: its process is gone
    script = ("import sys; from pathlib import Path; from swarmsim.experiments import claims; "
              "print('trying', flush=True); print(claims.claim(Path(sys.argv[1])), flush=True)")
    judged = claims.holder
    others = []

    def holder_while_another_process_claims(path):
        found = judged(path)
        if not others:  # once, while this process holds its judgement
            other = subprocess.Popen([sys.executable, "-c", script, str(run_dir)],
                                     stdout=subprocess.PIPE, text=True)
            others.append(other)
            assert other.stdout.readline().strip() == "trying"
            time.sleep(0.5)  # time enough to claim, unless it must wait for this process
        return found

    monkeypatch.setattr(claims, "holder", holder_while_another_process_claims)
    mine = claims.claim(run_dir)
    theirs = others[0].communicate(timeout=60)[0].strip()
    assert [mine, theirs] == [True, "False"]
    assert json.loads((run_dir / "claim.json").read_text())["pid"] == os.getpid()


def test_runs_are_claimed_one_at_a_time_so_a_sweep_started_later_shares_the_rest(tmp_path):
    runs = spec_from_dict({**TINY, "grid": {"robots": [20, 21, 22, 23]}}).runs()
    out = tmp_path / "out"
    other = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(120)"])

    def meanwhile(run, status):  # after our first run, "another process" takes two runs
        if run.run_id != runs[0].run_id:
            return
        taken = out / "runs" / runs[2].run_id
        taken.mkdir(parents=True)
        (taken / "claim.json").write_text(_claim_held_by(other.pid))      # running there
        done = out / "runs" / runs[3].run_id
        done.mkdir(parents=True)
        for name in ("run.json", "summary.json", "timeseries.csv"):     # finished there
            (done / name).write_bytes((out / "runs" / runs[0].run_id / name).read_bytes())

    try:
        report = run_sweep(runs, out, workers=1, progress=False, on_result=meanwhile)
    finally:
        other.kill()
        other.wait()
    assert report.ran == 2 and report.busy == 1 and report.skipped == 1


def _descendants(pid: int) -> set[int]:
    """Live processes under ``pid`` (Linux /proc)."""
    children: dict[int, list[int]] = {}
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if fields[0] != "Z":
            children.setdefault(int(fields[1]), []).append(int(stat.parent.name))
    found, todo = set(), [pid]
    while todo:
        kids = children.get(todo.pop(), [])
        found.update(kids)
        todo.extend(kids)
    return found


def _alive(pid: int) -> bool:
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


@pytest.mark.slow
@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs Linux /proc")
def test_sigterm_stops_a_sweep_and_its_worker_processes(tmp_path):
    """`kill` of a sweep (a batch system's time limit) must not leave its workers running."""
    import signal

    path = write_spec(tmp_path, 'world = "tiny"\ncontroller = "ggc"\nseeds = [0, 1, 2]\n'
                      "[params]\nmax_ticks = 10000000\nstop_on_complete = false\n"
                      "plateau_ticks = 10000000\n")
    cmd = [sys.executable, "-m", "swarmsim", "sweep", str(path), "--out", "o", "--workers", "2",
           "--quiet"]
    proc = subprocess.Popen(cmd, cwd=tmp_path, stderr=subprocess.PIPE, text=True)
    workers: set[int] = set()
    try:
        deadline = time.monotonic() + 120
        while len(list(tmp_path.glob("o/runs/*/claim.json"))) < 2:
            assert proc.poll() is None and time.monotonic() < deadline, proc.stderr.read()
            time.sleep(0.1)
        workers = _descendants(proc.pid)
        assert workers
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=60)
        assert proc.returncode == 130, err
        assert "run the same command again to resume" in err
        deadline = time.monotonic() + 30
        while any(map(_alive, workers)) and time.monotonic() < deadline:
            time.sleep(0.1)
        assert not [w for w in workers if _alive(w)]
        assert not list(tmp_path.glob("o/runs/*/claim.json"))
        assert not (tmp_path / "o").exists()  # no run had finished: no empty runs/<id>/ left
    finally:
        for pid in [proc.pid, *workers]:
            with contextlib.suppress(OSError):
                os.kill(pid, signal.SIGKILL)


@pytest.mark.slow
def test_two_sweep_processes_on_one_folder_never_run_a_run_twice(tmp_path):
    path = write_spec(tmp_path, 'world = "tiny"\ncontroller = "dispersion"\nreps = 6\n'
                                "[params]\nmax_ticks = 150\n")
    out = tmp_path / "out"
    cmd = [sys.executable, "-m", "swarmsim", "sweep", str(path), "--out", str(out),
           "--workers", "1", "--quiet"]
    other = subprocess.Popen(cmd, stdout=subprocess.PIPE, text=True)
    ours = run_sweep(load_spec(path).runs(), out, workers=1, progress=False)
    theirs = other.communicate(timeout=300)[0]
    ran_there = int(theirs.split("(")[1].split(" run now")[0])
    assert ours.ran + ran_there == 6, (ours.line(), theirs)
    assert len(list(out.glob("runs/*/summary.json"))) == 6
    assert not list(out.glob("runs/*/claim.json"))


@pytest.mark.slow
def test_a_claim_is_exclusive_and_a_reused_pid_does_not_hold_it(tmp_path):
    run_dir = tmp_path / "run"
    assert claims.claim(run_dir) and not claims.claim(run_dir)  # held, by this process too
    probe = ("import sys; from pathlib import Path; from swarmsim.experiments import claims; "
             "print(claims.claim(Path(sys.argv[1])))")
    other = subprocess.run([sys.executable, "-c", probe, str(run_dir)], capture_output=True,
                           text=True, check=True)
    assert other.stdout.strip() == "False"
    claims.release(run_dir)
    assert not (run_dir / "claim.json").exists()
    # a claim written by an earlier process that had this process's pid (after a restart)
    (run_dir / "claim.json").write_text(json.dumps(
        {"host": socket.gethostname(), "pid": os.getpid(),
         "process": "another-boot:1"}))
    assert claims.holder(run_dir) is None and claims.claim(run_dir)
    claims.release(run_dir)


def test_cli_sweep_writes_runs_and_table(tmp_path, capsys):
    path = write_spec(tmp_path, 'world = "tiny"\ncontroller = "dispersion"\nreps = 2\n'
                                "[params]\nmax_ticks = 20\n[grid]\nd_cover = [5, 6]\n")
    out = tmp_path / "out"
    assert main(["sweep", str(path), "--out", str(out), "--workers", "1", "--quiet"]) == 0
    assert "4 runs: 4 done" in capsys.readouterr().out
    rows = read_table(out / "results.csv")
    assert len(rows) == 4
    for row in rows:
        run_dir = out / "runs" / row["run_id"]
        summary = json.loads((run_dir / "summary.json").read_text())
        assert summary["ticks"] == 20 and (run_dir / "timeseries.csv").is_file()


@pytest.mark.slow
def test_a_table_mixing_code_versions_says_so(tmp_path):
    import swarmsim

    runs = spec_from_dict({**TINY, "reps": 2}).runs()
    out = tmp_path / "out"
    first = run_sweep(runs, out, workers=1, progress=False)
    ours = next(iter(first.versions))
    assert first.versions == {ours: 2} and ours.startswith(swarmsim.__version__)
    assert "warning" not in first.line()
    path = out / "runs" / runs[0].run_id / "summary.json"
    path.write_text(json.dumps({**json.loads(path.read_text()), "code_version": "0.0.1"}))
    again = run_sweep(runs, out, workers=1, progress=False)
    assert again.ran == 0 and again.versions == {ours: 1, "0.0.1": 1}
    assert "warning: the table mixes runs made by different code" in again.line()
    assert "0.0.1 (1)" in again.line()
    assert "Warning" in rp.versions_line(again.versions)
    assert rp.versions_line({ours: 2}) == f"Code: {ours} (2 runs)."
    summaries = [json.loads(p.read_text()) for p in out.glob("runs/*/summary.json")]
    cpu = [s["cpu_seconds"] for s in summaries]
    assert len(cpu) == 2 and all(c > 0 for c in cpu)
    assert Sweep(runs, out).run_seconds() == pytest.approx(sum(cpu))  # CPU, not wall time
    assert run_cost({"wall_seconds": 3.0}) == 3.0  # a run made before cpu_seconds


def _local_results(runs, out, **kw):
    run_sweep(runs, out, progress=False, **kw)
    return {r.run_id: no_wall(json.loads((out / "runs" / r.run_id / "summary.json").read_text()))
            for r in runs}


@pytest.mark.slow
def test_process_pool_gives_the_same_results_as_in_process(tmp_path):
    runs = spec_from_dict({**TINY, "reps": 2}).runs()
    assert (_local_results(runs, tmp_path / "a", workers=2)
            == _local_results(runs, tmp_path / "b", workers=1))


@pytest.mark.slow
def test_dask_cluster_runs_the_same_sweep(tmp_path):
    distributed = pytest.importorskip("dask.distributed")
    runs = spec_from_dict({**TINY, "reps": 2, "grid": {"d_cover": [5, 6]}}).runs()
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        on_dask = _local_results(runs, tmp_path / "dask", scheduler=client)
        again = run_sweep(runs, tmp_path / "dask", scheduler=cluster.scheduler_address,
                          progress=False)
    assert again.ran == 0
    assert on_dask == _local_results(runs, tmp_path / "local", workers=1)


def test_dask_missing_is_a_clear_error(monkeypatch, tmp_path):
    import builtins

    real_import = builtins.__import__

    def no_dask(name, *args, **kwargs):
        if name.startswith("dask"):
            raise ImportError(f"No module named {name!r}")
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_dask)
    runs = spec_from_dict(TINY).runs()
    with pytest.raises(ConfigError, match=r"swarmsim\[dask\]"):
        run_sweep(runs, tmp_path / "out", scheduler="tcp://127.0.0.1:1", progress=False)


# ----------------------------------------------------------------------------- failures
@dataclass(frozen=True)
class ScriptParams:
    leave_initial: int = 5
    start_moving: int = 15
    arrive: int = 30


class Scripted:
    """Test controller: every robot leaves Initial at tick 5, moves from 15, even ids arrive
    at 30 (ticks as perceived; they show in the broadcast one tick later)."""

    name = "scripted"
    max_groups = 3  # its leaders, one per group, never fail
    Params = ScriptParams
    STATUSES = ("Initial", "Detection", "Coverage", "Arrive")
    MESSAGE_FIELDS = GRADIENT_FIELDS
    SILENT = SILENT
    LEADER_FIELD, GROUP_FIELD = "leader", "group"
    INITIAL_STATUSES, COVERING_STATUSES, SETTLED_STATUSES = ("Initial",), ("Coverage",), ("Arrive",)

    @classmethod
    def sensing_range(cls, params):
        return 3.0

    def __init__(self, setup: RobotSetup, params: ScriptParams, rng):
        self.setup, self.params = setup, params

    def step(self, perception: Perception) -> Action:
        t, s = perception.tick, self.setup
        arrived = t >= self.params.arrive and s.robot_id % 2 == 0
        status = 0 if t < self.params.leave_initial else 1 if t < self.params.start_moving else (
            3 if arrived else 2)
        moving = status == 2
        msg = (s.robot_id, status, moving, 0 if s.leader else INF_GRADIENT, s.group, s.leader)
        return Action((0.05, 0.0) if moving else (0.0, 0.0), msg)


SCRIPTED = f"{__name__}:Scripted"


def injector(sim: Simulation) -> FaultInjector:
    """The run's fault injector: the one FaultInjector among its loop hooks."""
    found = [hook for hook in sim.hooks if isinstance(hook, FaultInjector)]
    assert len(found) == 1, sim.hooks
    return found[0]


@pytest.mark.parametrize("phase, tick, fired", [("gradient", 0, 6), ("coverage", 0, 16),
                                                ("tick", 40, 40)])
def test_failures_fire_when_their_phase_starts(phase, tick, fired):
    sim = Simulation("tiny", SCRIPTED, robots=30, groups=3, seed=4, max_ticks=60,
                     settings={"failures": 5, "failure_phase": phase, "failure_tick": tick,
                               "mode": "ghost", "stall_ticks": 100})
    hook = injector(sim)
    res = sim.run()
    assert hook.fired_tick == fired and len(hook.robots) == 5
    assert res.summary["failed_robots"] == 5
    leaders = {i for i, c in enumerate(sim.swarm.robots) if c.setup.leader}
    assert leaders.isdisjoint(hook.robots.tolist())
    if phase == "tick":  # after tick 31 the even robots have arrived: only odd ones may fail
        assert all(i % 2 == 1 for i in hook.robots)


def test_failed_robots_never_move_after_failing():
    sim = Simulation("tiny", "dispersion", seed=0, max_ticks=150,
                     settings={"failures": 6, "failure_phase": "tick", "failure_tick": 20,
                               "mode": "ghost"})
    positions = {0: sim.positions.copy()}
    sim.run(on_tick=lambda s: positions.__setitem__(s.tick, s.positions.copy()))
    hook = injector(sim)
    failed, t0 = hook.robots, hook.fired_tick
    assert t0 == 20 and len(failed) == 6 and sim.failed.sum() == 6
    assert np.hypot(*(positions[t0][failed] - positions[t0 - 5][failed]).T).min() > 0.05
    # the drive brakes within the tick after the failure; from then on they are frozen
    frozen = positions[t0 + 1][failed]
    for t in range(t0 + 1, sim.tick + 1):
        assert np.array_equal(positions[t][failed], frozen), t
    others = np.setdiff1d(np.arange(sim.n), failed)
    assert np.hypot(*(positions[sim.tick][others] - positions[t0 + 1][others]).T).max() > 0.5
    assert (sim.messages["id"][failed] == -1).all()  # silent


def test_same_seed_same_failures():
    def failed(seed):
        sim = Simulation("tiny", "dispersion", seed=seed, max_ticks=15,
                         settings={"failures": 4, "failure_phase": "coverage"})
        sim.run()
        return injector(sim).robots.tolist()

    assert failed(1) == failed(1)
    assert failed(1) != failed(2)


@pytest.mark.parametrize("settings, key", [
    ({"failures": 41}, "failures"), ({"failures": -1}, "failures"),
    ({"failures": 2, "failure_phase": "lunch"}, "failure_phase"),
    ({"failures": 2, "failure_phase": "tick"}, "failure_tick"),
])
def test_bad_failure_settings_are_config_errors(settings, key):
    with pytest.raises(ConfigError, match=f"key '{key}'"):
        Simulation("tiny", "dispersion", settings=settings)
    with pytest.raises(ConfigError):
        FaultPlan(2, "lunch")


def test_cli_run_with_failures(tmp_path, capsys):
    out = tmp_path / "run"
    assert main(["run", "tiny", "--controller", "dispersion", "--max-ticks", "20", "--quiet",
                 "--set", "failures=3", "--set", "failure_phase=gradient",
                 "--out", str(out)]) == 0
    assert json.loads((out / "summary.json").read_text())["failed_robots"] == 3


# ----------------------------------------------------------------------------- reproduce
def _ids(runs):
    return [r.run_id for r in runs]


def _by(runs, key, value):
    return [r for r in runs if r.settings.get(key) == value]


def test_reproduce_judges_ggc_under_its_default_and_the_papers_rule_sets():
    both = rp.plan("all", rp.PAPER, reps=3)
    # one group at d_cover 8 and 10: the two rule sets make the same run, made once
    assert len(both["fig17"]) == 2 * 18 - 2 * 3
    assert rp.shared_runs("fig17", rp.PAPER, reps=3) == {"fig17": 2 * 3}
    assert {r.settings["ruleset"] for r in both["fig17"]} == {DEFAULT, "paper"}
    # the baselines of Figure 24 have no rule sets: run once, shown in both columns
    baselines = [r for r in both["fig24"] if r.controller != "ggc"]
    assert baselines and all("ruleset" not in r.settings for r in baselines)
    assert len(baselines) == len(set(_ids(baselines)))
    paper = rp.setup_with(rp.PAPER, extra={"ruleset": "paper"})
    assert paper == rp.setup_with(rp.PAPER, rulesets=["paper"])
    assert {r.settings["ruleset"] for r in rp.plan("fig17", paper)["fig17"]} == {"paper"}
    with pytest.raises(ConfigError, match="disagree"):
        rp.setup_with(rp.PAPER, rulesets=["yield"], extra={"ruleset": "paper"})
    with pytest.raises(ConfigError, match="--rulesets"):
        rp.setup_with(rp.PAPER, rulesets=["paper", "paper"])
    with pytest.raises(ConfigError, match="ruleset"):
        rp.plan("fig17", rp.setup_with(rp.PAPER, rulesets=["paper", "nosuch"]), reps=1)


def test_registry_expands_to_the_papers_runs():
    plan = rp.plan("all", rp.setup_with(rp.PAPER, rulesets=["paper"]), reps=3)
    assert list(plan) == ["fig14", *(f"fig{n}" for n in range(17, 25)), "table3"]
    fig17, fig18, fig21, fig23 = plan["fig17"], plan["fig18"], plan["fig21"], plan["fig23"]
    assert len(fig17) == 18 and {r.settings["d_cover"] for r in fig17} == {1, 2, 4, 6, 8, 10}
    assert {r.settings["groups"] for r in fig17} == {1} and {r.world for r in fig17} == {"K"}
    assert {r.seed for r in fig17} == {0, 1, 2}
    assert "robots" not in fig17[0].settings  # the world's default: 603 on K
    assert {r.settings["groups"] for r in fig18} == {3}
    assert len(fig21) == 18 and {r.settings["groups"] for r in fig21} == {1, 3, 4, 6, 8, 10}
    assert {r.settings["d_cover"] for r in fig21} == {6}
    # figures of total distance reuse the coverage figures' runs
    assert _ids(plan["fig19"]) == _ids(fig17) and _ids(plan["fig20"]) == _ids(fig18)
    assert _ids(plan["fig22"]) == _ids(fig21)
    # d_cover 6 / 3 groups is one set of runs across Figures 18, 21 and 23 (no failures)
    shared = _ids(_by(fig18, "d_cover", 6))
    assert shared == _ids(_by(fig21, "groups", 3)) == _ids([r for r in fig23
                                                            if not r.settings.get("failures")])
    # (a) the paper's gradient-phase failure (no_gradient), (b) coverage, (c) gradient phase
    # with dead bodies
    assert len(fig23) == 3 * (1 + 3 * 4)
    phases = {(r.settings.get("failures", 0), r.settings.get("failure_phase"),
               r.settings.get("failure_mode")) for r in fig23}
    assert phases == {(0, None, None)} | {(n, p, m) for n in (1, 5, 10, 20)
                                          for p, m in (("gradient", "no_gradient"),
                                                       ("coverage", None), ("gradient", None))}
    panels = failure_panels(rp.setup_with(rp.PAPER, rulesets=["paper"]).columns()[0])
    assert [p.title[:3] for p in panels] == ["(a)", "(b)", "(c)"]
    assert "no_gradient" in panels[0].title and "coverage" in panels[1].title
    dispersion = failure_panels(rp.PaperSetup(world="tiny", controller="dispersion"))
    assert len(dispersion) == 2  # declares no gradient-phase failure of its own
    assert not any("failure_mode" in c.settings for p in dispersion for c in p.conditions)
    fig24 = plan["fig24"]
    from swarmsim.controller import available_controllers

    expected = [c for c in rp.PAPER.comparison if c in available_controllers()]
    assert sorted({r.controller for r in fig24}) == sorted(expected)
    assert _ids([r for r in fig24 if r.controller == "ggc"]) == shared
    # Figure 14's random starts are runs of their own (Figure 18's start from formations)
    assert not set(_ids(plan["fig14"])) & set(_ids(fig18)) and len(plan["fig14"]) == 3


def test_registry_setup_is_easy_to_change():
    setup = rp.setup_with(rp.PAPER, world="house", robots=942, extra={"eps0": 0.02})
    runs = rp.figure_runs("fig21", setup, reps=2, max_ticks=500)
    assert len(runs) == 12
    assert all(r.world == "house" and r.settings["robots"] == 942 and
               r.settings["eps0"] == 0.02 and r.settings["max_ticks"] == 500 for r in runs)
    with pytest.raises(ConfigError, match="fig99"):
        rp.plan("fig99")
    with pytest.raises(ConfigError, match="--reps"):
        rp.plan("fig17", reps=0)


def test_reproduce_dry_run_lists_runs(capsys):
    assert main(["reproduce", "all", "--dry-run", "--reps", "2"]) == 0
    out = capsys.readouterr().out
    # two rule sets; one group at d_cover 8 and 10 is the same run under both
    assert "fig17: 20 runs" in out and "4 of them made once for more than one column" in out
    assert "total:" in out
    assert main(["reproduce", "fig17", "--dry-run", "--reps", "2", "--rulesets", "paper"]) == 0
    assert "fig17: 12 runs" in capsys.readouterr().out
    assert main(["reproduce", "fig21", "fig22", "--dry-run", "--reps", "2"]) == 0
    out = capsys.readouterr().out
    assert "fig21:" in out and "fig22:" in out and "fig17:" not in out


@pytest.mark.slow
def test_small_reproduction_writes_tables_plots_and_report(tmp_path):
    setup = rp.PaperSetup(world="tiny", controller="dispersion", d_cover_values=(4, 6),
                          failure_counts=(0, 3), comparison=("dispersion", "no-such-ctrl"))
    out = tmp_path / "repro"
    done = []
    result = rp.reproduce(["fig17", "fig19", "fig23", "fig24"], out, setup, reps=1,
                          max_ticks=25, workers=1, progress=False,
                          on_result=lambda run, status: done.append(status))
    # fig19 shares fig17's 2 runs; fig23: 2 phases x 1, and its run without failures is
    # fig17's d_cover 6 run (dispersion has no groups: fig23's groups 3 is left out);
    # fig24: 1 (shared)
    assert result.runs == 2 + 2 and done == ["done"] * 4
    for fig in ("fig17", "fig19", "fig23", "fig24"):
        for name in ("results.csv", "conditions.csv", f"{fig}.png", "REPORT.md"):
            assert (out / fig / name).is_file(), (fig, name)
    assert len(read_table(out / "fig17" / "results.csv")) == 2
    assert read_table(out / "fig23" / "conditions.csv")[0]["panel"].startswith("(a)")
    report = (out / "REPORT.md").read_text()
    assert "Figure 17" in report and "Figure 23" in report and "paper's claim" in report
    assert "Code: 0.1" in report and "(4 runs)" in report
    assert "Run time: 4 finished runs simulated for" in report
    assert "no-such-ctrl" in (out / "fig24" / "REPORT.md").read_text()
    again = rp.reproduce("fig17", out, setup, reps=1, max_ticks=25, workers=1, progress=False)
    assert again.sweep_line.startswith("2 runs: 2 done (0 run now")
    more = rp.describe_plan(rp.plan("fig17", setup, reps=2, max_ticks=25), out)
    assert "total: 4 distinct runs, 2 done, 2 to run: about" in more and "s a run)" in more


def test_world_may_be_given_only_as_a_grid_key(tmp_path):
    path = write_spec(tmp_path, 'controller = "dispersion"\n[grid]\nworld = ["tiny", "corridor"]\n')
    runs = load_spec(path).runs()
    assert [r.world for r in runs] == ["tiny", "corridor"]


@pytest.mark.parametrize("grid, message", [
    ('groups = [0, 2]', "key 'groups': must be positive, got 0 (in the run with groups=0"),
    ('mode = ["ghost", "bogus"]', "'bogus' (in the run with mode='bogus'"),
])
def test_a_bad_value_in_a_grid_is_refused_before_any_run(tmp_path, grid, message):
    path = write_spec(tmp_path, f'world = "tiny"\ncontroller = "dispersion"\n[grid]\n{grid}\n')
    with pytest.raises(ConfigError) as err:
        load_spec(path)
    assert message in str(err.value) and str(path) in str(err.value)


def test_reproduce_refuses_a_bad_setting_before_any_run():
    setup = rp.setup_with(rp.PAPER, extra={"eps": 0.02})
    with pytest.raises(ConfigError, match="key 'eps': unknown parameter"):
        rp.plan("fig17", setup, reps=1)
    with pytest.raises(ConfigError, match="unknown world 'nosuch'"):
        rp.plan("fig17", rp.setup_with(rp.PAPER, world="nosuch"), reps=1)


def test_dry_run_counts_failed_runs_apart_from_those_to_run(tmp_path):
    plan = rp.plan("fig17", rp.setup_with(rp.PAPER, world="tiny", robots=5), reps=1,
                   max_ticks=20)
    runs = plan["fig17"]
    failed = tmp_path / "runs" / runs[0].run_id
    failed.mkdir(parents=True)
    (failed / "error.txt").write_text("boom\n")
    text = rp.describe_plan(plan, tmp_path)
    assert f"0 done, 1 failed, {len(runs) - 1} to run" in text and "--retry-failed" in text
    again = rp.describe_plan(plan, tmp_path, retry_failed=True)
    assert f"0 done, 1 failed, {len(runs)} to run" in again


def test_set_robots_is_the_setup_robot_count_that_claims_judge():
    setup = rp.setup_with(rp.PAPER, extra={"robots": 40})
    assert setup.robots == 40 and "robots" not in setup.extra
    assert setup == rp.setup_with(rp.PAPER, robots=40)
    with pytest.raises(ConfigError, match="disagree"):
        rp.setup_with(rp.PAPER, robots=30, extra={"robots": 40})


def test_a_spec_that_is_not_utf8_is_one_clear_error(tmp_path):
    path = tmp_path / "spec.toml"
    path.write_bytes('world = "tiny"\n# r\xe9sum\xe9\n'.encode("latin-1"))
    with pytest.raises(ConfigError, match="not a UTF-8 text file"):
        load_spec(path)


@pytest.mark.slow
def test_a_report_over_several_invocations_names_every_code_version(tmp_path):
    """REPORT.md collects every figure reproduced in the folder: its code line counts all
    their runs (it counted only the last invocation's), and each section names its setup."""
    setup = rp.PaperSetup(world="tiny", controller="dispersion", d_cover_values=(4, 6),
                          failure_counts=(0, 3))
    out = tmp_path / "repro"
    rp.reproduce("fig17", out, setup, reps=1, max_ticks=25, workers=1, progress=False)
    for path in (out / "runs").glob("*/summary.json"):  # as if made by older code
        summary = json.loads(path.read_text())
        path.write_text(json.dumps({**summary, "code_version": "0.0.9+gOLD"}))
    rp.reproduce("fig23", out, rp.setup_with(setup, robots=30), reps=1, max_ticks=25,
                 workers=1, progress=False)
    report = (out / "REPORT.md").read_text()
    assert "Warning: these runs were made by 2 code versions" in report
    assert "0.0.9+gOLD (2 runs)" in report
    fig17 = (out / "fig17" / "REPORT.md").read_text()
    assert "robots world default" in fig17 and "Code: 0.1" in fig17  # as when it was made
    assert "robots 30" in (out / "fig23" / "REPORT.md").read_text()


@pytest.mark.slow
def test_a_second_spec_in_the_same_folder_says_the_first_ones_runs_are_not_in_its_table(
        tmp_path):
    out = tmp_path / "out"
    first = spec_from_dict({**TINY, "grid": {"robots": [20, 21]}}).runs()
    second = spec_from_dict({**TINY, "grid": {"robots": [21, 22]}}).runs()
    assert "other runs" not in run_sweep(first, out, workers=1, progress=False).line()
    line = run_sweep(second, out, workers=1, progress=False).line()
    assert "note: 1 other runs in the runs folder" in line
    assert len(read_table(out / "results.csv")) == 2


def test_an_interrupt_inside_compiled_code_is_not_recorded_as_a_failed_run(monkeypatch):
    """Ctrl-C that numba wraps in a SystemError stops the sweep; the run is not 'failed'."""
    from swarmsim.experiments.runner import execute_run

    def interrupted(*_args, **_kwargs):
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt as exc:
            raise SystemError("returned a result with an exception set") from exc

    monkeypatch.setattr(Simulation, "step", interrupted)
    run = spec_from_dict({"world": "tiny", "controller": "dispersion"}).runs()[0]
    with pytest.raises(KeyboardInterrupt):
        execute_run(run)


@pytest.mark.slow
def test_a_reproduction_shows_both_rule_sets_side_by_side(tmp_path):
    setup = rp.PaperSetup(world="tiny", d_cover_values=(6,), groups=1)
    out = tmp_path / "repro"
    result = rp.reproduce("fig17", out, setup, reps=1, max_ticks=30, workers=1, progress=False)
    assert result.runs == 2 and result.failed == 0
    rows = read_table(out / "fig17" / "results.csv")
    assert sorted(r["ruleset"] for r in rows) == sorted(["paper", DEFAULT])
    conditions = read_table(out / "fig17" / "conditions.csv")
    assert sorted(r["ruleset"] for r in conditions) == sorted(["paper", DEFAULT])
    claims = read_table(out / "fig17" / "claims.csv")
    assert {r["ruleset"] for r in claims} == {"paper", DEFAULT}
    section = (out / "fig17" / "REPORT.md").read_text()
    assert f"### Column `{DEFAULT}`" in section and "### Column `paper`" in section
    assert (f"| paper's claim | test (where) | {DEFAULT}: measured | verdict | paper: measured "
            "| verdict |") in section
    report = (out / "REPORT.md").read_text()
    assert "## Claims" in report and f"| {DEFAULT}: verdict | paper: verdict |" in report
    assert f"Rule sets judged side by side: {DEFAULT}, paper." in report
    import imageio.v3 as iio

    assert iio.imread(out / "fig17" / "fig17.png").shape[0] >= 2 * 450  # one row per rule set


@pytest.mark.slow
def test_a_run_the_same_under_both_rule_sets_is_made_once_and_shown_in_both(tmp_path):
    """One group at d_cover 8 (no holes filled there; the default rule set's other rules act
    only between groups): the paper's run, made once, reported in both columns. At d_cover 6
    the rule sets differ: two runs."""
    setup = rp.PaperSetup(world="tiny", d_cover_values=(6, 8), groups=1)
    out = tmp_path / "repro"
    result = rp.reproduce("fig17", out, setup, reps=1, max_ticks=30, workers=1, progress=False)
    assert result.runs == 3 and result.failed == 0
    assert len(list((out / "runs").glob("*/summary.json"))) == 3
    made = read_table(out / "results.csv")  # each run once, as the settings that name it
    assert sorted((r["ruleset"], r["d_cover"]) for r in made) == sorted([
        ("paper", "6"), ("paper", "8"), (DEFAULT, "6")])
    rows = read_table(out / "fig17" / "results.csv")
    by = {(r["ruleset"], r["d_cover"]): r for r in rows}
    assert sorted(by) == sorted([("paper", "6"), ("paper", "8"), (DEFAULT, "6"), (DEFAULT, "8")])
    assert by[("paper", "8")]["run_id"] == by[(DEFAULT, "8")]["run_id"]
    assert by[("paper", "6")]["run_id"] != by[(DEFAULT, "6")]["run_id"]
    assert by[("paper", "8")]["coverage"] == by[(DEFAULT, "8")]["coverage"] != ""
    shared = out / "runs" / by[("paper", "8")]["run_id"] / "run.json"
    assert json.loads(shared.read_text())["settings"]["ruleset"] == "paper"
    conditions = read_table(out / "fig17" / "conditions.csv")
    assert sorted((r["ruleset"], r["d_cover"], r["done"]) for r in conditions) == sorted([
        ("paper", "6", "1"), ("paper", "8", "1"), (DEFAULT, "6", "1"), (DEFAULT, "8", "1")])
    claims_rows = read_table(out / "fig17" / "claims.csv")
    assert {r["ruleset"] for r in claims_rows} == {"paper", DEFAULT}
    section = (out / "fig17" / "REPORT.md").read_text()
    assert section.count("Runs: 2 of 2 done, 0 failed") == 2  # each column counts its own
    # the plot's curves: each column's d_cover 8 condition has the run's curve
    contexts = [rp.Context(Sweep([], out, runs_dir=out / "runs"), col, 1, 30, rp.get_figure)
                for col in setup.columns()]
    eights = [next(s for s in ctx.stats("fig17") if s.cond.value == 8) for ctx in contexts]
    assert [s.done for s in eights] == [1, 1]
    assert all(s.bands["coverage"] is not None for s in eights)
    assert eights[0].curves["coverage"][0][1].tolist() == \
        eights[1].curves["coverage"][0][1].tolist()
    plan = rp.describe_plan(rp.plan("fig17", setup, reps=1, max_ticks=30), out,
                            shared=rp.shared_runs("fig17", setup, reps=1, max_ticks=30))
    assert "fig17: 3 runs (3 done)" in plan and "1 of them made once" in plan


def test_a_ghost_column_runs_the_first_rule_set_with_point_robots():
    setup = rp.setup_with(rp.PAPER, ghost=True)
    names = [c.column_name for c in setup.columns()]
    assert names == [DEFAULT, "paper", f"{DEFAULT} (ghost)"]
    ghost_runs = [r for r in rp.plan("fig21", setup, reps=1)["fig21"]
                  if r.params().get("mode") == "ghost"]
    assert len(ghost_runs) == len(rp.PAPER.group_values)
    assert all(r.params().get("ruleset", DEFAULT) == DEFAULT for r in ghost_runs)
    with pytest.raises(ConfigError, match="key '--ghost': adds a column of point robots"):
        rp.setup_with(rp.PAPER, extra={"mode": "rigid"}, ghost=True)
