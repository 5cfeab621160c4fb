"""A run's GGC robots: their state rows and per-group arrays (state.py) and the chunk
driver's Python side.

:meth:`GGCSwarm.decide` gathers a chunk's neighbour columns and runs the compiled driver
(decide.py) on the chunk's state rows, in place; it answers the floor-probe questions the
driver asked (all of a round in one ``probe_many``) and runs it again for the robots that
asked (each from its row as it was), until none is pending; then it returns the chunk's
actions and broadcasts as columns.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Callable, Sequence
from dataclasses import fields, replace

import numpy as np
from numba import njit

from swarmsim.controller import (
    ChunkActions,
    DecideBatch,
    NeighbourBatch,
    RobotSetup,
    message_dtype,
)

from .decide import (
    PARAM_NAMES,
    RULE_CASTS,
    Actions,
    Chunk,
    ChunkArgs,
    Probes,
    RuleParams,
    ScatteredRuleParams,
    Sensors,
    decide_chunk,
    ensure_driver,
)
from .heard import Heard
from .params import GGCParams
from .rules.common import MAX_PROBES
from .rules.gradient import lose_gradient
from .rules.rulesets import ANY_GROUPS, BETWEEN_GROUPS, FLAG_SCOPE, HOLES, RULESETS, SURPLUS
from .schema import BROADCAST_NAMES, PerGroup
from .state import broadcast_rows, message_fields, new_per_group, new_state
from .statuses import FORMED, STATUSES

FAILURE_MODES = {
    "no_gradient": "the paper's failure during gradient formation (Section 5): the robot "
                   "cannot obtain its neighbours' gradient, so its gradient is infinite; it "
                   "sets off to cover first, follows the edge round its nearest robot and "
                   "takes a gradient from the structure from then on (a mover loses its "
                   "gradient and takes one again; a leader keeps its own)",
}
"""The failure modes GGC simulates (GGC.FAILURE_MODES), beside the engine's "dead"."""


def rule_params(params: GGCParams, groups: int, scattered: bool,
                turn_rate: float = math.inf, reverse: bool = True) -> RuleParams:
    """The rules' parameters for a run with ``groups`` groups (``scattered``: start
    "random") of robots whose drive turns them at most ``turn_rate`` rad/tick (``inf``:
    holonomic, they need no turning) and can (``reverse``) or cannot back up:
    ``params``' fields (decide.PARAM_NAMES, cast by their types) and the run's derived values
    (decide.DERIVED)."""
    selection = (params.h_max + 1) * params.T_settle
    one = groups == 1
    flags = rule_flags(params)
    derived = {
        "groups": int(groups), "scattered": bool(scattered), "flags": flags,
        "surplus_rule": bool(params.surplus_stop and params.d_cover > params.yield_release
                             and (one or surplus_between_groups(flags))),
        "boundary_fill": one, "selection_ticks": int(selection),
        "gather_deadline": int(selection + params.aggregation_timeout + 1),
        "surplus_turn": math.radians(params.surplus_winding),
        "confined_span": confined_span(params),
        "confined_radius": float(params.confined_reach * params.d_cover),
        "confined_path": confined_path(params),
        "face_to_leave": not (math.isinf(turn_rate) or reverse),
    }
    own = {f.name: RULE_CASTS[f.type](getattr(params, f.name)) for f in fields(params)
           if f.name in PARAM_NAMES}
    return (ScatteredRuleParams if scattered else RuleParams)(**own, **derived)


def confined_span(params: GGCParams) -> int:
    """How long a mover may stay within its reach before it gives up (rules/confined.py):
    params.confined_ticks at d_cover = d_safe, in proportion to d_safe + d_cover (ticks)."""
    return round(params.confined_ticks * (params.d_safe + params.d_cover) / (2 * params.d_safe))


def confined_path(params: GGCParams) -> float:
    """How far a mover may walk in Coverage since leaving its formation before it gives up
    (rules/confined.py): params.confined_walk * d_cover * max(d_cover, 2 d_safe) / d_safe
    (units)."""
    return float(params.confined_walk * params.d_cover * max(params.d_cover, 2 * params.d_safe)
                 / params.d_safe)


