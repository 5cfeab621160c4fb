"""The tick loop: determinism, order independence, stopping rules and bad input."""

import dataclasses
import gc
import json
import weakref
from pathlib import Path

import numpy as np
import pytest
import shapely

from controllers.ggc.statuses import ARRIVE
from swarmsim import ConfigError, Simulation
from swarmsim.cli import main
from swarmsim.controller import Action, Perception, RobotSetup
from swarmsim.engine.costs import WORK_FIELDS
from swarmsim.engine.hooks import Hook
from swarmsim.engine.sim import TIMING_FIELDS
from tests.conftest import square_world


def run(seed=3, **kw):
    kw.setdefault("max_ticks", 250)
    sim = Simulation(square_world(), controller="dispersion", robots=30, seed=seed,
                     settings=kw.pop("settings", {}), **kw)
    res = sim.run()
    summary = {k: v for k, v in res.summary.items() if k not in TIMING_FIELDS}
    return summary, res.timeseries, sim


@pytest.mark.slow
def test_same_seed_same_run_bit_for_bit():
    a, ta, sa = run()
    b, tb, sb = run()
    assert a == b and ta == tb
    assert np.array_equal(sa.positions, sb.positions)
    assert a["total_distance"] > 0


@pytest.mark.slow
def test_different_seed_different_run():
    a, _, _ = run(seed=3)
    b, _, _ = run(seed=4)
    assert a != b


@pytest.mark.slow
def test_shuffled_decision_order_changes_nothing():
    a, ta, sa = run()
    b, tb, sb = run(settings={"decide_order": "shuffled"})
    assert a == b and ta == tb
    assert np.array_equal(sa.positions, sb.positions)


def test_failed_robots_are_counted_as_failed_in_the_status_counts():
    sim = Simulation("tiny", seed=0, max_ticks=100,
                     settings={"failures": 3, "failure_phase": "tick", "failure_tick": 50})
    counts = sim.run().summary["status_counts"]
    assert counts["Failed"] == 3 and sum(counts.values()) == 40


@pytest.mark.slow
def test_shuffled_decision_order_changes_nothing_with_noise_and_message_loss_either():
    """Noise and message loss are drawn in index order, whatever order controllers are
    called in (they were drawn in the calling order: a shuffled run differed from tick 2)."""
    noisy = {"distance_noise": 0.05, "bearing_noise": 0.05, "message_loss": 0.1}
    a, ta, sa = run(settings=noisy)
    b, tb, sb = run(settings={**noisy, "decide_order": "shuffled"})
    assert a == b and ta == tb
    assert np.array_equal(sa.positions, sb.positions)


@pytest.mark.slow
def test_deciding_in_chunks_changes_nothing(monkeypatch):
    """Sensing and deciding a few awake robots at a time (to bound memory) is the same run,
    with sensing noise and message loss drawn in pieces."""
    import swarmsim.engine.sim as sim_module

    def fingerprint():
        sim = Simulation(square_world(), controller="ggc", robots=60, groups=2, seed=5,
                         settings={"distance_noise": 0.05, "bearing_noise": 0.05,
                                   "message_loss": 0.1})
        for _ in range(300):
            sim.step()
        return sim.positions.copy(), sim.messages.copy(), sim.metrics.rows[-1]

    monkeypatch.setattr(sim_module, "DECIDE_CHUNK", 10**9)
    whole = fingerprint()
    monkeypatch.setattr(sim_module, "DECIDE_CHUNK", 7)
    chunked = fingerprint()
    assert np.array_equal(whole[0], chunked[0]) and np.array_equal(whole[1], chunked[1])
    assert whole[2] == chunked[2] and whole[2]["awake"] > 7  # several chunks were decided


