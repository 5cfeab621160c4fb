"""The compiled driver: one pass over a chunk's robots, each decided by its status's rule.

:func:`decide_chunk` gives robot j of the chunk its own view (rows ``starts[j]:starts[j+1]``
of the chunk's neighbour columns), its own sensors, its own probe slots and its own state
row, and writes its action. A robot whose floor probe asked a question not answered yet is
marked pending: the caller (swarm.py) answers the questions and decides it again from its
row as it was (rules are deterministic, so the second pass asks the same questions first).
"""

from __future__ import annotations

import inspect
from collections import namedtuple

import numba
from numba import njit, types
from numba.extending import overload

from .borrow import borrowed
from .rules.aggregation import gather, select_leaders
from .rules.common import Probe, Sense, View
from .rules.coverage import coverage, stopped
from .rules.detection import detection
from .rules.holes import cover_radius, settled
from .rules.rulesets import HOLES
from .rules.travel import initial
from .statuses import (
    APPROACH,
    ARRIVE,
    COVERAGE,
    DETECTION,
    FORMED,
    INITIAL,
    JOIN,
    PEND,
    STOP,
)

RuleParams = namedtuple("RuleParams", [
    "d_safe", "d_cover", "d_min", "R_c", "v", "radial_gain", "arrive_tolerance",
    "probe_distance", "yield_distance", "orbit", "T_r", "theta", "T_s", "init_timeout",
    "T_settle", "T_quiet", "handover_reach", "join_tolerance", "boundary_probe",
    "surplus_frontier", "surplus_winding", "surplus_spread", "yield_release", "lattice_stop",
    "lattice_reach", "groups", "scattered", "surplus_rule", "boundary_fill",
    "selection_ticks", "gather_deadline", "ruleset", "confined_ticks", "confined_reach",
    "confined_walk"])
"""The run's parameters as the rules read them (GGCParams' plus the run's: groups, start,
which of our additions apply; surplus_winding in radians; confined_reach and confined_walk in
units)."""


ScatteredRuleParams = namedtuple("ScatteredRuleParams", RuleParams._fields)
"""RuleParams of a run of the scattered start: a type of its own, so that numba compiles the
aggregation rules (rules/aggregation.py; their cost: docs/reports/cold-build.md) into the
driver only for runs that start scattered (a formation's robots never reach them)."""


def decide_robot(view, me, sense, pb, P):  # pragma: no cover - compiled
    """One robot's tick (its odometry already advanced): its status's rule, the scattered
    start's leader selection and aggregation first. Compiled only, chosen by the type of
    ``P`` when numba compiles the driver (:func:`_decide_robot`)."""
    raise NotImplementedError("compiled only (decide_chunk)")


@overload(decide_robot)
def _decide_robot(view, me, sense, pb, P):
    """A formation start's robots are decided by their status's rule; a scattered start's
    (``P`` a ScatteredRuleParams) select leaders first and gather while aggregating. The
    implementation is the rule function's own Python code: numba compiles it once, inside
    the driver, not as one more kernel that would optimise every rule again."""
    if getattr(P, "instance_class", None) is ScatteredRuleParams:
        return _scattered_rules.py_func
    return status_rule.py_func


@njit(cache=True)
def _scattered_rules(view, me, sense, pb, P):  # pragma: no cover - compiled
    """A robot of the scattered start: leader selection first, then the aggregation rules
    (Approach, Pend, Join, Formed), then its status's rule."""
    if sense.tick < P.selection_ticks:
        return select_leaders(view, me, sense, P)
    s = me.status
    if s == APPROACH or s == PEND or s == JOIN or s == FORMED:
        return gather(view, me, sense, pb, P)
    return status_rule(view, me, sense, pb, P)


@njit(cache=True)
def status_rule(view, me, sense, pb, P):  # pragma: no cover - compiled
    """The rule of a robot's status, but the aggregation statuses' (see _scattered_rules)."""
    s = me.status
    if s == COVERAGE:
        return coverage(view, me, sense, pb, P)
    if s == INITIAL:
        return initial(view, me, sense, P)
    if s == DETECTION:
        return detection(view, me, sense, pb, P)
    if s == STOP:
        return stopped(view, me, sense, pb, P)
    if s == ARRIVE and P.ruleset & HOLES:
        return settled(view, me, sense, pb, P)
    return 0.0, 0.0, True, 0.0, True, -1  # Arrive, Surplus


@njit(cache=True)
def listen_range(status, P):  # pragma: no cover - compiled
    """How far a robot in ``status`` needs to hear next tick (units)."""
    if status == COVERAGE or status == STOP:
        return min(2 * P.d_cover, P.R_c)
    if status == APPROACH or status == PEND or status == JOIN or status == FORMED:
        return P.R_c
    if status == INITIAL:
        return 1.5 * P.d_min
    if status == DETECTION:
        return max(P.d_cover, 1.5 * P.d_min)
    if status == ARRIVE and P.ruleset & HOLES:
        return P.d_cover + cover_radius(P)
    return P.d_safe  # Arrive, Surplus


