"""Kilobot's decision for a chunk of robots, compiled (numba): :func:`decide_chunk` runs, for
every robot of the chunk in one call, what ``KilobotRobot.step`` (robot.py) does, with the
same arithmetic in the same order, so the same numbers to the bit (Python's ``math.hypot``:
controllers/common/pyhypot.py; ``atan2`` and Python's float ``%`` as numba computes them, the
C library's and CPython's).

A robot's floor probe is asked from Python (the engine's ``probe_many``), so a chunk is
decided in two calls: :func:`probe_questions` finds, without changing any state, the one
probe each robot may ask this tick (where ``KilobotRobot.should_join`` or ``wander`` would),
and :func:`decide_chunk` decides with the answers.

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
from controllers.common.pyhypot import py_hypot
from swarmsim.controller import NO_SENDER

from .params import INSIDE, JOINED, OUTSIDE, TRAVEL, WAIT


class Rows(NamedTuple):
    """The run's robots' state, row i robot i's (KilobotRobot's attributes)."""

    robot_id: np.ndarray  # (N,) int64
    leader: np.ndarray  # (N,) bool
    status: np.ndarray  # (N,) int64, an index into STATUSES
    grad: np.ndarray  # (N,) int64, INF_GRADIENT: none yet
    cmd: np.ndarray  # (N,) int64, CMD_NONE, CMD_TRAVEL or CMD_HALT
    travel: np.ndarray  # (N, 2) the travel velocity it relays, units per tick
    heading: np.ndarray  # (N, 2) unit vector (zeros: none yet)
    circling_id: np.ndarray  # (N,) int64, the robot it circles (NO_SENDER: none)
    circled: np.ndarray  # (N,) radians gone round it
    last_bearing: np.ndarray  # (N,) radians
    has_bearing: np.ndarray  # (N,) bool: last_bearing is set (KilobotRobot's not None)
    odometer: np.ndarray  # (N, 2) units moved since the last progress sample
    progress_tick: np.ndarray  # (N,) int64
    escape_until: np.ndarray  # (N,) int64
    traps: np.ndarray  # (N,) int64


class Sensed(NamedTuple):
    """A chunk's sensing (swarmsim.controller.DecideBatch) as C-contiguous columns."""

    tick: int
    rows: np.ndarray  # (R,) int64, the chunk's robots
    starts: np.ndarray  # (R + 1,) int64
    offsets: np.ndarray  # (P, 2) units
    distances: np.ndarray  # (P,) units
    sender: np.ndarray  # (P,) int64, the broadcasts' id (NO_SENDER: not heard)
    status: np.ndarray  # (P,) int64
    moving: np.ndarray  # (P,) bool
    gradient: np.ndarray  # (P,) int64
    cmd: np.ndarray  # (P,) int64
    vx: np.ndarray  # (P,) float64 (the broadcast's float32)
    vy: np.ndarray  # (P,) float64
    on_target: np.ndarray  # (R,) bool
    moved: np.ndarray  # (R, 2) units
    beacons: np.ndarray  # (R, 2) unit bearings (zeros without a beacon)
    has_beacon: bool


class Params(NamedTuple):
    """KilobotParams' values, as floats and ints."""

    d_safe: float
    d_cover: float
    d_min: float
    v: float
    gradient_reach: float
    start_range: float
    quiet_range: float
    yield_distance: float
    radial_gain: float
    arrive_tolerance: float
    probe_distance: float
    orbit: float
    init_timeout: int
    T_r: int
    theta: float


class Out(NamedTuple):
    """The chunk's actions, row k robot k's (NaN: None)."""

    velocity: np.ndarray  # (R, 2) units per tick
    listen: np.ndarray  # (R,) units
    sleep: np.ndarray  # (R,) bool
    wake_range: np.ndarray  # (R,) units
    wake_tick: np.ndarray  # (R,) int64, -1: none


@njit(cache=True)
def _first_structure(moving, a, b):  # pragma: no cover - compiled
    """The first (nearest) row in a:b of a robot that is not moving, or -1."""
    for j in range(a, b):
        if not moving[j]:
            return j
    return -1


