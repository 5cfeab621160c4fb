"""What observers read of robots' roles from a snapshot: groups and leaders.

The controller names the broadcast fields that carry them (ControllerInfo.group_field and
leader_field; a controller need not have either). A robot that has not broadcast yet (tick 0:
its row is the silent message, status -1) shows the role the run gave it at the start
(``Snapshot.start_groups`` / ``start_leaders``), so the first frame shows the formations'
groups and leaders as they stand.
"""

from __future__ import annotations

import numpy as np

from swarmsim.results.snapshot import Snapshot


def _has(snapshot: Snapshot, field: str | None) -> bool:
    return field is not None and field in (snapshot.messages.dtype.names or ())


def heard(snapshot: Snapshot) -> np.ndarray:
    """(N,) bool: robots that have broadcast at least once (their row is not silent)."""
    return np.asarray(snapshot.messages["status"]) >= 0


def _unheard_start(snapshot: Snapshot, start: np.ndarray | None) -> np.ndarray:
    """(N,) bool: robots to show with their start role: not heard yet, not failed."""
    n = snapshot.n_robots
    if start is None or np.shape(start) != (n,):
        return np.zeros(n, dtype=bool)
    failed = np.asarray(snapshot.failed, dtype=bool).reshape(-1)
    return ~heard(snapshot) & ~(failed if failed.shape == (n,) else np.zeros(n, dtype=bool))


def category(snapshot: Snapshot, field: str, group_field: str | None) -> np.ndarray:
    """(N,) int values of a "category" field (0 = none); the group field's shows robots that
    have not broadcast yet in their start group."""
    if not _has(snapshot, field):
        return np.zeros(snapshot.n_robots, dtype=np.int64)
    g = np.asarray(snapshot.messages[field]).astype(np.int64)
    if field == group_field:
        use_start = _unheard_start(snapshot, snapshot.start_groups)
        if use_start.any():
            g = np.where(use_start, np.asarray(snapshot.start_groups, dtype=np.int64), g)
    return g


def scale(snapshot: Snapshot, field: str) -> tuple[np.ndarray, float]:
    """(N,) int64 values of a "scale" field, and the value meaning "unknown" (the field
    type's largest; negative values mean unknown too). Without the field every value is
    unknown."""
    if not _has(snapshot, field):
        return np.full(snapshot.n_robots, -1, dtype=np.int64), np.inf
    values = np.asarray(snapshot.messages[field])
    kind = values.dtype
    unknown = np.iinfo(kind).max if np.issubdtype(kind, np.integer) else np.inf
    return values.astype(np.int64), unknown


def leaders(snapshot: Snapshot, field: str | None) -> np.ndarray:
    """(N,) bool: robots drawn as leaders (none without a leader field)."""
    n = snapshot.n_robots
    if not _has(snapshot, field):
        return np.zeros(n, dtype=bool)
    lead = np.asarray(snapshot.messages[field], dtype=bool).reshape(-1)
    use_start = _unheard_start(snapshot, snapshot.start_leaders)
    if use_start.any():
        lead = np.where(use_start, np.asarray(snapshot.start_leaders, dtype=bool), lead)
    return lead


def group_count(snapshot: Snapshot, field: str | None) -> int | None:
    """Distinct groups (ids > 0) among robots that have not failed, or None without a group
    field."""
    if not _has(snapshot, field):
        return None
    g = category(snapshot, field, field)
    failed = np.asarray(snapshot.failed, dtype=bool).reshape(-1)
    if failed.shape == g.shape:
        g = g[~failed]
    return len(np.unique(g[g > 0]))