@njit(cache=True)
def decide_chunk(todo, rows, state, saved, again, c, tick, on_target, moved, beacons,
                 has_beacon, req, ans, calls, pending, P, velocity, sleep, wake_range,
                 wake_on_motion, wake_tick, listen):  # pragma: no cover - compiled
    """Decide the chunk's robots ``todo`` (indices j into the chunk: robot j's state row is
    ``state[rows[j]]``, its sensors row j of the sensor arrays, its neighbours rows
    ``c[0][j]:c[0][j+1]`` of the chunk's columns ``c``: starts, then View's fields) into row
    j of the action arrays. ``pending[j]``: decide it again (``again``: its row is put back
    from ``saved[j]`` first) once its probe questions ``req[j, :calls[j]]`` are answered in
    ``ans``."""
    starts = c[0]
    c = (starts, borrowed(c[1]), borrowed(c[2]), borrowed(c[3]), borrowed(c[4]),
         borrowed(c[5]), borrowed(c[6]), borrowed(c[7]), borrowed(c[8]), borrowed(c[9]),
         borrowed(c[10]), borrowed(c[11]), borrowed(c[12]), borrowed(c[13]), borrowed(c[14]),
         borrowed(c[15]), borrowed(c[16]), borrowed(c[17]), borrowed(c[18]), borrowed(c[19]),
         borrowed(c[20]), borrowed(c[21]), borrowed(c[22]), borrowed(c[23]))
    req, ans, calls, pending = borrowed(req), borrowed(ans), borrowed(calls), borrowed(pending)
    view = View(c[1][:0], c[2][:0], c[3][:0], c[4][:0], c[5][:0], c[6][:0], c[7][:0],
                c[8][:0], c[9][:0], c[10][:0], c[11][:0], c[12][:0], c[13][:0], c[14][:0],
                c[15][:0], c[16][:0], c[17][:0], c[18][:0], c[19][:0], c[20][:0], c[21][:0],
                c[22][:0], c[23][:0])
    pb = Probe(req[0], ans[0], calls[0:1], pending[0:1])
    for j in todo:
        i = rows[j]
        if again:
            state[i] = saved[j]
        else:
            saved[j] = state[i]
        a, b = starts[j], starts[j + 1]
        # the view is one struct, pointed at robot j's rows (each rule call passes a pointer)
        view.off, view.dist, view.id, view.status = c[1][a:b], c[2][a:b], c[3][a:b], c[4][a:b]
        view.grad, view.group, view.leader = c[5][a:b], c[6][a:b], c[7][a:b]
        view.moving, view.cmd, view.vx, view.vy = c[8][a:b], c[9][a:b], c[10][a:b], c[11][a:b]
        view.touch, view.stepped, view.enclosed = c[12][a:b], c[13][a:b], c[14][a:b]
        view.h, view.handover, view.quiet = c[15][a:b], c[16][a:b], c[17][a:b]
        view.ldist, view.lepoch, view.hole = c[18][a:b], c[19][a:b], c[20][a:b]
        view.hx, view.hy, view.blocked = c[21][a:b], c[22][a:b], c[23][a:b]
        sense = Sense(tick, on_target[j], moved[j, 0], moved[j, 1], has_beacon,
                      beacons[j, 0], beacons[j, 1])
        calls[j] = 0
        pending[j] = False
        pb.req, pb.ans, pb.calls, pb.pending = req[j], ans[j], calls[j:j + 1], pending[j:j + 1]
        me = state[i]
        me.odo_x += sense.moved_x
        me.odo_y += sense.moved_y
        vx, vy, asleep, wake, on_motion, until = decide_robot(view, me, sense, pb, P)
        velocity[j, 0], velocity[j, 1] = vx, vy
        sleep[j], wake_range[j], wake_on_motion[j], wake_tick[j] = asleep, wake, on_motion, until
        listen[j] = listen_range(me.status, P)


ChunkArgs = namedtuple("ChunkArgs", inspect.signature(decide_chunk.py_func).parameters)
"""decide_chunk's arguments, by name."""

_DRIVERS: set[type] = set()
"""The RuleParams types (one per start) whose driver :func:`ensure_driver` compiled (or
loaded) in this process."""


def driver_types(args: ChunkArgs) -> tuple:
    """numba's types of :func:`decide_chunk`'s arguments ``args``, with every broadcast column
    (``c[3:]``, views of the heard messages' fields) typed as strided ('A').

    numba types an array C-contiguous when numpy flags it so, as it does every array of 0 or
    1 rows: a chunk that heard one message (a lone awake robot) would then need a driver
    compiled anew for its types, mid-run (about a minute). Typed 'A', one compiled driver
    takes every chunk (numba converts a C-contiguous column to 'A' on the call)."""
    typed = args._replace(**{name: numba.typeof(value) for name, value in args._asdict().items()})
    columns = typed.c
    return tuple(typed._replace(c=types.Tuple([*columns[:3],
                                               *(t.copy(layout="A") for t in columns[3:])])))


def ensure_driver(args: ChunkArgs) -> None:
    """Compile (or load from the cache) the driver for ``args``' types (as
    :func:`driver_types` gives them) unless this process has it for their start (the type of
    ``args.P``); numba compiles nothing else: a call whose types no driver can take fails
    loudly (TypeError) instead of compiling for a minute mid-run."""
    start = type(args.P)
    if start in _DRIVERS:
        return
    decide_chunk.disable_compile(False)
    try:
        decide_chunk.compile(driver_types(args))
    finally:
        decide_chunk.disable_compile()
    _DRIVERS.add(start)