@njit(cache=True)
def _edge_follow(ox, oy, dist, p):  # pragma: no cover - compiled
    """KilobotRobot.edge_follow: the velocity that keeps d_cover from a robot at (ox, oy)."""
    m = max(dist, 1e-9)
    rx, ry = ox / m, oy / m
    tx, ty = ry * p.orbit, -rx * p.orbit
    error = max(-1.0, min(1.0, (dist - p.d_cover) * p.radial_gain))
    ux, uy = unit(tx + error * rx, ty + error * ry)
    return ux * p.v, uy * p.v


@njit(cache=True)
def _lowest_gradient(s, a, b, reach):  # pragma: no cover - compiled
    """formationkernel.lowest_gradient over rows a:b."""
    found, best = False, 0
    distances, moving, sender, gradient = s.distances, s.moving, s.sender, s.gradient
    for j in range(a, b):  # (columns in locals: a NamedTuple's array read in a loop costs
        # reference counts each time)
        if (distances[j] <= reach and not moving[j] and sender[j] != NO_SENDER
                and gradient[j] < INF_GRADIENT and (not found or gradient[j] < best)):
            found, best = True, gradient[j]
    return best if found else -1


@njit(cache=True)
def _blocked(s, a, b, p, grad, me):  # pragma: no cover - compiled
    """formationkernel.blocked over rows a:b (Kilobot's start rule)."""
    distances, moving, sender, gradient, status = (s.distances, s.moving, s.sender,
                                                   s.gradient, s.status)
    for j in range(a, b):
        if sender[j] != NO_SENDER and distances[j] <= p.quiet_range and moving[j]:
            return True
    for j in range(a, b):
        if sender[j] == NO_SENDER or not distances[j] <= p.start_range:
            continue
        if ((status[j] == WAIT or status[j] == TRAVEL)
                and (gradient[j] > grad or (gradient[j] == grad and sender[j] > me))):
            return True
    return False


@njit(cache=True)
def probe_questions(rows, s, p, ask, offsets):  # pragma: no cover - compiled
    """Where each robot of the chunk may probe this tick: ``ask[k]`` and ``offsets[k]``
    (units). A waiting or moving robot on the target asks the probe of ``should_join`` (its
    nearest stationary robot at least d_cover - arrive_tolerance away, ahead along its edge
    velocity) or of ``wander`` (none: ahead along its heading). No state changes."""
    near = p.d_cover - p.arrive_tolerance
    for k in range(len(s.rows)):
        i = s.rows[k]
        ask[k] = False
        st = rows.status[i]
        if not s.on_target[k] or not (st == WAIT or st == OUTSIDE or st == INSIDE):
            continue
        a, b = s.starts[k], s.starts[k + 1]
        nearest = _first_structure(s.moving, a, b)
        if nearest < 0:
            hx, hy = rows.heading[i, 0], rows.heading[i, 1]
            if hx == 0.0 and hy == 0.0:
                hx, hy = 1.0, 0.0
        else:
            if s.distances[nearest] < near:
                continue
            vx, vy = _edge_follow(s.offsets[nearest, 0], s.offsets[nearest, 1],
                                  s.distances[nearest], p)
            hx, hy = unit(vx, vy)
        ask[k] = True
        offsets[k, 0], offsets[k, 1] = hx * p.probe_distance, hy * p.probe_distance


@njit(cache=True)
def decide_chunk(rows, s, p, answers, out):  # pragma: no cover - compiled
    """Decide every robot of the chunk (KilobotRobot.step), updating its rows and writing
    its action into ``out``; ``answers[k]``: robot k's probe at probe_questions' offset."""
    for k in range(len(s.rows)):
        i = s.rows[k]
        rows.odometer[i, 0] += s.moved[k, 0]
        rows.odometer[i, 1] += s.moved[k, 1]
        out.velocity[k, 0], out.velocity[k, 1] = 0.0, 0.0
        out.sleep[k] = False
        out.wake_range[k] = math.nan
        out.wake_tick[k] = -1
        st = rows.status[i]
        if st == TRAVEL:
            if rows.leader[i]:
                _lead(rows, s, p, k, i, out)
            else:
                _follow(rows, s, p, k, i, out)
        elif st == WAIT:
            _wait(rows, s, p, k, i, answers, out)
        elif st == OUTSIDE or st == INSIDE:
            _move(rows, s, p, k, i, answers, out)
        else:
            out.sleep[k] = True
            out.wake_range[k] = 0.0
        out.listen[k] = _listen_range(rows.status[i], p)


