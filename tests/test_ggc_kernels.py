"""GGC's compiled kernels give the scalar rules' answers to the bit: the movers' kernel
(moverkernel.py: CPython's hypot, edge following, the valley, the heading and the circling
count), the enclosure test (enclosure.py) and the movers' rows (moverrows.py)."""

import math
from types import SimpleNamespace

import numpy as np
from numba import njit

from controllers.ggc import GGC, GGCParams
from controllers.ggc.batch import first_two_rows
from controllers.ggc.enclosure import enclosed_robots
from controllers.ggc.geometry import ENCLOSED_GAP, unit, widest_gap
from controllers.ggc.moverkernel import mover_geometry, py_hypot, warm_up
from controllers.ggc.moverrows import gradient_sources, mover_rows
from controllers.ggc.robot import MESSAGE_FIELDS, GGCRobot
from controllers.ggc.statuses import ARRIVE, COVERAGE, DETECTION, INITIAL, STOP, SURPLUS
from swarmsim.controller import NO_SENDER, RobotSetup, message_dtype


@njit
def hypots(x, y):
    out = np.empty(len(x))
    for i in range(len(x)):
        out[i] = py_hypot(x[i], y[i])
    return out


def bits(values) -> np.ndarray:
    return np.asarray(values, dtype=float).view(np.int64)


def test_py_hypot_is_pythons_to_the_bit():
    rng = np.random.default_rng(3)
    x = np.concatenate([rng.normal(size=50_000) * s for s in (1e-6, 1e-2, 1.0, 30.0, 1e9)])
    y = np.concatenate([rng.normal(size=50_000) * s for s in (1e-6, 1e-2, 1.0, 30.0, 1e9)])
    x[:500], y[500:1000] = 0.0, -0.0  # axes
    y[1000:1500] = x[1000:1500]  # equal legs
    special = [0.0, -0.0, 3.0, math.inf, -math.inf, math.nan]
    sx, sy = np.array([[a, b] for a in special for b in special]).T
    x, y = np.concatenate([x, sx]), np.concatenate([y, sy])
    expected = [math.hypot(a, b) for a, b in zip(x.tolist(), y.tolist(), strict=True)]
    np.testing.assert_array_equal(bits(hypots(x, y)), bits(expected))


def random_mover(rng: np.random.Generator, p: GGCParams) -> GGCRobot:
    r = GGCRobot(RobotSetup(7, leader=False, group=1, groups=3), p, np.random.default_rng(0))
    r.sense = float(rng.choice([-1.0, 1.0]))
    r.heading = rng.normal(size=2) if rng.random() < 0.7 else np.zeros(2)
    r.circling_id = int(rng.choice([NO_SENDER, 4, 9]))
    r.last_bearing = None if rng.random() < 0.2 else float(rng.uniform(-math.pi, math.pi))
    r.circled = float(rng.normal() * 4)
    return r


def random_offsets(rng: np.random.Generator, p: GGCParams, count: int) -> np.ndarray:
    """Neighbour offsets around d_cover, with ties, opposite pairs and a robot on top."""
    d = rng.choice([p.d_cover, p.d_cover * 0.5, p.d_cover * 1.3, 0.0], size=count,
                   p=[0.1, 0.4, 0.45, 0.05]) * rng.uniform(0.9, 1.1, size=count)
    angle = rng.uniform(-math.pi, math.pi, size=count)
    offsets = np.column_stack((d * np.cos(angle), d * np.sin(angle)))
    offsets[1::7] = -offsets[0:-1:7][: len(offsets[1::7])]  # exactly opposite
    turned = offsets[0:-2:7][: len(offsets[2::7])]
    offsets[2::7] = np.column_stack((-turned[:, 1], turned[:, 0]))  # exactly perpendicular
    return offsets


def expected(r: GGCRobot, offsets: np.ndarray, distances: np.ndarray, a: int, b: int,
             sender: int):
    """The scalar rules of coverage.py and edges.py, as ``coverage`` applies them."""
    velocity = r.edge_follow(offsets[a], float(distances[a]))
    if b >= 0 and distances[b] < r.p.d_cover:
        valley = r.valley_between(float(distances[a]), float(distances[b]),
                                  offsets[a].tolist(), offsets[b].tolist())
        velocity = velocity if valley is None else valley
    view = SimpleNamespace(messages={"id": np.array([sender])}, offsets=offsets[a:a + 1])
    full = r.circling(view, 0)
    return velocity, unit(velocity), r.last_bearing, r.circled, full