def surplus_between_groups(flags: int) -> bool:
    """With groups, surplus movers stop under the rule set's SURPLUS flag where holes are not
    filled (``flags`` as :func:`rule_flags` gives them: no HOLES once d_cover +
    arrive_tolerance > lattice_reach): there the lattice leaves holes by design, so a
    structure with no free floor round it is full. Where holes are filled, the movers that
    found no place go on to fill them, until the run completes."""
    return bool(flags & SURPLUS) and not flags & HOLES


def rule_flags(params: GGCParams) -> int:
    """The rule set's flags (rules/rulesets.py) as they apply at this d_cover: holes are filled
    only while d_cover + arrive_tolerance <= lattice_reach (a wider lattice leaves holes by
    design, as the paper's d_cover 8 and 10 do)."""
    flags = RULESETS[params.ruleset]
    if params.d_cover + params.arrive_tolerance > params.lattice_reach:
        flags &= ~HOLES
    return int(flags)


def acting_flags(params: GGCParams, groups: int) -> int:
    """The flags of :func:`rule_flags` that can act in a run with ``groups`` groups, as
    rulesets.FLAG_SCOPE declares them: with one group, none whose scope is BETWEEN_GROUPS,
    nor one whose scope is a length that d_cover exceeds. Two rule sets with the same
    acting flags make the same run, tick for tick."""
    flags = rule_flags(params)
    if groups == 1:
        for flag, scope in FLAG_SCOPE.items():
            if scope == BETWEEN_GROUPS or (scope != ANY_GROUPS
                                           and params.d_cover > getattr(params, scope)):
                flags &= ~flag
    return int(flags)


def same_run_ruleset(params: GGCParams, groups: int) -> str:
    """The rule set that names the run of ``params`` with ``groups`` groups canonically: the
    first of "paper", then RULESETS in order, with the same :func:`acting_flags` as
    ``params.ruleset`` (``params.ruleset`` itself when no earlier one has them). The
    experiments give runs of rule sets that name the same canonical one a single run id
    (GGC.same_run_settings)."""
    mine = acting_flags(params, groups)
    for name in dict.fromkeys(("paper", *RULESETS)):
        if acting_flags(replace(params, ruleset=name), groups) == mine:
            return name
    return params.ruleset


