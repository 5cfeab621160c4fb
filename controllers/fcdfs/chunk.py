"""FCDFS's decision for a chunk of robots, compiled (numba): :func:`decide_chunk` runs, for
every robot it is given, what ``FCDFSRobot.step`` (robot.py) does, with the same arithmetic in
the same order, so the same numbers to the bit (Python's ``math.hypot`` where the robot calls
``unit``: controllers/common/pyhypot.py; the C library's ``hypot`` where it calls
``np.hypot``, as numba's ``math.hypot`` does).

Floor probes are asked from Python (the engine's ``probe_many``), and which probes a robot asks
depends on earlier answers. So a robot is decided as a transaction against :class:`Probes`, a
cache of the chunk's asked probes: a probe not in the cache is recorded as a question, read as
False, and the robot is marked ``missed``; at the end of its decision a robot that missed is
put back as it was (its rows restored, no action written). swarm.py asks the questions at once
and decides those robots again, until none misses: every robot ends decided on true answers
only, having asked only probes it asks (the engine's probes are pure lookups of the floor).

The robots' state lives in the columns of :class:`Rows`, the chunk's sensing in
:class:`Sensed`, the parameters in :class:`Params`; the kernel writes the chunk's actions into
:class:`Out`. Robot k of the chunk is robot ``rows[k]`` and owns neighbour rows
``starts[k]:starts[k + 1]``.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from controllers.common.formation import CMD_HALT, CMD_TRAVEL
from controllers.common.formationkernel import unit
from controllers.common.gradient import INF_GRADIENT
from swarmsim.controller import NO_SENDER

from .params import DOOR, MAX_HOPS, MIN_PROBE_RANGE, MOVING, NO_DOOR, QUEUE, SETTLED, TRAVEL

AXES_X = (1, 0, -1, 0)
AXES_Y = (0, 1, 0, -1)
GO, WAIT, SETTLE = 0, 1, 2  # what FCDFSRobot.decide chose: a cell, None, "settle"


class Rows(NamedTuple):
    """The run's robots' state, row i robot i's (FCDFSRobot's attributes)."""

    robot_id: np.ndarray  # (N,) int64
    leader: np.ndarray  # (N,) bool
    status: np.ndarray  # (N,) int64
    grad: np.ndarray  # (N,) int64
    cmd: np.ndarray  # (N,) int64
    travel: np.ndarray  # (N, 2) units per tick
    door: np.ndarray  # (N,) int64, the door robot's id (NO_DOOR: none)
    pdir: np.ndarray  # (N,) int64, index into AXES
    touch: np.ndarray  # (N,) bool
    hops: np.ndarray  # (N,) int64
    cell: np.ndarray  # (N, 2) int64
    goal: np.ndarray  # (N, 2) int64
    has_goal: np.ndarray  # (N,) bool (FCDFSRobot's goal is not None)
    hist_n: np.ndarray  # (N,) int64, len(history) (capped at 2: only the last two are read)
    hist: np.ndarray  # (N, 2, 2) int64, history[-1], history[-2]
    pos: np.ndarray  # (N, 2) position from the door, units
    waited: np.ndarray  # (N,) int64
    stepping: np.ndarray  # (N,) bool
    stepped: np.ndarray  # (N,) units


class Sensed(NamedTuple):
    """A chunk's sensing (swarmsim.controller.DecideBatch) as C-contiguous columns."""

    tick: int
    rows: np.ndarray  # (R,) int64
    starts: np.ndarray  # (R + 1,) int64
    offsets: np.ndarray  # (P, 2) units
    distances: np.ndarray  # (P,) units
    sender: np.ndarray  # (P,) int64 (NO_SENDER: not heard)
    status: np.ndarray  # (P,) int64
    moving: np.ndarray  # (P,) bool
    gradient: np.ndarray  # (P,) int64
    cmd: np.ndarray  # (P,) int64
    vx: np.ndarray  # (P,) float64
    vy: np.ndarray  # (P,) float64
    door: np.ndarray  # (P,) int64
    pdir: np.ndarray  # (P,) int64
    touch: np.ndarray  # (P,) bool
    hops: np.ndarray  # (P,) int64
    ci: np.ndarray  # (P,) int64
    cj: np.ndarray  # (P,) int64
    on_target: np.ndarray  # (R,) bool
    moved: np.ndarray  # (R, 2) units
    beacons: np.ndarray  # (R, 2) (zeros without a beacon)
    has_beacon: bool


