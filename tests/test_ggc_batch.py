"""GGC.prepare answers the movers' and waiting robots' neighbourhood queries for a whole chunk
at once: the same answers each robot finds alone, and runs the same to the bit with or
without it."""

import collections

import numpy as np
import pytest

from controllers.ggc import GGCParams
from controllers.ggc.batch import BLOCKED_BY_MOVER, BLOCKED_BY_WAITING, NOT_BLOCKED, prepare_chunk
from controllers.ggc.robot import COVERAGE, DETECTION, STOP, GGCRobot
from swarmsim import Simulation
from swarmsim.controller import NeighbourBatch, RobotSetup

from .test_ggc import small_world
from .test_ggc_small_views import SMALL_VIEW, STATUSES, random_perception


def random_chunk(rng: np.random.Generator, groups: int, params: GGCParams):
    """Robots of one run (same params and groups) with random statuses and perceptions."""
    robots, perceptions = [], []
    for _ in range(int(rng.integers(1, 40))):
        setup = RobotSetup(int(rng.choice([10, 49, 50, 51, 90])), leader=False,
                           group=int(rng.integers(1, groups + 1)), groups=groups)
        robot = GGCRobot(setup, params, np.random.default_rng(0))
        robot.status = int(rng.choice(STATUSES))
        robot.grad = int(rng.integers(0, 6))
        robots.append(robot)
        p = random_perception(rng, int(rng.integers(0, 3 * SMALL_VIEW)),
                              reach=float(rng.choice([2.0, 3.0, 12.0])))
        on_edge = rng.random(len(p.distances)) < 0.2  # exactly at a query's reach
        reaches = [params.yield_distance, params.d_cover, 1.5 * params.d_min,
                   params.d_cover + params.arrive_tolerance]
        p.distances[on_edge] = rng.choice(reaches, size=int(on_edge.sum()))
        p.distances.sort()
        perceptions.append(p)
    counts = [len(p.distances) for p in perceptions]
    batch = NeighbourBatch(np.concatenate([p.messages for p in perceptions]),
                           np.concatenate([p.distances for p in perceptions]),
                           np.concatenate(([0], np.cumsum(counts))))
    return robots, perceptions, batch


@pytest.mark.parametrize("follow_all", [False, True])
def test_prepared_answers_are_each_robots_own(follow_all):
    rng = np.random.default_rng(11)
    seen = collections.Counter()
    for _ in range(150):
        groups = int(rng.choice([1, 3]))
        robots, perceptions, batch = random_chunk(
            rng, groups, GGCParams(follow_other_formations=follow_all))
        prepare_chunk(robots, batch)
        for robot, p in zip(robots, perceptions, strict=True):
            pre = robot.pre
            if robot.status not in (COVERAGE, STOP):
                assert pre is None
                continue
            robot.pre = None
            assert pre.edge == robot.nearest_edge_robots(p)
            assert pre.movers == list(robot.other_group_movers(p))
            assert pre.ahead == list(robot.movers_outranking(p))
            seen[("edge", len(pre.edge))] += 1
            seen[("movers", bool(pre.movers), groups)] += 1
            seen[("ahead", bool(pre.ahead))] += 1
    assert {("edge", 0), ("edge", 1), ("edge", 2)} <= set(seen)
    assert {("movers", True, 3), ("movers", False, 3), ("ahead", True), ("ahead", False)} <= set(seen)


def test_prepared_waiting_answers_are_each_robots_own():
    rng = np.random.default_rng(12)
    seen = collections.Counter()
    for _ in range(200):
        groups = int(rng.choice([1, 3]))
        robots, perceptions, batch = random_chunk(rng, groups, GGCParams())
        prepare_chunk(robots, batch)
        waiting = sum(r.status == DETECTION for r in robots)
        if waiting:  # chunks with few and with many waiting robots
            seen[("few", 4 * waiting <= len(robots))] += 1
        for robot, p in zip(robots, perceptions, strict=True):
            pre = robot.pre_wait
            if robot.status != DETECTION:
                assert pre is None
                continue
            robot.pre_wait = None
            surplus = robot.surplus_rule and robot.hears_surplus(p)
            assert pre.surplus == surplus
            grad = robot.gradient_from(p, 1.5 * robot.p.d_min)
            assert pre.grad == grad
            if grad is not None:
                robot.grad = grad  # as detection() does before asking blocked()
            assert pre.blocker == robot.blocked(p)
            seen[("surplus", surplus)] += 1
            seen[("grad", grad is None)] += 1
            seen[pre.blocker] += 1
    assert {("surplus", True), ("surplus", False), ("grad", True), ("grad", False),
            NOT_BLOCKED, BLOCKED_BY_WAITING, BLOCKED_BY_MOVER, ("few", True), ("few", False)
            } <= set(seen), seen


def two_groups(prepared: bool, ticks: int) -> tuple[Simulation, collections.Counter]:
    # prepare() as the step path calls it (decide_batch calls batch.py itself)
    sim = Simulation(small_world(40.0, 30.0), controller="ggc", robots=90, groups=2, seed=3,
                     max_ticks=ticks, settings={"batch_decide": False})
    used = collections.Counter()
    prepare = sim.swarm._prepare

    def counting(robots, batch):
        prepare(robots, batch)
        used["answers"] += sum(r.pre is not None for r in robots)
        used["movers met"] += sum(bool(r.pre and r.pre.movers) for r in robots)
        used["waiting"] += sum(r.pre_wait is not None for r in robots)

    sim.swarm._prepare = counting if prepared else None  # None: every robot answers alone
    for _ in range(ticks):
        sim.step()
    return sim, used


def test_a_run_is_the_same_with_and_without_prepare():
    (with_batch, used), (alone, _) = two_groups(True, 1500), two_groups(False, 1500)
    assert with_batch.positions.tobytes() == alone.positions.tobytes()
    assert with_batch.messages.tobytes() == alone.messages.tobytes()
    assert used["answers"] > 5000 and used["movers met"] > 0 and used["waiting"] > 500, used