class GGCSwarm:
    """The run's GGC robots: ``state`` (one row per robot, the robot's index), beside it
    ``per_group`` (a schema.PerGroup of (robots, groups) arrays, row i robot i's; no columns
    unless the robots start scattered) and the rules' parameters."""

    def __init__(self, setups: Sequence[RobotSetup], params: GGCParams,
                 rngs: Sequence[np.random.Generator]):
        groups = setups[0].groups if setups else 1
        scattered = bool(setups[0].scattered) if setups else False
        self.params = params
        body = setups[0] if setups else RobotSetup(0)
        self.rules = rule_params(params, groups, scattered, body.turn_rate, body.reverse)
        self.state = new_state(setups, params.orbit, params.h_max, rngs)
        self.per_group = new_per_group(setups)
        # scattered start only: per robot, the first tick it had a group / was Formed (-1 =
        # not yet), for the summary's grouping and aggregation figures (GatherTicks)
        self.gather = GatherTicks.new(len(self.state)) if scattered else None
        # the driver's saved rows, reused by every chunk (a chunk has at most one row per
        # robot; the driver writes a row there before it reads it back)
        self._saved = np.empty(len(self.state), dtype=self.state.dtype)
        self._saved_groups = _scratch(self.per_group)
        self._driver_types: tuple | None = None  # argument_types of _driver_fn's chunks
        self._driver_fn: Callable[..., None] = decide_chunk
        # the broadcasts' kernel is typed by the run's message dtype (message_fields):
        # compiled or loaded now, before the run's clock starts
        broadcast_rows(self.state, self.per_group, np.zeros(0, dtype=np.int64),
                       message_dtype(message_fields(groups, scattered)))
        open_probes(np.zeros(0, dtype=np.intp), np.zeros(0, dtype=np.int64),
                    np.zeros((0, MAX_PROBES), dtype=np.int8), np.zeros((0, MAX_PROBES, 2)))

    def warm_up(self) -> None:
        """Compile (the first time) or load the driver for this run's types now, before the
        run's clock starts: a made-up chunk of two robots that hear each other (nothing is
        decided). Only the run's start's rules are compiled (decide.ScatteredRuleParams)."""
        groups, scattered = self.rules.groups, self.rules.scattered
        messages = np.zeros(2, dtype=message_dtype(message_fields(groups, scattered)))
        batch = DecideBatch(0, NeighbourBatch(messages, np.ones(2), np.array([0, 1, 2])),
                            np.array([[1.0, 0.0], [-1.0, 0.0]]), [False, False],
                            np.zeros((2, 2)), np.zeros((2, 2)), lambda k: None, None,
                            lambda ks, offsets: np.zeros(len(ks), dtype=bool))
        ensure_driver(self._chunk_args(np.arange(2, dtype=np.intp), batch))

    def _chunk_args(self, robots: np.ndarray, batch: DecideBatch) -> ChunkArgs:
        """The driver's arguments for a chunk (``robots``: their rows, C-contiguous intp), its
        robots all to decide, afresh."""
        n = len(robots)
        m = batch.neighbours.messages.view()
        m.flags.writeable = False  # the rules read it (one compiled signature: read-only)
        # each column a strided view of the heard rows, not a copy: the rules read a
        # neighbour's fields from its one record
        heard = Heard._make((np.ascontiguousarray(batch.neighbours.starts, dtype=np.int64),
                             np.ascontiguousarray(batch.offsets, dtype=np.float64),
                             np.ascontiguousarray(batch.neighbours.distances, dtype=np.float64),
                             *[m[name] for name in BROADCAST_NAMES]))
        has_beacon = batch.beacons is not None
        return ChunkArgs(
            chunk=Chunk(todo=np.arange(n), rows=robots, state=self.state,
                        saved=self._saved[:n], again=False, per_group=self.per_group,
                        saved_groups=self._saved_groups),
            heard=heard,
            sensors=Sensors(
                tick=int(batch.tick), on_target=np.ascontiguousarray(batch.on_target, dtype=bool),
                moved=np.ascontiguousarray(batch.moved, dtype=np.float64),
                beacons=(np.ascontiguousarray(batch.beacons, dtype=np.float64) if has_beacon
                         else np.zeros((n, 2))),
                has_beacon=has_beacon),
            probes=Probes(req=np.zeros((n, MAX_PROBES, 2)),
                          ans=_filled((n, MAX_PROBES), -1, np.int8),
                          calls=np.zeros(n, dtype=np.int64), pending=np.zeros(n, dtype=bool)),
            P=self.rules,
            actions=Actions(velocity=np.zeros((n, 2)), sleep=np.zeros(n, dtype=bool),
                            wake_range=_filled(n, np.nan, np.float64),
                            wake_on_motion=_filled(n, True, np.bool_),
                            wake_tick=_filled(n, -1, np.int64), listen=np.zeros(n)))

    def decide(self, robots: np.ndarray, batch: DecideBatch) -> ChunkActions:
        """The actions of the chunk's robots (``robots``: their rows, in the batch's order),
        in the dense column form (every robot's broadcast and sleep request)."""
        robots = np.ascontiguousarray(robots, dtype=np.intp)
        a = self._chunk_args(robots, batch)
        driver = self._driver(a, batch)
        chunk, probes, actions = a.chunk, a.probes, a.actions
        while len(chunk.todo):
            driver(*a)
            chunk = chunk._replace(todo=np.flatnonzero(probes.pending), again=True)
            a = a._replace(chunk=chunk)
            if len(chunk.todo):
                self._answer(batch, chunk.todo, probes)
        if self.gather is not None:
            self.gather.mark(self.state, robots, int(batch.tick))
        broadcast = broadcast_rows(self.state, self.per_group, robots,
                                   batch.neighbours.messages.dtype)
        return ChunkActions.columns(
            velocities=actions.velocity, listen=actions.listen, broadcast=broadcast,
            sleep=actions.sleep, wake_range=actions.wake_range,
            wake_on_motion=actions.wake_on_motion, wake_tick=actions.wake_tick)

    def _driver(self, a: ChunkArgs, batch: DecideBatch) -> Callable[..., None]:
        """The driver for ``a``, a chunk's arguments (decide.ensure_driver: one compiled
        signature per start, whatever the chunk's sizes). Looked up again only when the
        arguments' numba types could differ from the last chunk's: every argument is made
        here with fixed types but for what :func:`argument_types` names."""
        types = argument_types(a, batch)
        if types != self._driver_types:
            self._driver_types, self._driver_fn = types, ensure_driver(a)
        return self._driver_fn

    def __getstate__(self) -> dict:
        """A copy (pickle) without the compiled entry point, which is looked up again, and
        without the driver's saved rows (scratch: a chunk writes each row before it reads
        it back, within one :meth:`decide`), which are made again."""
        state = {**self.__dict__, "_driver_types": None, "_driver_fn": decide_chunk}
        del state["_saved"], state["_saved_groups"]
        return state

    def __setstate__(self, state: dict) -> None:
        self.__dict__.update(state)
        self._saved = np.empty(len(self.state), dtype=self.state.dtype)
        self._saved_groups = _scratch(self.per_group)

    @staticmethod
    def _answer(batch: DecideBatch, todo: np.ndarray, probes: Probes) -> None:
        """Answer the open probe questions of the robots ``todo`` (in place, in
        ``probes.ans``)."""
        k, c, offsets = open_probes(todo, probes.calls, probes.ans, probes.req)
        if len(k) == 0:
            return
        if batch.probe_many is not None:
            answers = batch.probe_many(k, offsets)
        else:
            answers = [batch.probe(j)(offset) for j, offset in zip(k.tolist(), offsets,
                                                                     strict=True)]
        probes.ans[k, c] = answers

    def fail(self, robots: np.ndarray, mode: str) -> None:
        """The robots at ``robots`` fail as ``mode`` (one of :data:`FAILURE_MODES`) says: for
        "no_gradient", each loses its gradient (rules/gradient.py, lose_gradient). ValueError
        for another mode."""
        if mode not in FAILURE_MODES:
            raise ValueError(f"GGC simulates the failure modes {sorted(FAILURE_MODES)}, not "
                             f"{mode!r}")
        _lose_gradients(self.state, np.ascontiguousarray(robots, dtype=np.int64))

    def summarize(self, failed: np.ndarray | None = None) -> dict:
        """Per-run GGC figures: final statuses (failed robots as "Failed"), deadlocks (every
        detection; episodes of consecutive detections, released or still open), Stops for
        other groups' movers, robots that gave up after a surplus lap."""
        s = self.state
        working = np.ones(len(s), dtype=bool) if failed is None else ~np.asarray(failed, bool)
        counts = Counter(STATUSES[code] for code in s["status"][working].tolist())
        if not working.all():
            counts["Failed"] = int((~working).sum())
        open_ = int(s["in_deadlock"].sum())
        gather = {} if self.gather is None else self.gather.summary(working)
        return {"status_counts": dict(sorted(counts.items())),
                "deadlocks_detected": int(s["deadlocks"].sum()),
                "deadlock_episodes": int(s["episodes"].sum()),
                "deadlocks_released": int(s["episodes"].sum()) - open_,
                "deadlocks_open": open_,
                "collision_stops": int(s["collision_stops"].sum()),
                "surplus_stops": int(s["surplus"].sum()), **gather}


