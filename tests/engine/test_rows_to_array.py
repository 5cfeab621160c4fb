"""The engine's broadcast rows -> structured array conversion
(swarmsim.engine.actioncheck.Broadcasts.array): numpy's values, checked."""

import numpy as np
import pytest

from swarmsim.actionvalues import BadAction
from swarmsim.engine.actioncheck import Broadcasts

DTYPE = np.dtype([("id", "<i4"), ("status", "i1"), ("moving", "?"), ("vx", "<f4"),
                  ("ldist", "<f4", (3,)), ("lepoch", "<i4", (3,))])
BROADCASTS = Broadcasts(DTYPE, ("A", "B", "C", "D", "E"))


def rows(per_group):
    rng = np.random.default_rng(0)
    return [(i, i % 5 - 2, bool(i % 2), float(rng.normal()),
             per_group(rng.normal(size=3) * 1e3), per_group(np.arange(3) + i))
            for i in range(50)]


@pytest.mark.parametrize("per_group", [lambda a: a, lambda a: a.tolist(), tuple],
                         ids=["arrays", "lists", "tuples"])
def test_the_same_bytes_as_numpy_row_by_row_but_the_id(per_group):
    given = rows(per_group)
    got, numpy = BROADCASTS.array(given), np.array(given, dtype=DTYPE)
    assert (got["id"] == 0).all()  # the engine's to write (tickrows.sign_rows)
    numpy["id"] = 0
    assert got.tobytes() == numpy.tobytes()


@pytest.mark.parametrize("bad, names", [
    ((1, 300, True, 0.0, np.zeros(3), np.zeros(3, dtype=int)), "status is 300"),
    ((1, 2, True, 0.0, np.zeros(3)), "tuple of 5 values; expected 6"),
    ((1, 2, True, 0.0, np.zeros(4), np.zeros(3, dtype=int)), "ldist is array"),
    ((1, 2, True, 0.0, np.zeros(3), np.full(3, 0.5)), "lepoch is array"),
    ((1, 2, "yes", 0.0, np.zeros(3), np.zeros(3, dtype=int)), "moving is 'yes'"),
    ((1, 2, True, 1e300, np.zeros(3), np.zeros(3, dtype=int)), r"vx is 1e\+300; expected a number within float32's range")])
def test_a_row_that_does_not_fit_is_named(bad, names):
    good = rows(tuple)[:3]
    with pytest.raises(BadAction, match=names) as caught:
        BROADCASTS.array([*good, bad])
    assert caught.value.row == 3
