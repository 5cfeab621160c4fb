"""The compiled driver: one pass over a chunk's robots, each decided by its status's rule.

:func:`decide_chunk` gives robot j of the chunk its own view (rows ``starts[j]:starts[j+1]``
of the chunk's neighbour columns), its own sensors, its own probe slots, its own state row
and its own rows of the per-group arrays, and writes its action. A robot whose floor probe
asked a question not answered yet is marked pending: the caller (swarm.py) answers the
questions and decides it again from its rows as they were (rules are deterministic, so the
second pass asks the same questions first).
"""

from __future__ import annotations

import inspect
from collections import namedtuple
from collections.abc import Callable
from dataclasses import fields

import numba
from numba import njit
from numba.extending import overload

from ._generated import (
    borrow_heard,
    borrow_per_group,
    copy_group_rows,
    empty_view,
    group_rows,
    point_view,
)
from .borrow import borrowed
from .params import GGCParams
from .rules.aggregation import gather, select_leaders
from .rules.common import Probe, Sense
from .rules.coverage import coverage, stopped
from .rules.detection import detection
from .rules.holes import cover_radius, settled
from .rules.rulesets import HOLES, SOW
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

RULE_CASTS = {"float": float, "int": int, "bool": bool}
"""The GGCParams fields the rules read: those of these types (annotations), cast so; the rule
set's name is not one of them (the rules read its flags, ``flags``)."""
PARAM_NAMES = tuple(f.name for f in fields(GGCParams) if f.type in RULE_CASTS)
"""The GGCParams fields in RuleParams, by the same names."""
DERIVED = {
    "groups": "the run's number of groups",
    "scattered": "the robots start scattered (start \"random\")",
    "flags": "the rule set's flags as they apply at this d_cover (swarm.rule_flags)",
    "surplus_rule": "surplus movers stop (rules/surplus.py; swarm.rule_params)",
    "boundary_fill": "edge-followers step in onto the target's boundary (one group)",
    "selection_ticks": "scattered start: ticks of leader selection",
    "gather_deadline": "scattered start: the tick a robot not in its formation covers alone",
    "surplus_turn": "surplus_winding in radians",
    "confined_span": "confined_ticks at this d_cover (ticks; swarm.confined_span)",
    "confined_radius": "confined_reach in units (confined_reach * d_cover)",
    "confined_path": "confined_walk at this d_cover (units; swarm.confined_path)",
    "face_to_leave": "the robots must turn round to leave their formation: their drive turns "
                     "them and cannot back up (kilobot; RobotSetup.turn_rate, reverse)",
}
"""The values the rules read that are not GGCParams fields: computed for each run
(swarm.rule_params), each with its meaning."""

RuleParams = namedtuple("RuleParams", [*PARAM_NAMES, *DERIVED])
"""The run's parameters as the rules read them: GGCParams' fields (:data:`PARAM_NAMES`)
and the run's :data:`DERIVED` values."""


ScatteredRuleParams = namedtuple("ScatteredRuleParams", RuleParams._fields)
"""RuleParams of a run of the scattered start: a type of its own, so that numba compiles the
aggregation rules (rules/aggregation.py; their cost: docs/reports/cold-build.md) into the
driver only for runs that start scattered (a formation's robots never reach them)."""


def decide_robot(view, me, mine, sense, pb, P):  # pragma: no cover - compiled
    """One robot's tick (its odometry already advanced): its status's rule, the scattered
    start's leader selection and aggregation first (``mine``: its per-group rows, a
    schema.PerGroup). Compiled only, chosen by the type of ``P`` when numba compiles the
    driver (:func:`_decide_robot`)."""
    raise NotImplementedError("compiled only (decide_chunk)")


@overload(decide_robot)
def _decide_robot(view, me, mine, sense, pb, P):
    """A formation start's robots are decided by their status's rule; a scattered start's
    (``P`` a ScatteredRuleParams) select leaders first and gather while aggregating. The
    implementation is the rule function's own Python code: numba compiles it once, inside
    the driver, not as one more kernel that would optimise every rule again."""
    if getattr(P, "instance_class", None) is ScatteredRuleParams:
        return _scattered_rules.py_func
    return status_rule.py_func


@njit(cache=True)
def _scattered_rules(view, me, mine, sense, pb, P):  # pragma: no cover - compiled
    """A robot of the scattered start: leader selection first, then the aggregation rules
    (Approach, Pend, Join, Formed), then its status's rule."""
    if sense.tick < P.selection_ticks:
        return select_leaders(view, me, mine, sense, P)
    s = me.status
    if s == APPROACH or s == PEND or s == JOIN or s == FORMED:
        return gather(view, me, mine, sense, pb, P)
    return status_rule(view, me, mine, sense, pb, P)


@njit(cache=True)
def status_rule(view, me, mine, sense, pb, P):  # pragma: no cover - compiled
    """The rule of a robot's status, but the aggregation statuses' (see _scattered_rules;
    they alone read the per-group rows ``mine``)."""
    s = me.status
    if s == COVERAGE:
        return coverage(view, me, sense, pb, P)
    if s == INITIAL:
        return initial(view, me, sense, pb, P)
    if s == DETECTION:
        return detection(view, me, sense, pb, P)
    if s == STOP:
        return stopped(view, me, sense, pb, P)
    if s == ARRIVE and P.flags & HOLES:
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
        return max(P.d_cover, 1.5 * P.d_min) if P.flags & SOW else 1.5 * P.d_min
    if status == DETECTION:
        return max(P.d_cover, 1.5 * P.d_min)
    if status == ARRIVE and P.flags & HOLES:
        return P.d_cover + cover_radius(P)
    return P.d_safe  # Arrive, Surplus


