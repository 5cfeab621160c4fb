"""What each waiting robot (Detection) of a chunk reads from its rows, compiled (numba): is a
Surplus robot of its group near, the gradient it takes, and is its way out blocked by a
waiting robot or by a mover (Algorithms 1 and 7). The answers of the numpy masks batch.py
used before, in one pass over each waiting robot's own rows (integer tests and comparisons
of the same floats, so the same answers).
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def waiting_answers(starts, d, group, status, sender, moving, gradient, enclosed, chosen,
                    own_group, own_id, own_grad, codes, reaches, inf_gradient, no_sender,
                    surplus_rule, several_groups):  # pragma: no cover - compiled
    """For each chosen robot ``k = chosen[j]`` (rows ``starts[k]:starts[k+1]``;
    ``own_group[j]``, ``own_id[j]``, ``own_grad[j]`` its group, id and gradient):

    Args:
        codes: the status codes (ARRIVE, SURPLUS, STOP, COVERAGE).
        reaches: (surplus reach d_cover + arrive_tolerance, formation reach 1.5 d_min,
            rival reach d_cover), units.

    Returns (each (C,), in the order of ``chosen``): surplus (bool: a Surplus robot of my
    group within the surplus reach, when ``surplus_rule``), best (int64: the smallest gradient
    among my group's stationary robots within 1.5 d_min that are not in Coverage;
    ``inf_gradient``: none), by_waiting and by_any (bool: a rival, a robot of my group within
    d_cover that is neither settled nor enclosed (nor, with several groups, in Stop) and
    outranks me by gradient then id, that is waiting / of any kind).
    """
    arrive, surplus_code, stop, coverage = codes[0], codes[1], codes[2], codes[3]
    surplus_reach, formation_reach, rival_reach = reaches[0], reaches[1], reaches[2]
    c = len(chosen)
    surplus = np.zeros(c, dtype=np.bool_)
    best = np.full(c, inf_gradient, dtype=np.int64)
    by_waiting, by_any = np.zeros(c, dtype=np.bool_), np.zeros(c, dtype=np.bool_)
    for j in range(c):
        k = chosen[j]
        mine_group = own_group[j]
        for row in range(starts[k], starts[k + 1]):
            if group[row] != mine_group:
                continue
            if surplus_rule and d[row] <= surplus_reach and status[row] == surplus_code:
                surplus[j] = True
            if (d[row] <= formation_reach and sender[row] != no_sender and not moving[row]
                    and gradient[row] < inf_gradient and status[row] != coverage):
                best[j] = min(best[j], gradient[row])
        g = best[j] + 1 if best[j] < inf_gradient else own_grad[j]
        for row in range(starts[k], starts[k + 1]):
            s = status[row]
            if (d[row] <= rival_reach and group[row] == mine_group and sender[row] != no_sender
                    and s != arrive and s != surplus_code and not enclosed[row]
                    and not (several_groups and s == stop)
                    and (gradient[row] > g or (gradient[row] == g and sender[row] > own_id[j]))):
                by_any[j] = True
                if not moving[row]:
                    by_waiting[j] = True
    return surplus, best, by_waiting, by_any


def warm_up(messages: np.ndarray) -> None:
    """Compile (first time on a machine) or load (from the cache) the kernel now, for the
    field types of ``messages`` (a run's broadcast rows)."""
    row = np.zeros(1, dtype=messages.dtype)
    ints = np.zeros(1, dtype=np.int64)
    waiting_answers(np.array([0, 1]), np.ones(1),
                    *(np.ascontiguousarray(row[name]) for name in
                      ("group", "status", "id", "moving", "gradient", "enclosed")),
                    ints, ints, ints, ints, np.zeros(4, dtype=np.int64), np.ones(3), 1, -1,
                    True, True)