@njit(cache=True)
def _listen_range(status, p):  # pragma: no cover - compiled
    """KilobotRobot.listen_range (NaN: None)."""
    if status == TRAVEL:
        return 1.5 * p.d_min
    if status == WAIT:
        return max(p.start_range, p.quiet_range, 1.5 * p.d_min)
    if status == JOINED:
        return p.d_safe
    return math.nan


@njit(cache=True)
def _lead(rows, s, p, k, i, out):  # pragma: no cover - compiled
    """KilobotRobot.lead: the seed heads for the beacon until it is on the target."""
    if s.on_target[k] or not s.has_beacon:
        rows.cmd[i] = CMD_HALT
        rows.travel[i, 0], rows.travel[i, 1] = 0.0, 0.0
        rows.status[i] = JOINED
        return
    rows.cmd[i] = CMD_TRAVEL
    rows.travel[i, 0] = s.beacons[k, 0] * p.v
    rows.travel[i, 1] = s.beacons[k, 1] * p.v
    out.velocity[k, 0], out.velocity[k, 1] = rows.travel[i, 0], rows.travel[i, 1]


@njit(cache=True)
def _follow(rows, s, p, k, i, out):  # pragma: no cover - compiled
    """KilobotRobot.follow: copy the gradient parent's travel command."""
    a, b = s.starts[k], s.starts[k + 1]
    reach = 1.5 * p.d_min
    low = _lowest_gradient(s, a, b, reach)
    parent = -1
    if low >= 0:
        rows.grad[i] = low + 1
        for j in range(a, b):
            if (s.distances[j] <= reach and not s.moving[j] and s.sender[j] != NO_SENDER
                    and s.gradient[j] == rows.grad[i] - 1):
                parent = j
                break
    if parent < 0:
        if s.tick >= p.init_timeout:
            rows.status[i] = WAIT
        out.sleep[k] = True
        out.wake_range[k] = 1.5 * p.d_min
        out.wake_tick[k] = p.init_timeout
        return
    cmd = s.cmd[parent]
    rows.cmd[i] = cmd
    if cmd == CMD_TRAVEL:
        rows.travel[i, 0], rows.travel[i, 1] = s.vx[parent], s.vy[parent]
    else:
        rows.travel[i, 0], rows.travel[i, 1] = 0.0, 0.0
    if cmd == CMD_HALT:
        rows.status[i] = WAIT
        return
    out.velocity[k, 0], out.velocity[k, 1] = rows.travel[i, 0], rows.travel[i, 1]


@njit(cache=True)
def _wait(rows, s, p, k, i, answers, out):  # pragma: no cover - compiled
    """KilobotRobot.wait: relay the gradient; start moving unless blocked."""
    a, b = s.starts[k], s.starts[k + 1]
    low = _lowest_gradient(s, a, b, 1.5 * p.d_min)
    if low >= 0:
        rows.grad[i] = low + 1
    if _blocked(s, a, b, p, rows.grad[i], rows.robot_id[i]):
        out.sleep[k] = True
        out.wake_range[k] = max(p.start_range, p.quiet_range)
        return
    rows.status[i] = INSIDE if s.on_target[k] else OUTSIDE
    rows.odometer[i, 0], rows.odometer[i, 1] = 0.0, 0.0
    rows.progress_tick[i] = s.tick
    _move(rows, s, p, k, i, answers, out)


@njit(cache=True)
def _turn_between(before, after):  # pragma: no cover - compiled
    """controllers.common.edges.turn_between (Python's float %, as numba computes it)."""
    return (after - before + math.pi) % (2 * math.pi) - math.pi


@njit(cache=True)
def _circling(rows, s, i, nearest):  # pragma: no cover - compiled
    """CirclingWatch.circling: True once robot i has gone all the way round its nearest."""
    sender = s.sender[nearest]
    bearing = math.atan2(-s.offsets[nearest, 1], -s.offsets[nearest, 0])
    if sender != rows.circling_id[i] or sender == NO_SENDER or not rows.has_bearing[i]:
        rows.circling_id[i], rows.circled[i] = sender, 0.0
        rows.last_bearing[i], rows.has_bearing[i] = bearing, True
        return False
    rows.circled[i] += _turn_between(rows.last_bearing[i], bearing)
    rows.last_bearing[i] = bearing
    return abs(rows.circled[i]) > 2 * math.pi


