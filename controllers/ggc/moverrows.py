"""Which of its rows each robot of a chunk reads as a mover, compiled (numba): its nearest
two edge robots, the other groups' movers that outrank it, the moving robots it gives
way to, and the robot it takes its gradient from. The answers of :class:`~controllers.ggc.batch.MoverAnswers`, in one pass over the
chunk's rows instead of a dozen numpy masks over all of them (comparisons only, so the same
answers).
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def mover_rows(starts, d, group, status, sender, moving, own_group, own_id, foreign_edges,
               d_cover, yield_distance, arrive, surplus, coverage, no_sender
               ):  # pragma: no cover - compiled
    """Each robot k's rows (``starts[k]:starts[k+1]``, nearest first) of interest to a mover.

    Args:
        starts: (R+1,) the robots' first rows; d: (P,) distances, units; group, status,
            sender, moving: (P,) the broadcast fields; own_group, own_id: (P,) the listening
            robot's group and id on each of its rows.
        foreign_edges: another group's formation counts as an edge to follow.
        d_cover, yield_distance: units. arrive, surplus, coverage: status codes;
            no_sender: a silent row's id.

    Returns:
        nearest, second: (R,) the first two edge rows (not moving; with ``foreign_edges``
        off, of my group, arrived, surplus or silent), -1: none; movers, movers_first: the
        rows of other groups' robots in Coverage within d_cover with a larger id (robot k's
        are ``movers[movers_first[k]:movers_first[k+1]]``); ahead, ahead_first: the rows of
        moving robots within yield_distance with a larger id, the same way.
    """
    robots, rows = len(starts) - 1, len(d)
    nearest, second = np.full(robots, -1, dtype=np.int64), np.full(robots, -1, dtype=np.int64)
    movers, ahead = np.empty(rows, dtype=np.int64), np.empty(rows, dtype=np.int64)
    movers_first = np.zeros(robots + 1, dtype=np.int64)
    ahead_first = np.zeros(robots + 1, dtype=np.int64)
    n_movers = n_ahead = 0
    for k in range(robots):
        movers_first[k], ahead_first[k] = n_movers, n_ahead
        for row in range(starts[k], starts[k + 1]):
            edge = not moving[row]
            if edge and not foreign_edges:
                edge = (group[row] == own_group[row] or status[row] == arrive
                        or status[row] == surplus or sender[row] == no_sender)
            if edge:
                if nearest[k] < 0:
                    nearest[k] = row
                elif second[k] < 0:
                    second[k] = row
            outranks = sender[row] > own_id[row]
            if (outranks and d[row] <= d_cover and group[row] != own_group[row]
                    and status[row] == coverage):
                movers[n_movers] = row
                n_movers += 1
            if outranks and d[row] <= yield_distance and moving[row]:
                ahead[n_ahead] = row
                n_ahead += 1
    movers_first[robots], ahead_first[robots] = n_movers, n_ahead
    return nearest, second, movers[:n_movers], movers_first, ahead[:n_ahead], ahead_first


@njit(cache=True)
def gradient_sources(a, movers, starts, d, group, own_group, moving, reach
                     ):  # pragma: no cover - compiled
    """The row each mover takes its gradient from (``follow_gradient``): its nearest edge
    robot's (``a[j]``), or where that robot is of another group, the first (nearest) row of
    a stationary robot of its own group within ``reach`` (units); -1: none.

    Args:
        a: (M,) each mover's nearest edge row; movers: (M,) each mover's index in the chunk.
        starts, d, group, own_group, moving: the chunk's rows, as in :func:`mover_rows`.
    """
    source = a.copy()
    for j in range(len(a)):
        if group[a[j]] == own_group[a[j]]:
            continue
        source[j] = -1
        k = movers[j]
        for row in range(starts[k], starts[k + 1]):
            if not moving[row] and group[row] == own_group[row] and d[row] <= reach:
                source[j] = row
                break
    return source


def warm_up(messages: np.ndarray) -> None:
    """Compile (first time on a machine) or load (from the cache) the kernel now, for the
    field types of ``messages`` (a run's broadcast rows)."""
    row = np.zeros(1, dtype=messages.dtype)
    ints = np.zeros(1, dtype=np.int64)
    mover_rows(np.array([0, 1]), np.ones(1), *(np.ascontiguousarray(row[name])
                                             for name in ("group", "status", "id", "moving")),
               ints, ints, True, 1.0, 1.0, 0, 1, 2, -1)
    gradient_sources(ints, ints, np.array([0, 1]), np.ones(1),
                     np.ascontiguousarray(row["group"]), ints,
                     np.ascontiguousarray(row["moving"]), 1.0)
