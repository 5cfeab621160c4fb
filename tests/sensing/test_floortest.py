"""The compiled floor test answers as shapely's contains_xy: interior only, holes excluded."""

import numpy as np
import pytest
import shapely
from shapely.geometry import Polygon

from swarmsim.sensing.floortest import contains, polygon_edges, probe
from swarmsim.sensing.sensing import FloorSensor
from swarmsim.world.world import load_world

RING = Polygon([(0, 0), (10, 0), (10, 10), (0, 10)], [[(3, 3), (7, 3), (7, 7), (3, 7)]])


@pytest.mark.parametrize("target", [load_world("K").target, load_world("house").target, RING],
                         ids=["K", "house", "ring with a hole"])
def test_the_same_answers_as_shapely_inside_outside_and_on_the_outline(target):
    rng = np.random.default_rng(0)
    lo, hi = np.array(target.bounds[:2]) - 2, np.array(target.bounds[2:]) + 2
    xy = rng.uniform(lo, hi, (50_000, 2))
    corners = np.vstack([np.asarray(r.coords) for r in (target.exterior, *target.interiors)])
    on_edges = (corners[:-1] + corners[1:]) / 2
    xy = np.vstack([xy, corners, on_edges])
    mine = contains(xy[:, 0], xy[:, 1], polygon_edges(target))
    theirs = shapely.contains_xy(target, xy[:, 0], xy[:, 1])
    assert np.array_equal(mine, theirs)
    assert 0.2 < mine.mean() < 0.8


def test_probes_stop_at_the_first_offset_past_the_range():
    at = np.array([[5.0, 1.5], [1.5, 5.0]])
    found, beyond = probe(at, np.array([0, 1]), np.array([[0.0, 0.0], [3.0, 0.0]]), 9.0,
                          polygon_edges(RING))
    assert beyond == -1 and found.tolist() == [True, False]  # (4.5, 5.0) is in the hole
    _, beyond = probe(at, np.array([0, 1]), np.array([[0.0, 0.0], [3.0, 0.0]]), 8.0,
                      polygon_edges(RING))
    assert beyond == 1
    many = FloorSensor(RING, probe_range=2.0).probes(at)
    with pytest.raises(ValueError, match="beyond the probe range"):
        many(np.array([1]), np.array([[3.0, 0.0]]))
