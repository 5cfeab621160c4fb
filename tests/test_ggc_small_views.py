"""GGC's neighbourhood queries that loop over Python values for a few neighbours (SMALL_VIEW)
give the answers of the numpy masks they replace, on random neighbourhoods of every size.

The references below are the numpy forms as they were written before the loops."""

import collections
import math

import numpy as np
import pytest

from controllers.ggc import GGCParams
from controllers.ggc.batch import BLOCKED_BY_MOVER, BLOCKED_BY_WAITING, NOT_BLOCKED
from controllers.ggc.geometry import ENCLOSED_GAP, SMALL_VIEW, widest_gap
from controllers.ggc.robot import (
    ARRIVE,
    COVERAGE,
    DETECTION,
    INITIAL,
    MESSAGE_FIELDS,
    STOP,
    SURPLUS,
    GGCRobot,
)
from controllers.gradient import INF_GRADIENT
from swarmsim.controller import NO_SENDER, Perception, RobotSetup, message_dtype

STATUSES = [INITIAL, DETECTION, COVERAGE, ARRIVE, STOP, SURPLUS]


def random_robot(rng: np.random.Generator, groups: int) -> GGCRobot:
    setup = RobotSetup(50, leader=False, group=1, groups=groups)
    r = GGCRobot(setup, GGCParams(), np.random.default_rng(0))
    r.grad = int(rng.integers(0, 6))
    r.heading = rng.normal(size=2) if rng.random() < 0.7 else np.zeros(2)
    return r


def random_perception(rng: np.random.Generator, n: int, reach: float = 12.0) -> Perception:
    """n neighbours within ``reach``, nearest first, with every field drawn from a few values
    so that ties (same gradient, same id as mine) and silent rows (NO_SENDER) occur."""
    m = np.zeros(n, dtype=message_dtype(MESSAGE_FIELDS))
    m["id"] = rng.choice([NO_SENDER, 10, 49, 50, 51, 90], size=n)
    m["status"] = rng.choice(STATUSES, size=n)
    m["gradient"] = rng.choice([0, 1, 2, 3, 4, 5, INF_GRADIENT], size=n)
    m["group"] = rng.integers(0, 4, size=n)
    m["moving"] = rng.random(n) < 0.4
    m["enclosed"] = rng.random(n) < 0.2
    distances = np.sort(rng.uniform(0.5, reach, size=n))
    angles = rng.uniform(0, 2 * np.pi, size=n)
    offsets = np.stack([distances * np.cos(angles), distances * np.sin(angles)], axis=1)
    return Perception(tick=10, offsets=offsets, distances=np.hypot(*offsets.T), messages=m,
                      on_target=False, probe=lambda offset: False, beacon=None,
                      moved=np.zeros(2))


def gradient_in_reference(r: GGCRobot, m: np.ndarray) -> int | None:
    ok = ~m["moving"] & (m["group"] == r.group)
    ok &= (m["id"] != NO_SENDER) & (m["gradient"] < INF_GRADIENT)
    ok &= m["status"] != COVERAGE
    return int(m["gradient"][ok].min()) + 1 if ok.any() else None


def blocked_reference(r: GGCRobot, p: Perception) -> int:
    m = p.messages[:int(np.searchsorted(p.distances, r.p.d_cover, side="right"))]
    status = m["status"]
    near = (m["group"] == r.group) & (m["id"] != NO_SENDER)
    near &= (status != ARRIVE) & (status != SURPLUS)
    if r.groups > 1:
        near &= status != STOP
    outranks = near & ~m["enclosed"] & ((m["gradient"] > r.grad)
                                        | ((m["gradient"] == r.grad) & (m["id"] > r.id)))
    if not outranks.any():
        return NOT_BLOCKED
    return BLOCKED_BY_MOVER if m["moving"][outranks].all() else BLOCKED_BY_WAITING


def other_group_mover_reference(r: GGCRobot, p: Perception) -> bool:
    if r.groups == 1:
        return False
    k = int(np.searchsorted(p.distances, r.p.d_cover, side="right"))
    m = p.messages[:k]
    others = (m["group"] != r.group) & (m["id"] > r.id) & (m["status"] == COVERAGE)
    if r.p.stop_ahead_only and np.any(r.heading):
        others &= p.offsets[:k] @ r.heading > 0
    return bool(others.any())


def give_way_reference(r: GGCRobot, p: Perception, velocity: np.ndarray):
    k = int(np.searchsorted(p.distances, r.p.yield_distance, side="right"))
    m = p.messages[:k]
    ahead = (m["moving"] & (m["id"] > r.id)).nonzero()[0]
    ahead = ahead[p.offsets[ahead] @ velocity > 0]
    if len(ahead) == 0:
        return None
    other = ahead[0]
    if p.distances[other] < r.p.yield_distance * 0.75:
        return -p.offsets[other] / np.hypot(*p.offsets[other]) * r.p.v * 0.5
    return np.zeros(2)


def waiting_near_reference(r: GGCRobot, p: Perception) -> np.ndarray:
    k = int(np.searchsorted(p.distances, 1.5 * r.p.d_min, side="right"))
    status = p.messages["status"][:k]
    return ((status == INITIAL) | (status == DETECTION)).nonzero()[0]


