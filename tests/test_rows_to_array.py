"""The engine's broadcast rows -> structured array conversion (swarmsim.sim.rows_to_array)."""

import numpy as np
import pytest

from swarmsim.sim import rows_to_array

DTYPE = np.dtype([("id", "<i4"), ("status", "i1"), ("moving", "?"), ("vx", "<f4"),
                  ("ldist", "<f4", (3,)), ("lepoch", "<i4", (3,))])


def rows(per_group):
    rng = np.random.default_rng(0)
    return [(i, i % 5 - 2, bool(i % 2), float(rng.normal()),
             per_group(rng.normal(size=3) * 1e3), per_group(np.arange(3) + i))
            for i in range(50)]


@pytest.mark.parametrize("per_group", [lambda a: a, lambda a: a.tolist(), tuple],
                         ids=["arrays", "lists", "tuples"])
def test_the_same_bytes_as_numpy_row_by_row(per_group):
    given = rows(per_group)
    assert rows_to_array(given, DTYPE).tobytes() == np.array(given, dtype=DTYPE).tobytes()


def test_bad_rows_fail_as_numpy_would():
    too_big = [(1, 300, True, 0.0, np.zeros(3), np.zeros(3, dtype=int))]
    with pytest.raises(OverflowError):
        np.array(too_big, dtype=DTYPE)
    with pytest.raises(OverflowError):
        rows_to_array(too_big, DTYPE)
    short = [(1, 2, True, 0.0, np.zeros(3))]
    with pytest.raises(ValueError):
        rows_to_array(short, DTYPE)
    wrong_width = [(1, 2, True, 0.0, np.zeros(4), np.zeros(3, dtype=int))]
    with pytest.raises(ValueError):
        rows_to_array(wrong_width, DTYPE)
