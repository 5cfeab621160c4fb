"""GGC (one group): statuses, gradients, coverage of a small world, determinism, parameters."""

import numpy as np
import pytest

from controllers.common.gradient import INF_GRADIENT
from controllers.ggc import GGCParams
from controllers.ggc.statuses import ARRIVE, COVERAGE, DETECTION, INITIAL, STATUSES
from swarmsim import ConfigError, Simulation
from swarmsim.engine.costs import WORK_FIELDS
from swarmsim.engine.sim import TIMING_FIELDS
from swarmsim.world.world import world_from_dict
from tests.conftest import small_world
from tests.ggc_bot import ggc_state


def run_small(seed=1, robots=60, max_ticks=12000, **settings):
    sim = Simulation(small_world(), controller="ggc", robots=robots, groups=1, seed=seed,
                     max_ticks=max_ticks, settings=settings)
    return sim, sim.run()


@pytest.fixture(scope="module")
def small_run():
    return run_small()


@pytest.mark.slow
def test_small_world_is_covered_fully(small_run):
    _, res = small_run
    s = res.summary
    assert s["stop_reason"] == "complete", s
    assert s["coverage"] >= 0.99 and s["completion_tick"] == s["ticks"]
    assert s["max_overlap"] < 0.05 * 0.4


def bits(*statuses: int) -> int:
    return sum(1 << s for s in statuses)


@pytest.mark.slow
def test_status_sequences_follow_figure_3(small_run):
    """Every robot's statuses were a prefix of Initial -> Detection -> Coverage -> Arrive
    (the leader: Initial -> Arrive), by the statuses each robot has had."""
    state = ggc_state(small_run[0])
    leaders = state[state["leader"]]
    assert len(leaders) == 1 and leaders["visited"][0] == bits(INITIAL, ARRIVE)
    full = [INITIAL, DETECTION, COVERAGE, ARRIVE]
    prefixes = {bits(*full[:k]) for k in range(1, 5)}
    others = state[~state["leader"]]
    had = {tuple(s for s in range(len(STATUSES)) if v >> s & 1) for v in others["visited"]}
    assert set(others["visited"].tolist()) <= prefixes, had
    assert (others["visited"] == bits(*full)).sum() >= 20


@pytest.mark.slow
def test_arrived_robots_stay_on_target_and_keep_their_spacing(small_run):
    sim, _ = small_run
    state = ggc_state(sim)
    arrived = (state["status"] == ARRIVE) & ~state["leader"]
    on = sim.floor.on_target(sim.positions)
    assert on[arrived].mean() > 0.95
    assert not ((state["status"] == ARRIVE) & (state["gradient"] == INF_GRADIENT)).any()
    # spacing: each arrived robot's nearest arrived neighbour about d_cover (6) away (rule b
    # stops at d_cover - arrive_tolerance or more; a deadlocked mover may stop a little closer)
    settled = sim.positions[state["status"] == ARRIVE]
    gaps = np.hypot(*(settled[:, None] - settled[None]).transpose(2, 0, 1))
    np.fill_diagonal(gaps, np.inf)
    nearest = gaps.min(axis=1)
    assert len(settled) >= 20
    assert nearest.min() > 0.8 * sim.params.d_cover, nearest.min()
    assert abs(np.median(nearest) - sim.params.d_cover) < 0.5, np.median(nearest)


def test_gradient_grows_outward_from_the_leader():
    sim = Simulation(small_world(), controller="ggc", robots=60, groups=1, seed=2,
                     max_ticks=40)
    sim.run()
    state = ggc_state(sim)
    leader = int(np.flatnonzero(state["leader"])[0])
    d = np.hypot(*(sim.positions - sim.positions[leader]).T)
    grads = state["gradient"]
    assert grads[leader] == 0
    assert (grads < INF_GRADIENT).all()
    assert np.corrcoef(d, grads)[0, 1] > 0.9  # hop count follows distance


