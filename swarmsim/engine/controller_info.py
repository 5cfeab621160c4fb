"""What the engine knows of a controller class, read once from its declarations.

The engine asks a controller class nothing else: :func:`describe` reads the declarations of
:class:`swarmsim.controller.ControllerClass` (with their defaults) into a frozen
:class:`ControllerInfo`, and the run uses that.
"""

from __future__ import annotations

import dataclasses
import math
import numbers
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

import numpy as np

from swarmsim.actionvalues import show
from swarmsim.controller import RobotSetup, Swarm, message_dtype, run_message_fields
from swarmsim.errors import ConfigError, ControllerError

COLOURING_KINDS = ("scale", "category")


@dataclass(frozen=True)
class ControllerInfo:
    """A controller class's declarations (see ControllerClass for each one's meaning).

    Attributes:
        cls: the class.
        name: its registered name.
        statuses: names of its status codes.
        settled: statuses meaning "done, standing still".
        initial: statuses before any robot covers (the fault phase "gradient").
        covering: statuses of robots covering (the fault phase "coverage").
        silent: message field values of a neighbour that is not heard.
        colourings: message field -> "scale" or "category" (video colourings).
        leader_field: the bool message field marking leaders, or None.
        group_field: the message field holding a robot's group, or None.
        layouts: the names of the start layouts it can start from (default: every one in
            swarmsim.world.layouts).
        default_start: the start layout used unless the run names one.
        requires_beacon: the world must have a beacon.
        max_groups: the most groups a run may have, or None: the controller forms no groups
            of its own (a run has groups only if its start layout makes them).
        probe_params: parameters that are floor-probe lengths, units.
        min_probe_range: the floor probe reach it needs at least, units.
        commands: what its actions' velocities are: "velocity" (a wish) or "wheels" (the
            (left, right) wheel speeds; needs a drive with wheels).
        failure_modes: the failure modes it simulates itself (its FAILURE_MODES), name ->
            meaning; the engine's own "dead" is not among them.
    """

    cls: type
    name: str
    statuses: tuple[str, ...]
    settled: tuple[str, ...]
    initial: tuple[str, ...]
    covering: tuple[str, ...]
    silent: Mapping[str, Any]
    colourings: Mapping[str, str]
    leader_field: str | None
    group_field: str | None
    layouts: tuple[str, ...]
    default_start: str
    requires_beacon: bool
    max_groups: int | None
    probe_params: tuple[str, ...]
    min_probe_range: float
    commands: str = "velocity"
    failure_modes: Mapping[str, str] = dataclasses.field(
        default_factory=lambda: MappingProxyType({}))

    @property
    def batch(self) -> bool:
        """True for a batch controller (``create_swarm``), False for a per-robot one."""
        return hasattr(self.cls, "create_swarm")

    def uses_groups(self, start: str = "") -> bool:
        """Whether a run's number of groups means anything with this start ("": the
        default start): the controller forms groups (it declares ``max_groups``: GGC), or the
        start layout makes one formation per group (swarmsim.world.layouts.GROUPED). Otherwise a
        run has one group."""
        from swarmsim.world.layouts import GROUPED

        return self.max_groups is not None or (start or self.default_start) in GROUPED

    def same_run_settings(self, params: Any, config: Any) -> dict[str, Any]:
        """Settings that make the run of ``params`` (the run's controller parameters) and
        ``config`` (its SimConfig) tick for tick by construction, in the controller's canonical
        form: the class's ``same_run_settings``; {} when it declares none or names this run
        canonically already. A run's id is made with them in place of its own settings."""
        hook = getattr(self.cls, "same_run_settings", None)
        return {} if hook is None else dict(hook(params, config))

    def codes(self, names: Sequence[str]) -> tuple[int, ...]:
        """The status codes of these status names (names it does not have are left out)."""
        return tuple(i for i, s in enumerate(self.statuses) if s in names)

    def message_fields(self, groups: int, scattered: bool) -> list[tuple[str, Any]]:
        """Its broadcast fields beyond the base fields, for a run with ``groups`` groups, its
        robots started ``scattered`` or not (controller.run_message_fields)."""
        return run_message_fields(self.cls, groups, scattered)

    def sensing_range(self, params: Any) -> float:
        """How far its robots sense, units: the class's ``sensing_range(params)``, checked.
        Raises ControllerError unless it is a finite number > 0."""
        value = self.cls.sensing_range(params)
        if (isinstance(value, bool) or not isinstance(value, numbers.Real)
                or not math.isfinite(value) or value <= 0):
            raise ControllerError(f"sensing_range() returned {show(value)}; expected a "
                                  "distance > 0, units", controller=self.name)
        return float(value)

    def message_dtype(self, groups: int, scattered: bool) -> np.dtype:
        """The run's broadcast dtype: the base fields, then the class's (``message_fields``).
        Raises ConfigError naming ``MESSAGE_FIELDS`` when numpy cannot make it (a bad type, a
        field named twice or a base field again) or when ``SILENT``, ``COLOURINGS``,
        ``LEADER_FIELD`` or ``GROUP_FIELD`` name a field it does not have."""
        fields = self.message_fields(groups, scattered)
        try:
            dtype = message_dtype(fields)
        except (TypeError, ValueError) as exc:
            raise ConfigError(f"{self.name}: MESSAGE_FIELDS {fields!r} is not a list of "
                              f"(name, numpy type) with names of its own beside id, status and "
                              f"moving ({' '.join(str(exc).split())})", key="controller") from None
        named = {"SILENT": list(self.silent), "COLOURINGS": list(self.colourings),
                 "LEADER_FIELD": [self.leader_field] if self.leader_field else [],
                 "GROUP_FIELD": [self.group_field] if self.group_field else []}
        for declaration, names in named.items():
            unknown = [n for n in names if n not in dtype.names]
            if unknown:
                raise ConfigError(f"{self.name}: {declaration} names {unknown}, which it does not "
                                  f"broadcast; its fields are {list(dtype.names)}",
                                  key="controller")
        return dtype

    def warm_up(self) -> None:
        """Compile or load its kernels (before a run's clock starts)."""
        warm = getattr(self.cls, "warm_up", None)
        if warm is not None:
            warm()

    def create_swarm(self, setups: Sequence[RobotSetup], params: Any,
                     rngs: Sequence[np.random.Generator], **options: Any) -> Swarm:
        """The run's swarm: the class's own, or its robots driven one by one (``options``
        go to :class:`swarmsim.engine.swarm.RobotSwarm`)."""
        if self.batch:
            return self.cls.create_swarm(setups, params, rngs)
        from swarmsim.engine.swarm import RobotSwarm

        return RobotSwarm(self.cls, setups, params, rngs, **options)