class Params(NamedTuple):
    """FCDFSParams' values (spacing and clearance resolved)."""

    d_safe: float
    d_min: float
    v: float
    turn: int
    queue_gap: float
    door_depth: float
    door_radius: float
    clearance: float
    arrive_tolerance: float
    avoid_range: float
    patience: int
    init_timeout: int
    spacing: float


class Probes(NamedTuple):
    """The chunk's probe cache: robot k's j-th question ``offsets[k, j]`` (units) and its
    answer ``answers[k, j]`` (-1: not asked yet), ``count[k]`` of them; ``missed[k]``: robot k
    read a probe not yet answered this round."""

    offsets: np.ndarray  # (R, Q, 2)
    answers: np.ndarray  # (R, Q) int8
    count: np.ndarray  # (R,) int64
    missed: np.ndarray  # (R,) bool


class Out(NamedTuple):
    """The chunk's actions and the broadcast fields act() derives, row k robot k's."""

    velocity: np.ndarray  # (R, 2)
    listen: np.ndarray  # (R,) NaN: None
    sleep: np.ndarray  # (R,) bool
    wake_range: np.ndarray  # (R,) NaN: None
    wake_tick: np.ndarray  # (R,) int64, -1: None
    moving: np.ndarray  # (R,) bool
    gradient: np.ndarray  # (R,) int64
    ci: np.ndarray  # (R,) int64
    cj: np.ndarray  # (R,) int64


@njit(cache=True)
def _probe(q, k, ox, oy):  # pragma: no cover - compiled
    """Robot k's probe at (ox, oy): the cached answer, or a new question (read as False)."""
    for j in range(q.count[k]):
        if q.offsets[k, j, 0] == ox and q.offsets[k, j, 1] == oy:
            if q.answers[k, j] < 0:
                q.missed[k] = True
                return False
            return q.answers[k, j] == 1
    j = q.count[k]
    if j >= q.answers.shape[1]:
        raise RuntimeError("an FCDFS robot asked more floor probes in one tick than its cache holds")
    q.offsets[k, j, 0], q.offsets[k, j, 1] = ox, oy
    q.answers[k, j] = -1
    q.count[k] = j + 1
    q.missed[k] = True
    return False


@njit(cache=True)
def _rotate(dx, dy, turn):  # pragma: no cover - compiled
    """params.rotate."""
    if turn > 0:
        return -dy, dx
    return dy, -dx


@njit(cache=True)
def _axis(dx, dy):  # pragma: no cover - compiled
    """AXES.index((dx, dy))."""
    for a in range(4):
        if AXES_X[a] == dx and AXES_Y[a] == dy:
            return a
    return -1


@njit(cache=True)
def _act(rows, p, k, i, out, vx, vy, sleep, wake_range, wake_tick):  # pragma: no cover
    """FCDFSRobot.act: the action and the broadcast fields it derives."""
    out.velocity[k, 0], out.velocity[k, 1] = vx, vy
    out.sleep[k], out.wake_range[k], out.wake_tick[k] = sleep, wake_range, wake_tick
    st = rows.status[i]
    if st == MOVING and rows.has_goal[i]:
        c0, c1 = rows.goal[i, 0], rows.goal[i, 1]
    else:
        c0, c1 = rows.cell[i, 0], rows.cell[i, 1]
    if st == TRAVEL or st == QUEUE or st == DOOR:
        out.gradient[k] = rows.grad[i]
    else:
        out.gradient[k] = abs(c0) + abs(c1)
    out.ci[k], out.cj[k] = c0, c1
    out.moving[k] = st == MOVING or ((st == QUEUE or st == DOOR) and (vx != 0.0 or vy != 0.0))
    if st == TRAVEL and not rows.leader[i]:
        out.listen[k] = 1.5 * p.d_min
    elif st == SETTLED or st == DOOR:
        out.listen[k] = p.d_safe
    else:
        out.listen[k] = math.nan


@njit(cache=True)
def _go_act(rows, p, k, i, out, vx, vy):  # pragma: no cover - compiled
    """act(velocity)."""
    _act(rows, p, k, i, out, vx, vy, False, math.nan, -1)