@njit(cache=True)
def _stuck(rows, s, p, i):  # pragma: no cover - compiled
    """KilobotRobot.stuck (ProgressWatch.sample_progress): moved <= theta in T_r ticks."""
    if s.tick - rows.progress_tick[i] < p.T_r:
        return False
    moved = py_hypot(rows.odometer[i, 0], rows.odometer[i, 1])
    rows.odometer[i, 0], rows.odometer[i, 1] = 0.0, 0.0
    rows.progress_tick[i] = s.tick
    if moved > p.theta:
        rows.traps[i] = 0
    return moved <= p.theta


@njit(cache=True)
def _should_join(rows, s, p, k, i, nearest, answers):  # pragma: no cover - compiled
    """KilobotRobot.should_join (its probe: ``answers[k]``)."""
    if not s.on_target[k] or s.distances[nearest] < p.d_cover - p.arrive_tolerance:
        return False
    if not answers[k]:
        return True
    return (s.sender[nearest] != NO_SENDER and s.status[nearest] == JOINED
            and s.gradient[nearest] >= rows.grad[i])


@njit(cache=True)
def _must_yield(rows, s, p, k, i, vx, vy):  # pragma: no cover - compiled
    """KilobotRobot.must_yield: a moving robot with a larger id close ahead."""
    distances, moving, sender, offsets = s.distances, s.moving, s.sender, s.offsets
    me = rows.robot_id[i]
    for j in range(s.starts[k], s.starts[k + 1]):
        if (distances[j] <= p.yield_distance and moving[j] and sender[j] > me
                and offsets[j, 0] * vx + offsets[j, 1] * vy > 0):
            return True
    return False


@njit(cache=True)
def _move(rows, s, p, k, i, answers, out):  # pragma: no cover - compiled
    """KilobotRobot.move: follow the edge of the structure, join, escape or yield."""
    rows.status[i] = INSIDE if s.on_target[k] else OUTSIDE
    a, b = s.starts[k], s.starts[k + 1]
    nearest = _first_structure(s.moving, a, b)
    if nearest < 0:
        _wander(rows, s, p, k, i, answers, out)
        return
    vx, vy = _edge_follow(s.offsets[nearest, 0], s.offsets[nearest, 1], s.distances[nearest], p)
    rows.heading[i, 0], rows.heading[i, 1] = unit(vx, vy)
    circled = _circling(rows, s, i, nearest)
    if circled:
        rows.circled[i] = 0.0
    trapped = circled or _stuck(rows, s, p, i)
    if trapped:
        rows.traps[i] += 1
    if (_should_join(rows, s, p, k, i, nearest, answers)
            or (trapped and (s.on_target[k] or rows.traps[i] > 2))):
        rows.status[i] = JOINED
        return
    if trapped and s.has_beacon:
        rows.escape_until[i] = s.tick + p.T_r
    if s.tick < rows.escape_until[i] and s.has_beacon:
        vx, vy = s.beacons[k, 0] * p.v, s.beacons[k, 1] * p.v
    low = _lowest_gradient(s, a, b, p.gradient_reach * p.d_cover)
    if low >= 0:
        rows.grad[i] = low + 1
    if _must_yield(rows, s, p, k, i, vx, vy):
        rows.progress_tick[i] = s.tick
        rows.odometer[i, 0], rows.odometer[i, 1] = 0.0, 0.0
        return
    out.velocity[k, 0], out.velocity[k, 1] = vx, vy


@njit(cache=True)
def _wander(rows, s, p, k, i, answers, out):  # pragma: no cover - compiled
    """KilobotRobot.wander: no stationary robot in range: head for the beacon."""
    if s.has_beacon and not s.on_target[k]:
        rows.heading[i, 0], rows.heading[i, 1] = s.beacons[k, 0], s.beacons[k, 1]
    if rows.heading[i, 0] == 0.0 and rows.heading[i, 1] == 0.0:
        rows.heading[i, 0], rows.heading[i, 1] = 1.0, 0.0
    if s.on_target[k] and not answers[k]:
        rows.status[i] = JOINED
        return
    out.velocity[k, 0] = rows.heading[i, 0] * p.v
    out.velocity[k, 1] = rows.heading[i, 1] * p.v


__all__ = ["Out", "Params", "Rows", "Sensed", "decide_chunk", "probe_questions"]
