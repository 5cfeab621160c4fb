"""The paper's comparison algorithms (issue 7): each makes real progress on a small world,
keeps robots apart, is deterministic, and declares itself properly. The checks of a
controller's declarations and of sleep run for every registered controller
(``available_controllers()``): a new one is checked without editing a list.

World "tiny": a 36 x 24 rectangle 15 units above a 36 x 8 spawn band, 40 robots; coverage
starts at 0 (no robot can reach the target from the spawn band). Thresholds are well below
what each controller reaches by the tick limit (seed 1, measured), and far above 0.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from swarmsim import Simulation
from swarmsim.controller import (
    Action,
    Perception,
    available_controllers,
    get_controller,
    run_message_fields,
)
from swarmsim.engine.controller_info import describe
from swarmsim.engine.sim import TIMING_FIELDS

CONTROLLERS = available_controllers()

# controller -> (ticks, coverage it must reach by then). Measured on seed 1 (tick: coverage):
# cvt 390: 0.99 (complete); meanshift 379: 0.99 (complete); dash 1250: 0.88;
# kilobot 3760: 0.75; fcdfs 2400: 0.75; dispersion 940: 0.99 (complete).
PROGRESS = {
    "dispersion": (1000, 0.9),
    "cvt": (600, 0.9),
    "meanshift": (600, 0.9),
    "dash": (1300, 0.6),
    "kilobot": (4000, 0.5),
    "fcdfs": (2500, 0.5),
}
BASELINES = tuple(PROGRESS)
"""The baselines: the paper's comparison algorithms and dispersion."""
PROGRESS_ELSEWHERE = {"ggc": "tests/controllers/ggc/test_ggc.py"}
"""Registered controllers whose progress is checked in another file."""
MAX_OVERLAP = 0.05


def run(name: str, ticks: int, seed: int = 1, **settings):
    sim = Simulation("tiny", controller=name, seed=seed, max_ticks=ticks,
                     settings=settings or None)
    return sim, sim.run()


@pytest.mark.parametrize("name", CONTROLLERS)
def test_registered_and_declared(name):
    cls = get_controller(name)
    params = cls.Params()
    assert dataclasses.is_dataclass(params) and params.__dataclass_params__.frozen
    assert cls.sensing_range(params) > 0
    assert cls.__doc__ and cls.__doc__.strip().splitlines()[0]  # `swarmsim controllers`' line
    assert len(cls.STATUSES) >= 2
    describe(cls, name).message_dtype(groups=1, scattered=False)  # its declarations hold
    if name in BASELINES:
        module = __import__(cls.__module__, fromlist=["_"])
        assert "Sensing:" in module.__doc__
    for f in dataclasses.fields(params):  # every parameter is documented
        assert f"{f.name}:" in cls.Params.__doc__, f"{name}: {f.name} undocumented"


@pytest.mark.parametrize("name", CONTROLLERS)
def test_every_controller_has_a_progress_check(name):
    assert name in PROGRESS or name in PROGRESS_ELSEWHERE, (
        f"{name}: add its measured (ticks, coverage) on 'tiny' to PROGRESS")


@pytest.mark.parametrize("name,bad", [
    ("kilobot", {"d_cover": -1.0}), ("kilobot", {"orbit": 0}),
    ("cvt", {"cell_radius": 7.0}), ("cvt", {"gain": 0.0}),
    ("meanshift", {"inertia": 1.0}), ("meanshift", {"r_sense": 11.0}),
    ("dash", {"s_start": 7.0}), ("dash", {"probe_distance": 3.0}),
    ("fcdfs", {"turn": 2}), ("fcdfs", {"cell": 7.0}),
])
def test_params_are_validated(name, bad):
    with pytest.raises(ValueError, match=next(iter(bad))):  # the message names the parameter
        get_controller(name).Params(**bad)


@pytest.mark.slow
@pytest.mark.parametrize("name", BASELINES)
def test_makes_progress_without_overlap(name):
    ticks, threshold = PROGRESS[name]
    _, res = run(name, ticks)
    s = res.summary
    assert res.timeseries[0]["coverage"] == 0.0
    assert s["coverage"] >= threshold, (name, s["coverage"], s["ticks"])
    assert s["max_overlap"] <= MAX_OVERLAP, (name, s["max_overlap"])
    assert s["robots_on_target"] >= 10


@pytest.mark.slow
@pytest.mark.parametrize("name", BASELINES)
def test_same_seed_same_run(name):
    ticks = 400 if name in ("kilobot", "fcdfs") else 250
    (_, a), (_, b) = run(name, ticks, seed=5), run(name, ticks, seed=5)
    sa = {k: v for k, v in a.summary.items() if k not in TIMING_FIELDS}
    sb = {k: v for k, v in b.summary.items() if k not in TIMING_FIELDS}
    assert sa == sb
    assert a.timeseries == b.timeseries
    assert sa["total_distance"] > 0


@pytest.mark.slow
def test_robots_sleep_once_settled():
    """Idle robots sleep, so big runs stay cheap (dash settles completely on tiny)."""
    _, res = run("dash", 4000, stop_on_complete=False)
    assert res.summary["stop_reason"] == "stalled"
    assert res.timeseries[-1]["awake"] == 0


@pytest.mark.slow
def test_formation_controllers_wait_in_formation():
    """Kilobot and FCDFS start as a formation that travels first; most robots sleep."""
    for name in ("kilobot", "fcdfs"):
        _, res = run(name, 800)
        assert min(r["awake"] for r in res.timeseries[5:]) < 20, name


