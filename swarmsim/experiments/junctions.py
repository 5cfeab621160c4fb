"""Uncovered target area where groups meet (the paper's Section 6.1 and 6.2 "gaps at the
junction of each group"), measured on a finished run's stored files.

Definition. Triangulate the robots that have a group (Delaunay; group 0, robots not grouped
yet or failed, are left out): a lattice's triangles, and across a gap the triangles that span
it. A target pixel of the coverage raster (coverage.npz) lies **at a junction** when the
triangle its centre lies in has corners of two groups or more; a pixel outside every triangle
(beyond the swarm's rim) does not. The **junction band** is the set of such pixels; its
**gaps** are the band's uncovered pixels. With one group there is no band, so no junction
gap, whatever the run.

Groups that mix (their robots interleave instead of meeting along a line) make the band wide:
its share of the target is reported with it, and gaps are "at the junctions" only where the
band loses more than its share: :attr:`JunctionGaps.band_density` above the uncovered density
elsewhere. A lattice wider than sqrt(3) r (d_cover 8, 10) leaves holes everywhere, the band's
included, so the band's gaps are also judged against the uncovered density of one-group runs
at the same d_cover (:meth:`JunctionGaps.excess`): what the band would lose without junctions.
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.spatial import Delaunay, QhullError

from swarmsim.errors import ConfigError


@dataclass(frozen=True)
class JunctionGaps:
    """One run's uncovered area, split by the junction band (counts of raster pixels).

    Attributes:
        target: target pixels.
        uncovered: uncovered target pixels.
        band: target pixels at a junction (in a triangle of robots of two groups or more).
        band_uncovered: uncovered pixels in the band (the junction gaps).
        groups: groups that have robots.
    """

    target: int
    uncovered: int
    band: int
    band_uncovered: int
    groups: int

    @property
    def band_share(self) -> float:
        """The band's share of the target, in [0, 1]."""
        return self.band / self.target if self.target else 0.0

    @property
    def outside_density(self) -> float | None:
        """Uncovered share of the target outside the band (None when the band is all)."""
        rest = self.target - self.band
        return (self.uncovered - self.band_uncovered) / rest if rest else None

    @property
    def uncovered_density(self) -> float:
        """Uncovered share of the target, in [0, 1]."""
        return self.uncovered / self.target if self.target else 0.0

    @property
    def band_density(self) -> float | None:
        """Uncovered share of the band (None without a band)."""
        return self.band_uncovered / self.band if self.band else None

    @property
    def junction_share(self) -> float | None:
        """The junction gaps' share of the uncovered area (None when all is covered)."""
        return self.band_uncovered / self.uncovered if self.uncovered else None

    def own_excess(self) -> float:
        """Junction gaps beyond what the band would lose at the uncovered density outside it
        in the same run, as a share of the target (0 without a band or outside)."""
        rest = self.outside_density
        return 0.0 if rest is None or not self.band else self.excess(rest)

    def excess(self, baseline_density: float) -> float:
        """Junction gaps beyond what the band would lose at ``baseline_density`` (the
        uncovered share of the target without junctions, e.g. one group's), as a share of the
        target: (band_uncovered - band x baseline) / target."""
        if not self.target:
            return 0.0
        return (self.band_uncovered - self.band * baseline_density) / self.target


def junction_band(centres: np.ndarray, positions: np.ndarray, groups: np.ndarray
                  ) -> np.ndarray:
    """(M,) bool: which points ``centres`` (M, 2) lie in a triangle of the Delaunay
    triangulation of the grouped robots whose corners are of two groups or more; robots at
    ``positions`` (N, 2), their ``groups`` (N,) ints, group 0 left out. All False with
    fewer than two groups, or no triangle (fewer than three grouped robots, or all on a
    line)."""
    groups = np.asarray(groups)
    mine = groups > 0
    centres = np.asarray(centres, dtype=float).reshape(-1, 2)
    if len(np.unique(groups[mine])) < 2 or mine.sum() < 3 or len(centres) == 0:
        return np.zeros(len(centres), dtype=bool)
    points = np.asarray(positions, dtype=float)[mine]
    try:
        tri = Delaunay(points)
    except QhullError:  # all on a line, say: no triangle, so no junction
        return np.zeros(len(centres), dtype=bool)
    simplex = tri.find_simplex(centres)
    corners = groups[mine][tri.simplices]  # (triangles, 3)
    mixed = (corners != corners[:, :1]).any(axis=1)
    return (simplex >= 0) & mixed[np.maximum(simplex, 0)]


def junction_gaps(target: np.ndarray, covered: np.ndarray, origin: tuple[float, float],
                  cell: tuple[float, float], positions: np.ndarray, groups: np.ndarray
                  ) -> JunctionGaps:
    """:class:`JunctionGaps` of a coverage raster: ``target`` and ``covered`` (rows, cols)
    bool (row index grows with y, as coverage.npz stores them), cell (i, j) centred at
    (x0 + (j + 0.5) dx, y0 + (i + 0.5) dy) for ``origin`` (x0, y0) and ``cell`` (dx, dy),
    units; robots at ``positions`` (N, 2) with their ``groups`` (N,)."""
    rows, cols = np.nonzero(target)
    centres = np.column_stack([origin[0] + (cols + 0.5) * cell[0],
                               origin[1] + (rows + 0.5) * cell[1]])
    band = junction_band(centres, positions, groups)
    open_ = ~np.asarray(covered, bool)[rows, cols]
    groups = np.asarray(groups)
    return JunctionGaps(target=len(centres), uncovered=int(open_.sum()), band=int(band.sum()),
                        band_uncovered=int((band & open_).sum()),
                        groups=len(np.unique(groups[groups > 0])))


def run_junction_gaps(run_dir: str | Path) -> JunctionGaps:
    """:func:`junction_gaps` of a finished run's folder (``swarmsim run --out`` or a sweep's
    ``runs/<id>``): its coverage.npz and robots.csv (x, y, group).

    Raises ConfigError (key ``run``) when a file or the robots' ``group`` column is missing."""
    run = Path(run_dir)
    for name in ("coverage.npz", "robots.csv"):
        if not (run / name).is_file():
            raise ConfigError(f"{run} has no {name}: not a finished run's folder", key="run")
    grid = np.load(run / "coverage.npz")
    with open(run / "robots.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    if rows and "group" not in rows[0]:
        raise ConfigError(f"{run}/robots.csv has no group column (the controller broadcasts "
                          "no group)", key="run")
    positions = np.array([[float(r["x"]), float(r["y"])] for r in rows]).reshape(-1, 2)
    groups = np.array([int(r["group"] or 0) for r in rows], dtype=np.int64)
    return junction_gaps(grid["target"], grid["covered"], (float(grid["x0"]), float(grid["y0"])),
                         (float(grid["dx"]), float(grid["dy"])), positions, groups)


__all__ = ["JunctionGaps", "junction_band", "junction_gaps", "run_junction_gaps"]