@njit(cache=True)
def _sleep_act(rows, p, k, i, out, wake_range):  # pragma: no cover - compiled
    """act(sleep=True, wake_range=wake_range)."""
    _act(rows, p, k, i, out, 0.0, 0.0, True, wake_range, -1)


@njit(cache=True)
def _snapshot(rows, i):  # pragma: no cover - compiled
    """Robot i's rows, to put back if its decision read an unanswered probe."""
    ints = np.array([rows.status[i], rows.grad[i], rows.cmd[i], rows.door[i], rows.pdir[i],
                     rows.hops[i], rows.cell[i, 0], rows.cell[i, 1], rows.goal[i, 0],
                     rows.goal[i, 1], rows.hist_n[i], rows.hist[i, 0, 0], rows.hist[i, 0, 1],
                     rows.hist[i, 1, 0], rows.hist[i, 1, 1], rows.waited[i],
                     np.int64(rows.touch[i]), np.int64(rows.has_goal[i]),
                     np.int64(rows.stepping[i])])
    floats = np.array([rows.travel[i, 0], rows.travel[i, 1], rows.pos[i, 0], rows.pos[i, 1],
                       rows.stepped[i]])
    return ints, floats


@njit(cache=True)
def _restore(rows, i, ints, floats):  # pragma: no cover - compiled
    """Put robot i's rows back as :func:`_snapshot` took them."""
    rows.status[i], rows.grad[i], rows.cmd[i], rows.door[i] = ints[0], ints[1], ints[2], ints[3]
    rows.pdir[i], rows.hops[i], rows.cell[i, 0], rows.cell[i, 1] = ints[4], ints[5], ints[6], ints[7]
    rows.goal[i, 0], rows.goal[i, 1], rows.hist_n[i] = ints[8], ints[9], ints[10]
    rows.hist[i, 0, 0], rows.hist[i, 0, 1] = ints[11], ints[12]
    rows.hist[i, 1, 0], rows.hist[i, 1, 1] = ints[13], ints[14]
    rows.waited[i] = ints[15]
    rows.touch[i], rows.has_goal[i], rows.stepping[i] = ints[16] != 0, ints[17] != 0, ints[18] != 0
    rows.travel[i, 0], rows.travel[i, 1] = floats[0], floats[1]
    rows.pos[i, 0], rows.pos[i, 1], rows.stepped[i] = floats[2], floats[3], floats[4]


@njit(cache=True)
def decide_chunk(rows, s, p, q, todo, out):  # pragma: no cover - compiled
    """Decide the chunk's robots ``todo`` (chunk indices) as FCDFSRobot.step does, against
    the probe cache ``q``; a robot that read an unanswered probe is put back (q.missed)."""
    for k in todo:
        i = s.rows[k]
        ints, floats = _snapshot(rows, i)
        q.missed[k] = False
        _step(rows, s, p, q, k, i, out)
        if q.missed[k]:
            _restore(rows, i, ints, floats)


@njit(cache=True)
def _step(rows, s, p, q, k, i, out):  # pragma: no cover - compiled
    """FCDFSRobot.step."""
    rows.pos[i, 0] = rows.pos[i, 0] + s.moved[k, 0]
    rows.pos[i, 1] = rows.pos[i, 1] + s.moved[k, 1]
    st = rows.status[i]
    if st == TRAVEL:
        rows.touch[i] = s.on_target[k]
        if rows.leader[i]:
            _lead(rows, s, p, q, k, i, out)
        else:
            _follow(rows, s, p, q, k, i, out)
    elif st == QUEUE:
        _queue(rows, s, p, q, k, i, out)
    elif st == MOVING:
        _moving(rows, s, p, q, k, i, out)
    elif st == DOOR and rows.stepping[i]:
        _door_step(rows, s, p, q, k, i, out)
    else:
        _sleep_act(rows, p, k, i, out, 0.0)


# ---------------------------------------------------------------------- travel (formation)
@njit(cache=True)
def _formation_gradient(s, k, p):  # pragma: no cover - compiled
    """FCDFSRobot.formation_gradient (-1: None)."""
    found, best = False, 0
    for j in range(s.starts[k], s.starts[k + 1]):
        if s.distances[j] > 1.5 * p.d_min:
            break  # the rows are nearest first
        st = s.status[j]
        if (s.sender[j] != NO_SENDER
                and (st == TRAVEL or st == QUEUE or st == DOOR)
                and s.gradient[j] < INF_GRADIENT and (not found or s.gradient[j] < best)):
            found, best = True, s.gradient[j]
    return best + 1 if found else -1


