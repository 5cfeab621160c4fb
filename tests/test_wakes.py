"""The compiled wake step (swarmsim/wakes.py) gives the numpy code's answers: which robots
drifted or were pushed, and which sleepers a changed robot wakes."""

import numpy as np

from swarmsim.wakes import drifted, wake_pairs


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


def test_wake_pairs_is_the_numpy_rule():
    rng = np.random.default_rng(9)
    woken = 0
    for _ in range(50):
        n, pairs = int(rng.integers(2, 200)), int(rng.integers(0, 400))
        positions = rng.integers(0, 40, size=(n, 2)) * 0.25  # exact rims: 2.25, 6.25, 15.25
        asleep = rng.random(n) < 0.6
        wake_range = rng.choice([2.0, 6.0, 15.0], size=n)
        wake_on_motion, wakes_all = rng.random(n) < 0.5, rng.random(n) < 0.3
        sources = np.unique(rng.integers(0, n, size=int(rng.integers(1, 20))))
        k = rng.integers(0, len(sources), size=pairs)
        near = rng.integers(0, n, size=pairs)
        margin = 0.25
        src = sources[k]  # the numpy code's masks
        d = np.hypot(*(positions[near] - positions[src]).T)
        hit = asleep[near] & (d <= wake_range[near] + margin)
        hit &= wake_on_motion[near] | wakes_all[src]
        want = asleep.copy()
        want[near[hit]] = False
        wake_pairs(positions, asleep, wake_range, wake_on_motion, wakes_all, sources, k, near,
                   margin)
        assert asleep.tolist() == want.tolist()
        woken += int(hit.any())
    assert woken > 20