class GatherTicks:
    """A scattered start's grouping and aggregation (paper Section 4), as the summary reports
    them: per robot, the first tick at whose end it had a group (``grouped``) and the first
    at whose end it had been in its group's formation (status Formed, ``formed``); -1 = not
    yet. Observed after each decision, from the robots' own state rows (no control use)."""

    def __init__(self, grouped: np.ndarray, formed: np.ndarray):
        self.grouped, self.formed = grouped, formed

    @classmethod
    def new(cls, robots: int) -> GatherTicks:
        return cls(np.full(robots, -1, dtype=np.int64), np.full(robots, -1, dtype=np.int64))

    def mark(self, state: np.ndarray, robots: np.ndarray, tick: int) -> None:
        """Note ``tick`` for the robots (rows ``robots`` of ``state``) that have a group or
        have been Formed for the first time."""
        grouped = (state["group"][robots] != 0) & (self.grouped[robots] < 0)
        self.grouped[robots[grouped]] = tick
        was_formed = ((state["visited"][robots] >> FORMED) & 1).astype(bool)
        formed = was_formed & (self.formed[robots] < 0)
        self.formed[robots[formed]] = tick

    def summary(self, working: np.ndarray) -> dict:
        """``grouped_tick``: the tick by which every working robot had a group (None if one
        never had); ``formed_robots``: working robots that were ever Formed; ``formed_tick``:
        the tick the last of them first was (None if none was)."""
        grouped, formed = self.grouped[working], self.formed[working]
        was = formed[formed >= 0]
        return {"grouped_tick": int(grouped.max()) if len(grouped) and grouped.min() >= 0
                else None,
                "formed_robots": len(was),
                "formed_tick": int(was.max()) if len(was) else None}