@njit(cache=True)
def _travel_parent(rows, s, p, k, i):  # pragma: no cover - compiled
    """FormationTravel.travel_parent (formationkernel.first_parent), -1: None."""
    for j in range(s.starts[k], s.starts[k + 1]):
        if s.distances[j] > 1.5 * p.d_min:
            break  # the rows are nearest first
        if (not s.moving[j] and s.sender[j] != NO_SENDER
                and s.gradient[j] == rows.grad[i] - 1):
            return j
    return -1


@njit(cache=True)
def _lead(rows, s, p, q, k, i, out):  # pragma: no cover - compiled
    """FCDFSRobot.lead."""
    touching = -1
    for j in range(s.starts[k], s.starts[k + 1]):
        if s.touch[j] and s.sender[j] != NO_SENDER and s.status[j] == TRAVEL:
            touching = j
            break
    if s.on_target[k] or touching >= 0 or not s.has_beacon:
        rows.cmd[i] = CMD_HALT
        rows.travel[i, 0], rows.travel[i, 1] = 0.0, 0.0
        if s.on_target[k] or touching < 0:
            rows.door[i] = rows.robot_id[i]
        else:
            rows.door[i] = s.sender[touching]
        if s.has_beacon:
            bx, by = s.beacons[k, 0], s.beacons[k, 1]
            best, arg = 0.0, -1
            for a in range(4):
                dot = bx * AXES_X[a] + by * AXES_Y[a]
                if arg < 0 or dot > best:
                    best, arg = dot, a
            rows.pdir[i] = arg
        _halt(rows, s, p, q, k, i, out)
        return
    rows.cmd[i] = CMD_TRAVEL
    rows.travel[i, 0], rows.travel[i, 1] = s.beacons[k, 0] * p.v, s.beacons[k, 1] * p.v
    _go_act(rows, p, k, i, out, rows.travel[i, 0], rows.travel[i, 1])


@njit(cache=True)
def _follow(rows, s, p, q, k, i, out):  # pragma: no cover - compiled
    """FCDFSRobot.follow (FormationTravel.follow_travel)."""
    grad = _formation_gradient(s, k, p)
    parent = -1
    if grad >= 0:
        rows.grad[i] = grad
        parent = _travel_parent(rows, s, p, k, i)
    if parent < 0:
        if s.tick >= p.init_timeout:
            rows.cmd[i] = CMD_HALT
            _halt(rows, s, p, q, k, i, out)
            return
        _act(rows, p, k, i, out, 0.0, 0.0, True, 1.5 * p.d_min, p.init_timeout)
        return
    cmd = s.cmd[parent]
    rows.cmd[i] = cmd
    if cmd == CMD_TRAVEL:
        rows.travel[i, 0], rows.travel[i, 1] = s.vx[parent], s.vy[parent]
    else:
        rows.travel[i, 0], rows.travel[i, 1] = 0.0, 0.0
    if cmd == CMD_HALT:
        rows.door[i], rows.pdir[i] = s.door[parent], s.pdir[parent]
        _halt(rows, s, p, q, k, i, out)
        return
    _go_act(rows, p, k, i, out, rows.travel[i, 0], rows.travel[i, 1])


@njit(cache=True)
def _halt(rows, s, p, q, k, i, out):  # pragma: no cover - compiled
    """FCDFSRobot.halt."""
    if rows.door[i] == rows.robot_id[i]:
        rows.status[i], rows.hops[i] = DOOR, 0
        rows.cell[i, 0], rows.cell[i, 1] = 0, 0
        rows.stepping[i] = True
        _door_step(rows, s, p, q, k, i, out)
        return
    rows.status[i] = QUEUE
    _go_act(rows, p, k, i, out, 0.0, 0.0)