@pytest.mark.slow
def test_sleeping_changes_nothing_but_saves_work():
    """Robots that sleep must act exactly as if they had been asked every tick."""
    def settle(allow_sleep):
        sim = Simulation(square_world(size=12, spawn=20), controller="dispersion", robots=40,
                         seed=2, max_ticks=1500, settings={"d_cover": 3.0, "allow_sleep":
                                                           allow_sleep, "stop_on_complete": False})
        res = sim.run()
        return {k: v for k, v in res.summary.items()
                if k not in TIMING_FIELDS + WORK_FIELDS}, res.timeseries, res.summary

    (a, ta, sa), (b, tb, sb) = settle(True), settle(False)
    assert a == b
    assert sa["decisions"] < sb["decisions"]  # sleeping saved decisions
    assert [r["coverage"] for r in ta] == [r["coverage"] for r in tb]
    assert min(r["awake"] for r in ta[5:]) < 20  # robots really slept
    assert min(r["awake"] for r in tb[5:]) == 40


@pytest.mark.slow
def test_sleeping_changes_nothing_when_robots_fail_either():
    """A robot that fails falls silent: that wakes its sleeping neighbours as any changed
    broadcast does (it did not, and failure runs depended on allow_sleep)."""
    def run(allow_sleep):
        sim = Simulation("tiny", seed=0, max_ticks=600,
                         settings={"allow_sleep": allow_sleep, "failures": 5,
                                   "failure_phase": "tick", "failure_tick": 300})
        res = sim.run()
        assert res.summary["failed_robots"] == 5
        fewest_awake = min(r["awake"] for r in res.timeseries[1:])
        return sim.positions, [r["coverage"] for r in res.timeseries], fewest_awake

    (pa, ca, fewest), (pb, cb, _) = run(True), run(False)
    assert np.array_equal(pa, pb) and ca == cb
    assert fewest < len(pa) - 5  # robots really slept


@pytest.mark.slow
def test_a_run_freezes_old_objects_only_while_it_runs_and_leaves_no_garbage():
    seen = []
    sim = Simulation(square_world(), controller="dispersion", robots=10, seed=1, max_ticks=20)
    sim.run(on_tick=lambda s: seen.append(gc.get_freeze_count()))
    assert min(seen) > 0  # the objects from before the run sat out full collections
    assert gc.get_freeze_count() == 0  # and were handed back afterwards
    gone = weakref.ref(sim.swarm)
    del sim
    gc.collect()
    assert gone() is None  # a finished run's robots are collected as usual


def test_a_run_leaves_the_callers_own_frozen_objects_alone():
    gc.freeze()
    try:
        before = gc.get_freeze_count()
        sim = Simulation(square_world(), controller="dispersion", robots=10, seed=1,
                         max_ticks=20)
        seen = []
        sim.run(on_tick=lambda s: seen.append(gc.get_freeze_count()))
        assert max(seen) <= before  # the run froze nothing more (the sim's objects stay out)
        assert gc.get_freeze_count() > before / 2  # and did not unfreeze the caller's
    finally:
        gc.unfreeze()


def test_stops_on_stall_and_reports_it():
    sim = Simulation(square_world(beacon=False), controller="dispersion", robots=5, seed=1,
                     settings={"stall_ticks": 30, "spawn_spacing": 4.0})
    res = sim.run()
    assert res.summary["stop_reason"] == "stalled"
    assert res.summary["ticks"] < 200


@dataclasses.dataclass(frozen=True)
class NoParams:
    """No parameters."""


class StandStill:
    """A per-robot controller whose robots stand still and say so (the same broadcast every
    tick: the broadcasts change on tick 1 only)."""

    name = "stand-still"
    Params = NoParams
    STATUSES = ("Standing",)

    @classmethod
    def sensing_range(cls, params) -> float:
        return 2.0

    def __init__(self, setup: RobotSetup, params, rng: np.random.Generator):
        pass

    def step(self, perception: Perception) -> Action:
        return Action((0.0, 0.0), {"status": 0, "moving": False})


@pytest.mark.parametrize("stall_ticks, plateau_ticks, reason", [
    (10, 11, "stalled"), (12, 11, "plateau"), (12, 12, "max_ticks")])