def describe(cls: type, name: str | None = None) -> ControllerInfo:
    """Read a controller class's declarations, with their defaults; ConfigError if one is
    malformed."""
    name = name or getattr(cls, "name", cls.__name__)
    statuses = _statuses(cls, name)
    colourings = dict(getattr(cls, "COLOURINGS", {}))
    for field, kind in colourings.items():
        if kind not in COLOURING_KINDS:
            raise ConfigError(f"COLOURINGS[{field!r}] must be one of {COLOURING_KINDS}, got "
                              f"{kind!r}", key="controller")
    for attr in ("SETTLED_STATUSES", "INITIAL_STATUSES", "COVERING_STATUSES"):
        unknown = [s for s in getattr(cls, attr, ()) if s not in statuses]
        if unknown:
            raise ConfigError(f"{name}: {attr} names unknown statuses {unknown}",
                              key="controller")
    _refuse_engine_names(cls, name)
    return ControllerInfo(
        cls=cls, name=name, statuses=statuses,
        settled=tuple(getattr(cls, "SETTLED_STATUSES", ())),
        initial=tuple(getattr(cls, "INITIAL_STATUSES", ())),
        covering=tuple(getattr(cls, "COVERING_STATUSES", ())),
        silent=MappingProxyType(dict(getattr(cls, "SILENT", {}))),
        colourings=MappingProxyType(colourings),
        leader_field=getattr(cls, "LEADER_FIELD", None),
        group_field=getattr(cls, "GROUP_FIELD", None),
        layouts=_layouts(cls, name),
        default_start=getattr(cls, "default_start", "random"),
        requires_beacon=bool(getattr(cls, "requires_beacon", False)),
        max_groups=getattr(cls, "max_groups", None),
        probe_params=tuple(getattr(cls, "probe_params", ())),
        min_probe_range=float(getattr(cls, "min_probe_range", 0.0)),
        commands=_commands(cls, name),
        failure_modes=_failure_modes(cls, name))


