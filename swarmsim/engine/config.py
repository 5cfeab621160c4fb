"""Run settings: engine parameters, their defaults, and resolving ``--set KEY=VALUE``.

A run has three kinds of parameters, all with documented defaults:

* :class:`SimConfig`: the tick loop, metrics and stopping rules (paper Table 2 where it has one),
* :class:`swarmsim.physics.physics.PhysicsConfig`: bodies and drive,
* the controller's own ``Params`` dataclass (e.g. GGC's d_cover, R_c, ...).

``resolve_settings`` routes each key to the one place that knows it; an unknown key, a value
of the wrong type, or a non-finite number (inf, nan) where a finite one is meant, is a
:class:`ConfigError` naming the key and value.
"""

from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

from swarmsim import limits
from swarmsim.errors import ConfigError, unknown_name
from swarmsim.limits import (
    GROUPS_SIZE,
    MAX_GRID_SIZE,
    MAX_GROUPS,
    MAX_RECORD_ROWS,
    MAX_ROBOTS,
    MAX_TICKS,
    at_most,
)
from swarmsim.physics.physics import PhysicsConfig
from swarmsim.robots.imperfections import NoiseLevels

DEAD = "dead"
"""The failure mode every controller has (SimConfig.failure_mode's default): a failed robot stops
moving and communicating but stays a physical body (swarmsim/engine/faults.py)."""

UNBOUNDED_PARAMS = frozenset({"spin_traction"})
"""Parameters for which +inf is a documented value (PhysicsConfig.spin_traction: robots never
turn). Every other number must be finite; nan never is."""


