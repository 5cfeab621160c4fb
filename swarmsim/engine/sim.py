"""The tick loop: sense (one snapshot) -> decide (every awake robot) -> act -> physics -> record.

Every robot decides from the same snapshot and the messages broadcast on the previous tick,
so the order in which controllers are called changes nothing. Robots whose controllers asked to
sleep are skipped until something within their sensing range moves or changes its message.
"""

from __future__ import annotations

import dataclasses
import functools
import gc
import math
import time
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from swarmsim import interrupts
from swarmsim.actionvalues import BadAction, move_problem, show, wake_range_problem
from swarmsim.controller import (
    NO_SENDER,
    Action,
    ChunkActions,
    DecideBatch,
    FailingSwarm,
    NeighbourBatch,
    Perception,
    RobotSetup,
    make_perception,
    silent_message,
)
from swarmsim.engine import tickrows, wakes
from swarmsim.engine.actioncheck import (
    Broadcasts,
    blame,
    check_columns,
    column_problems,
    columns_of,
)
from swarmsim.engine.config import DEAD, SimConfig, build_configs, check_given_once
from swarmsim.engine.controller_info import ControllerInfo, describe
from swarmsim.engine.costs import TIMING_FIELDS as COST_TIMING_FIELDS
from swarmsim.engine.costs import CostCounter, heard_count
from swarmsim.engine.hooks import LoopHook, stop_rules
from swarmsim.errors import ConfigError, ControllerError, did_you_mean, interrupt_within
from swarmsim.kernels import kernelbuild
from swarmsim.kernels.carrays import as_records
from swarmsim.kernels.warmup import registered_warm_ups
from swarmsim.metrics import CoverageGrid, CoveragePart, FinalState, RunMetrics, standard_parts
from swarmsim.physics.physics import Physics, PhysicsConfig
from swarmsim.registry import resolve_controller
from swarmsim.results.provenance import code_version
from swarmsim.results.snapshot import Snapshot
from swarmsim.results.summary import SummaryCollector
from swarmsim.robots.drives import make_drive
from swarmsim.robots.imperfections import Imperfections
from swarmsim.sensing.sensing import FlatViews, FloorSensor, NeighbourSearch
from swarmsim.world import spawn
from swarmsim.world.layouts import LAYOUTS, LayoutRequest
from swarmsim.world.world import World, load_world

if TYPE_CHECKING:
    from swarmsim.engine.faults import FaultInjector

NEVER = np.iinfo(np.int64).max
"""wake_tick of a sleeping robot that set no timeout."""
DEFAULT_CONTROLLER = "ggc"
"""The controller of a run that names none, in a world that names none (the paper's GGC)."""

PHASES = ("sense", "decide", "physics", "metrics")
"""Where a tick's time goes (Simulation.phase_seconds accumulates seconds per phase)."""

TIMING_FIELDS = ("wall_seconds", "cpu_seconds", *COST_TIMING_FIELDS)
"""Summary fields that time the run (the run's seconds, the controller's milliseconds per
robot-tick): the only ones in which two runs of the same seed and settings differ."""

DECIDE_CHUNK = 1024
"""Robots sensed and decided, or whose neighbours are woken, together: bounds a tick's
memory (see Simulation._sense_and_decide) without changing its result."""


@dataclass(frozen=True)
class RunResult:
    """What a finished run returns: the summary and the time series rows."""

    summary: dict[str, Any]
    timeseries: list[dict[str, Any]] = field(default_factory=list)
    robots: list[dict[str, Any]] = field(default_factory=list)
    """One row per robot (robots.csv): final position, status, group, gradient, distance
    moved, settle tick, contacts (columns: docs/outputs.md)."""