def test_mover_geometry_is_the_scalar_rules():
    rng, p = np.random.default_rng(11), GGCParams()
    checked = gave_way = 0
    for _ in range(300):
        rows, m = int(rng.integers(2, 12)), int(rng.integers(1, 6))
        offsets = random_offsets(rng, p, rows)
        distances = np.hypot(offsets[:, 0], offsets[:, 1])
        distances[(rng.random(rows) < 0.15) & (distances > 0)] = 0.75 * p.yield_distance
        a = rng.integers(0, rows, size=m)
        b = np.where(rng.random(m) < 0.8, rng.integers(0, rows, size=m), -1)
        sender = rng.choice([NO_SENDER, 4, 9], size=m).astype(np.int64)
        movers = [random_mover(rng, p) for _ in range(m)]
        for r, row in zip(movers, a.tolist(), strict=True):
            if rng.random() < 0.3:  # no turn this tick, on the rim of a whole circle
                r.last_bearing = math.atan2(-offsets[row, 1], -offsets[row, 0])
                r.circled = float(rng.choice([2 * math.pi, np.nextafter(2 * math.pi, 9),
                                              -2 * math.pi]))
        last = [math.nan if r.last_bearing is None else r.last_bearing for r in movers]
        ahead = [sorted(rng.choice(rows, size=int(rng.integers(0, min(rows, 4))),
                                   replace=False).tolist())
                 for _ in range(m)]  # the rows each mover gives way to, nearest first
        ahead_first = np.concatenate(([0], np.cumsum([len(x) for x in ahead])))
        got = mover_geometry(offsets, distances, a, b,
                             np.array([r.sense for r in movers]),
                             np.array([r.heading for r in movers]).reshape(-1, 2), sender,
                             np.array([r.circling_id for r in movers], dtype=np.int64),
                             np.array(last), np.array([r.circled for r in movers]),
                             p.d_cover, p.radial_gain, p.v, NO_SENDER, np.arange(m),
                             np.array([r for x in ahead for r in x], dtype=np.intp), ahead_first,
                             p.yield_distance)
        velocity, heading, usable, bearing, circled, full, gives_way, give_way = got
        for j, r in enumerate(movers):
            usable_j = distances[a[j]] > 0 and (b[j] < 0 or distances[b[j]] > 0)
            assert usable[j] == usable_j
            if not usable_j:
                continue  # the mover takes step(): the kernel's numbers are not used
            want = expected(r, offsets, distances, int(a[j]), int(b[j]), int(sender[j]))
            np.testing.assert_array_equal(bits(velocity[j]), bits(want[0]))
            np.testing.assert_array_equal(bits(heading[j]), bits(want[1]))
            assert bits(bearing[j]) == bits(want[2])
            assert bits(circled[j]) == bits(want[3]) and full[j] == want[4]
            r.pre = SimpleNamespace(ahead=ahead[j])
            way = r.give_way(SimpleNamespace(offsets=offsets, distances=distances), want[0])
            assert gives_way[j] == (way is not None)
            if way is not None:
                np.testing.assert_array_equal(bits(give_way[j]), bits(way))
                gave_way += 1
            checked += 1
    assert checked > 600 and gave_way > 100


def test_warm_up_compiles_the_signature_runs_use(monkeypatch):
    from controllers.ggc import movers
    from swarmsim import Simulation

    calls = []

    def counted(*args):
        calls.append(len(args[2]))
        return mover_geometry(*args)

    monkeypatch.setattr(movers, "mover_geometry", counted)
    warm_up()
    compiled = len(mover_geometry.signatures)
    GGC.warm_up()  # all of GGC's kernels
    sources = len(gradient_sources.signatures)
    sim = Simulation("K", controller="ggc", seed=1, robots=60,
                     settings={"stop_on_complete": False})
    for _ in range(1500):
        sim.step()
    assert sum(calls) > 100  # movers were decided by the kernel
    assert len(mover_geometry.signatures) == compiled
    assert len(gradient_sources.signatures) == sources


def enclosed_reference(offsets, distances, status, reach) -> bool:
    """detection.py's ``is_enclosed`` on one robot's rows (nearest first)."""
    near = int(distances.searchsorted(reach, side="right"))
    waiting = [j for j in range(near) if status[j] in (INITIAL, DETECTION)]
    return len(waiting) >= 3 and widest_gap(offsets[waiting]) < ENCLOSED_GAP


def test_enclosed_robots_is_the_scalar_rule():
    rng, reach = np.random.default_rng(7), 1.5 * GGCParams().d_min
    answers = []
    for _ in range(200):
        counts = rng.integers(0, 20, size=int(rng.integers(1, 8)))
        views = []
        for count in counts.tolist():
            lattice = rng.random() < 0.4  # ties: robots on a hexagonal lattice round me
            angle = (rng.integers(0, 6, size=count) * math.pi / 3 if lattice
                     else rng.uniform(-math.pi, math.pi, size=count))
            d = rng.choice([reach, reach * 0.6, reach * 1.2], size=count, p=[0.4, 0.4, 0.2])
            d = d if lattice else d * rng.uniform(0.8, 1.2, size=count)
            offsets = np.column_stack((d * np.cos(angle), d * np.sin(angle)))
            distances = np.hypot(offsets[:, 0], offsets[:, 1])
            order = np.argsort(distances, kind="stable")
            status = rng.choice([INITIAL, DETECTION, COVERAGE, ARRIVE], size=count,
                                p=[0.4, 0.4, 0.1, 0.1])
            views.append((offsets[order], distances[order], status))
        starts = np.concatenate(([0], np.cumsum(counts))).astype(np.int64)
        got = enclosed_robots(np.concatenate([v[0] for v in views]).reshape(-1, 2),
                              np.concatenate([v[1] for v in views]),
                              np.concatenate([v[2] for v in views]).astype(np.int64),
                              starts, reach, INITIAL, DETECTION, ENCLOSED_GAP)
        want = [enclosed_reference(*view, reach) for view in views]
        assert got.tolist() == want
        answers += want
    assert 50 < sum(answers) < len(answers) - 50  # both answers were tested, many times