@dataclass(frozen=True)
class SimConfig:
    """Engine settings of one run.

    Attributes:
        robots: number of robots N.
        groups: number of groups K (paper Section 4).
        seed: the one seed that decides the run.
        max_ticks: hard limit on ticks.
        start: "random" (uniform in the spawn areas) or a layout the controller offers, e.g.
            GGC's "formation" (one hexagonal formation
            per group around its leader); "" lets the controller choose.
        spawn_spacing: minimum centre distance at a random start, units (d_safe = 1).
        formation_spacing: lattice spacing of a formation start, units (d_min = d_safe = 1).
        v_max: top speed v, units per tick (paper: 0.1).
        coverage_radius: coverage radius r of one robot, units (paper: 4).
        eps0: completion threshold: done when 1 - P <= eps0 (paper's epsilon_0).
        grid_size: the coverage raster is grid_size x grid_size pixels (paper: 100).
        record_every: a time-series row every this many ticks (kept in memory until the run
            ends: at most 1,000,000 rows, max_ticks / record_every).
        plateau_ticks: stop ("plateau") when coverage has not risen by plateau_delta for this
            many ticks (long enough for a slow last stretch: see
            docs/reports/measurements-journal.md).
        plateau_delta: see plateau_ticks (fraction of the target).
        stall_ticks: stop ("stalled") when no robot moved or changed its message for this long.
        stop_on_complete: stop at the completion tick.
        probe_range: longest floor-probe offset a robot may look at, units.
        wake_eps: displacement (units) that counts as "moved" for waking sleeping robots.
        decide_order: "index" or "shuffled": the order controllers are called in each tick (a
            check: results must not depend on it; sensing and noise are drawn in index order).
        allow_sleep: honour controllers' sleep requests (a check: results must not depend on it).
        failures: number of robots that fail during the run (paper Section 6.6; 0 = none). They
            stop moving and communicating but stay in the way. See swarmsim/engine/faults.py for the
            rule that picks them (random working non-leader robots that have not arrived).
        failure_phase: when they fail: "gradient" (when the first robot leaves its Initial
            status; tick 1 for controllers without one), "coverage" (when the first robot
            starts moving to cover) or "tick" (at failure_tick).
        failure_tick: the tick at which robots fail with failure_phase = "tick" (>= 1).
        failure_mode: how they fail: "dead" (they stop moving and communicating but stay in
            the way) or a mode the controller declares (its FAILURE_MODES, e.g. GGC's
            "no_gradient": the robot loses its gradient and cannot take one from its
            formation, so it sets off to cover first; 'swarmsim params --controller NAME'
            lists a controller's modes). Only with failures > 0.
        speed_noise: actuation noise: relative sd of a moving robot's speed each tick (0 = off;
            0.05 = 5 %). See swarmsim/robots/imperfections.py for every imperfection's model.
        heading_noise: actuation noise: sd of a moving robot's heading each tick, radians.
        distance_noise: sensing noise: relative sd of each sensed neighbour distance.
        bearing_noise: sensing noise: sd of each sensed neighbour bearing, radians.
        message_loss: probability that a neighbour's broadcast is lost (per receiver,
            neighbour and tick), in [0, 1]; a lost message reads like a silent neighbour. With
            message_model "logistic" it is a loss on top that does not depend on distance.
        message_model: "uniform" (loss does not depend on distance: message_loss) or
            "logistic" (a broadcast from distance d arrives with probability 1 / (1 +
            exp((d - message_range50) / message_falloff)), per receiver, neighbour and tick;
            see docs/sensing-models.md).
        message_range50: logistic model: distance at which half the broadcasts arrive, units
            (> 0 with message_model "logistic"; 0 otherwise).
        message_falloff: logistic model: width of the fall-off, units: success falls from
            about 73 % at message_range50 - message_falloff to about 27 % at message_range50 +
            message_falloff (> 0 with message_model "logistic"; 0 otherwise).
        floor_edge_band: a robot whose centre is within this distance (units) of the target's
            edge, on either side, may misread its floor sensor (on_target); 0 = exact
            everywhere. Set with floor_edge_misread.
        floor_edge_misread: probability that a robot within floor_edge_band reads its floor
            sensor wrongly (per robot and tick), in [0, 1]; the floor probe stays exact.
        sensing_limit: largest distance (units) at which a robot senses and hears neighbours,
            whatever its controller's range (e.g. GGC's R_c = 15); 0 = the controller's range.
        displaced_threshold: a settled robot (GGC: Arrive) counts as displaced (pushed out of
            place) once it is this far from where it settled, units.
    """

    robots: int = field(default=100, metadata=at_most(MAX_ROBOTS,
                                                           "robots in one run"))
    groups: int = field(default=1, metadata=at_most(MAX_GROUPS, GROUPS_SIZE))
    seed: int = 0
    max_ticks: int = field(default=100_000, metadata=at_most(MAX_TICKS, "ticks in one run"))
    start: str = ""
    spawn_spacing: float = 1.0
    formation_spacing: float = 1.0
    v_max: float = 0.1
    coverage_radius: float = 4.0
    eps0: float = 0.01
    grid_size: int = field(default=100, metadata=at_most(
        MAX_GRID_SIZE, "the coverage raster has grid_size x grid_size cells"))
    record_every: int = field(default=10, metadata=at_most(MAX_TICKS))
    plateau_ticks: int = field(default=10000, metadata=at_most(MAX_TICKS))
    plateau_delta: float = 0.002
    stall_ticks: int = field(default=1000, metadata=at_most(MAX_TICKS))
    stop_on_complete: bool = True
    probe_range: float = 2.0
    wake_eps: float = 1e-3
    decide_order: str = "index"
    allow_sleep: bool = True
    failures: int = 0
    failure_phase: str = "coverage"
    failure_tick: int = field(default=0, metadata=at_most(MAX_TICKS))
    failure_mode: str = DEAD
    speed_noise: float = 0.0
    heading_noise: float = 0.0
    distance_noise: float = 0.0
    bearing_noise: float = 0.0
    message_loss: float = 0.0
    message_model: str = "uniform"
    message_range50: float = 0.0
    message_falloff: float = 0.0
    floor_edge_band: float = 0.0
    floor_edge_misread: float = 0.0
    sensing_limit: float = 0.0
    displaced_threshold: float = 0.1

    def __post_init__(self) -> None:
        for f in dataclasses.fields(self):
            check_finite(f.name, getattr(self, f.name))
        positive = ("robots", "groups", "max_ticks", "spawn_spacing", "formation_spacing",
                    "v_max", "coverage_radius", "grid_size", "record_every", "plateau_ticks",
                    "stall_ticks", "probe_range", "wake_eps")
        for name in positive:
            value = getattr(self, name)
            if not value > 0:
                raise ConfigError(f"must be positive, got {value!r}", key=name)
        limits.check_fields(self)
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise ConfigError(f"must be a non-negative integer, got {self.seed!r}", key="seed")
        for name in ("eps0", "plateau_delta"):
            if not 0 <= getattr(self, name) < 1:
                raise ConfigError(f"must be in [0, 1), got {getattr(self, name)!r}", key=name)
        rows = self.max_ticks // self.record_every
        if rows > MAX_RECORD_ROWS:
            least = -(-self.max_ticks // MAX_RECORD_ROWS)
            raise ConfigError(f"{self.record_every} makes {rows:,} time-series rows in memory "
                              f"over max_ticks = {self.max_ticks:,}, more than "
                              f"{MAX_RECORD_ROWS:,}: set record_every to {least:,} or more",
                              key="record_every")
        if self.groups > self.robots:
            raise ConfigError(f"{self.groups} groups need at least as many robots "
                              f"(robots = {self.robots})", key="groups")
        if not isinstance(self.start, str):
            raise ConfigError(f"must be a start layout's name, got {self.start!r}", key="start")
        if self.decide_order not in ("index", "shuffled"):
            raise ConfigError(f"must be 'index' or 'shuffled', got {self.decide_order!r}",
                              key="decide_order")
        self._check_failures()
        self._check_imperfections()

    def _check_failures(self) -> None:
        if not 0 <= self.failures <= self.robots:
            raise ConfigError(f"must be in [0, robots = {self.robots}], got {self.failures!r}",
                              key="failures")
        if self.failure_phase not in ("gradient", "coverage", "tick"):
            raise ConfigError("must be 'gradient', 'coverage' or 'tick', got "
                              f"{self.failure_phase!r}", key="failure_phase")
        if self.failure_tick < 0 or (self.failure_phase == "tick" and self.failures
                                     and self.failure_tick < 1):
            raise ConfigError(f"must be >= 1 with failure_phase 'tick', got {self.failure_tick!r}",
                              key="failure_tick")
        if self.failure_tick and self.failure_phase != "tick":
            raise ConfigError(f"is used only with failure_phase 'tick' (got {self.failure_tick!r} "
                              f"with failure_phase {self.failure_phase!r}): set failure_phase "
                              "too", key="failure_tick")
        if not isinstance(self.failure_mode, str) or not self.failure_mode:
            raise ConfigError(f"must be a failure mode's name, got {self.failure_mode!r}",
                              key="failure_mode")
        if self.failure_mode != DEAD and not self.failures:
            raise ConfigError(f"is used only with failures > 0 (got {self.failure_mode!r} with "
                              "failures 0): set failures too", key="failure_mode")


    def _check_imperfections(self) -> None:
        for name in ("speed_noise", "heading_noise", "distance_noise", "bearing_noise",
                     "sensing_limit"):
            value = getattr(self, name)
            if not value >= 0:
                raise ConfigError(f"must be >= 0, got {value!r}", key=name)
        if not 0 <= self.message_loss <= 1:
            raise ConfigError(f"must be in [0, 1], got {self.message_loss!r}", key="message_loss")
        if not self.displaced_threshold > 0:
            raise ConfigError(f"must be positive, got {self.displaced_threshold!r}",
                              key="displaced_threshold")
        self._check_message_model()
        self._check_floor_misreads()

    def _check_message_model(self) -> None:
        if self.message_model not in ("uniform", "logistic"):
            raise ConfigError(f"must be 'uniform' or 'logistic', got {self.message_model!r}",
                              key="message_model")
        for name in ("message_range50", "message_falloff"):
            value = getattr(self, name)
            if self.message_model == "logistic" and not value > 0:
                raise ConfigError(f"must be positive with message_model 'logistic', got "
                                  f"{value!r}", key=name)
            if self.message_model == "uniform" and value != 0:
                raise ConfigError(f"is used only with message_model 'logistic' (got {value!r} "
                                  "with message_model 'uniform'): set message_model too",
                                  key=name)

    def _check_floor_misreads(self) -> None:
        if not self.floor_edge_band >= 0:
            raise ConfigError(f"must be >= 0, got {self.floor_edge_band!r}",
                              key="floor_edge_band")
        if not 0 <= self.floor_edge_misread <= 1:
            raise ConfigError(f"must be in [0, 1], got {self.floor_edge_misread!r}",
                              key="floor_edge_misread")
        if (self.floor_edge_band > 0) != (self.floor_edge_misread > 0):
            given, other = (("floor_edge_band", "floor_edge_misread")
                            if self.floor_edge_band > 0 else
                            ("floor_edge_misread", "floor_edge_band"))
            raise ConfigError(f"{getattr(self, given)!r} does nothing while {other} is 0: set "
                              f"{other} too", key=given)

    def noise_levels(self) -> NoiseLevels:
        """The run's imperfections (all zero by default)."""
        return NoiseLevels(self.speed_noise, self.heading_noise, self.distance_noise,
                           self.bearing_noise, self.message_loss, self.message_model,
                           self.message_range50, self.message_falloff, self.floor_edge_band,
                           self.floor_edge_misread)


def settings_from_pairs(pairs: Sequence[str], options: Mapping[str, Any]) -> dict[str, Any]:
    """``KEY=VALUE`` pairs (``--set``) as settings (``-`` in a key read as ``_``, values by
    parse_value). A key given twice, by two pairs or by a pair and one of ``options`` (the
    command-line options that set a key, by key, e.g. ``{"robots": 5}`` for ``--robots 5``;
    None: not given), is a ConfigError naming both."""
    out: dict[str, Any] = {}
    written: dict[str, tuple[str, Any]] = {}
    for pair in pairs:
        key, sep, value = pair.partition("=")
        if not sep or not key.strip():
            raise ConfigError(f"expected KEY=VALUE, got {pair!r}", key="--set")
        key = key.strip().replace("-", "_")
        check_given_once({key: written[key]} if key in written else {},
                         {key: (f"--set {pair}", value)})
        written[key] = (f"--set {pair}", value)
        out[key] = parse_value(value)
    given = {key: (f"--{key.replace('_', '-')} {value}", value)
             for key, value in options.items() if value is not None}
    check_given_once(given, written)
    return out


def parse_value(text: str) -> Any:
    """Parse a ``--set`` value: int, float, true/false, or a plain string."""
    low = text.strip().lower()
    if low in ("true", "yes", "on"):
        return True
    if low in ("false", "no", "off"):
        return False
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


def check_finite(key: str, value: Any, unbounded: bool = False) -> None:
    """Refuse a float that is nan, or infinite unless ``unbounded`` (+inf allowed)."""
    if (isinstance(value, float) and not math.isfinite(value)
            and not (unbounded and value == math.inf)):
        what = "a finite number" if not unbounded else "a number (or inf)"
        raise ConfigError(f"must be {what}, got {value!r}", key=key)


def coerce(value: Any, default: Any, key: str) -> Any:
    """Convert ``value`` to the type of the field's ``default``; error if it cannot be, or if
    it is a non-finite number (+inf is allowed for the parameters in UNBOUNDED_PARAMS)."""
    out = _coerce(value, default, key)
    check_finite(key, out, key in UNBOUNDED_PARAMS)
    return out


def _coerce(value: Any, default: Any, key: str) -> Any:
    if isinstance(default, bool):
        if isinstance(value, bool):
            return value
        if isinstance(value, str):
            parsed = parse_value(value)
            if isinstance(parsed, bool):
                return parsed
    elif isinstance(default, int):
        if isinstance(value, int) and not isinstance(value, bool):
            return value
        if isinstance(value, float) and value.is_integer():
            return int(value)
        if isinstance(value, str) and isinstance(parse_value(value), int):
            return parse_value(value)
    elif isinstance(default, float):
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            return float(value)
        if isinstance(value, str) and isinstance(parse_value(value), (int, float)):
            return float(parse_value(value))
    elif isinstance(default, str):
        return str(value)
    else:
        return value
    raise ConfigError(f"expected {type(default).__name__}, got {value!r}", key=key)


def field_defaults(cls: type) -> dict[str, Any]:
    """Default value of every field of a dataclass."""
    out = {}
    for f in dataclasses.fields(cls):
        if f.default is not dataclasses.MISSING:
            out[f.name] = f.default
        elif f.default_factory is not dataclasses.MISSING:
            out[f.name] = f.default_factory()
    return out


def engine_settings() -> dict[str, str]:
    """The engine's settings: each SimConfig and PhysicsConfig field name -> its class's
    name. A controller's Params may name none of them (controller_info.describe)."""
    return {f.name: cls.__name__ for cls in (SimConfig, PhysicsConfig)
            for f in dataclasses.fields(cls)}


def resolve_settings(settings: Mapping[str, Any], params_cls: type
                     ) -> tuple[dict[str, Any], dict[str, Any], dict[str, Any]]:
    """Split ``settings`` into SimConfig, PhysicsConfig and controller-params keyword dicts."""
    targets = (field_defaults(SimConfig), field_defaults(PhysicsConfig),
               field_defaults(params_cls))
    out: tuple[dict, dict, dict] = ({}, {}, {})
    for key, value in settings.items():
        for defaults, dest in zip(targets, out, strict=True):
            if key in defaults:
                dest[key] = coerce(value, defaults[key], key)
                break
        else:
            message = unknown_name("parameter", key, set().union(*targets),
                                   "see 'swarmsim params'")
            raise ConfigError(f"{message} (value {value!r})", key=key)
    return out


def build_configs(settings: Mapping[str, Any], params_cls: type
                  ) -> tuple[SimConfig, PhysicsConfig, Any]:
    """Build validated configs; every error names the key and value."""
    sim_kw, phys_kw, ctrl_kw = resolve_settings(settings, params_cls)
    sim = SimConfig(**sim_kw)
    limits.check_values(PhysicsConfig, phys_kw)  # before building: a bound sizes something
    limits.check_values(params_cls, ctrl_kw)
    try:
        phys = PhysicsConfig(**phys_kw)
    except ValueError as exc:
        raise ConfigError(str(exc), key=_named_key(str(exc), phys_kw)) from None
    try:
        params = params_cls(**ctrl_kw)
    except (TypeError, ValueError) as exc:
        raise ConfigError(str(exc), key=_named_key(str(exc), ctrl_kw)) from None
    speed = ctrl_kw.get("v")
    if speed is not None and speed > sim.v_max:
        raise ConfigError(f"{speed!r} is faster than the engine's top speed v_max = {sim.v_max!r}"
                          f", which caps every robot's speed: set v_max too (v_max={speed!r})",
                          key="v")
    return sim, phys, params


def _named_key(message: str, settings: Mapping[str, Any]) -> str | None:
    """The setting a validation message is about: the first of ``settings`` it names."""
    named = [(m.start(), key) for key in settings
             if (m := re.search(rf"\b{re.escape(key)}\b", message))]
    return min(named)[1] if named else None


def check_given_once(given: Mapping[str, tuple[str, Any]],
                     settings_given: Mapping[str, tuple[str, Any]]) -> None:
    """Refuse a setting given both by an option and among the ``--set`` pairs.

    ``given`` and ``settings_given`` map a setting's key to (how it was written, value), e.g.
    ``{"robots": ("--robots 5", 5)}`` and ``{"robots": ("--set robots=7", 7)}``; only the
    keys given in both are compared."""
    for key in sorted(set(given) & set(settings_given)):
        raise ConfigError(f"given twice: {given[key][0]} and {settings_given[key][0]}; give "
                          "it once", key=key)