@njit(cache=True)
def _door_step(rows, s, p, q, k, i, out):  # pragma: no cover - compiled
    """FCDFSRobot.door_step: along P until door_depth of target floor lies behind."""
    px, py = float(AXES_X[rows.pdir[i]]), float(AXES_Y[rows.pdir[i]])
    if (rows.stepping[i] and not _probe(q, k, -px * p.door_depth, -py * p.door_depth)
            and _probe(q, k, px * p.door_depth, py * p.door_depth)
            and rows.stepped[i] < 4 * p.door_depth):
        rows.stepped[i] += p.v
        _go_act(rows, p, k, i, out, px * p.v, py * p.v)
        return
    rows.stepping[i] = False
    _sleep_act(rows, p, k, i, out, 0.0)


# ---------------------------------------------------------------------- queue (the line)
@njit(cache=True)
def _clear_ahead(s, p, k, hx, hy):  # pragma: no cover - compiled
    """FCDFSRobot.clear_ahead: no robot within queue_gap in a 60-degree cone."""
    distances, offsets = s.distances, s.offsets
    for j in range(s.starts[k], s.starts[k + 1]):
        d = distances[j]
        if d > p.queue_gap:
            break  # the rows are nearest first
        if offsets[j, 0] * hx + offsets[j, 1] * hy > 0.5 * d:
            return False
    return True


@njit(cache=True)
def _queue_sleep(rows, p, k, i, out, wake_range):  # pragma: no cover - compiled
    """FCDFSRobot.queue_sleep."""
    _sleep_act(rows, p, k, i, out, max(wake_range, p.avoid_range + 0.5))


@njit(cache=True)
def _queue(rows, s, p, q, k, i, out):  # pragma: no cover - compiled
    """FCDFSRobot.queue."""
    a, b = s.starts[k], s.starts[k + 1]
    if rows.door[i] == NO_DOOR:
        for j in range(a, b):
            if s.sender[j] != NO_SENDER and s.door[j] != NO_DOOR:
                rows.door[i], rows.pdir[i] = s.door[j], s.pdir[j]
                break
    door_id = rows.door[i]
    # one pass: the door's row, the first robot entering close by, the line's fewest hops
    # (the columns in locals: a NamedTuple's array read in a loop costs reference counts)
    sender, status, distances, hops_of, doors = s.sender, s.status, s.distances, s.hops, s.door
    at, mover, any_link, low = -1, -1, False, 0
    reach, make_way = 2.0 * p.d_min, p.avoid_range + 0.5
    for j in range(a, b):
        if sender[j] == NO_SENDER:
            continue
        if at < 0 and sender[j] == door_id:
            at = j
        st = status[j]
        if mover < 0 and st == MOVING and distances[j] <= make_way:
            mover = j
        if (distances[j] <= reach and hops_of[j] < INF_GRADIENT
                and (st == QUEUE or st == DOOR) and doors[j] == door_id):  # a link of the line
            if not any_link or hops_of[j] < low:
                low = hops_of[j]
            any_link = True
    if at >= 0:
        hops = 1
    elif any_link:
        hops = low + 1
    else:
        hops = INF_GRADIENT
    rows.hops[i] = hops if hops <= MAX_HOPS else INF_GRADIENT
    if mover >= 0:
        m = max(s.distances[mover], 1e-9)
        ax, ay = -s.offsets[mover, 0] / m, -s.offsets[mover, 1] / m
        share = 1.0 if _clear_ahead(s, p, k, ax, ay) else 0.5
        _go_act(rows, p, k, i, out, ax * p.v * share, ay * p.v * share)
        return
    wake = math.nan
    if at >= 0:
        dx, dy = s.offsets[at, 0], s.offsets[at, 1]
        if s.moving[at]:
            _queue_sleep(rows, p, k, i, out, math.hypot(dx, dy) + 0.5)
            return
        candidate = math.hypot(dx, dy) <= p.door_radius
        if candidate and _try_enter(rows, s, p, q, k, i, out, dx, dy):
            return
        px, py = float(AXES_X[rows.pdir[i]]), float(AXES_Y[rows.pdir[i]])
        gx = dx - px * 0.6 * p.door_radius
        gy = dy - py * 0.6 * p.door_radius
        if candidate:
            wake = p.clearance + p.door_radius + 0.5
        if math.hypot(gx, gy) <= p.queue_gap:
            _queue_sleep(rows, p, k, i, out, _or(wake, p.queue_gap + 0.5))
            return
    else:
        parent, own = -1, rows.hops[i]
        for j in range(a, b):
            if distances[j] > reach:
                break  # the rows are nearest first; a link is within 2 d_min
            st = status[j]
            if (distances[j] <= reach and sender[j] != NO_SENDER and hops_of[j] < INF_GRADIENT
                    and (st == QUEUE or st == DOOR) and doors[j] == door_id
                    and hops_of[j] < own):  # a link of the line with fewer hops
                parent = j
                break
        if parent < 0:
            _queue_sleep(rows, p, k, i, out, 2.0 * p.d_min)
            return
        gx, gy = s.offsets[parent, 0], s.offsets[parent, 1]
    hx, hy = unit(gx, gy)
    if not _clear_ahead(s, p, k, hx, hy):
        _queue_sleep(rows, p, k, i, out, _or(wake, p.queue_gap + 0.5))
        return
    _go_act(rows, p, k, i, out, hx * p.v, hy * p.v)