Chunk = namedtuple("Chunk", ["todo", "rows", "state", "saved", "again", "per_group",
                             "saved_groups"])
"""Which robots a pass decides: indices j into the chunk (``todo``); robot j's state row is
``state[rows[j]]``, kept in ``saved[j]`` before its decision (put back first when
``again``); its per-group rows are row ``rows[j]`` of the arrays ``per_group`` (a
schema.PerGroup), kept in row j of ``saved_groups``'s in a scattered start."""
Sensors = namedtuple("Sensors", ["tick", "on_target", "moved", "beacons", "has_beacon"])
"""The chunk's robots' own sensors, row j robot j's: the tick, floor sensor (n,),
displacement over the last tick (n, 2), unit bearing to the beacon (n, 2), if the world has
one (``has_beacon``)."""
Probes = namedtuple("Probes", ["req", "ans", "calls", "pending"])
"""Each robot's floor-probe questions (n, MAX_PROBES, 2), their answers (n, MAX_PROBES; -1:
none yet), how many it asked (n,), and whether it waits for an answer (n,)."""
Actions = namedtuple("Actions", ["velocity", "sleep", "wake_range", "wake_on_motion",
                                 "wake_tick", "listen"])
"""The chunk's actions, row j robot j's (swarmsim.controller.ChunkActions' columns)."""


@njit(cache=True)
def decide_chunk(chunk, heard, sensors, probes, P, actions):  # pragma: no cover - compiled
    """Decide the chunk's robots ``chunk.todo`` (see :data:`Chunk`) into row j of
    ``actions``; robot j hears rows ``heard.starts[j]:heard.starts[j+1]`` of the chunk's
    columns ``heard`` (a rules.common.Heard). ``probes.pending[j]``: decide it again (with
    ``chunk.again``) once its probe questions are answered."""
    starts = heard.starts
    heard = borrow_heard(heard)
    req, ans = borrowed(probes.req), borrowed(probes.ans)
    calls, pending = borrowed(probes.calls), borrowed(probes.pending)
    state, saved, rows, again = chunk.state, chunk.saved, chunk.rows, chunk.again
    per_group = borrow_per_group(chunk.per_group)
    saved_groups = borrow_per_group(chunk.saved_groups)
    tick, on_target, moved = sensors.tick, sensors.on_target, sensors.moved
    has_beacon, beacons = sensors.has_beacon, sensors.beacons
    velocity, sleep, listen = actions.velocity, actions.sleep, actions.listen
    wake_range, wake_on_motion, wake_tick = (actions.wake_range, actions.wake_on_motion,
                                             actions.wake_tick)
    view = empty_view(heard)
    pb = Probe(req[0], ans[0], calls[0:1], pending[0:1])
    for j in chunk.todo:
        i = rows[j]
        if again:
            state[i] = saved[j]
            if P.scattered:
                copy_group_rows(saved_groups, j, per_group, i)
        else:
            saved[j] = state[i]
            if P.scattered:
                copy_group_rows(per_group, i, saved_groups, j)
        # the view is one struct, pointed at robot j's rows (each rule call passes a pointer)
        point_view(view, heard, starts[j], starts[j + 1])
        sense = Sense(tick=tick, on_target=on_target[j], moved_x=moved[j, 0],
                      moved_y=moved[j, 1], has_beacon=has_beacon, beacon_x=beacons[j, 0],
                      beacon_y=beacons[j, 1])
        calls[j] = 0
        pending[j] = False
        pb.req, pb.ans, pb.calls, pb.pending = req[j], ans[j], calls[j:j + 1], pending[j:j + 1]
        me = state[i]
        me.odo_x += sense.moved_x
        me.odo_y += sense.moved_y
        mine = group_rows(per_group, i)
        vx, vy, asleep, wake, on_motion, until = decide_robot(view, me, mine, sense, pb, P)
        velocity[j, 0], velocity[j, 1] = vx, vy
        sleep[j], wake_range[j], wake_on_motion[j], wake_tick[j] = asleep, wake, on_motion, until
        listen[j] = listen_range(me.status, P)


ChunkArgs = namedtuple("ChunkArgs", inspect.signature(decide_chunk.py_func).parameters)
"""decide_chunk's arguments, by name (its parameters')."""

_DRIVERS: set[type] = set()
"""The RuleParams types (one per start) whose driver :func:`ensure_driver` compiled (or
loaded) in this process."""


def ensure_driver(args: ChunkArgs) -> Callable[..., None]:
    """Compile (or load from the cache) the driver for ``args``' types unless this process
    has it for their start (the type of ``args.P``); numba compiles nothing else: a call
    whose types no driver can take fails loudly (TypeError) instead of compiling for a
    minute mid-run. Every broadcast column is typed strided (rules.common.Heard), so one
    driver takes every chunk.

    Returns the driver for arguments of exactly ``args``' numba types: the compiled
    signature's entry point, which skips the dispatcher's typing of the six namedtuple
    arguments on each call (the caller must pass it arguments of those types only:
    :class:`DriverTypes`); :func:`decide_chunk` itself (which types each call and refuses
    what no driver takes) when no compiled signature matches."""
    signature = tuple(numba.typeof(value) for value in args)
    start = type(args.P)
    if start not in _DRIVERS:
        decide_chunk.disable_compile(False)
        try:
            decide_chunk.compile(signature)
        finally:
            decide_chunk.disable_compile()
        _DRIVERS.add(start)
    compiled = decide_chunk.overloads.get(signature)
    return decide_chunk if compiled is None else compiled.entry_point
