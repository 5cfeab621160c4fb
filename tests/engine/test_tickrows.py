"""The compiled per-tick row passes give the numpy expressions' values, to the bit."""

from __future__ import annotations

import numpy as np

from swarmsim.engine import tickrows


def _numpy_clamp(v: np.ndarray, v_max: float) -> np.ndarray:
    speed = np.hypot(v[:, 0], v[:, 1])
    fast = speed > v_max
    v = v.copy()
    v[fast] *= (v_max / speed[fast])[:, None]
    return v


def test_clamp_rows_matches_numpy_on_the_rows_and_leaves_the_others():
    rng = np.random.default_rng(1)
    v = rng.normal(0.0, 0.3, (500, 2))
    v[::7] = 0.0
    v[3] = (0.2, 0.0)  # exactly v_max: kept
    rows = np.arange(0, 500, 2)
    out = v.copy()
    tickrows.clamp_rows(out, rows, 0.2)
    expected = v.copy()
    expected[rows] = _numpy_clamp(v[rows], 0.2)
    assert np.array_equal(out, expected)
    assert np.array_equal(out[1::2], v[1::2])  # not in rows: untouched
    assert np.hypot(out[rows, 0], out[rows, 1]).max() <= 0.2 * (1 + 1e-15)
    assert (np.hypot(v[rows, 0], v[rows, 1]) > 0.2).sum() > 100  # the test clamps many


def test_bearings_match_numpy_and_are_zero_on_the_beacon():
    rng = np.random.default_rng(2)
    at = rng.uniform(-50, 50, (300, 2))
    beacon = (3.25, -7.5)
    at[5] = beacon
    d = np.asarray(beacon) - at
    n = np.hypot(d[:, 0], d[:, 1])[:, None]
    expected = np.divide(d, n, out=np.zeros_like(d), where=n > 1e-12)
    got = tickrows.bearings(beacon, at)
    assert np.array_equal(got, expected)
    assert np.array_equal(got[5], [0.0, 0.0])
    assert np.allclose(np.hypot(got[:5, 0], got[:5, 1]), 1.0)


def test_rows_differ_finds_each_changed_field_in_the_rows_asked():
    dtype = np.dtype([("id", "i4"), ("status", "i1"), ("ldist", "f4", (3,)), ("flag", "?")])
    old = np.zeros(10, dtype=dtype)
    new = old.copy()
    new["status"][1] = 2
    new["ldist"][4, 2] = 1.5
    new["flag"][6] = True
    new["id"][7] = 9  # changed, but not asked about
    got = tickrows.rows_differ(new, old, np.array([1, 2, 4, 6]))
    assert got.tolist() == [i in (1, 4, 6) for i in range(10)]
    assert not tickrows.rows_differ(old, old.copy(), np.arange(10)).any()


def test_put_moves_writes_the_rows_and_caps_listening_at_the_reach():
    velocities, listen = np.zeros((6, 2)), np.full(6, 15.0)
    rows = np.array([4, 1, 2])
    vel = np.array([[0.1, -0.2], [0.0, 0.0], [0.3, 0.4]])
    tickrows.put_moves(rows, vel, np.array([np.nan, 3.0, 99.0]), 15.0, velocities, listen)
    assert np.array_equal(velocities[rows], vel)
    assert np.array_equal(velocities[[0, 3, 5]], np.zeros((3, 2)))
    assert listen.tolist() == [15.0, 3.0, 15.0, 15.0, 15.0, 15.0]


def test_put_sleep_puts_only_still_robots_that_asked_to_sleep():
    n = 6
    asleep, wake_range = np.zeros(n, dtype=bool), np.full(n, -1.0)
    on_motion, wake_tick = np.ones(n, dtype=bool), np.zeros(n, dtype=np.int64)
    rows = np.array([5, 0, 3, 2])
    vel = np.array([[0.0, 0.0], [0.0, 0.1], [0.0, 0.0], [0.0, 0.0]])
    tickrows.put_sleep(rows, vel, np.array([True, True, True, False]),
                       np.array([np.nan, 2.0, 4.0, 1.0]), np.array([False, True, True, False]),
                       np.array([-1, 7, 40, 9]), 15.0, 10**9, asleep, wake_range, on_motion,
                       wake_tick)
    assert np.flatnonzero(asleep).tolist() == [3, 5]  # 0 moves, 2 did not ask
    assert wake_range[[5, 3]].tolist() == [15.0, 4.0]  # NaN: the sensing range
    assert on_motion[[5, 3]].tolist() == [False, True]
    assert wake_tick[[5, 3]].tolist() == [10**9, 40]  # negative: never
    assert wake_range[[0, 1, 2, 4]].tolist() == [-1.0] * 4


def test_c_array_passes_arrays_through_only_when_they_qualify():
    from swarmsim.kernels.carrays import c_array
    a = np.zeros((4, 2))
    assert c_array(a, np.float64) is a
    assert c_array(a[:, 0], np.float64).flags.c_contiguous
    assert c_array(np.arange(3), np.float64).dtype == np.float64
    frozen = np.zeros(3)
    frozen.flags.writeable = False
    assert c_array(frozen, np.float64) is frozen
    copied = c_array(frozen, np.float64, writeable=True)
    assert copied.flags.writeable and np.array_equal(copied, frozen)


RECORD_DTYPES = [np.dtype([("id", "i4"), ("status", "i1"), ("x", "f8", (4,)), ("y", "i2", (3,)),
                           ("z", "u1")]),  # 44 bytes: 4-byte words
                 np.dtype([("id", "i4"), ("status", "i1"), ("ldist", "f4", (3,)), ("flag", "?")]),
                 np.dtype([("id", "i4"), ("g", "f4")]),  # 8-byte words
                 np.dtype([("id", "i4"), ("s", "i1"), ("t", "i1"), ("u", "i1")])]  # 7: bytes


def _random_rows(rng: np.random.Generator, dtype: np.dtype, n: int) -> np.ndarray:
    return rng.integers(0, 256, n * dtype.itemsize, dtype=np.uint8).view(dtype)


def test_rows_differ_is_the_bytewise_comparison_of_the_rows_asked():
    rng = np.random.default_rng(7)
    for dtype in RECORD_DTYPES:
        old = _random_rows(rng, dtype, 300)
        new = old.copy()
        raw = new.view(np.uint8).reshape(300, -1)
        changed = rng.choice(300, 60, replace=False)
        bits = (1 << rng.integers(0, 8, 60)).astype(np.uint8)  # one bit flipped in each
        raw[changed, rng.integers(0, dtype.itemsize, 60)] ^= bits
        rows = np.sort(rng.choice(300, 150, replace=False))
        differ = (new.view(np.uint8).reshape(300, -1) != old.view(np.uint8).reshape(300, -1))
        expected = np.zeros(300, dtype=bool)
        expected[rows] = differ[rows].any(axis=1)
        assert np.array_equal(tickrows.rows_differ(new, old, rows), expected)
        assert expected.sum() > 10