@njit(cache=True)
def _or(wake, otherwise):  # pragma: no cover - compiled
    """``wake or otherwise`` (NaN: None)."""
    return otherwise if math.isnan(wake) or wake == 0.0 else wake


@njit(cache=True)
def _try_enter(rows, s, p, q, k, i, out, dx, dy):  # pragma: no cover - compiled
    """FCDFSRobot.try_enter: True when it entered (its action written)."""
    a, b = s.starts[k], s.starts[k + 1]
    door_id = rows.door[i]
    mine = math.hypot(dx, dy)
    sender, status, doors, offsets = s.sender, s.status, s.door, s.offsets
    for j in range(a, b):
        if sender[j] == NO_SENDER or doors[j] != door_id or status[j] != MOVING:
            continue
        if math.hypot(offsets[j, 0] - dx, offsets[j, 1] - dy) <= p.clearance:
            return False
    me = rows.robot_id[i]
    for j in range(a, b):
        if sender[j] == NO_SENDER or doors[j] != door_id or status[j] != QUEUE:
            continue
        from_door = math.hypot(offsets[j, 0] - dx, offsets[j, 1] - dy)
        if not from_door <= p.door_radius:
            continue
        tie = abs(from_door - mine) <= 1e-6
        if (from_door < mine and not tie) or (tie and sender[j] < me):
            return False
    rows.pos[i, 0], rows.pos[i, 1] = -dx, -dy
    found, ex, ey = _entry_cell(rows, s, p, q, k, i)
    if (not found or _settled_at(rows, s, p, k, i, ex, ey)
            or _active_at(rows, s, p, k, i, ex, ey)):
        return False
    rows.status[i] = MOVING
    rows.cell[i, 0], rows.cell[i, 1] = 0, 0
    rows.hist_n[i] = 0
    rows.goal[i, 0], rows.goal[i, 1], rows.has_goal[i] = ex, ey, True
    rows.waited[i] = 0
    _moving(rows, s, p, q, k, i, out)
    return True


@njit(cache=True)
def _entry_cell(rows, s, p, q, k, i):  # pragma: no cover - compiled
    """FCDFSRobot.entry_cell: (found, cell)."""
    px, py = AXES_X[rows.pdir[i]], AXES_Y[rows.pdir[i]]
    sx, sy = _rotate(px, py, p.turn)
    for dx, dy in ((px, py), (sx, sy), (-sx, -sy), (-px, -py)):
        if not _wall(rows, s, p, q, k, i, dx, dy):
            return True, dx, dy
    return False, 0, 0


# ---------------------------------------------------------------------- moving (FCDFS)
@njit(cache=True)
def _wall(rows, s, p, q, k, i, cx, cy):  # pragma: no cover - compiled
    """FCDFSRobot.wall: cell (cx, cy)'s centre is not target floor (or out of reach)."""
    ox = float(cx) * p.spacing - rows.pos[i, 0]
    oy = float(cy) * p.spacing - rows.pos[i, 1]
    if ox * ox + oy * oy > MIN_PROBE_RANGE ** 2:
        return True
    return not _probe(q, k, ox, oy)


@njit(cache=True, inline="always")  # called per neighbour
def _near_centre(x, y, ox, oy, cx, cy, spacing):  # pragma: no cover - compiled
    """A neighbour at (ox, oy) from a robot at (x, y) stands within half a cell of cell
    (cx, cy)'s centre (units)."""
    tx = x + ox - float(cx) * spacing
    ty = y + oy - float(cy) * spacing
    return math.hypot(tx, ty) < 0.5 * spacing


