"""The compiled wake step (swarmsim/engine/wakes.py) gives the numpy code's answers: which robots
drifted or were pushed, and which sleepers a changed robot wakes."""

import numpy as np

from swarmsim.engine.wakes import awake_robots, drifted, hypot_at_most, wake_near


def test_drifted_is_the_numpy_rule():
    rng = np.random.default_rng(4)
    for _ in range(50):
        n = int(rng.integers(1, 300))
        ref = rng.integers(0, 200, size=(n, 2)) * 0.25
        positions = ref + rng.choice([0.0, 0.1, 0.25, 1.0], size=(n, 1)) * rng.normal(size=(n, 2))
        positions[: n // 10] = ref[: n // 10] + [0.25, 0.0]  # exactly eps away
        velocities = np.where(rng.random((n, 1)) < 0.5, 0.0, rng.normal(size=(n, 2)))
        velocities[rng.random(n) < 0.1] = [-0.0, 0.0]
        velocities[rng.random(n) < 0.1] = [0.0, 0.02]  # told to move along one axis only
        eps = 0.25
        want_drift = np.hypot(*(positions - ref).T) > eps
        want_pushed = want_drift & ~velocities.any(axis=1)
        want_ref = ref.copy()
        want_ref[want_drift] = positions[want_drift]
        drift, pushed = drifted(positions, ref, velocities, eps)
        assert drift.tolist() == want_drift.tolist() and pushed.tolist() == want_pushed.tolist()
        np.testing.assert_array_equal(ref, want_ref)
        assert 0 < want_drift.sum() < n or n < 20


def test_wake_near_is_the_rule_over_every_pair():
    rng = np.random.default_rng(9)
    woken = spared = 0
    for trial in range(80):
        n = int(rng.integers(2, 200))
        spread = [10, 40, 400][trial % 3]  # crowded, sparse, far apart (sources off the grid)
        positions = rng.integers(0, spread, size=(n, 2)) * 0.25  # exact rims: 2.25, 6.25, 15.25
        asleep = rng.random(n) < 0.6
        wake_range = rng.choice([2.0, 6.0, 15.0], size=n)
        wake_on_motion, wakes_all = rng.random(n) < 0.5, rng.random(n) < 0.3
        sources = np.unique(rng.integers(0, n, size=int(rng.integers(1, 20))))
        margin = 0.25
        src, near = np.repeat(sources, n), np.tile(np.arange(n), len(sources))
        d = np.hypot(*(positions[near] - positions[src]).T)
        hit = asleep[near] & (d <= wake_range[near] + margin)
        hit &= wake_on_motion[near] | wakes_all[src]
        want = asleep.copy()
        want[near[hit]] = False
        before = asleep.copy()
        wake_near(positions, asleep, wake_range, wake_on_motion, wakes_all, sources, margin)
        assert asleep.tolist() == want.tolist()
        woken += int(hit.any())
        spared += int((want & before).any())
    assert woken > 30 and spared > 30


def test_wake_near_wakes_exactly_at_the_rim():
    positions = np.array([[0.0, 0.0], [6.25, 0.0], [6.5, 0.0], [-3.0, 4.0]])
    asleep = np.array([False, True, True, True])
    wake_on_motion = np.ones(4, dtype=bool)
    wake_near(positions, asleep, np.full(4, 6.0), wake_on_motion, np.zeros(4, dtype=bool),
              np.array([0]), 0.25)
    assert asleep.tolist() == [False, False, True, False]  # 6.25 and 5.0 away: woken


def test_awake_robots_lists_the_awake_and_the_sleepers_woken_now():
    # robots 0-5 in a row, 10 units apart; 1-5 asleep, 5 failed
    positions = np.array([[10.0 * i, 0.0] for i in range(6)])
    ref = positions.copy()
    asleep = np.array([False, True, True, True, True, True])
    failed = np.array([False] * 5 + [True])
    wake_tick = np.array([0, 7, 99, 99, 99, 99], dtype=np.int64)
    quiet, every = np.zeros(6, dtype=bool), np.ones(6, dtype=bool)
    ranges, velocities = np.full(6, 5.0), np.zeros((6, 2))

    def awake(tick, changed=quiet):
        return awake_robots(asleep, failed, wake_tick, tick, positions, ref, velocities, 0.1,
                            changed, ranges, every, 1.0).tolist()

    assert awake(6) == [0]
    assert awake(7) == [0, 1]  # its own timeout
    positions[3, 0] += 0.5  # pushed: it drifted without being told to move
    assert awake(8) == [0, 1, 3] and ref[3, 0] == positions[3, 0]
    changed = quiet.copy()
    changed[3] = True  # its broadcast changed: robots within 5 + 1 units of it wake
    positions[2, 0] = 25.0
    assert awake(9, changed) == [0, 1, 2, 3]  # robot 2 drifted and is near; 4 is 10.5 away
    asleep[:] = False
    positions[0, 0] = -3.0
    assert awake(10) == [0, 1, 2, 3, 4] and ref[0, 0] == -3.0  # no sleeper: refs follow


def test_hypot_at_most_is_hypot_compared_to_the_bit_at_and_near_the_limit():
    rng = np.random.default_rng(5)
    dx = rng.normal(size=4000) * 10.0 ** rng.integers(-200, 200, 4000)
    dy = rng.normal(size=4000) * 10.0 ** rng.integers(-200, 200, 4000)
    exact = np.hypot(dx, dy)
    ulps = rng.integers(-3, 4, 4000)
    limits = np.concatenate([
        exact,  # on the rim
        np.nextafter(exact, np.where(ulps > 0, np.inf, -np.inf)),  # an ulp either side
        exact * (1 + rng.normal(size=4000) * 1e-9),  # by the margin the squares decide on
        exact * rng.uniform(0, 2, 4000),
        [-1.0, -0.0, 0.0, np.nan, np.inf, 1e-160, 1e200]])
    for k, limit in enumerate(limits):
        i = k % len(dx)
        assert hypot_at_most(dx[i], dy[i], limit) == (np.hypot(dx[i], dy[i]) <= limit), (
            dx[i], dy[i], limit)
    assert hypot_at_most(0.0, 0.0, 0.0) and hypot_at_most(3.0, 4.0, 5.0)
    assert not hypot_at_most(3.0, 4.0, np.nextafter(5.0, 0.0))
