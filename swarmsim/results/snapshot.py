"""Snapshots: the read-only picture of a run at one tick, for observers.

Metrics, renderers and users read snapshots; they never touch the physics. Everything in a
snapshot is a copy, so keeping one does not pin the simulation's buffers.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Snapshot:
    """State of the swarm at the end of a tick.

    Attributes:
        tick: tick number (0 = the start layout).
        positions: (N, 2) robot centres, world units.
        messages: (N,) structured array of the robots' last broadcasts: the engine's base
            fields (see swarmsim.controller) and the controller's own; observers read a field
            such as ``gradient`` or ``group`` only if the dtype has it.
        statuses: names of the status codes (index = code) of the controller in use.
        radius: robot body radius, units.
        coverage: coverage fraction P(t) in [0, 1].
        covered: (rows, cols) bool grid of covered target pixels (see metrics.CoverageGrid), or
            None when not requested.
        in_contact: (N,) bool, robots touching another robot or a wall this tick.
        failed: (N,) bool, robots that have failed.
        start_groups: (N,) int, the group the run gave each robot at the start
            (``RobotSetup.group``, 0 = none), or None. Observers use it for robots that have
            not broadcast yet (tick 0), whose ``messages`` rows are silent.
        start_leaders: (N,) bool, the robots the run made leaders at the start
            (``RobotSetup.leader``), or None; used like ``start_groups``.
        headings: (N,) float, each robot's heading, radians in the world frame (0 = +x,
            counter-clockwise), or None for a drive without one (holonomic). Renderers draw a
            heading mark only when it is given.
    """

    tick: int
    positions: np.ndarray
    messages: np.ndarray
    statuses: tuple[str, ...]
    radius: float
    coverage: float
    covered: np.ndarray | None
    in_contact: np.ndarray
    failed: np.ndarray
    start_groups: np.ndarray | None = None
    start_leaders: np.ndarray | None = None
    headings: np.ndarray | None = None

    @property
    def n_robots(self) -> int:
        return int(self.positions.shape[0])