class Simulation:
    """One run of a controller on a world.

    Args:
        world: a World or the name/path of a world file.
        controller: registered controller name (default: the world's ``defaults.controller``,
            else "ggc", the paper's method, as on the command line; e.g. "dispersion",
            "kilobot"), "module:Class", or a controller class (the summary names it by its
            registered name, else "module:Class").
        robots: number of robots (default: the world's ``defaults.robots``).
        groups: number of groups K (default: the world's ``defaults.groups``, else 1). Only
            a controller that forms groups (one that declares ``max_groups``: GGC) or a
            formation start (one formation per group) uses groups; any other run has one
            group (its summary says groups 1) and asking it for more is an error.
        seed: the one seed that decides the run (default 0).
        d_cover: the controller's coverage distance, units (paper Table 2: 6).
        max_ticks: hard tick limit.
        settings: any other parameter by name (engine, physics or controller), e.g.
            ``{"eps0": 0.02, "radius": 0.5}``; unknown names are an error, and so is a name
            also given as an argument above (``robots=5`` and ``{"robots": 7}``).
    """

    def __init__(self, world: World | str, controller: str | type | None = None,
                 robots: int | None = None, groups: int | None = None, seed: int | None = None,
                 d_cover: float | None = None, max_ticks: int | None = None,
                 settings: Mapping[str, Any] | None = None):
        self._configure(world, controller, robots, groups, seed, d_cover, max_ticks, settings)
        self._setup()
        self.engine_hooks = len(self.hooks)
        """How many of ``hooks`` the run made itself (the rest are a user's)."""

    @classmethod
    def check(cls, world: World | str, controller: str | type | None = None,
              robots: int | None = None, groups: int | None = None, seed: int | None = None,
              d_cover: float | None = None, max_ticks: int | None = None,
              settings: Mapping[str, Any] | None = None) -> tuple[SimConfig, Any]:
        """Check a run's world, controller and settings as the constructor does, without
        building the run (no layout, no bodies: milliseconds). Raises ConfigError naming the
        key and value. Sweeps and reproductions check every run this way before the first.
        Returns the run's engine settings and controller parameters as the run would have
        them (the world's defaults filled in)."""
        sim = cls.__new__(cls)
        sim._configure(world, controller, robots, groups, seed, d_cover, max_ticks, settings)
        return sim.config, sim.params

    def _configure(self, world: World | str, controller: str | type | None, robots: int | None,
                   groups: int | None, seed: int | None, d_cover: float | None,
                   max_ticks: int | None, settings: Mapping[str, Any] | None) -> None:
        """Load the world and the controller class and build the validated configs."""
        self.world = world if isinstance(world, World) else load_world(world)
        controller = controller or self.world.defaults.get("controller", DEFAULT_CONTROLLER)
        self.controller_cls, controller = resolve_controller(controller)
        self.controller_name = controller
        self.info: ControllerInfo = describe(self.controller_cls, self.controller_name)
        if self.info.requires_beacon and self.world.beacon is None:
            raise ConfigError(f"controller {controller!r} needs a [beacon] in the world file",
                              source=self.world.source, key="beacon")
        merged = self._merge_settings(robots, groups, seed, d_cover, max_ticks, settings or {})
        self.config, self.physics_config, self.params = build_configs(merged,
                                                                      self.controller_cls.Params)
        self._check_configs()

    def _check_configs(self) -> None:
        """Checks that span the engine's, the physics' and the controller's settings."""
        most = self.info.max_groups
        if most is not None and self.config.groups > most:
            raise ConfigError(f"value {self.config.groups}: controller "
                              f"{self.controller_name!r} supports at most {most} groups",
                              key="groups")
        start = self._start()
        if start not in self.info.layouts:
            offered = ", ".join(self.info.layouts)
            raise ConfigError(f"controller {self.controller_name!r} offers the starts {offered}; "
                              f"got {start!r}", key="start")
        body = 2 * self.physics_config.radius
        if self.world.target_area < np.pi * body * body / 4:
            raise ConfigError(f"{self.physics_config.radius!r}: one robot's disc is larger than "
                              f"the target's free floor ({self.world.target_area:.3g} units^2)",
                              source=self.world.source, key="radius")
        for name in ("spawn_spacing", "formation_spacing"):
            if getattr(self.config, name) < body:
                raise ConfigError(f"{getattr(self.config, name)!r} is less than a body's width "
                                  f"(2 x radius = {body:g}): robots would start overlapping",
                                  key=name)
        if self.info.commands == "wheels" and self.physics_config.drive == "holonomic":
            raise ConfigError(f"controller {self.controller_name!r} commands wheels (COMMANDS = "
                              "'wheels'), but drive=holonomic has none: set drive=diff or "
                              "drive=kilobot", key="drive")
        self._check_failure_mode()
        spawn.check_capacity(self.world, self.config.robots, self._start(),
                             self.config.spawn_spacing, self.config.formation_spacing)
        reach = self._probe_range()
        for name in self.info.probe_params:
            value = getattr(self.params, name)
            if not 0 < value <= reach:
                raise ConfigError(f"must be in (0, {reach:g}], got {value!r}: a floor probe reaches"
                                  " probe_range at most (set probe_range too)", key=name)

    def _check_failure_mode(self) -> None:
        """Refuse a failure_mode the run's controller does not simulate ("dead" is every
        controller's; others are its FAILURE_MODES), naming the controller and its modes."""
        mode, modes = self.config.failure_mode, self.info.failure_modes
        if mode == DEAD or mode in modes:
            return
        name, known = self.controller_name, [DEAD, *modes]
        hint = did_you_mean(mode, known).removeprefix("; ")
        others = _controllers_with_failure_mode(mode)
        what = (f"is a failure mode of {', '.join(others)}, not of controller {name!r}"
                if others else f"is not a failure mode of controller {name!r}"
                               + (f" ({hint})" if hint else ""))
        offered = (f"its modes: {', '.join(known)} ('swarmsim params --controller {name}' "
                   "says what each does)" if modes else f"its only mode is {DEAD!r}")
        raise ConfigError(f"{mode!r} {what}; {offered}", key="failure_mode")

    def _start(self) -> str:
        """The run's start layout: the setting, else the controller class's default_start,
        else "random"."""
        return self.config.start or self.info.default_start

    def _probe_range(self) -> float:
        """How far a robot's floor probe reaches, units: the engine's probe_range, or more if
        the controller class needs it (``min_probe_range``)."""
        return max(self.config.probe_range, self.info.min_probe_range)

    def _merge_settings(self, robots, groups, seed, d_cover, max_ticks,
                        settings: Mapping[str, Any]) -> dict[str, Any]:
        merged: dict[str, Any] = {}
        defaults = self.world.defaults
        for key in ("robots", "groups", "max_ticks", "start", "drive", "grid_size"):
            if key in defaults:
                merged[key] = defaults[key]
        if "d_cover" in defaults and _has_field(self.controller_cls.Params, "d_cover"):
            merged["d_cover"] = defaults["d_cover"]
        explicit = {"robots": robots, "groups": groups, "seed": seed, "d_cover": d_cover,
                    "max_ticks": max_ticks}
        given = {key: (f"{key}={value!r}", value) for key, value in explicit.items()
                 if value is not None}
        check_given_once(given, {key: (f"settings {key}={value!r}", value)
                                 for key, value in settings.items()})
        merged.update({key: value for key, (_, value) in given.items()})
        merged.update(settings)
        if "d_cover" in merged and not _has_field(self.controller_cls.Params, "d_cover"):
            raise ConfigError(f"controller {self.controller_name!r} has no d_cover parameter "
                              f"(value {merged['d_cover']!r})", key="d_cover")
        if "groups" in merged and not self.info.uses_groups(str(merged.get("start") or "")):
            self._no_groups(merged, settings.get("groups", groups))
        return merged

    def _no_groups(self, merged: dict[str, Any], explicit: Any) -> None:
        """A run whose controller and start have no use for groups has one: the world's
        default is dropped; more than one, asked for, is an error."""
        if explicit is None:
            del merged["groups"]
        elif not (isinstance(explicit, int) and not isinstance(explicit, bool) and explicit <= 1):
            raise ConfigError(f"controller {self.controller_name!r} has no groups (value "
                              f"{explicit!r}): only a controller that forms groups (ggc) or a "
                              "formation start (start=formation: one formation per group) "
                              "uses them", key="groups")

    # ----------------------------------------------------------------------------- setup
    def _setup(self) -> None:
        cfg = self.config
        seeds = np.random.SeedSequence(cfg.seed).spawn(4)
        layout_rng, role_rng, order_rng = (np.random.default_rng(s) for s in seeds[:3])
        robot_seeds = seeds[3].spawn(cfg.robots)
        start = self._start()
        self.start = start
        positions, setups = self._initial_layout(start, layout_rng, role_rng)
        self.n = len(positions)
        self.start_groups = np.array([s.group for s in setups], dtype=np.int64)
        self.start_leaders = np.array([s.leader for s in setups], dtype=bool)
        self.drive = make_drive(self.physics_config, cfg.seed, self.n)
        """The robots' drive model (swarmsim/robots/drives.py): holonomic, diff, kilobot."""
        setups = self._with_drive_traits(setups)
        self.physics = Physics(self.world, positions, self.physics_config,
                               angles=self.drive.start_headings())
        probe_range = self._probe_range()
        self.floor = FloorSensor(self.world.target, probe_range)
        with self._controller_call("sensing_range()"):
            self.sensing_range = self.info.sensing_range(self.params)
        if cfg.sensing_limit > 0:
            self.sensing_range = min(self.sensing_range, cfg.sensing_limit)
        self.swarm = self._create_swarm(setups, [np.random.default_rng(s) for s in robot_seeds],
                                        order_rng)
        self._decider = getattr(self.swarm, "decider", "decide()")
        """What the run calls its controller's actions by in errors ("step()", ...)."""
        self.statuses = self.info.statuses
        scattered = any(s.scattered for s in setups)
        self.dtype = self.info.message_dtype(cfg.groups, scattered)
        self.broadcasts = Broadcasts(self.dtype, self.statuses)
        self.silent = silent_message(self.dtype, self.info.silent)
        self.messages = np.zeros(self.n, dtype=self.dtype)
        self.messages[:] = self.silent
        self.costs = CostCounter.for_dtype(self.dtype)
        """Decisions, broadcasts heard and controller time so far (swarmsim/engine/costs.py)."""
        self.tick = 0
        self.positions, _ = self.physics.read()
        self._prev_positions = self.positions.copy()
        self._ref_positions = self.positions.copy()
        self._changed_msg = np.zeros(self.n, dtype=bool)  # broadcasts changed last tick
        self.asleep = np.zeros(self.n, dtype=bool)
        self.wake_range = np.full(self.n, self.sensing_range)
        self.listen = np.full(self.n, self.sensing_range)
        self.wake_on_motion = np.ones(self.n, dtype=bool)
        self.wake_tick = np.full(self.n, NEVER, dtype=np.int64)
        self.failed = np.zeros(self.n, dtype=bool)
        """(N,) the robots failed "dead": silent bodies, never decided again."""
        self.failed_in_mode = np.zeros(self.n, dtype=bool)
        """(N,) the robots failed in a mode of the controller's (FAILURE_MODES): still working."""
        self.velocities = np.zeros((self.n, 2))
        self._turned = np.zeros(self.n)
        """(N,) each body's turn over the previous tick, rad (Perception.turned); zeros for a
        holonomic drive."""
        if self.drive.has_heading:
            self._motion = np.zeros((self.n, 2))
            self._headings = self.physics.headings()
            """(N,) the body angles at the start of this tick, rad (read before deciding)."""
        self.grid = CoverageGrid.for_target(self.world.target, cfg.coverage_radius,
                                            cfg.grid_size, cfg.grid_size, self.world.obstacles)
        self.metrics = RunMetrics(standard_parts(self.grid, cfg, self.physics,
                                                 self.settled_codes(), self.dtype),
                                  cfg.record_every)
        self.imperfect = Imperfections(cfg.noise_levels(), cfg.seed)
        self.on_target = self.floor.on_target(self.positions)
        self.phase_seconds = dict.fromkeys(PHASES, 0.0)
        self.awake_count = self.n
        """Robots that decided in the last tick (all of them before the first)."""
        injector = self._fault_injector()
        self.hooks: list[LoopHook] = [*([injector] if injector is not None else []),
                                      self.metrics, *stop_rules(cfg, self.metrics)]
        """What runs around each tick, in order (swarmsim.engine.hooks.LoopHook): the fault
        injector, the metrics, the stop rules; a user's hook is appended."""
        for hook in self.hooks:
            hook.start(self)
        warm_ups = [*registered_warm_ups(),  # the engine's kernels, each module's own
                    (f"controller {self.info.name}", self._warm_up_controller)]
        for k, (name, warm_up) in enumerate(warm_ups, 1):  # before the run's clock starts
            with kernelbuild.step(name, k, len(warm_ups)):
                warm_up()  # compiled (the first time) or loaded from the cache
        self.stop_reason: str | None = None
        self.wall_seconds = 0.0
        self.cpu_seconds = 0.0  # this process's CPU time in the tick loop, s
        self.summary_sources = SummaryCollector()
        """Where summary.json's fields come from, in order (add a source to add fields)."""
        self.summary_sources.add("run", self._run_fields)
        self.summary_sources.add("metrics",
                                 lambda: self.metrics.summary(self.positions, self.on_target))
        self._travel_floor: float | None = None
        """The world's travel floor at this run's v_max, ticks, once measured."""
        self.summary_sources.add("floor", self._floor_fields)
        self.summary_sources.add("failures", lambda: {
            "failed_robots": int(self.failed.sum() + self.failed_in_mode.sum())})
        self.summary_sources.add("costs", lambda: self.costs.fields())
        if cfg.failures:
            self.summary_sources.add("faults", lambda: {
                "fault_tick": None if injector is None else injector.fired_tick})
        self.summary_sources.add("controller", self._controller_summary)

    def _with_drive_traits(self, setups: list[RobotSetup]) -> list[RobotSetup]:
        """``setups`` telling each robot what its drive can do (turn rate, reverse); a
        holonomic run's as they are (the defaults say holonomic)."""
        if not self.drive.has_heading:
            return setups
        rates, reverse = self.drive.turn_rates().tolist(), self.drive.reverse
        return [dataclasses.replace(setup, turn_rate=rate, reverse=reverse)
                for setup, rate in zip(setups, rates, strict=True)]

    def _fault_injector(self) -> FaultInjector | None:
        """The hook that fails robots as the run's ``failures`` settings ask (None: none)."""
        cfg = self.config
        if not cfg.failures:
            return None
        from swarmsim.engine.faults import FaultPlan, fault_injector, fault_rng
        return fault_injector(FaultPlan.from_config(cfg), self.n, fault_rng(cfg.seed))

    def _create_swarm(self, setups: list[RobotSetup], rngs: list[np.random.Generator],
                      order_rng: np.random.Generator) -> Any:
        """The run's Swarm (ControllerError if the controller's class cannot make one)."""
        cfg = self.config
        call = "create_swarm()" if self.info.batch else "__init__()"
        with self._controller_call(call):
            swarm = self.info.create_swarm(setups, self.params, rngs,
                                           shuffled=cfg.decide_order == "shuffled",
                                           order_rng=order_rng)
        if not all(callable(getattr(swarm, name, None)) for name in ("decide", "summarize")):
            raise ControllerError(f"{call} returned {show(swarm)}; expected a Swarm (with "
                                  "decide and summarize)", controller=self.controller_name)
        if cfg.failures and cfg.failure_mode != DEAD and not isinstance(swarm, FailingSwarm):
            raise ControllerError(f"{call} returned a Swarm without fail(robots, mode), which "
                                  "its class's FAILURE_MODES need (failure_mode "
                                  f"{cfg.failure_mode!r})", controller=self.controller_name)
        return swarm

    @contextmanager
    def _controller_call(self, call: str, tick: int | None = None) -> Iterator[None]:
        """Turn an exception of the controller's ``call`` into a ControllerError naming the
        controller (the controller's own exception its cause). A ConfigError (the controller
        refusing its settings) and an interrupt pass as they are."""
        try:
            yield
        except ConfigError:
            raise
        except Exception as exc:  # noqa: BLE001 - the controller's code may raise anything
            raise self._blamed(exc, call, tick)

    def _blamed(self, exc: Exception, call: str, tick: int | None,
                robots: np.ndarray | None = None) -> Exception:
        """The ControllerError of an exception of the controller's ``call`` or of a BadAction
        of what it returned (row k: robot ``robots[k]``), naming this run's controller; an
        interrupt (swarmsim.errors.interrupt_within) as it is."""
        return exc if interrupt_within(exc) else blame(exc, self.controller_name, call, tick,
                                                        robots)

    def _controller_summary(self) -> Mapping[str, Any]:
        """The controller's own summary fields (Swarm.summarize)."""
        with self._controller_call("summarize()", self.tick):
            summary = self.swarm.summarize(self.failed)
        if not isinstance(summary, Mapping):
            raise ControllerError(f"summarize() returned {show(summary)}; expected a dict",
                                  controller=self.controller_name, tick=self.tick)
        return summary

    def _warm_up_controller(self) -> None:
        """Compile or load the controller's kernels: its class's, then its swarm's (the
        optional ``warm_up`` of each)."""
        with self._controller_call("warm_up()"):
            self.info.warm_up()
            warm_up = getattr(self.swarm, "warm_up", None)
            if warm_up is not None:
                warm_up()

    @property
    def controllers(self) -> list:
        """The robots' controller objects, one per robot (per-robot controllers only; a batch
        controller keeps its robots' state in its ``swarm``)."""
        robots = getattr(self.swarm, "robots", None)
        if robots is None:
            raise AttributeError(f"controller {self.controller_name!r} keeps its robots' state "
                                 "in sim.swarm, not in per-robot objects")
        return robots

    def settled_codes(self) -> tuple[int, ...]:
        """Status codes in which the controller's robots are done (its SETTLED_STATUSES)."""
        return self.info.codes(self.info.settled)

    def _initial_layout(self, start: str, layout_rng: np.random.Generator,
                        role_rng: np.random.Generator) -> tuple[np.ndarray, list[RobotSetup]]:
        """Where the robots start and what each is told (a layout the controller offers:
        checked in _check_configs)."""
        cfg = self.config
        request = LayoutRequest(cfg.robots, cfg.groups, cfg.spawn_spacing,
                                cfg.formation_spacing, self.physics_config.radius)
        return LAYOUTS[start](self.world, request, layout_rng, role_rng)

    # ----------------------------------------------------------------------------- loop
    def step(self) -> None:
        """Advance the run by one tick (sense -> decide -> act -> physics -> record)."""
        clock = time.perf_counter
        t0 = clock()
        for hook in self.hooks:
            hook.pre_step(self)
        pos = self.positions
        if self.drive.has_heading:
            self._read_headings()
        search = NeighbourSearch(pos)
        awake = self._awake_robots()
        new_messages = as_records(self.messages).copy().view(self.dtype)
        velocities = np.zeros((self.n, 2))
        decide_s = self._sense_and_decide(search, awake, new_messages, velocities)
        t1 = clock()
        self._changed_msg = tickrows.rows_differ(new_messages, self.messages, awake)
        self.messages = new_messages
        if self.info.commands == "wheels":  # (left, right) wheel speeds
            top = self.physics_config.wheel_speed
            np.clip(velocities, -top, top, out=velocities)
            self.velocities = self.imperfect.actuate_wheels(velocities)
        else:
            tickrows.clamp_rows(velocities, awake, self.config.v_max)  # the others stand still
            self.velocities = self.imperfect.actuate(velocities)
        t2 = clock()
        sense_s, decide_s = (t1 - t0) - decide_s, decide_s + (t2 - t1)
        self._command_drive()
        self.physics.step()
        self.tick += 1
        self._prev_positions = pos
        self.positions, _ = self.physics.read()
        self.on_target = self._on_target_now(pos)
        t3 = clock()
        self.awake_count = len(awake)
        for hook in self.hooks:  # faults, metrics, the stop rules' bookkeeping
            hook.post_step(self)
        t4 = clock()
        for phase, dt in zip(PHASES, (sense_s, decide_s, t3 - t2, t4 - t3), strict=True):
            self.phase_seconds[phase] += dt
        interrupts.raise_pending()  # one noted during the physics step: the tick is whole

    @property
    def motion(self) -> np.ndarray:
        """(N, 2) what the drive made of ``velocities`` this tick: the velocities of the
        robots' drive points, units/tick (a holonomic run's: ``velocities`` themselves)."""
        return self._motion if self.drive.has_heading else self.velocities

    def _command_drive(self) -> None:
        """Hand this tick's ``velocities`` to the bodies: directly (holonomic: the code path
        of every run before drives existed), or through the drive, which steers each body
        from its heading."""
        if not self.drive.has_heading:
            self.physics.command(self.velocities)
            return
        wheels = self.info.commands == "wheels"
        lin, spin = self.drive.motion(None if wheels else self.velocities,
                                      self.velocities if wheels else None, self._headings,
                                      ~self.failed)
        self._motion = lin
        self.physics.command_motion(lin, spin)

    def _read_headings(self) -> None:
        """Read the body angles at the start of a tick (a drive with a heading) and each
        robot's turn since the last read (odometry: Perception.turned), wrapped to
        [-pi, pi)."""
        headings = self.physics.headings()
        self._turned = (headings - self._headings + np.pi) % (2 * np.pi) - np.pi
        self._headings = headings

    def _on_target_now(self, before: np.ndarray) -> np.ndarray:
        """(N,) the floor sensors after the physics step (robots were at ``before``)."""
        return self.floor.on_target_after(self.on_target, self.positions, before)

    def _awake_robots(self) -> np.ndarray:
        """Indices of robots to decide this tick: awake ones plus sleepers something woke
        (their own timeouts, drift, a changed or pushed robot near them: wakes.awake_robots)."""
        margin = 2 * self.config.v_max + self.config.wake_eps
        return wakes.awake_robots(self.asleep, self.failed, self.wake_tick, self.tick,
                                  self.positions, self._ref_positions, self.velocities,
                                  self.config.wake_eps, self._changed_msg, self.wake_range,
                                  self.wake_on_motion, margin)

    def _sense_and_decide(self, search: NeighbourSearch, awake: np.ndarray,
                          new_messages: np.ndarray, velocities: np.ndarray
                          ) -> float:
        """Sense and decide ``DECIDE_CHUNK`` awake robots at a time; seconds spent deciding.

        Everyone decides from the same snapshot (positions, last tick's broadcasts), so the
        chunks change nothing but the memory: the neighbour views and the heard messages (one
        row per neighbour: GGC's are 44 bytes for formations, 8 more per group for the scattered
        start) exist for one chunk at a time. On the first tick of a 10,000-robot formation
        every robot hears ~800 neighbours: with rows of 162 bytes (16 groups' fields, as GGC's
        once were), ~1.3 GB in one piece.
        """
        clock = time.perf_counter
        moved = self.positions - self._prev_positions
        perturb = self.imperfect.perturb_offsets if self.imperfect.perturbs_sensing else None
        decide_s = 0.0
        for start in range(0, len(awake), DECIDE_CHUNK):
            chunk = awake[start:start + DECIDE_CHUNK]
            views = search.neighbourhoods_flat(chunk, self.listen[chunk], perturb=perturb)
            began = clock()
            self._decide(chunk, views, moved, new_messages, velocities)
            decide_s += clock() - began
            del views  # before the next chunk's are made
        return decide_s

    def _decide(self, awake: np.ndarray, views: FlatViews, moved: np.ndarray,
                new_messages: np.ndarray, velocities: np.ndarray) -> None:
        """Decide the awake robots of one chunk from their neighbourhood ``views``."""
        if len(awake) == 0:
            return
        heard, heard_rows = self._heard(views.neighbours,
                                        lambda: np.repeat(awake, views.counts))
        starts = np.zeros(len(awake) + 1, dtype=np.int64)
        np.cumsum(views.counts, out=starts[1:])
        offsets, distances = views.offsets, views.distances
        here = np.take(self.positions, awake, axis=0)  # positions[awake]; take is faster
        bearings = None if self.world.beacon is None else tickrows.bearings(self.world.beacon,
                                                                           here)
        probe_at, tick = self.floor.probe_at, self.tick
        on = self.imperfect.read_floor(self.on_target[awake],
                                       lambda: self.floor.edge_distance(here))
        shift = np.take(moved, awake, axis=0)
        turned = self._turned[awake]

        @functools.cache  # the per-robot path's Python lists, made when first asked for
        def listed() -> tuple[list, list, list, list]:
            return starts.tolist(), here.tolist(), on.tolist(), turned.tolist()

        def perceive(k: int) -> Perception:
            bounds, at, on_list, turned_list = listed()
            a, b = bounds[k], bounds[k + 1]
            return make_perception(tick, offsets[a:b], distances[a:b], heard[a:b], on_list[k],
                                   probe_at(*at[k]), None if bearings is None else bearings[k],
                                   shift[k], turned_list[k])

        batch = DecideBatch(tick, NeighbourBatch(heard, distances, starts), offsets, on, shift,
                            bearings, lambda k: probe_at(*listed()[1][k]), perceive,
                            self.floor.probes(here), turned)
        began = time.process_time()
        try:
            actions = self.swarm.decide(awake, batch)
        except Exception as exc:  # noqa: BLE001 - the controller's code may raise anything
            raise self._blamed(exc, self._decider, tick, awake)  # a BadAction of put: its row
        self.costs.add(len(awake), heard_rows, time.process_time() - began)
        try:
            self._apply(awake, actions, new_messages, velocities)
        except BadAction as bad:
            raise self._blamed(bad, self._decider, tick, awake) from None

    def _heard(self, senders: np.ndarray, receivers: Callable[[], np.ndarray]
               ) -> tuple[np.ndarray, int]:
        """The broadcasts heard from ``senders`` (read-only; failed robots and lost messages
        read as silent), and how many of them have a sender (costs.heard_count);
        ``receivers()``: who hears each (asked only by a message model that depends on
        distance)."""
        # the rows as opaque records, taken with np.take: bytes copied, not field by field
        heard = np.take(as_records(self.messages), senders).view(self.dtype)
        quiet = self.messages["id"] == NO_SENDER
        if np.count_nonzero(self.failed):
            quiet |= self.failed
            heard[self.failed[senders]] = self.silent
        distances = None
        if self.imperfect.loss_needs_distances:  # true distances, not the sensed ones
            gap = self.positions[senders] - self.positions[receivers()]
            distances = np.sqrt(gap[:, 0] * gap[:, 0] + gap[:, 1] * gap[:, 1])
        lost = self.imperfect.lost(len(heard), distances)
        if lost is not None:
            heard[lost] = self.silent
        heard.flags.writeable = False  # every robot gets a read-only view of its part
        return heard, heard_count(senders, quiet, lost)

    def _apply(self, awake: np.ndarray, actions: list[Action] | ChunkActions,
               new_messages: np.ndarray, velocities: np.ndarray) -> None:
        """Write the awake robots' actions: velocities, broadcasts, listening and sleep.
        Each is checked as it is written (swarmsim.engine.actioncheck); BadAction names the chunk's
        row of the first that breaks the controller API."""
        if len(awake) == 0:
            return
        if isinstance(actions, ChunkActions):
            check_columns(actions, len(awake), self.dtype)
        elif isinstance(actions, (list, tuple)):
            actions = columns_of(actions, len(awake))
        else:
            raise BadAction(None, f"{show(actions)}; expected a ChunkActions or a list of "
                                  "Actions")
        vel = actions.velocities
        reach = self.sensing_range
        try:
            bad = tickrows.put_moves(awake, vel, actions.listen, reach, velocities, self.listen)
        except Exception:  # columns numpy or numba cannot take: named
            _name_columns(actions, len(awake))
            raise
        if bad != -1:
            _name_columns(actions, len(awake), bad)
            raise BadAction(bad, move_problem(vel[bad], actions.listen[bad]))
        if actions.broadcast is not None:
            if actions.broadcast.dtype == self.dtype:
                as_records(new_messages)[awake] = as_records(actions.broadcast)
            else:
                new_messages[awake] = actions.broadcast
            self._sign(new_messages, awake)
        elif actions.messages:
            self._send(awake, actions.messages, new_messages)
        if not self.config.allow_sleep:
            return
        if actions.sleep is not None:
            try:
                bad = tickrows.put_sleep(awake, vel, actions.sleep, actions.wake_range,
                                         actions.wake_on_motion, actions.wake_tick, reach,
                                         NEVER, self.asleep, self.wake_range,
                                         self.wake_on_motion, self.wake_tick)
            except Exception:  # columns numpy or numba cannot take: named
                _name_columns(actions, len(awake))
                raise
            if bad != -1:
                _name_columns(actions, len(awake), bad)
                raise BadAction(bad, wake_range_problem(actions.wake_range[bad]))
            return
        for k, action in actions.sleepers.items():  # checked: swarmsim.engine.actioncheck
            if vel[k, 0] == 0 and vel[k, 1] == 0:
                i = awake[k]
                self.asleep[i] = True
                self.wake_on_motion[i] = action.wake_on_motion
                tick = action.wake_tick  # past int64 (10**30, say) is never, as None
                self.wake_tick[i] = NEVER if tick is None else min(int(tick), NEVER)
                wake = action.wake_range
                self.wake_range[i] = reach if wake is None else min(float(wake), reach)

    def _send(self, awake: np.ndarray, messages: dict[int, Any],
              new_messages: np.ndarray) -> None:
        """Write the new broadcasts ({k: row} of the chunk's robots; a row is a tuple in the
        dtype's order or a dict by field name: swarmsim.engine.actioncheck.Broadcasts)."""
        sent = np.fromiter(messages, dtype=np.int64, count=len(messages))
        try:
            rows = self.broadcasts.array(list(messages.values()))
        except BadAction as bad:
            raise BadAction(None if bad.row is None else int(sent[bad.row]), bad.problem) from None
        new_messages[awake[sent]] = rows
        self._sign(new_messages, awake[sent], sent)

    def _sign(self, new_messages: np.ndarray, robots: np.ndarray,
              rows: np.ndarray | None = None) -> None:
        """Stamp the new broadcasts of ``robots`` (the chunk's ``rows``; None: all its rows, in
        order) with their senders' own ids, and check their status codes (BadAction)."""
        bad = tickrows.sign_rows(new_messages, robots, len(self.statuses))
        if bad >= 0:
            status = int(new_messages["status"][robots[bad]])
            raise BadAction(bad if rows is None else int(rows[bad]),
                            self.broadcasts.status_problem(status))

    def fail(self, robots: np.ndarray, mode: str = DEAD) -> None:
        """Make robots fail now. "dead": they stop moving and communicating but stay physical
        bodies. A mode of the controller's (its FAILURE_MODES; the run checked it): its
        swarm's ``fail(robots, mode)`` changes their state, and they are woken to act on it
        (ControllerError if the controller's fail raises)."""
        robots = np.asarray(robots, dtype=np.intp)
        if mode != DEAD:
            with self._controller_call("fail()", self.tick):
                self.swarm.fail(robots, mode)
            self.failed_in_mode[robots] = True
            self.asleep[robots] = False
            return
        self.failed[robots] = True
        self.messages[self.failed] = self.silent
        if hasattr(self, "_changed_msg"):  # fell silent: wakes sleeping neighbours next tick
            self._changed_msg[robots] = True

    # ----------------------------------------------------------------------------- running
    @property
    def broadcasts_changed(self) -> bool:
        """Did a broadcast change in the last tick (or a robot fall silent)?"""
        return np.count_nonzero(self._changed_msg) > 0

    def finished(self) -> str | None:
        """Why the run should stop now: the reason of the first hook in ``hooks`` whose
        ``is_finished`` gives one ("complete", "stalled", "plateau", "max_ticks", or a user
        hook's), else None."""
        for hook in self.hooks:
            reason = hook.is_finished(self)
            if reason is not None:
                return reason
        return None

    def advance(self, on_tick: Callable[[Simulation], None] | None = None) -> str | None:
        """Run one tick (:meth:`step`), then ``on_tick(self)`` if given, then set and return
        ``stop_reason`` (:meth:`finished`: None while the run goes on)."""
        self.step()
        if on_tick is not None:
            on_tick(self)
        self.stop_reason = self.finished()
        return self.stop_reason

    def run(self, progress: bool = False, on_tick: Callable[[Simulation], None] | None = None
            ) -> RunResult:
        """Run until a stop rule (a loop hook's ``is_finished``: completion, stall, plateau,
        max_ticks, or a user's) says stop; return the summary, the series and robots.csv."""
        bar = _progress_bar(self.config.max_ticks, progress)
        start, start_cpu = time.perf_counter(), time.process_time()
        try:
            with _old_objects_frozen(), interrupts.handled():  # never a lost Ctrl-C
                while self.stop_reason is None:
                    self.advance(on_tick)
                    if bar is not None and (self.tick % 50 == 0 or self.stop_reason):
                        bar.set_postfix_str(f"coverage {100 * self.metrics.coverage:5.1f}%",
                                            refresh=False)
                        bar.update(self.tick - bar.n)  # redraws at most every mininterval
        finally:
            self.wall_seconds += time.perf_counter() - start
            self.cpu_seconds += time.process_time() - start_cpu
            if bar is not None:
                bar.close()
        return self.result()

    def result(self) -> RunResult:
        """The run as it stands now (at its end, what ``run`` returns): the summary, the time
        series with a row for this tick, and robots.csv's rows. A run not yet ended has
        ``stop_reason`` None in its summary."""
        self.metrics.record(self.tick, force=True)
        return RunResult(self.summary(), list(self.metrics.rows),
                         self.metrics.robot_rows(self.final_state()))

    def summary(self) -> dict[str, Any]:
        """The run's summary: the fields of summary.json, from ``summary_sources``."""
        return self.summary_sources.collect()

    def travel_floor_ticks(self) -> float:
        """The world's travel floor at this run's v_max, ticks (swarmsim/world/floor.py):
        measured on first use, then kept by this run."""
        if self._travel_floor is None:
            from swarmsim.world.floor import travel_floor_ticks

            self._travel_floor = travel_floor_ticks(self.world, self.config.v_max)
        return self._travel_floor

    def _floor_fields(self) -> dict[str, Any]:
        """The travel floor, ticks (None when obstacles wall part of the target off), and the
        completion tick's ratio to it (None when the run has not completed, or the floor is
        None or 0: the target lies in a spawn area)."""
        floor = self.travel_floor_ticks()
        if not math.isfinite(floor):
            return {"travel_floor_ticks": None, "floor_ratio": None}
        done = self.metrics.part(CoveragePart).completion_tick
        ratio = round(done / floor, 3) if done is not None and floor > 0 else None
        return {"travel_floor_ticks": round(floor, 1), "floor_ratio": ratio}

    def _run_fields(self) -> dict[str, Any]:
        """What the run was: world, controller, settings, how and when it ended."""
        d_cover = getattr(self.params, "d_cover", None)
        return {
            "world": self.world.name,
            "controller": self.controller_name,
            "robots": self.n,
            "groups": self.config.groups,
            "d_cover": d_cover,
            "seed": self.config.seed,
            "start": self.start,
            "mode": self.physics_config.mode,
            "ticks": self.tick,
            "stop_reason": self.stop_reason,
            "wall_seconds": round(self.wall_seconds, 3),
            "cpu_seconds": round(self.cpu_seconds, 3),
            "code_version": code_version(),
        }

    def final_state(self) -> FinalState:
        """The state robots.csv reads (positions, broadcasts, failures): a copy, now."""
        info = self.info
        fields = (*info.colourings, *([info.leader_field] if info.leader_field else []))
        return FinalState(self.positions.copy(), self.messages.copy(), self.statuses,
                          self.failed.copy(), fields, info.silent)

    def snapshot(self, with_coverage: bool = True) -> Snapshot:
        """A read-only copy of the current state, for observers (render, analysis)."""
        covered = self.grid.covered_grid(self.positions) if with_coverage else None
        in_contact = self.physics.contact_state().in_contact
        return Snapshot(tick=self.tick, positions=self.positions.copy(),
                        messages=self.messages.copy(), statuses=self.statuses,
                        radius=self.physics_config.radius, coverage=self.metrics.coverage,
                        covered=covered, in_contact=in_contact, failed=self.failed.copy(),
                        start_groups=self.start_groups.copy(),
                        start_leaders=self.start_leaders.copy(),
                        headings=self.physics.headings().copy() if self.drive.has_heading
                        else None)

    def save(self, path: str | Path) -> None:
        """Write the run's whole state to ``path`` (atomically), between two ticks (after
        :meth:`advance`, or from its ``on_tick``): :meth:`restore` continues it, in any
        process. Saving is an event in the run: the run goes on from the state loaded back
        from the file, so it and every restore of the file end identically (summary, time
        series, robots.csv, positions; not the timing fields), though not as the same run
        never saved would (docs/checkpoints.md). ConfigError (nothing written) for a
        run with a user's loop hook or a part that cannot be pickled (named). Format:
        swarmsim/engine/checkpoint.py."""
        from swarmsim.engine import checkpoint

        checkpoint.save(self, path)

    @classmethod
    def restore(cls, path: str | Path) -> Simulation:
        """The run saved at ``path`` by :meth:`save`, at the tick it was saved. ConfigError
        (one line naming the file) if it is not a checkpoint, is truncated or damaged, or was
        written by another code version."""
        from swarmsim.engine import checkpoint

        return checkpoint.load(path, cls)[0]

    def __getstate__(self) -> dict[str, Any]:
        """The run's state for a copy (pickle), without open renderers."""
        from swarmsim.engine import checkpoint

        return checkpoint.run_state(self)

    def render(self, color_by: str | None = None, width: int = 800, **options: Any
               ) -> np.ndarray:
        """The current state drawn off-screen: an (H, W, 3) uint8 frame (no window needed).

        ``color_by`` is "status" or a message field the controller declares in COLOURINGS
        (None: its first, GGC's "gradient"); other options go to
        swarmsim.render.Renderer. Drawing never changes the run.
        """
        key = (color_by, width, tuple(sorted(options.items())))
        if getattr(self, "_renderer_key", None) != key:
            self._renderer = self.new_renderer(width=width, color_by=color_by, **options)
            self._renderer_key = key
        return self._renderer.draw(self.snapshot())

    def view(self, width: int | None = None, color_by: str | None = None,
             max_frames: int | None = None) -> Any:
        """Run this simulation live in a window until the user quits (or ``max_frames``
        frames); returns the closed swarmsim.render.viewer.Viewer. ConfigError when there is
        no display. Viewing never changes the run."""
        from swarmsim.render.viewer import view

        return view(self, width=width, color_by=color_by, max_frames=max_frames)

    def _repr_png_(self) -> bytes:
        """Jupyter shows a Simulation as its current frame, 640 px wide (a PNG)."""
        from swarmsim.render.notebook import png_bytes

        return png_bytes(self.render(width=640))

    def show(self, width: int = 640, color_by: str | None = None) -> None:
        """Display the current frame in a notebook now (IPython's display; the extra
        ``notebook``). ConfigError naming the extra without IPython."""
        from swarmsim.render.notebook import show_frame

        show_frame(self, width=width, color_by=color_by)

    def video(self, ticks: int | None = None, every: int = 10, width: int = 480,
              fps: float = 30, color_by: str | None = None) -> Any:
        """Run ``ticks`` more ticks (None: until the run stops) as ``run`` would, drawing a
        frame every ``every`` ticks; returns a swarmsim.render.notebook.InlineVideo, which
        a notebook shows as an HTML5 video (its ``mp4`` bytes, ``save(path)``)."""
        from swarmsim.render.notebook import record_video

        return record_video(self, ticks=ticks, every=every, width=width, fps=fps,
                            color_by=color_by)

    def offered_colourings(self, color_by: str | None = None) -> tuple[str, ...]:
        """The robot colourings this run offers: "status", then the controller's COLOURINGS.
        Raises ConfigError (key --color-by) when ``color_by`` is given and is none of them."""
        offered = ("status", *self.info.colourings)
        if color_by is not None and color_by not in offered:
            hint = did_you_mean(color_by, offered)
            raise ConfigError(f"controller {self.controller_name!r} colours robots by "
                              f"{', '.join(offered)}; got {color_by!r}{hint}", key="--color-by")
        return offered

    def new_renderer(self, **options: Any) -> Any:
        """A swarmsim.render.Renderer of this run's world and coverage grid that colours and
        marks robots as the controller declares (COLOURINGS, LEADER_FIELD, GROUP_FIELD);
        ``options`` go to the Renderer (width, color_by, ...). Raises ConfigError for an
        option it refuses."""
        from swarmsim.render import Renderer

        return Renderer(self.world, self.grid, colourings=self.info.colourings,
                        leader_field=self.info.leader_field, group_field=self.info.group_field,
                        **options)