@njit(cache=True)
def _settled_at(rows, s, p, k, i, cx, cy):  # pragma: no cover - compiled
    """FCDFSRobot.settled_at."""
    a, b = s.starts[k], s.starts[k + 1]
    door_id, x, y = rows.door[i], rows.pos[i, 0], rows.pos[i, 1]
    sender, status, doors, ci, cj, offsets = s.sender, s.status, s.door, s.ci, s.cj, s.offsets
    for j in range(a, b):
        if ((status[j] == SETTLED or status[j] == DOOR) and sender[j] != NO_SENDER
                and doors[j] == door_id and ci[j] == cx and cj[j] == cy):
            return True
    for j in range(a, b):
        if ((status[j] == SETTLED or status[j] == DOOR) and sender[j] != NO_SENDER
                and doors[j] != door_id
                and _near_centre(x, y, offsets[j, 0], offsets[j, 1], cx, cy, p.spacing)):
            return True
    return False


@njit(cache=True)
def _blocked(rows, s, p, q, k, i, cx, cy):  # pragma: no cover - compiled
    """FCDFSRobot.blocked."""
    return ((cx == 0 and cy == 0) or _settled_at(rows, s, p, k, i, cx, cy)
            or _wall(rows, s, p, q, k, i, cx, cy))


@njit(cache=True)
def _active_at(rows, s, p, k, i, cx, cy):  # pragma: no cover - compiled
    """FCDFSRobot.active_at."""
    a, b = s.starts[k], s.starts[k + 1]
    door_id, x, y = rows.door[i], rows.pos[i, 0], rows.pos[i, 1]
    sender, status, doors, ci, cj, offsets = s.sender, s.status, s.door, s.ci, s.cj, s.offsets
    for j in range(a, b):
        if (status[j] == MOVING and sender[j] != NO_SENDER and doors[j] == door_id
                and ci[j] == cx and cj[j] == cy):
            return True
    for j in range(a, b):
        if (status[j] == MOVING and sender[j] != NO_SENDER
                and _near_centre(x, y, offsets[j, 0], offsets[j, 1], cx, cy, p.spacing)):
            return True
    return False


@njit(cache=True)
def _turn_to(rows, s, p, k, i, dx, dy):  # pragma: no cover - compiled
    """FCDFSRobot.turn_to: (WAIT or GO, cell)."""
    rows.pdir[i] = _axis(dx, dy)
    nx, ny = rows.cell[i, 0] + dx, rows.cell[i, 1] + dy
    if _active_at(rows, s, p, k, i, nx, ny):
        return WAIT, 0, 0
    return GO, nx, ny


@njit(cache=True)
def _decide(rows, s, p, q, k, i):  # pragma: no cover - compiled
    """FCDFSRobot.decide: (GO, cell), (WAIT, _) or (SETTLE, _)."""
    c0, c1 = rows.cell[i, 0], rows.cell[i, 1]
    px, py = AXES_X[rows.pdir[i]], AXES_Y[rows.pdir[i]]
    sx, sy = _rotate(px, py, p.turn)
    for dx, dy in ((px, py), (sx, sy)):
        nx, ny = c0 + dx, c1 + dy
        if not _blocked(rows, s, p, q, k, i, nx, ny):
            if _active_at(rows, s, p, k, i, nx, ny):
                return WAIT, 0, 0
            return GO, nx, ny
    if rows.hist_n[i] > 0:
        came_x, came_y = rows.hist[i, 0, 0] - c0, rows.hist[i, 0, 1] - c1
    else:
        came_x, came_y = -px, -py
    free_n, free_x, free_y = 0, 0, 0
    for a in range(4):
        if not _blocked(rows, s, p, q, k, i, c0 + AXES_X[a], c1 + AXES_Y[a]):
            if free_n == 0:
                free_x, free_y = AXES_X[a], AXES_Y[a]
            free_n += 1
    if free_n <= 1:
        if free_n == 0 or (free_x == came_x and free_y == came_y):
            return SETTLE, 0, 0
        return _turn_to(rows, s, p, k, i, free_x, free_y)
    gx, gy = c0 - (px + sx), c1 - (py + sy)
    if ((rows.hist_n[i] >= 2 and rows.hist[i, 1, 0] == gx and rows.hist[i, 1, 1] == gy)
            or not _blocked(rows, s, p, q, k, i, gx, gy)):
        return SETTLE, 0, 0
    if -px == came_x and -py == came_y:
        return _turn_to(rows, s, p, k, i, -sx, -sy)
    return _turn_to(rows, s, p, k, i, -px, -py)


