"""Contact rows from pymunk.batch's arbiter rows: robots by body id, depth and impulse as
numpy computed them before (np.maximum(0, -distance), np.hypot)."""

import numpy as np

from swarmsim.physics.bodysleep import IdTable
from swarmsim.physics.contactrows import from_batch


def test_arbiter_rows_become_contact_rows():
    rng = np.random.default_rng(5)
    bodies = (np.arange(1, 41, dtype=np.uint64) * 48).tolist()
    table = IdTable(bodies[:30], range(30))  # the last 10 bodies are not robots (walls)
    ids = rng.choice(np.array(bodies, dtype=np.uint64), size=2 * 200)
    floats = rng.normal(size=3 * 200)
    floats[2::9] = 0.0  # touching, not overlapping
    robots, depth, impulse = from_batch(ids, floats, *table.arrays)
    rows = floats.reshape(-1, 3)
    assert np.array_equal(robots, table.lookup(ids.reshape(-1, 2)))
    assert (robots == -1).any() and (robots >= 0).any()
    assert np.array_equal(depth, np.maximum(0.0, -rows[:, 2]))
    assert np.array_equal(impulse, np.hypot(rows[:, 0], rows[:, 1]))