def _name_columns(actions: ChunkActions, robots: int, refused: int = -2) -> None:
    """BadAction naming the column of a chunk's ``actions`` (``robots`` rows) that a compiled
    pass could not take (it raised) or ``refused`` (-2: not one row per robot); nothing for a
    refused row (>= 0), which the caller names."""
    if refused >= 0:
        return
    column_problems(actions, robots)
    if refused == -2:
        raise BadAction(None, "columns of different lengths")


@contextmanager
def _old_objects_frozen() -> Iterator[None]:
    """Keep the objects that exist now out of Python's full garbage collections for a while.

    A run allocates little that lives long, but every full collection walks every object in
    the process (controllers, world, modules). Frozen objects are unfrozen afterwards, so a
    discarded Simulation is collected as usual. Left alone if the caller froze objects
    already (their GC, their rules). Changes no result: collection order decides nothing.
    """
    if gc.get_freeze_count():
        yield
        return
    gc.freeze()
    try:
        yield
    finally:
        gc.unfreeze()


def _controllers_with_failure_mode(mode: str) -> list[str]:
    """The registered controllers that declare failure mode ``mode`` (for an error message;
    one that cannot be loaded or described is left out)."""
    from swarmsim.registry import available_controllers, get_controller

    found = []
    for name in available_controllers():
        try:
            modes = describe(get_controller(name), name).failure_modes
        except Exception:  # noqa: BLE001 - a broken controller is not this run's error
            modes = {}
        if mode in modes:
            found.append(name)
    return found


def _has_field(cls: type, name: str) -> bool:
    return name in getattr(cls, "__dataclass_fields__", {})


def _progress_bar(total: int, enabled: bool):
    if not enabled:
        return None
    import sys

    from tqdm import tqdm

    # redrawn twice a second on a terminal; in a log file (not a tty) every 30 s
    interval = 0.5 if sys.stderr.isatty() else 30.0
    # No bar and no time left: a run usually stops long before max_ticks (completion, plateau,
    # stall), so a share of max_ticks and an ETA from it would mislead.
    fmt = "tick {n_fmt} of at most {total_fmt} [{elapsed}, {rate_fmt}{postfix}]"
    return tqdm(total=total, unit="tick", dynamic_ncols=True, leave=False, mininterval=interval,
                bar_format=fmt)


__all__ = ["PhysicsConfig", "RunResult", "SimConfig", "Simulation"]