@njit(cache=True)
def _settle(rows, p, k, i, out):  # pragma: no cover - compiled
    """FCDFSRobot.settle."""
    rows.status[i] = SETTLED
    rows.has_goal[i] = False
    _sleep_act(rows, p, k, i, out, 0.0)


@njit(cache=True)
def _moving(rows, s, p, q, k, i, out):  # pragma: no cover - compiled
    """FCDFSRobot.moving."""
    if rows.has_goal[i] and _settled_at(rows, s, p, k, i, rows.goal[i, 0], rows.goal[i, 1]):
        rows.has_goal[i] = False
    if not rows.has_goal[i]:
        tx = float(rows.cell[i, 0]) * p.spacing - rows.pos[i, 0]
        ty = float(rows.cell[i, 1]) * p.spacing - rows.pos[i, 1]
        if math.hypot(tx, ty) > p.arrive_tolerance:
            _go(rows, s, p, k, i, out, tx, ty)
            return
    else:
        tx = float(rows.goal[i, 0]) * p.spacing - rows.pos[i, 0]
        ty = float(rows.goal[i, 1]) * p.spacing - rows.pos[i, 1]
        if math.hypot(tx, ty) > p.arrive_tolerance:
            _go(rows, s, p, k, i, out, tx, ty)
            return
        if not (rows.cell[i, 0] == 0 and rows.cell[i, 1] == 0):
            rows.hist[i, 1, 0], rows.hist[i, 1, 1] = rows.hist[i, 0, 0], rows.hist[i, 0, 1]
            rows.hist[i, 0, 0], rows.hist[i, 0, 1] = rows.cell[i, 0], rows.cell[i, 1]
            rows.hist_n[i] = min(rows.hist_n[i] + 1, 2)
        rows.cell[i, 0], rows.cell[i, 1] = rows.goal[i, 0], rows.goal[i, 1]
        rows.has_goal[i] = False
    if rows.cell[i, 0] == 0 and rows.cell[i, 1] == 0:
        rows.status[i] = QUEUE
        _go_act(rows, p, k, i, out, 0.0, 0.0)
        return
    choice, nx, ny = _decide(rows, s, p, q, k, i)
    if choice == SETTLE:
        _settle(rows, p, k, i, out)
        return
    if choice == WAIT:
        rows.waited[i] += 1
        if rows.waited[i] >= p.patience:
            _settle(rows, p, k, i, out)
            return
        _go_act(rows, p, k, i, out, 0.0, 0.0)
        return
    rows.waited[i] = 0
    rows.goal[i, 0], rows.goal[i, 1], rows.has_goal[i] = nx, ny, True
    _go(rows, s, p, k, i, out, float(nx) * p.spacing - rows.pos[i, 0],
        float(ny) * p.spacing - rows.pos[i, 1])


@njit(cache=True)
def _go(rows, s, p, k, i, out, tx, ty):  # pragma: no cover - compiled
    """FCDFSRobot.go: toward (tx, ty) at speed v, side-stepping robots close ahead."""
    dist = math.hypot(tx, ty)
    speed = min(p.v, dist)
    ux, uy = unit(tx, ty)
    vx, vy = ux * speed, uy * speed
    for j in range(s.starts[k], s.starts[k + 1]):
        d = s.distances[j]
        if d > p.avoid_range:
            break  # the rows are nearest first
        if not d > 1e-9:
            continue
        ex, ey = s.offsets[j, 0] / d, s.offsets[j, 1] / d
        toward = vx * ex + vy * ey
        if toward > 0:
            rx, ry = (-ey, ex) if p.turn > 0 else (ey, -ex)
            vx = (vx - toward * ex) + rx * toward
            vy = (vy - toward * ey) + ry * toward
    ux, uy = unit(vx, vy)
    _go_act(rows, p, k, i, out, ux * speed, uy * speed)


__all__ = ["Out", "Params", "Probes", "Rows", "Sensed", "decide_chunk"]
