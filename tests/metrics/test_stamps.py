"""The compiled coverage stamps (swarmsim/metrics/stamps.py) cover exactly the pixels whose centre
passes the float test (cx - x)^2 + (cy - y)^2 <= r^2, as numpy evaluates it."""

import numpy as np
import pytest

from swarmsim.metrics.stamps import restamp


def brute_counts(positions, x0, y0, dx, dy, r2, rows, cols):
    """Robots covering each pixel, every pixel against every robot (numpy, the same floats)."""
    ey = (y0 + (np.arange(rows) + 0.5) * dy)[:, None] - positions[:, 1][None, :]
    ex = (x0 + (np.arange(cols) + 0.5) * dx)[:, None] - positions[:, 0][None, :]
    ey, ex = ey * ey, ex * ex
    return (ex[None, :, :] + ey[:, None, :] <= r2).sum(axis=2).ravel()


@pytest.mark.parametrize("seed", range(6))
def test_stamps_cover_the_pixels_the_float_test_admits_as_robots_move(seed):
    rng = np.random.default_rng(seed)
    rows, cols = int(rng.integers(5, 60)), int(rng.integers(5, 60))
    dx, dy = rng.uniform(0.1, 1.5), rng.uniform(0.1, 1.5)
    x0, y0 = rng.uniform(-50, 50), rng.uniform(-50, 50)
    radius = rng.uniform(0.05, 8.0)
    r2 = radius * radius
    half_i, half_j = int(np.ceil(radius / dy)) + 1, int(np.ceil(radius / dx)) + 1
    inside = rng.random(rows * cols) < 0.7
    count = np.zeros(rows * cols, dtype=np.int64)
    old = np.full((40, 2), np.nan)
    covered = 0
    for _ in range(5):
        # positions inside, beyond the grid's edges, and on pixel centres and their rims
        new = np.column_stack([x0 + rng.uniform(-3, cols * dx + 3, 40),
                               y0 + rng.uniform(-3, rows * dy + 3, 40)])
        new[:10, 0] = x0 + (rng.integers(0, cols, 10) + 0.5) * dx + radius * rng.choice(
            [-1.0, 1.0, 0.0], 10)
        new[:10, 1] = y0 + (rng.integers(0, rows, 10) + 0.5) * dy
        new[10:12] = np.nan  # a robot nowhere stamps nothing
        covered += restamp(count, inside, old, new, x0, y0, dx, dy, r2, half_i, half_j, rows,
                           cols)
        finite = np.isfinite(new).all(axis=1)
        expected = brute_counts(new[finite], x0, y0, dx, dy, r2, rows, cols)
        assert (count == expected).all()
        assert covered == int(((expected > 0) & inside).sum())
