"""The compiled coverage stamps (swarmsim/metrics/stamps.py) cover exactly the pixels whose centre
passes the float test (cx - x)^2 + (cy - y)^2 <= r^2, as numpy evaluates it."""

from typing import NamedTuple

import numpy as np
import pytest

from swarmsim.metrics.stamps import new_stamps, restamp


def brute_counts(positions, x0, y0, dx, dy, r2, rows, cols):
    """Robots covering each pixel, every pixel against every robot (numpy, the same floats)."""
    ey = (y0 + (np.arange(rows) + 0.5) * dy)[:, None] - positions[:, 1][None, :]
    ex = (x0 + (np.arange(cols) + 0.5) * dx)[:, None] - positions[:, 0][None, :]
    ey, ex = ey * ey, ex * ex
    return (ex[None, :, :] + ey[:, None, :] <= r2).sum(axis=2).ravel()


class Grid(NamedTuple):
    """A random coverage grid and empty stamps for ``robots`` robots (restamp's arguments)."""
    rows: int
    cols: int
    dx: float
    dy: float
    x0: float
    y0: float
    radius: float
    half_i: int
    half_j: int
    inside: np.ndarray
    count: np.ndarray
    old: np.ndarray
    spans: np.ndarray
    runs: np.ndarray

    def restamp(self, new: np.ndarray) -> int:
        return restamp(self.count, self.inside, self.old, new, self.spans, self.runs, self.x0,
                       self.y0, self.dx, self.dy, self.radius * self.radius, self.half_i, self.half_j,
                       self.rows, self.cols)

    def brute(self, positions: np.ndarray) -> np.ndarray:
        return brute_counts(positions, self.x0, self.y0, self.dx, self.dy, self.radius * self.radius,
                            self.rows, self.cols)


def random_grid(rng, most_cells: int, pixel: tuple[float, float], radius_of, robots: int
                ) -> Grid:
    """Up to ``most_cells`` rows and columns of pixels ``pixel`` (low, high) units wide; the
    radius ``radius_of(rng, dx)``; 70 % of the pixels inside the target."""
    rows, cols = int(rng.integers(5, most_cells)), int(rng.integers(5, most_cells))
    dx, dy = rng.uniform(*pixel), rng.uniform(*pixel)
    x0, y0 = rng.uniform(-50, 50), rng.uniform(-50, 50)
    radius = radius_of(rng, dx)
    half_i, half_j = int(np.ceil(radius / dy)) + 1, int(np.ceil(radius / dx)) + 1
    spans, runs = new_stamps(robots, half_i, rows)
    return Grid(rows, cols, dx, dy, x0, y0, radius, half_i, half_j,
                rng.random(rows * cols) < 0.7, np.zeros(rows * cols, dtype=np.int64),
                np.full((robots, 2), np.nan), spans, runs)


@pytest.mark.parametrize("seed", range(6))
def test_stamps_cover_the_pixels_the_float_test_admits_as_robots_move(seed):
    rng = np.random.default_rng(seed)
    g = random_grid(rng, 60, (0.1, 1.5), lambda rng, dx: rng.uniform(0.05, 8.0), 40)
    covered = 0
    for _ in range(5):
        # positions inside, beyond the grid's edges, and on pixel centres and their rims
        new = np.column_stack([g.x0 + rng.uniform(-3, g.cols * g.dx + 3, 40),
                               g.y0 + rng.uniform(-3, g.rows * g.dy + 3, 40)])
        new[:10, 0] = g.x0 + (rng.integers(0, g.cols, 10) + 0.5) * g.dx + g.radius * rng.choice(
            [-1.0, 1.0, 0.0], 10)
        new[:10, 1] = g.y0 + (rng.integers(0, g.rows, 10) + 0.5) * g.dy
        new[10:12] = np.nan  # a robot nowhere stamps nothing
        covered += g.restamp(new)
        finite = np.isfinite(new).all(axis=1)
        expected = g.brute(new[finite])
        assert (g.count == expected).all()
        assert covered == int(((expected > 0) & g.inside).sum())


@pytest.mark.parametrize("seed", range(6))
def test_stamps_follow_small_moves_and_rims_exactly(seed):
    """Robots stepping a fraction of a pixel (most ticks of a run: a stamp then changes at its
    rim only), some onto pixel centres exactly r away, one beyond the grid and back; the
    counts are the brute force's after every step."""
    rng = np.random.default_rng(100 + seed)
    g = random_grid(rng, 40, (0.2, 1.8), lambda rng, dx: rng.choice(
        [rng.uniform(0.05, 1.0), rng.uniform(1.0, 6.0), 2.0 * dx]), 30)
    pos = np.column_stack([g.x0 + rng.uniform(0, g.cols * g.dx, 30),
                           g.y0 + rng.uniform(0, g.rows * g.dy, 30)])
    covered = 0
    for step in range(25):
        pos = pos + rng.normal(0, 0.15, pos.shape) * (rng.random((30, 1)) < 0.6)
        rim = rng.integers(0, 30, 4)  # on a pixel's rim: the float test decides alone
        pos[rim, 0] = g.x0 + (rng.integers(0, g.cols, 4) + 0.5) * g.dx + g.radius
        pos[rim, 1] = g.y0 + (rng.integers(0, g.rows, 4) + 0.5) * g.dy
        pos[29] = (g.x0 - 3 * g.radius, g.y0) if step % 2 else (g.x0 + 1.0, g.y0 + 1.0)
        covered += g.restamp(pos)
        expected = g.brute(pos)
        assert (g.count == expected).all()
        assert covered == int(((expected > 0) & g.inside).sum())
    assert (g.old == pos).all()


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