def test_stop_rules_are_asked_in_their_order(stall_ticks, plateau_ticks, reason):
    """Robots standing still, off the target: stalled after stall_ticks from tick 1, plateau
    after plateau_ticks from tick 0, max_ticks at 11. Two or three rules say stop at tick 11:
    the first asked (stalled, plateau, max_ticks) names the reason."""
    sim = Simulation(square_world(beacon=False), controller=StandStill, robots=5,
                     max_ticks=11,
                     settings={"stall_ticks": stall_ticks, "plateau_ticks": plateau_ticks})
    s = sim.run().summary
    assert (s["stop_reason"], s["ticks"]) == (reason, 11)


@pytest.mark.parametrize("plateau_delta, reason, ticks", [(0.9, "plateau", 100),
                                                          (0.002, "max_ticks", 250)])
def test_stops_on_plateau_when_coverage_stops_rising_by_plateau_delta(plateau_delta, reason,
                                                                       ticks):
    # coverage rises by ~0.02 every 10 ticks from tick ~90: never by 0.9 at once
    s, series, _ = run(settings={"plateau_ticks": 100, "plateau_delta": plateau_delta})
    assert (s["stop_reason"], s["ticks"]) == (reason, ticks)
    assert 0 < s["coverage"] < 0.9 and series[0]["coverage"] == 0.0


class EnoughAt(Hook):
    """A user's stop rule: "enough" once coverage reaches a share, counting its calls."""

    def __init__(self, share: float):
        self.share = share
        self.calls = {"start": 0, "pre_step": 0, "post_step": 0}
        self.seen_coverage: list[float] = []

    def start(self, run) -> None:
        self.calls["start"] += 1

    def pre_step(self, run) -> None:
        self.calls["pre_step"] += 1

    def post_step(self, run) -> None:
        self.calls["post_step"] += 1
        self.seen_coverage.append(run.metrics.coverage)  # after the metrics: this tick's

    def is_finished(self, run) -> str | None:
        return "enough" if run.metrics.coverage >= self.share else None