COMMAND_KINDS = ("velocity", "wheels")
"""What a controller's actions may command (its ``COMMANDS``)."""


def _commands(cls: type, name: str) -> str:
    """The class's ``COMMANDS`` ("velocity" unless it declares one); ConfigError for another."""
    commands = getattr(cls, "COMMANDS", "velocity")
    if commands not in COMMAND_KINDS:
        raise ConfigError(f"{name}: COMMANDS must be one of {', '.join(COMMAND_KINDS)}, got "
                          f"{commands!r}", key="controller")
    return commands


def _failure_modes(cls: type, name: str) -> Mapping[str, str]:
    """The class's ``FAILURE_MODES`` (none unless it declares some), read-only; ConfigError
    unless they map names other than "dead" to their meanings, or when a per-robot class that
    declares some has no ``fail`` (a batch class's swarm is checked by the run that fails its
    robots so)."""
    from swarmsim.engine.config import DEAD

    declared = getattr(cls, "FAILURE_MODES", {})
    if not isinstance(declared, Mapping) or not all(
            isinstance(k, str) and k and k != DEAD and isinstance(v, str)
            for k, v in declared.items()):
        raise ConfigError(f"{name}: FAILURE_MODES must map failure mode names (not {DEAD!r}, "
                          f"the engine's own) to their meanings, got {declared!r}",
                          key="controller")
    if declared and not hasattr(cls, "create_swarm") and not callable(getattr(cls, "fail", None)):
        raise ConfigError(f"{name}: declares FAILURE_MODES {sorted(declared)} but has no "
                          "fail(mode) method to simulate them", key="controller")
    return MappingProxyType(dict(declared))


def _refuse_engine_names(cls: type, name: str) -> None:
    """ConfigError naming the first of the class's Params fields that is named like an engine
    setting (config.engine_settings): a run's value of that name would set the engine's
    setting, never the controller's parameter."""
    from swarmsim.engine.config import engine_settings

    engine = engine_settings()
    params = cls.Params
    for field in dataclasses.fields(params) if dataclasses.is_dataclass(params) else ():
        if field.name in engine:
            raise ConfigError(f"{name}: Params field {field.name!r} has the name of the engine "
                              f"setting {engine[field.name]}.{field.name}; a run's "
                              f"{field.name} would set the engine's, never the controller's: "
                              "rename the field", key="controller")


MAX_STATUSES = 127
"""The most statuses a controller may name: a broadcast's ``status`` is an int8."""


def _statuses(cls: type, name: str) -> tuple[str, ...]:
    """The class's STATUSES; ConfigError unless they are 1 to MAX_STATUSES distinct strings."""
    declared = cls.STATUSES
    statuses = () if isinstance(declared, str) else tuple(declared)
    if (not 0 < len(statuses) <= MAX_STATUSES or len(set(statuses)) != len(statuses)
            or not all(isinstance(s, str) for s in statuses)):
        raise ConfigError(f"{name}: STATUSES must be a tuple of 1 to {MAX_STATUSES} distinct "
                          f"names (its status codes 0, 1, ...), got {declared!r}",
                          key="controller")
    return statuses


def _layouts(cls: type, name: str) -> tuple[str, ...]:
    from swarmsim.world.layouts import LAYOUTS

    declared = tuple(getattr(cls, "LAYOUTS", LAYOUTS))
    unknown = [s for s in declared if s not in LAYOUTS]
    if unknown:
        raise ConfigError(f"{name}: LAYOUTS names unknown layouts {unknown}; known: "
                          f"{', '.join(LAYOUTS)}", key="controller")
    start = getattr(cls, "default_start", "random")
    if start not in declared:
        raise ConfigError(f"{name}: default_start {start!r} is not among its LAYOUTS",
                          key="controller")
    return declared


__all__ = ["ControllerInfo", "describe"]
