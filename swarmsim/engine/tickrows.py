"""Small per-tick passes over the awake robots' rows, compiled (numba).

Each gives the same values as the numpy expression it replaced in sim.py, to the bit: the
same IEEE operations in the same order (numba keeps them: no fast-math), and the distances
the C library's ``hypot``, which numpy's ``hypot`` calls too. Why compiled: each was a few
numpy calls over all robots (or over a chunk), ~40-50 microseconds a tick on K in call
overhead; a loop over the awake rows is a few microseconds.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from swarmsim.kernels.carrays import as_words, c_array
from swarmsim.kernels.warmup import kernel_warm_up


def clamp_rows(velocities: np.ndarray, rows: np.ndarray, v_max: float) -> None:
    """Scale rows ``rows`` of ``velocities`` (N, 2), units per tick, down to at most ``v_max``
    (units per tick) each, keeping their directions; in place. Other rows are left alone."""
    _clamp(velocities, c_array(rows, np.int64), float(v_max))


def bearings(beacon: tuple[float, float], at: np.ndarray) -> np.ndarray:
    """(k, 2) unit vectors from each point of ``at`` (k, 2), units, toward ``beacon`` (x, y);
    a zero row for a point on top of it (closer than 1e-12 units)."""
    return _bearings(float(beacon[0]), float(beacon[1]),
                     c_array(at, np.float64, writeable=True))


def rows_differ(new: np.ndarray, old: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """(N,) bool: which of rows ``rows`` differ, bytewise, between two structured arrays of one
    dtype, (N,) each (the other entries False)."""
    return _differ(as_words(new), as_words(old), c_array(rows, np.int64))


def put_moves(rows: np.ndarray, vel: np.ndarray, listen_in: np.ndarray, reach: float,
              velocities: np.ndarray, listen: np.ndarray) -> int:
    """Write a chunk's actions to the robots ``rows`` (R,): ``velocities[rows] = vel`` (R, 2),
    units per tick, and ``listen[rows]`` the asked ranges ``listen_in`` (R,), units (NaN: the
    sensing range ``reach``), at most ``reach``; in place. Returns -1; -2 (nothing written)
    when ``vel`` or ``listen_in`` is not of one row per robot; or the first k whose velocity
    is not finite or whose asked range is negative (rows from k on are not written)."""
    return _put_moves(c_array(rows, np.int64), c_array(vel, np.float64),
                      c_array(listen_in, np.float64), float(reach), velocities, listen)


def put_sleep(rows: np.ndarray, vel: np.ndarray, sleep: np.ndarray, wake_range_in: np.ndarray,
              wake_on_motion_in: np.ndarray, wake_tick_in: np.ndarray, reach: float,
              never: int, asleep: np.ndarray, wake_range: np.ndarray,
              wake_on_motion: np.ndarray, wake_tick: np.ndarray) -> int:
    """Put to sleep the robots ``rows[k]`` that asked (``sleep[k]``) and stand still (``vel[k]``
    zero), with their wake range (units; NaN: ``reach``; at most ``reach``), whether motion
    wakes them, and their wake tick (negative: ``never``); in place. Returns -1; -2 (nothing
    written) when a column is not of one row per robot; or the first such k whose wake range
    is negative (rows from k on are not written)."""
    return _put_sleep(c_array(rows, np.int64), c_array(vel, np.float64),
                      c_array(sleep, np.bool_), c_array(wake_range_in, np.float64),
                      c_array(wake_on_motion_in, np.bool_),
                      c_array(wake_tick_in, np.int64), float(reach), int(never), asleep,
                      wake_range, wake_on_motion, wake_tick)


def sign_rows(messages: np.ndarray, rows: np.ndarray, statuses: int) -> int:
    """Write each sender's own id into its broadcast: ``messages["id"][i] = i`` for the robots
    ``rows`` (messages: (N,) in a run's message dtype, row i robot i's); in place. Returns -1,
    or the first k whose row's status is not a status code (0 <= status < ``statuses``)."""
    return _sign_rows(messages["id"], messages["status"], c_array(rows, np.int64),
                      int(statuses))