def test_a_users_hook_can_stop_a_run():
    def make() -> Simulation:
        return Simulation(square_world(), controller="dispersion", robots=30, seed=3,
                          max_ticks=400)

    plain = make()
    series = plain.run().timeseries
    share = series[len(series) // 2]["coverage"]  # reached at some tick of the plain run
    reached = min(row["tick"] for row in series if row["coverage"] >= share)
    sim = make()
    hook = EnoughAt(share)
    sim.hooks.append(hook)
    res = sim.run()
    tick = res.summary["ticks"]
    assert res.summary["stop_reason"] == "enough" and 0 < tick <= reached < plain.tick
    assert hook.calls == {"start": 0, "pre_step": tick, "post_step": tick}  # added after start
    assert hook.seen_coverage[-1] >= share > max(hook.seen_coverage[:-1])
    assert res.timeseries[-1]["tick"] == tick  # the last row is the tick the hook stopped


@pytest.mark.slow
def test_completion_tick_when_target_covered():
    sim = Simulation(square_world(size=12, spawn=20), controller="dispersion", robots=40,
                     seed=2, max_ticks=3000, settings={"d_cover": 3.0})
    res = sim.run()
    s = res.summary
    assert s["stop_reason"] == "complete", s
    assert s["completion_tick"] == s["ticks"] and s["coverage"] >= 0.99


def test_the_summary_carries_the_travel_floor_and_the_completion_ticks_ratio_to_it():
    """The 12 x 12 target's far edge is 22 units above the spawn square's top (y -10): 220
    ticks at v_max 0.1, 440 at 0.05; the ratio is the completion tick over it, and null for a
    run that did not complete."""
    sim = Simulation(square_world(size=12, spawn=20), controller="dispersion", robots=40,
                     seed=2, max_ticks=3000, settings={"d_cover": 3.0})
    s = sim.run().summary
    assert s["stop_reason"] == "complete", s
    assert s["travel_floor_ticks"] == pytest.approx(220.0)
    assert s["floor_ratio"] == round(s["completion_tick"] / 220.0, 3) and s["floor_ratio"] > 1
    short = Simulation(square_world(size=12, spawn=20), controller="dispersion", robots=40,
                       seed=2, max_ticks=20, settings={"d_cover": 3.0, "v_max": 0.05})
    s = short.run().summary
    assert s["completion_tick"] is None and s["floor_ratio"] is None
    assert s["travel_floor_ticks"] == pytest.approx(440.0)


@pytest.mark.parametrize("kw,key", [
    ({"settings": {"no_such": 1}}, "no_such"),
    ({"settings": {"v_max": "fast"}}, "v_max"),
    ({"settings": {"eps0": 2.0}}, "eps0"),
    ({"groups": 50}, "groups"),
    ({"robots": 100000}, "robots"),
    ({"settings": {"d_cover": -1.0}}, "d_cover"),
    ({"settings": {"start": "anywhere"}}, "start"),
    ({"settings": {"radius": -1.0}}, "radius"),
    ({"settings": {"deadband": -1.0}}, "deadband"),
    ({"settings": {"plateau_delta": -1.0}}, "plateau_delta"),
    ({"settings": {"failures": 3, "failure_tick": 50}}, "failure_tick"),  # phase not 'tick'
    ({"settings": {"v": 0.2}}, "v"),  # faster than v_max caps it
])
def test_bad_parameters_are_named(kw, key):
    """Every bad value is reported as "key 'NAME'", whichever layer validates it."""
    kw.setdefault("robots", 30)
    with pytest.raises(ConfigError, match=f"key '{key}'"):
        Simulation(square_world(), controller="dispersion", **kw)


@pytest.mark.parametrize("settings, key", [
    ({"boundary_probe": 3.0}, "boundary_probe"),  # beyond the probe range: crashed mid-run
    ({"boundary_probe": -2.0}, "boundary_probe"),  # probing the wrong way
    ({"probe_distance": 2.5}, "probe_distance"),
    ({"h_max": 200}, "h_max"),  # broadcast as int8: crashed at tick 0
])
def test_bad_ggc_parameters_are_named_before_the_run(settings, key):
    with pytest.raises(ConfigError, match=f"key '{key}'"):
        Simulation(square_world(), controller="ggc", robots=30, settings=settings)


def test_a_longer_ggc_probe_is_accepted_with_a_longer_probe_range():
    sim = Simulation(square_world(), controller="ggc", robots=30,
                     settings={"probe_distance": 2.5, "probe_range": 3.0}, max_ticks=1)
    assert sim.params.probe_distance == 2.5 and sim.floor.probe_range == 3.0


def test_a_speed_above_v_max_is_accepted_with_v_max_and_a_lower_v_max_caps_v():
    fast = Simulation(square_world(), controller="dispersion", robots=30,
                      settings={"v": 0.2, "v_max": 0.2})
    slow = Simulation(square_world(), controller="dispersion", robots=30,
                      settings={"v_max": 0.05})
    assert fast.params.v == 0.2 and slow.config.v_max == 0.05


def test_unknown_controller_is_named():
    with pytest.raises(ConfigError, match="no_such_ctrl"):
        Simulation(square_world(), controller="no_such_ctrl", robots=5)
    with pytest.raises(ConfigError, match="no.module"):
        Simulation(square_world(), controller="no.module:Thing", robots=5)


@pytest.mark.slow
def test_cli_run_writes_outputs(tmp_path, capsys):
    out = tmp_path / "run"
    code = main(["run", "tiny", "--controller", "dispersion", "--max-ticks", "120", "--seed",
                 "2", "--out", str(out), "--quiet"])
    assert code == 0
    summary = json.loads((out / "summary.json").read_text())
    for key in ("world", "controller", "robots", "groups", "d_cover", "seed", "ticks",
                "coverage", "completion_tick", "total_distance", "robots_on_target",
                "collisions_robot_robot", "collisions_robot_wall", "max_overlap",
                "stop_reason", *TIMING_FIELDS):
        assert key in summary
    assert summary["ticks"] == 120 and summary["world"] == "tiny"
    lines = (out / "timeseries.csv").read_text().splitlines()
    assert lines[0].startswith("tick,coverage,total_distance")
    assert len(lines) == 1 + 13
    assert (out / "coverage.png").stat().st_size > 1000
    assert "coverage" in capsys.readouterr().out


@pytest.mark.parametrize("argv,needle", [
    (["run", "no-such-world"], "no-such-world"),
    (["run", "tiny", "--controller", "dispersion", "--set", "bogus=3"], "bogus"),
    (["run", "tiny", "--set", "novalue"], "KEY=VALUE"),
    (["run", "/no/such/file.toml"], "/no/such/file.toml"),
    (["run", "tiny", "--controller", "dispersion", "--robots", "-4"], "robots"),
    (["run", "tiny", "--seed", "-1"], "key 'seed': must be a non-negative integer, got -1"),
    (["run", "tiny", "--snapshot", "x.png", "--width", "10"], "key '--width'"),
    (["run", "tiny", "--video", "x.mp4", "--width", "321"], "got 321"),
    (["run", "tiny", "--snapshot", "x.jpg"], "key '--snapshot': must be a .png file"),
])
def test_cli_bad_input_is_one_clear_line(argv, needle, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("swarmsim: error:") and needle in err
    assert "Traceback" not in err


@pytest.mark.parametrize("option", ["--out", "--snapshot", "--video"])
def test_an_output_path_that_cannot_be_written_is_refused_before_the_run(option, tmp_path,
                                                                        capsys, monkeypatch):
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    path = blocker / ("run" if option == "--out" else "x.mp4" if option == "--video" else "x.png")
    ticks = []
    step = Simulation.step
    monkeypatch.setattr(Simulation, "step", lambda self: (ticks.append(1), step(self)))
    code = main(["run", "tiny", "--max-ticks", "50", "--quiet", option, str(path)])
    err = capsys.readouterr().err.strip()
    assert code == 2 and f"key '{option}': cannot create the folder" in err
    assert "Traceback" not in err and ticks == []  # refused before the first tick


def test_python_api_example_runs():
    from swarmsim import load_world

    sim = Simulation(load_world("tiny"), controller="dispersion", seed=1, max_ticks=50)
    res = sim.run()
    assert res.summary["ticks"] == 50 and res.timeseries[-1]["tick"] == 50


def test_a_formation_that_does_not_fit_is_an_error_not_robots_behind_walls():
    # A formation of n robots at spacing 1 has radius ~sqrt(0.866 n / pi): 23.5 for 2,000,
    # 16.6 for 1,000. Its centre lies in the 20 x 20 spawn square; such robots used to stand
    # behind the walls (10 units beyond the spawn) or on the target (2 units above it).
    with pytest.raises(ConfigError, match=r"key 'robots'.*2000 robots.*behind the arena walls"):
        Simulation(square_world(margin=10.0), controller="ggc", robots=2000, groups=1)
    with pytest.raises(ConfigError, match=r"\d+ on the target"):
        Simulation(square_world(gap=2.0, margin=40.0), controller="ggc", robots=1000, groups=1)
    world = square_world(margin=10.0)
    sim = Simulation(world, controller="ggc", robots=600, groups=1)  # spills onto open floor
    x0, y0, x1, y1 = world.arena
    pos = sim.snapshot().positions
    assert ((pos > (x0, y0)) & (pos < (x1, y1))).all()
    assert not shapely.contains_xy(world.target, pos[:, 0], pos[:, 1]).any()


def test_a_huge_robot_count_is_refused_clearly_and_cheaply():
    """50,000 robots (MAX_ROBOTS) on K: more than the floor off the target can hold at
    spacing 1, so refused from the areas alone (Simulation.check builds no layout). Checking
    that formations keep apart once measured every pair of them (33 GB at 100,000)."""
    with pytest.raises(ConfigError, match=r"key 'robots'.*50000 robots cannot start in "
                                          r"formation"):
        Simulation.check("K", robots=50_000)


def test_formations_that_overlap_are_refused_naming_the_groups():
    with pytest.raises(ConfigError, match=r"key 'groups'.*10 formations of 500 robots do not "
                                          r"fit apart"):
        Simulation("K", robots=5000, groups=10)


def test_the_python_api_and_the_command_line_run_the_same_controller_by_default():
    from swarmsim.cli import build_parser

    cli_default = build_parser().parse_args(["run", "tiny"]).controller
    sim = Simulation("tiny", controller=cli_default, max_ticks=1)
    assert sim.controller_name == Simulation("tiny", max_ticks=1).controller_name == "ggc"
    assert type(sim.swarm).__module__.startswith("controllers.ggc")


def test_a_world_file_may_name_the_controller_and_the_start(tmp_path):
    tiny = (Path(__file__).parents[2] / "worlds" / "tiny.toml").read_text()
    assert tiny.rstrip().splitlines()[-4] == "[defaults]"  # the last table: append to it
    path = tmp_path / "w.toml"
    path.write_text(tiny + 'controller = "dispersion"\nstart = "random"\n')
    sim = Simulation(str(path), max_ticks=1)
    assert sim.controller_name == "dispersion" and sim.config.start == "random"
    assert Simulation(str(path), controller="ggc", max_ticks=1).controller_name == "ggc"


def test_progress_bar_shows_ticks_and_coverage_but_no_share_of_max_ticks_or_eta():
    from swarmsim.engine.sim import _progress_bar

    bar = _progress_bar(100_000, enabled=True)
    try:
        bar.update(3_250)
        bar.set_postfix_str("coverage  37.1%", refresh=False)
        text = str(bar)
    finally:
        bar.close()
    assert text.startswith("tick 3250 of at most 100000 [")
    assert "coverage  37.1%" in text
    assert "%|" not in text and "<" not in text  # no bar, no time left: runs stop early


@pytest.mark.slow
def test_wake_near_wakes_exactly_the_sleepers_in_range():
    """wakes.wake_near, on a run's own sleepers, looks only in the cells round a changed
    robot: it must wake the same robots as checking every changed robot against every
    sleeper."""
    from swarmsim.engine import wakes
    from tests.conftest import small_world

    sim = Simulation(small_world(40, 30), controller="ggc", robots=120, groups=3, seed=1,
                     max_ticks=2000)
    rng = np.random.default_rng(0)
    checked = 0
    for tick in range(900):
        sim.step()
        if tick % 50 or not sim.asleep.any():
            continue
        changed = np.flatnonzero(rng.random(sim.n) < 0.3)
        by_message = rng.random(sim.n) < 0.5
        margin = 2 * sim.config.v_max + sim.config.wake_eps
        d = np.hypot(*(sim.positions[:, None, :] - sim.positions[None, changed, :]).T).T
        reached = (d <= sim.wake_range[:, None] + margin) & (
            sim.wake_on_motion[:, None] | by_message[changed][None, :])
        expected = sim.asleep & ~reached.any(axis=1)
        before = sim.asleep.copy()
        wakes.wake_near(sim.positions, sim.asleep, sim.wake_range, sim.wake_on_motion,
                        by_message, changed, margin)
        assert np.array_equal(sim.asleep, expected)
        checked += int((before & ~expected).sum())
        sim.asleep[:] = before  # leave the run as it was
    assert checked > 50  # sleepers were woken, with their different wake ranges


@pytest.mark.slow
def test_floor_sensors_follow_every_robot_that_moved():
    """The floor sensors are asked again only for robots that moved: they must read what
    asking every robot reads, every tick."""
    sim = Simulation(square_world(size=12, spawn=20), controller="dispersion", robots=40,
                     seed=2, max_ticks=400, settings={"d_cover": 3.0})
    flips = 0
    for _ in range(400):
        before = sim.on_target.copy()
        sim.step()
        assert np.array_equal(sim.on_target, sim.floor.on_target(sim.positions))
        flips += int((before != sim.on_target).sum())
    assert flips > 10  # robots crossed the target's edge


@pytest.mark.slow
def test_the_summary_gives_the_distance_per_placed_robot():
    """robots_placed: robots in a settled status (GGC: Arrive) on the target at the end."""
    sim = Simulation("tiny", seed=1, max_ticks=1500)
    sim.run()
    s = sim.summary()
    statuses = sim.swarm.state["status"]
    placed = int(((statuses == ARRIVE) & sim.on_target).sum())
    assert placed > 0 and s["robots_placed"] == placed
    assert s["distance_per_placed_robot"] == pytest.approx(s["total_distance"] / placed, abs=1e-3)
