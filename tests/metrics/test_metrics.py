"""Coverage metric on known layouts (paper: 100x100 grid, r = 4)."""

import math
import re
from types import SimpleNamespace

import numpy as np
import pytest
from shapely.geometry import box

from swarmsim.metrics import (
    CoverageGrid,
    MetricPart,
    Observation,
    ProgressPart,
    RunMetrics,
    SettledPart,
    first_within,
    nearest_neighbour_spacing,
)


def hex_lattice(spacing: float, extent: float) -> np.ndarray:
    pts = []
    rows = int(extent / (spacing * math.sqrt(3) / 2)) + 3
    cols = int(extent / spacing) + 3
    for r in range(-2, rows):
        for c in range(-2, cols):
            pts.append((c * spacing + (r % 2) * spacing / 2, r * spacing * math.sqrt(3) / 2))
    return np.array(pts)


def test_hex_lattice_spacing_6_covers_everything():
    grid = CoverageGrid.for_target(box(0, 0, 200, 200), radius=4.0)
    assert grid.coverage(hex_lattice(6.0, 200)) == 1.0


def test_hex_lattice_spacing_8_covers_about_90_7_percent():
    # analytic: 3 * (circle segment area) / hexagon cell area for s = 8, r = 4 -> pi/(2*sqrt3)
    # the box and a shift keep the lattice incommensurate with the 100x100 pixel grid
    grid = CoverageGrid.for_target(box(0, 0, 187.3, 191.1), radius=4.0)
    cov = grid.coverage(hex_lattice(8.0, 200) + np.array([0.37, 0.61]))
    assert abs(cov - math.pi / (2 * math.sqrt(3))) < 0.01


def test_no_robots_no_coverage_and_grid_size():
    grid = CoverageGrid.for_target(box(0, 0, 50, 30), radius=4.0)
    assert grid.shape == (100, 100)
    assert grid.n_target_pixels == 10000
    assert grid.coverage(np.zeros((0, 2))) == 0.0
    one = grid.coverage(np.array([[25.0, 15.0]]))
    assert abs(one - math.pi * 16 / 1500) < 0.01


def test_nearest_neighbour_spacing():
    mean, std, _ = nearest_neighbour_spacing(hex_lattice(6.0, 60))
    assert abs(mean - 6.0) < 1e-9 and std < 1e-9
    assert nearest_neighbour_spacing(np.zeros((1, 2))) == (None, None, None)


def test_incremental_coverage_equals_direct_computation():
    from swarmsim.metrics import IncrementalCoverage

    rng = np.random.default_rng(5)
    grid = CoverageGrid.for_target(box(0, 0, 37.3, 23.9), radius=4.0)
    pos = rng.uniform([-5, -5], [42, 29], size=(30, 2))
    inc = IncrementalCoverage(grid, pos)
    for _ in range(40):
        pos = pos.copy()
        movers = rng.random(30) < 0.3
        pos[movers] += rng.normal(0, 1.5, size=(movers.sum(), 2))
        assert inc.update(pos) == grid.coverage(pos)



def test_incremental_coverage_at_the_rim_and_off_the_grid():
    """Pixel centres exactly r from a robot count as covered; robots that leave the grid and
    come back leave no stamp behind; the count stays the direct computation's."""
    from swarmsim.metrics import IncrementalCoverage

    grid = CoverageGrid.for_target(box(0, 0, 20, 20), radius=2.0, cols=20, rows=20)
    pos = np.array([[5.5, 5.5], [10.5, 12.5], [30.0, 30.0], [-8.0, 3.0]])  # on pixel centres
    inc = IncrementalCoverage(grid, pos)
    assert inc.update(pos) == grid.coverage(pos) == 2 * 13 / 400  # 13 centres within 2.0
    path = [[19.5, 0.5], [25.0, -3.0], [0.5, 19.5], [5.5, 5.5], [60.0, 60.0], [10.5, 12.5]]
    for step, point in enumerate(path):
        pos = pos.copy()
        pos[step % 4] = point
        assert inc.update(pos) == grid.coverage(pos), step


def test_settle_point_ignores_the_flicker_of_robots_passing_by():
    # coverage reaches 0.842 at tick 300; passing robots lift it to 0.8445 later; it ends at
    # 0.8439: it settled at tick 300 (within plateau_delta 0.002), not at the last rise
    rises = [(0.5, 100, 10.0), (0.842, 300, 50.0), (0.843, 700, 90.0), (0.8445, 900, 120.0)]
    assert first_within(rises, 0.8439 - 0.002) == (300, 50.0)
    assert first_within(rises, 0.9) == (0, 0.0)
    coverage = SimpleNamespace(coverage=0.8439, completion_tick=None)
    config = SimpleNamespace(plateau_delta=0.002, v_max=1.0)
    progress = ProgressPart(3, coverage, SettledPart(3, (), 1.0), (), config, False)
    progress._rises = rises
    assert progress.settled_at() == (300, 50.0)
    coverage.completion_tick, progress.completion_distance = 950, 130.0
    assert progress.settled_at() == (950, 130.0)


class Reports(MetricPart):
    """A part that reports the given names (each value: the part's name)."""

    def __init__(self, name: str, columns=(), robots=(), fields=()):
        self.name, self._names = name, (columns, robots, fields)

    def columns(self):
        return {c: lambda: self.name for c in self._names[0]}

    def robot_columns(self):
        return {c: lambda: [self.name] * 2 for c in self._names[1]}

    def summary_fields(self):
        return {c: lambda: self.name for c in self._names[2]}


@pytest.mark.parametrize("output, names, message", [
    ("columns", ("coverage", "coverage"), ("time-series column 'coverage' reported by both "
                                          "metric parts 'a' and 'b'")),
    ("robots", ("distance", "distance"), ("robots.csv column 'distance' reported by both "
                                         "metric parts 'a' and 'b'")),
    ("fields", ("x", "x"), "summary field 'x' reported by both metric parts 'a' and 'b'"),
    ("columns", ("y", "tick"), ("metric part 'b': time-series column 'tick' is the "
                               "collector's own")),
])
def test_two_parts_reporting_one_name_are_refused(output, names, message):
    a, b = (Reports(part, **{output: (name,)}) for part, name in zip("ab", names, strict=True))
    with pytest.raises(ValueError, match=re.escape(message)):
        RunMetrics([a, b], record_every=1)
    with pytest.raises(ValueError, match="name 'a' reported by both"):
        RunMetrics([Reports("a"), Reports("a")], record_every=1)


def test_parts_report_in_their_order_after_the_collectors_own_columns():
    metrics = RunMetrics([Reports("a", columns=("p", "q"), robots=("r",), fields=("s",)),
                          Reports("b", columns=("t",), robots=("u",), fields=("v", "w"))],
                         record_every=5)
    now = Observation(5, np.zeros((2, 2)), np.zeros(2, bool), np.zeros(2), 2, np.zeros((2, 2)),
                      np.zeros(2, bool))
    metrics.observe(now)
    metrics.observe(Observation(6, now.positions, now.on_target, now.messages, 2,
                                now.commanded, now.failed))  # no row
    assert metrics.rows == [{"tick": 5, "p": "a", "q": "a", "t": "b"}]
    assert metrics.robot_rows() == [{"robot": 0, "r": "a", "u": "b"},
                                    {"robot": 1, "r": "a", "u": "b"}]
    assert metrics.summary(now.positions, now.on_target) == {"s": "a", "v": "b", "w": "b"}
