"""What observers read from a snapshot's broadcasts: gradient, group and leader flags.

Each field is read only if the controller's message dtype has it (a controller need not
broadcast a gradient or a group). A robot that has not broadcast yet (tick 0: its row is the
silent message, status -1) shows the role the run gave it at the start
(``Snapshot.start_groups`` / ``start_leaders``), so the first frame shows the formations'
groups and leaders as they stand.
"""

from __future__ import annotations

import numpy as np

from swarmsim.controller import INF_GRADIENT
from swarmsim.snapshot import Snapshot


def _names(snapshot: Snapshot) -> tuple[str, ...]:
    return snapshot.messages.dtype.names or ()


def heard(snapshot: Snapshot) -> np.ndarray:
    """(N,) bool: robots that have broadcast at least once (their row is not silent)."""
    msgs, names = snapshot.messages, _names(snapshot)
    if "status" in names:
        return np.asarray(msgs["status"]) >= 0
    if "id" in names:
        return np.asarray(msgs["id"]) >= 0
    return np.ones(snapshot.n_robots, dtype=bool)


def _unheard_start(snapshot: Snapshot, start: np.ndarray | None) -> np.ndarray:
    """(N,) bool: robots to show with their start role: not heard yet, not failed."""
    n = snapshot.n_robots
    if start is None or np.shape(start) != (n,):
        return np.zeros(n, dtype=bool)
    failed = np.asarray(snapshot.failed, dtype=bool).reshape(-1)
    return ~heard(snapshot) & ~(failed if failed.shape == (n,) else np.zeros(n, dtype=bool))


def groups(snapshot: Snapshot) -> np.ndarray | None:
    """(N,) int group of each robot (0 = none), or None when the broadcasts carry no group."""
    if "group" not in _names(snapshot):
        return None
    g = np.asarray(snapshot.messages["group"]).astype(np.int64)
    use_start = _unheard_start(snapshot, snapshot.start_groups)
    if use_start.any():
        g = np.where(use_start, np.asarray(snapshot.start_groups, dtype=np.int64), g)
    return g


def leaders(snapshot: Snapshot) -> np.ndarray:
    """(N,) bool: robots drawn as leaders (none when the broadcasts carry no leader flag)."""
    n = snapshot.n_robots
    if "leader" not in _names(snapshot):
        return np.zeros(n, dtype=bool)
    lead = np.asarray(snapshot.messages["leader"], dtype=bool).reshape(-1)
    use_start = _unheard_start(snapshot, snapshot.start_leaders)
    if use_start.any():
        lead = np.where(use_start, np.asarray(snapshot.start_leaders, dtype=bool), lead)
    return lead


def gradients(snapshot: Snapshot) -> np.ndarray:
    """(N,) int hop gradient of each robot; INF_GRADIENT when unknown or not broadcast."""
    if "gradient" not in _names(snapshot):
        return np.full(snapshot.n_robots, INF_GRADIENT, dtype=np.int64)
    return np.asarray(snapshot.messages["gradient"]).astype(np.int64)


def group_count(snapshot: Snapshot) -> int | None:
    """Distinct groups (ids > 0) among robots that have not failed, or None without groups."""
    g = groups(snapshot)
    if g is None:
        return None
    failed = np.asarray(snapshot.failed, dtype=bool).reshape(-1)
    if failed.shape == g.shape:
        g = g[~failed]
    return len(np.unique(g[g > 0]))