def _filled(shape: int | tuple[int, ...], value: float, dtype: type) -> np.ndarray:
    """``np.full(shape, value, dtype)``, the same array at half the cost (np.full is Python
    code around numpy's copyto; a chunk's scratch columns are made each tick)."""
    out = np.empty(shape, dtype=dtype)
    out.fill(value)
    return out


def _scratch(per_group: PerGroup) -> PerGroup:
    """Uninitialised arrays of ``per_group``'s shapes and types (the driver's saved rows)."""
    return PerGroup(*(np.empty_like(a) for a in per_group))


def argument_types(a: ChunkArgs, batch: DecideBatch) -> tuple:
    """What sets the numba types of a chunk's driver arguments ``a`` (made by
    GGCSwarm._chunk_args from ``batch``) beyond what _chunk_args fixes (dtypes, layouts): the
    heard messages' dtype, the number of dimensions of each array made from the batch's, and
    whether there is a beacon."""
    heard, sensors = a.heard, a.sensors
    return (batch.neighbours.messages.dtype, heard.starts.ndim, heard.off.ndim,
            heard.dist.ndim, sensors.on_target.ndim, sensors.moved.ndim, sensors.beacons.ndim,
            sensors.has_beacon)


@njit(cache=True)
def _lose_gradients(state, rows):  # pragma: no cover - compiled
    """lose_gradient for the robots at ``rows``, in their state rows."""
    for i in rows:
        lose_gradient(state[i])


@njit(cache=True)
def open_probes(todo, calls, ans, req):  # pragma: no cover - compiled
    """The probe questions of robots ``todo`` still unanswered: for robot k, its first
    ``calls[k]`` questions (at most as many as ``ans`` has slots) whose ``ans[k, c]`` is -1,
    robot by robot, question by question. Returns the robots (M,), the questions' slots (M,)
    and their offsets (M, 2), units."""
    most = len(todo) * ans.shape[1]
    robots, slots = np.empty(most, dtype=np.intp), np.empty(most, dtype=np.intp)
    offsets = np.empty((most, 2))
    m = 0
    for k in todo:
        for c in range(min(calls[k], ans.shape[1])):
            if ans[k, c] < 0:
                robots[m], slots[m] = k, c
                offsets[m, 0], offsets[m, 1] = req[k, c, 0], req[k, c, 1]
                m += 1
    return robots[:m], slots[:m], offsets[:m]