def mover_rows_reference(starts, d, m, own_group, own_id, foreign_edges, p):
    """The numpy masks MoverAnswers used before the kernel (batch.py)."""
    segment = np.repeat(np.arange(len(starts) - 1), np.diff(starts))
    robots = len(starts) - 1
    edge = ~m["moving"]
    if not foreign_edges:
        edge &= ((m["group"] == own_group) | (m["status"] == ARRIVE)
                 | (m["status"] == SURPLUS) | (m["id"] == NO_SENDER))
    movers = ((d <= p.d_cover) & (m["group"] != own_group) & (m["id"] > own_id)
              & (m["status"] == COVERAGE))
    ahead = (d <= p.yield_distance) & m["moving"] & (m["id"] > own_id)

    def spans(mask):
        rows = np.flatnonzero(mask)
        return rows, np.searchsorted(segment[rows], np.arange(robots + 1))

    rows, first = spans(edge)
    found = [[int(rows[first[k] + j]) if first[k] + j < first[k + 1] else -1
              for k in range(robots)] for j in (0, 1)]
    return (*found, *spans(movers), *spans(ahead))


def random_chunk_rows(rng: np.random.Generator, fewest: int, most: int
                      ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A chunk of 1-8 robots with fewest..most-1 rows each: (counts, starts, rows), the rows
    GGC broadcasts with random groups 0-2 (the other fields zero)."""
    counts = rng.integers(fewest, most, size=int(rng.integers(1, 9)))
    starts = np.concatenate(([0], np.cumsum(counts))).astype(np.int64)
    m = np.zeros(int(starts[-1]), dtype=message_dtype(MESSAGE_FIELDS))
    m["group"] = rng.integers(0, 3, size=len(m))
    return counts, starts, m


def test_mover_rows_are_the_masks():
    rng, p = np.random.default_rng(5), GGCParams()
    for case in range(150):
        counts, starts, m = random_chunk_rows(rng, 0, 25)
        rows = len(m)
        m["status"] = rng.choice([INITIAL, DETECTION, COVERAGE, ARRIVE, STOP, SURPLUS],
                                 size=rows)
        m["id"] = rng.choice([NO_SENDER, 3, 5, 8, 12], size=rows)
        m["moving"] = rng.random(rows) < 0.4
        d = np.sort(rng.choice([p.d_cover, p.yield_distance, 2.0, 9.0], size=rows)
                    * rng.choice([1.0, 1.0, 0.97], size=rows))
        own_group = np.repeat(rng.integers(0, 3, size=len(counts)), counts).astype(np.int64)
        own_id = np.repeat(rng.choice([3, 5, 8], size=len(counts)), counts).astype(np.int64)
        foreign = bool(case % 2)
        got = mover_rows(starts, d, *(np.ascontiguousarray(m[name])
                                      for name in ("group", "status", "id", "moving")),
                         own_group, own_id, foreign, p.d_cover, p.yield_distance, ARRIVE,
                         SURPLUS, COVERAGE, NO_SENDER)
        want = mover_rows_reference(starts, d, m, own_group, own_id, foreign, p)
        for g, w in zip(got, want, strict=True):
            assert np.asarray(g).tolist() == np.asarray(w).tolist()


def test_gradient_sources_are_the_masks():
    """The row each mover takes its gradient from: the compiled pass against the masks it
    replaced (first_two_rows over the whole chunk), with distances exactly at the reach."""
    rng, p = np.random.default_rng(6), GGCParams()
    reach, took_other = 1.5 * p.d_cover, 0
    for _ in range(200):
        counts, starts, m = random_chunk_rows(rng, 1, 20)
        rows = len(m)
        m["moving"] = rng.random(rows) < 0.4
        d = rng.choice([reach, 2.0, 12.0], size=rows) * rng.choice([1.0, 1.0, 0.99], size=rows)
        own_group = np.repeat(rng.integers(0, 3, size=len(counts)), counts).astype(np.int64)
        movers = np.flatnonzero(rng.random(len(counts)) < 0.7).astype(np.int64)
        a = np.array([rng.integers(starts[k], starts[k + 1]) for k in movers], dtype=np.int64)
        group, moving = np.ascontiguousarray(m["group"]), np.ascontiguousarray(m["moving"])
        got = gradient_sources(a, movers, starts, d, group, own_group, moving, reach)
        want = a.copy()
        foreign = group[a] != own_group[a]
        segment = np.repeat(np.arange(len(counts)), counts)
        mine = ~moving & (group == own_group) & (d <= reach)
        first, _ = first_two_rows(mine, segment, len(counts))
        want[foreign] = first[movers[foreign]]
        assert got.tolist() == want.tolist()
        took_other += int((foreign & (want >= 0)).sum())
    assert took_other > 100
