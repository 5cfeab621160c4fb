"""The compiled coverage stamps (swarmsim/metrics/stamps.py) cover exactly the pixels whose centre
passes the float test (cx - x)^2 + (cy - y)^2 <= r^2, as numpy evaluates it."""

import numpy as np
import pytest

from swarmsim.metrics.stamps import new_stamps, restamp


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
    spans, runs = new_stamps(40, half_i, rows)
    covered = 0
    for _ in range(5):
        # positions inside, beyond the grid's edges, and on pixel centres and their rims
        new = np.column_stack([x0 + rng.uniform(-3, cols * dx + 3, 40),
                               y0 + rng.uniform(-3, rows * dy + 3, 40)])
        new[:10, 0] = x0 + (rng.integers(0, cols, 10) + 0.5) * dx + radius * rng.choice(
            [-1.0, 1.0, 0.0], 10)
        new[:10, 1] = y0 + (rng.integers(0, rows, 10) + 0.5) * dy
        new[10:12] = np.nan  # a robot nowhere stamps nothing
        covered += restamp(count, inside, old, new, spans, runs, x0, y0, dx, dy, r2, half_i,
                           half_j, rows, cols)
        finite = np.isfinite(new).all(axis=1)
        expected = brute_counts(new[finite], x0, y0, dx, dy, r2, rows, cols)
        assert (count == expected).all()
        assert covered == int(((expected > 0) & inside).sum())


@pytest.mark.parametrize("seed", range(6))
def test_stamps_follow_small_moves_and_rims_exactly(seed):
    """Robots stepping a fraction of a pixel (most ticks of a run: a stamp then changes at its
    rim only), some onto pixel centres exactly r away, one beyond the grid and back; the
    counts are the brute force's after every step."""
    rng = np.random.default_rng(100 + seed)
    rows, cols = int(rng.integers(5, 40)), int(rng.integers(5, 40))
    dx, dy = rng.uniform(0.2, 1.8), rng.uniform(0.2, 1.8)
    x0, y0 = rng.uniform(-50, 50), rng.uniform(-50, 50)
    radius = rng.choice([rng.uniform(0.05, 1.0), rng.uniform(1.0, 6.0), 2.0 * dx])
    r2 = radius * radius
    half_i, half_j = int(np.ceil(radius / dy)) + 1, int(np.ceil(radius / dx)) + 1
    inside = rng.random(rows * cols) < 0.7
    count = np.zeros(rows * cols, dtype=np.int64)
    old = np.full((30, 2), np.nan)
    spans, runs = new_stamps(30, half_i, rows)
    pos = np.column_stack([x0 + rng.uniform(0, cols * dx, 30), y0 + rng.uniform(0, rows * dy, 30)])
    covered = 0
    for step in range(25):
        pos = pos + rng.normal(0, 0.15, pos.shape) * (rng.random((30, 1)) < 0.6)
        rim = rng.integers(0, 30, 4)  # on a pixel's rim: the float test decides alone
        pos[rim, 0] = x0 + (rng.integers(0, cols, 4) + 0.5) * dx + radius
        pos[rim, 1] = y0 + (rng.integers(0, rows, 4) + 0.5) * dy
        pos[29] = (x0 - 3 * radius, y0) if step % 2 else (x0 + 1.0, y0 + 1.0)
        covered += restamp(count, inside, old, pos, spans, runs, x0, y0, dx, dy, r2, half_i,
                           half_j, rows, cols)
        expected = brute_counts(pos, x0, y0, dx, dy, r2, rows, cols)
        assert (count == expected).all()
        assert covered == int(((expected > 0) & inside).sum())
    assert (old == pos).all()


@pytest.mark.parametrize("radius", [1e100, 1e200])
def test_a_huge_radius_covers_every_pixel(radius):
    """A radius past every guess (1e100) or whose square overflows (1e200: r^2 inf, as
    IncrementalCoverage makes it) covers the whole grid, with a capped stencil."""
    rows, cols, inside = 7, 9, np.ones(63, dtype=bool)
    r2 = radius * radius if radius < 1e150 else np.inf
    count = np.zeros(63, dtype=np.int64)
    old = np.full((2, 2), np.nan)
    new = np.array([[1.0, 2.0], [50.0, -5.0]])
    spans, runs = new_stamps(2, 2**31 + 1, rows)
    covered = restamp(count, inside, old, new, spans, runs, 0.0, 0.0, 1.0, 1.0, r2, 2**31 + 1,
                      2**31 + 1, rows, cols)
    assert covered == 63 and (count >= 1).all()
