"""GGC's broadcasts are its state rows' fields and per-group values, cast to the message's
types (state.py)."""

from __future__ import annotations

import numpy as np
import pytest

from controllers.ggc.state import STATE_DTYPE, PerGroup, broadcast_rows, message_fields
from controllers.ggc.statuses import MOVING_STATUSES, STATUSES
from swarmsim.controller import message_dtype


def _random_state(rng: np.random.Generator, n: int) -> np.ndarray:
    """Rows whose every byte is random, then valid statuses, booleans and finite floats."""
    state = np.frombuffer(rng.bytes(n * STATE_DTYPE.itemsize), dtype=STATE_DTYPE).copy()
    for name in STATE_DTYPE.names:
        if STATE_DTYPE[name] == np.bool_:
            state[name] = rng.random(n) < 0.5
    state["status"] = rng.integers(0, len(STATUSES), n)
    for name in ("travel_x", "travel_y", "hole_x", "hole_y"):
        state[name] = rng.normal(0, 50, n)
    return state


def _random_per_group(rng: np.random.Generator, n: int, groups: int) -> PerGroup:
    return PerGroup(ldist=rng.normal(0, 1e3, (n, groups)),
                    lepoch=rng.integers(-2**40, 2**40, (n, groups)))  # wraps to i4


@pytest.mark.parametrize(("groups", "scattered"), [(1, True), (3, True), (16, True),
                                                    (40, True), (3, False), (10, False)])
def test_broadcast_rows_equal_a_field_by_field_numpy_gather(groups, scattered):
    rng = np.random.default_rng(groups)
    state = _random_state(rng, 200)
    per_group = _random_per_group(rng, 200, groups if scattered else 0)
    rows = rng.permutation(200)[:77]
    dtype = message_dtype(message_fields(groups, scattered))
    assert dtype["ldist"].shape == ((groups,) if scattered else (0,))
    got = broadcast_rows(state, per_group, rows, dtype)
    expected = np.zeros(len(rows), dtype=dtype)
    for name in dtype.names:
        if name == "moving":
            expected[name] = np.isin(state["status"][rows], MOVING_STATUSES)
        elif name in PerGroup._fields:
            expected[name] = getattr(per_group, name)[rows]
        else:
            expected[name] = state[name][rows]  # one name in state and broadcast
    assert got.tobytes() == expected.tobytes()
    assert got["moving"].any() and not got["moving"].all()


def test_broadcast_rows_refuse_a_dtype_they_do_not_fill():
    dtype = message_dtype(message_fields(3, True) + [("extra", "i4")])
    with pytest.raises(ValueError, match="GGC broadcasts have the fields"):
        broadcast_rows(np.zeros(2, dtype=STATE_DTYPE), _random_per_group(_rng(), 2, 3),
                       np.arange(2), dtype)


def test_broadcast_rows_refuse_per_group_arrays_narrower_than_the_message():
    dtype = message_dtype(message_fields(3, True))
    with pytest.raises(ValueError, match="holds 3 groups, the per-group arrays 2"):
        broadcast_rows(np.zeros(2, dtype=STATE_DTYPE), _random_per_group(_rng(), 2, 2),
                       np.arange(2), dtype)


def _rng() -> np.random.Generator:
    return np.random.default_rng(0)


def test_open_probes_lists_the_unanswered_questions_in_order():
    from controllers.ggc.rules.common import MAX_PROBES
    from controllers.ggc.swarm import open_probes
    rng = np.random.default_rng(1)
    n = 50
    calls = rng.integers(0, MAX_PROBES + 2, n)  # more calls than slots: only the slots count
    ans = rng.choice(np.array([-1, 0, 1], dtype=np.int8), size=(n, MAX_PROBES))
    req = rng.normal(size=(n, MAX_PROBES, 2))
    todo = np.flatnonzero(rng.random(n) < 0.6)
    robots, slots, offsets = open_probes(todo, calls, ans, req)
    rows, c = np.nonzero((np.arange(MAX_PROBES) < calls[todo, None]) & (ans[todo] < 0))
    assert robots.tolist() == todo[rows].tolist() and slots.tolist() == c.tolist()
    assert np.array_equal(offsets, req[todo[rows], c])
    assert len(robots) > 10