@pytest.mark.slow
def test_same_seed_same_run_and_sleep_changes_nothing():
    a = run_small(seed=3, max_ticks=1500)[1]
    b = run_small(seed=3, max_ticks=1500, allow_sleep=False)[1]
    c = run_small(seed=3, max_ticks=1500, decide_order="shuffled")[1]
    strip = lambda r: {k: v for k, v in r.summary.items()
                       if k not in TIMING_FIELDS + WORK_FIELDS}
    assert strip(a) == strip(b) == strip(c)
    assert a.summary["decisions"] == c.summary["decisions"] < b.summary["decisions"]
    cols = lambda r: [(x["tick"], x["coverage"], x["total_distance"]) for x in r.timeseries]
    assert cols(a) == cols(b) == cols(c)
    assert a.summary["coverage"] > 0.2
    assert min(x["awake"] for x in a.timeseries[1:]) < 60  # robots really slept
    assert min(x["awake"] for x in b.timeseries) == 60


@pytest.mark.slow
def test_sleep_changes_nothing_at_d_cover_1_where_movers_push_the_formation():
    """A waiting robot blocked by a waiting neighbour sleeps until a broadcast changes; when
    movers push that neighbour out of d_cover it must wake too (it slept on: coverage 0.159
    with sleep against 0.187 without, tiny, 1,500 ticks)."""
    def summary(allow_sleep):
        sim = Simulation("tiny", controller="ggc", seed=0, max_ticks=1500, d_cover=1.0,
                         settings={"allow_sleep": allow_sleep})
        result = sim.run()
        fewest_awake = min(x["awake"] for x in result.timeseries[1:])
        return ({k: v for k, v in result.summary.items()
                 if k not in TIMING_FIELDS + WORK_FIELDS}, fewest_awake)

    (slept, fewest), (awake, _) = summary(True), summary(False)
    assert slept == awake
    assert fewest < slept["robots"]  # robots really slept


@pytest.mark.parametrize("bad", [{"d_cover": 0.5}, {"v": -1.0}, {"orbit": 2}, {"theta": 20.0},
                                 {"T_r": 0}])
def test_bad_ggc_parameters_are_named(bad):
    key = next(iter(bad))
    with pytest.raises(ConfigError, match=f"key '{key}'"):
        Simulation(small_world(), controller="ggc", robots=20, settings=bad)


def test_ggc_needs_a_beacon():
    world = world_from_dict({
        "name": "dark", "target": {"outline": [[0, 0], [10, 0], [10, 10], [0, 10]]},
        "spawn": [{"outline": [[0, -20], [10, -20], [10, -12], [0, -12]]}]})
    with pytest.raises(ConfigError, match="beacon"):
        Simulation(world, controller="ggc", robots=10)


def test_params_defaults_follow_table_2():
    params = GGCParams()
    assert (params.d_safe, params.d_cover, params.v, params.R_c) == (1.0, 6.0, 0.1, 15.0)


@pytest.fixture(scope="module")
def d_cover_runs():
    """One run per d_cover of Table 2 on the small world (60 robots, ~6 s each)."""
    return {d: run_small(d_cover=d, max_ticks=20000, plateau_ticks=2500)[1].summary
            for d in (1, 2, 4, 6, 8, 10)}


@pytest.mark.slow
def test_every_d_cover_run_terminates_by_a_stop_rule(d_cover_runs):
    for d, s in d_cover_runs.items():
        assert s["stop_reason"] in ("complete", "plateau", "stalled"), (d, s["stop_reason"])


@pytest.mark.slow
def test_coverage_follows_the_lattice_bound(d_cover_runs):
    cov = {d: s["coverage"] for d, s in d_cover_runs.items()}
    # 60 robots fill a lattice of 720 units^2 for d_cover 4 and 6 (capacity 52 and 23)
    assert cov[4] >= 0.99 and cov[6] >= 0.99
    # too few robots for d_cover 1 and 2 (capacity 831 and 208): coverage grows with d_cover
    assert cov[1] < cov[2] < cov[4]
    # discs of r = 4 on a lattice of spacing 8 or 10 cannot cover everything (90.7 %, 58 %)
    assert cov[10] < cov[8] < 0.95 and cov[10] < 0.7


@pytest.mark.slow
def test_larger_d_cover_uses_fewer_robots_and_less_distance(d_cover_runs):
    on = [d_cover_runs[d]["robots_on_target"] for d in (2, 4, 6, 8, 10)]
    assert on == sorted(on, reverse=True) and on[0] > 2 * on[-1]
    dist = [d_cover_runs[d]["distance_at_settle"] for d in (4, 6, 8, 10)]
    assert dist[1] < dist[0] and dist[3] < dist[1], dist