def widest_gap_reference(offsets: np.ndarray) -> float:
    """The numpy form of widest_gap, with the C library's atan2 (numpy's arctan2 may take
    an AVX-512 kernel whose last bit differs)."""
    angles = np.sort(np.array([math.atan2(y, x) for x, y in offsets.tolist()]))
    return max(float((angles[1:] - angles[:-1]).max()),
               float(angles[0]) + 2 * math.pi - float(angles[-1]))


def is_enclosed_reference(r: GGCRobot, p: Perception) -> bool:
    waiting = waiting_near_reference(r, p)
    return len(waiting) >= 3 and widest_gap_reference(p.offsets[waiting]) < ENCLOSED_GAP


def group_waiting_reference(r: GGCRobot, m: np.ndarray) -> bool:
    status = m["status"]
    return bool((((status == INITIAL) | (status == DETECTION)) & (m["group"] == r.group)).any())


def cases(seed: int, count: int = 600, reach: float = 12.0):
    """Random (robot, perception) pairs, neighbourhood sizes 0 .. 3 * SMALL_VIEW."""
    rng = np.random.default_rng(seed)
    for _ in range(count):
        r = random_robot(rng, groups=int(rng.choice([1, 3])))
        yield r, random_perception(rng, int(rng.integers(0, 3 * SMALL_VIEW)), reach), rng


def test_gradient_in_matches_the_numpy_masks():
    seen = collections.Counter()
    for r, p, _ in cases(1):
        got, want = r.gradient_in(p.messages), gradient_in_reference(r, p.messages)
        assert got == want
        seen[(want is None, len(p.messages) <= SMALL_VIEW)] += 1
    assert len(seen) == 4  # found and not found, by loop and by numpy


def test_blocked_matches_the_numpy_masks():
    seen = collections.Counter()
    for r, p, _ in cases(2):
        want = blocked_reference(r, p)
        assert r.blocked(p) == want
        seen[want] += 1
    assert set(seen) == {NOT_BLOCKED, BLOCKED_BY_MOVER, BLOCKED_BY_WAITING}


def test_nearest_edge_robots_are_the_first_two_edge_robots():
    lengths = collections.Counter()
    for follow_all in (False, True):
        for r, p, _ in cases(3):
            r.p = GGCParams(follow_other_formations=follow_all)
            want = r.edge_robots(p).nonzero()[0][:2].tolist()
            assert r.nearest_edge_robots(p) == want
            lengths[len(want)] += 1
    assert set(lengths) == {0, 1, 2}


@pytest.mark.parametrize("ahead_only", [False, True])
def test_other_group_mover_matches_the_numpy_masks(ahead_only):
    seen = collections.Counter()
    for r, p, _ in cases(4):
        r.p = GGCParams(stop_ahead_only=ahead_only)
        want = other_group_mover_reference(r, p)
        assert r.other_group_mover(p) == want
        seen[want] += 1
    assert set(seen) == {False, True}


def test_give_way_matches_the_numpy_masks():
    seen = collections.Counter()
    for r, p, rng in cases(5, count=1500):
        velocity = rng.normal(size=2)
        got, want = r.give_way(p, velocity), give_way_reference(r, p, velocity)
        assert (got is None) == (want is None)
        if want is not None:
            assert got.tobytes() == want.tobytes()
            seen["back off" if want.any() else "wait"] += 1
        else:
            seen["carry on"] += 1
    assert set(seen) == {"back off", "wait", "carry on"}


def test_widest_gap_matches_the_numpy_form_to_the_bit():
    rng = np.random.default_rng(6)
    for n in range(2, 3 * SMALL_VIEW):
        for scale in (1e-3, 1.0, 10.0):
            offsets = rng.normal(size=(n, 2)) * scale
            offsets[rng.random(n) < 0.2] = offsets[0]  # equal bearings: zero gaps
            offsets[rng.random(n) < 0.1, 1] = 0.0  # on the axis: bearings 0 and pi
            assert widest_gap(offsets) == widest_gap_reference(offsets)
            # and within rounding of numpy's own arctan2, whichever kernel it takes
            bearings = np.sort(np.arctan2(offsets[:, 1], offsets[:, 0]))
            numpy_gap = max(float(np.diff(bearings).max()),
                            float(bearings[0]) + 2 * math.pi - float(bearings[-1]))
            assert abs(widest_gap(offsets) - numpy_gap) <= 1e-12


def test_waiting_near_and_is_enclosed_match_the_numpy_masks():
    seen = collections.Counter()
    for r, p, _ in cases(7, count=1500, reach=2.5):  # dense: up to ~30 rows within 1.5
        assert list(r.waiting_near(p)) == waiting_near_reference(r, p).tolist()
        want = is_enclosed_reference(r, p)
        assert r.is_enclosed(p) == want
        k = int(np.searchsorted(p.distances, 1.5 * r.p.d_min, side="right"))
        seen[(want, k <= SMALL_VIEW)] += 1
    assert len(seen) == 4  # enclosed and not, by loop and by numpy


def test_group_waiting_in_matches_the_numpy_masks():
    seen = collections.Counter()
    for r, p, _ in cases(8, count=1500):
        m = p.messages
        want = group_waiting_reference(r, m)
        assert r.group_waiting_in(m) == want
        in_head = group_waiting_reference(r, m[:SMALL_VIEW])
        seen["not found" if not want else "nearest" if in_head else "farther"] += 1
    assert set(seen) == {"not found", "nearest", "farther"}