@kernel_warm_up("tick rows")
def warm_up() -> None:
    """Compile (first time on a machine) or load (from the cache) the kernels now."""
    one = np.zeros((1, 2))
    clamp_rows(one, np.zeros(1, dtype=np.int64), 1.0)
    bearings((0.0, 0.0), one)
    for size in ("i8", "i4", "i2", "i1"):  # each word size a run's broadcasts may have
        flag = np.zeros(1, dtype=[("a", size)])
        rows_differ(flag, flag.copy(), np.zeros(1, dtype=np.int64))
    row, no = np.zeros(1, dtype=np.int64), np.zeros(1, dtype=np.bool_)
    put_moves(row, one, np.ones(1), 1.0, one.copy(), np.ones(1))
    put_sleep(row, one, no, np.ones(1), no, row, 1.0, 1, no.copy(), np.ones(1), no.copy(),
              row.copy())


@njit(cache=True)
def _clamp(v, rows, v_max):  # pragma: no cover - compiled
    for i in rows:
        speed = math.hypot(v[i, 0], v[i, 1])
        if speed > v_max:
            scale = v_max / speed
            v[i, 0] *= scale
            v[i, 1] *= scale


@njit(cache=True)
def _bearings(bx, by, at):  # pragma: no cover - compiled
    out = np.zeros_like(at)
    for k in range(at.shape[0]):
        dx, dy = bx - at[k, 0], by - at[k, 1]
        n = math.hypot(dx, dy)
        if n > 1e-12:
            out[k, 0], out[k, 1] = dx / n, dy / n
    return out


@njit(cache=True)
def _differ(a, b, rows):  # pragma: no cover - compiled
    out = np.zeros(a.shape[0], dtype=np.bool_)
    for i in rows:
        for c in range(a.shape[1]):
            if a[i, c] != b[i, c]:
                out[i] = True
                break
    return out


@njit(cache=True)
def _put_moves(rows, vel, listen_in, reach, velocities, listen):  # pragma: no cover
    n = rows.shape[0]
    if vel.shape[0] != n or vel.shape[1] != 2 or listen_in.shape[0] != n:
        return -2
    for k in range(n):
        i = rows[k]
        vx, vy = vel[k, 0], vel[k, 1]
        ask = reach if math.isnan(listen_in[k]) else listen_in[k]
        if not (math.isfinite(vx) and math.isfinite(vy)) or ask < 0:
            return k
        velocities[i, 0], velocities[i, 1] = vx, vy
        listen[i] = min(ask, reach)
    return -1


@njit(cache=True)
def _put_sleep(rows, vel, sleep, wake_range_in, wake_on_motion_in, wake_tick_in, reach,
               never, asleep, wake_range, wake_on_motion, wake_tick):  # pragma: no cover
    n = rows.shape[0]
    if (vel.shape[0] != n or sleep.shape[0] != n or wake_range_in.shape[0] != n
            or wake_on_motion_in.shape[0] != n or wake_tick_in.shape[0] != n):
        return -2
    for k in range(n):
        if not sleep[k] or vel[k, 0] != 0 or vel[k, 1] != 0:
            continue
        i = rows[k]
        ask = reach if math.isnan(wake_range_in[k]) else wake_range_in[k]
        if ask < 0:
            return k
        asleep[i] = True
        wake_on_motion[i] = wake_on_motion_in[k]
        wake_tick[i] = never if wake_tick_in[k] < 0 else wake_tick_in[k]
        wake_range[i] = min(ask, reach)
    return -1


# one signature for every run: the fields of a run's broadcasts are strided, maybe unaligned
# views ('A' layout), or contiguous in a run of one robot
@njit("int64(int32[:], int8[:], int64[::1], int64)", cache=True)
def _sign_rows(ids, status, rows, statuses):  # pragma: no cover - compiled
    bad = -1
    for k in range(rows.shape[0]):
        i = rows[k]
        ids[i] = i
        if bad < 0 and not 0 <= status[i] < statuses:
            bad = k
    return bad