@pytest.mark.slow
def test_fcdfs_settles_on_a_lattice():
    """Settled FCDFS robots sit on a square lattice of spacing d_cover (intervals)."""
    sim, _ = run("fcdfs", 2500)
    pos = sim.positions[np.isin(sim.swarm.rows.status, (2, 4))]  # Door, Settled
    assert len(pos) >= 10
    d = np.hypot(*(pos[:, None] - pos[None]).transpose(2, 0, 1))
    np.fill_diagonal(d, np.inf)
    assert abs(np.median(d.min(axis=1)) - 6.0) < 0.3


def test_controllers_see_only_their_perception():
    """A controller works from a hand-made Perception (no engine state needed)."""
    from swarmsim.controller import RobotSetup, message_dtype, silent_message

    for name in CONTROLLERS:
        cls = get_controller(name)
        if describe(cls, name).batch:
            continue  # no per-robot step (GGC: tests/ggc_bot.py decides one robot)
        dtype = message_dtype(run_message_fields(cls, groups=1, scattered=False))
        msgs = np.zeros(1, dtype=dtype)
        msgs[0] = silent_message(dtype)
        ctl = cls(RobotSetup(0, leader=True, group=1), cls.Params(), np.random.default_rng(0))
        perception = Perception(tick=0, offsets=np.array([[3.0, 0.0]]),
                                distances=np.array([3.0]), messages=msgs, on_target=False,
                                probe=lambda o: bool(o[1] > 1.0), beacon=np.array([0.0, 1.0]),
                                moved=np.zeros(2))
        act = ctl.step(perception)
        assert isinstance(act, Action)
        assert np.hypot(*act.velocity) <= 0.1 + 1e-9
        assert act.message is None or len(act.message) == len(dtype.names)


SLEEP_CASES = {
    "fcdfs": [(700, ""),  # a queued robot slept through an entering one (differed at 564)
              (500, "random")],  # no gradient heard: init_timeout never fired while asleep
    "kilobot": [(600, "random")],  # the same (differed at 402)
    "cvt": [(600, "")],  # a resting robot resampled its cell after waking (differed at 429)
    "meanshift": [(520, "")],  # its robots start to sleep at about tick 450
}
"""Controller -> (ticks, start) of the runs that once told sleeping from awake; every other
controller is checked on DEFAULT_SLEEP_CASE."""
DEFAULT_SLEEP_CASE = (500, "")


@pytest.mark.slow
@pytest.mark.parametrize("name, ticks, start", [
    (name, ticks, start) for name in CONTROLLERS
    for ticks, start in SLEEP_CASES.get(name, [DEFAULT_SLEEP_CASE])])
def test_sleeping_changes_nothing(name, ticks, start):
    """A sleeping robot must act exactly as if it had been asked every tick."""
    def state(allow_sleep):
        sim = Simulation("tiny", controller=name, seed=0, max_ticks=ticks,
                         settings={"allow_sleep": allow_sleep, "start": start,
                                   "stop_on_complete": False})
        asleep = []
        sim.run(on_tick=lambda s: asleep.append(int(s.asleep.sum())))
        return sim.positions, sim.messages.tobytes(), max(asleep)

    (slept, said_asleep, asleep), (awake, said_awake, _) = state(True), state(False)
    assert np.array_equal(slept, awake) and said_asleep == said_awake
    assert asleep > 0  # robots really slept at some tick


def test_kilobot_counts_one_trap_per_lap_round_a_robot_off_the_target():
    """Circling a robot off the target traps a Kilobot once per full lap: it heads for the
    beacon, and stops for good only when trapped a third time (the lap count was never reset,
    so it stopped two ticks after its first lap)."""
    import math

    from controllers.kilobot import JOINED, OUTSIDE, WAIT, KilobotParams, KilobotRobot
    from swarmsim.controller import RobotSetup, make_perception, message_dtype

    params = KilobotParams()
    robot = KilobotRobot(RobotSetup(robot_id=10), params, np.random.default_rng(0))
    robot.status, robot.grad = OUTSIDE, 5
    msg = np.zeros(1, dtype=message_dtype(KilobotRobot.MESSAGE_FIELDS))
    msg["id"], msg["status"], msg["gradient"], msg["moving"] = 3, WAIT, 4, False
    laps = []
    for tick in range(160):  # 0.12 radians a tick: a lap every ~52 ticks
        angle = -0.12 * tick
        offset = -params.d_cover * np.array([math.cos(angle), math.sin(angle)])
        p = make_perception(tick, offset[None, :], np.array([params.d_cover]), msg, False,
                            lambda o: False, np.array([1.0, 0.0]), np.zeros(2))
        robot.step(p)
        if robot.traps > len(laps):
            laps.append(tick)
        if robot.status == JOINED:
            break
    assert len(laps) >= 2 and laps[1] - laps[0] > 40  # a lap apart, not a tick


STRIP = """
name = "strip"
description = "a 160 x 12 strip entered at one end: a crowd that must spread a long way"

[target]
outline = [[30, 10], [190, 10], [190, 22], [30, 22]]

[[spawn]]
outline = [[5, 6], [20, 6], [20, 26], [5, 26]]

[beacon]
position = [36, 16]

[arena]
margin = 15.0
"""


@pytest.mark.slow
def test_cvt_spreads_a_crowd_all_the_way(tmp_path):
    """Robots that rest must not stop Lloyd short. Entering a long strip at one end, the
    crowd thins out toward the far end; with the old tolerance (0.04) it rested there, the
    far end empty (72.6 % coverage, stalled at tick 2,592), and a still robot that kept its
    old sampling disc froze likewise. Now it completes (tick 1,962, seed 0)."""
    world = tmp_path / "strip.toml"
    world.write_text(STRIP)
    result = Simulation(str(world), controller="cvt", robots=80, seed=0, max_ticks=3000).run()
    assert result.summary["stop_reason"] == "complete"
    assert result.summary["coverage"] >= 0.99