@pytest.mark.slow
def test_surplus_robots_stop_once_the_target_is_full(d_cover_runs):
    # 60 robots, room for ~15 at d_cover 8 and ~10 at 10: the rest stop as Surplus (off the
    # target) instead of circling, and the run ends with every robot standing still
    for d in (8, 10):
        s = d_cover_runs[d]
        assert set(s["status_counts"]) == {"Arrive", "Surplus"}, (d, s["status_counts"])
        assert s["stop_reason"] == "stalled" and s["surplus_stops"] > 0, (d, s)


@pytest.mark.slow
def test_lattice_stop_still_covers_the_small_world():
    s = run_small(seed=3, lattice_stop=True)[1].summary
    assert s["stop_reason"] == "complete" and s["coverage"] >= 0.99, s
    assert abs(s["spacing_mean"] - 6.0) < 0.6  # robots stop on lattice sites, ~d_cover apart


@pytest.mark.slow
def test_without_lattice_stop_the_small_world_is_covered_too():
    s = run_small(seed=3, lattice_stop=False)[1].summary
    assert s["stop_reason"] == "complete" and s["coverage"] >= 0.99, s


@pytest.mark.parametrize("robots, groups, start", [
    (20, 1, "formation"), (20, 3, "random"), (1, 1, "formation"), (2, 2, "random")])
def test_the_warm_up_compiles_the_one_driver_a_run_needs(robots, groups, start):
    """A run's set-up compiles (or loads) its start's driver before the run's clock starts;
    the run then compiles nothing, whatever its chunks' sizes (a lone robot hears 0 rows)."""
    from controllers.ggc.decide import decide_chunk

    sim = Simulation("tiny", controller="ggc", robots=robots, groups=groups, seed=0,
                     max_ticks=30, settings={"start": start})
    compiled = list(decide_chunk.signatures)
    sim.run()
    assert list(decide_chunk.signatures) == compiled  # nothing compiled during the run
    assert len(compiled) <= 2  # at most one driver per start



def test_chunks_call_the_compiled_driver_and_other_types_meet_the_dispatcher():
    """A run's chunks call the entry point compiled for their types (no typing per call);
    arguments of types no driver was compiled for get the dispatcher, which refuses them."""
    from controllers.ggc.decide import decide_chunk, ensure_driver
    from controllers.ggc.swarm import GGCSwarm
    from swarmsim.controller import DecideBatch, NeighbourBatch

    sim = Simulation("tiny", controller="ggc", robots=6, seed=0, max_ticks=20)
    sim.run()
    swarm = sim.swarm
    assert isinstance(swarm, GGCSwarm)
    entry_points = [compiled.entry_point for compiled in decide_chunk.overloads.values()]
    assert any(swarm._driver_fn is entry for entry in entry_points)
    batch = DecideBatch(20, NeighbourBatch(np.zeros(2, dtype=sim.messages.dtype), np.ones(2),
                                           np.array([0, 1, 2])),
                        np.array([[1.0, 0.0], [-1.0, 0.0]]), np.zeros(2, dtype=bool),
                        np.zeros((2, 2)), np.zeros((2, 2)), lambda k: None, None)
    args = swarm._chunk_args(np.arange(2, dtype=np.intp), batch)
    assert ensure_driver(args) is swarm._driver_fn
    flat = args._replace(sensors=args.sensors._replace(moved=np.zeros(2)))  # (n,), not (n, 2)
    assert ensure_driver(flat) is decide_chunk
    with pytest.raises(TypeError):
        decide_chunk(*flat)


def test_a_ggc_swarm_pickles_and_the_copy_decides_alike():
    """A run's GGC swarm is copied whole (pickle: the compiled entry point is looked up again),
    and the copy's run goes on exactly as the original's."""
    import pickle

    sim = Simulation("tiny", seed=2, max_ticks=60)
    for _ in range(30):
        sim.step()
    copy = pickle.loads(pickle.dumps(sim.swarm))
    assert copy.state.tobytes() == sim.swarm.state.tobytes()  # NaN fields too
    sim.swarm = copy
    for _ in range(30):
        sim.step()
    other = Simulation("tiny", seed=2, max_ticks=60)
    for _ in range(60):
        other.step()
    assert np.array_equal(sim.positions, other.positions)
    assert sim.swarm.state.tobytes() == other.swarm.state.tobytes()
