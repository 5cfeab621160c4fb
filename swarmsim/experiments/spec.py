"""Sweep specs: a TOML file -> the list of runs (grid x seeds), each with a stable run id.

A spec::

    name = "dcover"              # optional; a label for the sweep
    description = "..."          # optional
    world = "tiny"               # shipped world name or .toml path (relative to the spec file)
    controller = "dispersion"    # registered name or module:Class (default "ggc")
    reps = 3                     # seeds seed_base .. seed_base + reps - 1 (default reps = 1) ...
    seed_base = 0                # ... or instead: seeds = [0, 7, 42]

    [params]                     # fixed run settings (any name `swarmsim params` lists)
    max_ticks = 2000
    groups = 1

    [grid]                       # lists: every combination is run (Cartesian product)
    d_cover = [4, 6, 8]
    robots = [30, 40]

``world`` and ``controller`` may also be grid keys (lists). Runs are ordered by the grid in file
order (the last key varies fastest) with the seeds innermost. Every problem is a ConfigError
naming the spec file, the key and the value.

A run's id is a hash of its world, controller, settings and seed (numbers compared by value, so
``6`` and ``6.0`` are the same run; ``failure_phase``/``failure_tick`` are left out when
``failures`` is 0 because they change nothing, and ``failure_mode`` when it is "dead", its
default, so that runs keep the ids they had before the setting existed). The same parameters always give the same id, in
any sweep: that is what resume and sharing runs between figures rely on. Runs that the
controller says are the same by construction (its ``same_run_settings``: e.g. GGC's rule sets
whose extra rules act nowhere in a run) share one id too, made from the canonical settings;
a run that is canonical already keeps the id of its own settings.
"""

from __future__ import annotations

import functools
import hashlib
import itertools
import json
import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from swarmsim.engine.config import DEAD, PhysicsConfig, SimConfig, coerce, field_defaults
from swarmsim.errors import ConfigError, did_you_mean, unknown_name
from swarmsim.limits import MAX_REPS, MAX_RUNS, check_at_most
from swarmsim.tomlfile import read_toml

TOP_KEYS = ("name", "description", "world", "controller", "reps", "seeds", "seed_base",
            "params", "grid")
RUN_KEYS = ("world", "controller")
"""Grid keys that choose the run's world/controller rather than a setting."""
INERT_WITHOUT_FAILURES = ("failures", "failure_phase", "failure_tick", "failure_mode")
"""Settings left out of a run's id when it has no failures (they change nothing then)."""
LEFT_OUT_AT_DEFAULT = {"failure_mode": DEAD}
"""Settings left out of a run's id at these values, their defaults: they were added after runs
had ids, and a run that names the default is the run that did not name it."""
SCALAR_TYPES = (bool, int, float, str)


@dataclass(frozen=True)
class RunSpec:
    """One run: world, controller, settings and seed.

    Attributes:
        world: the world as written (name or path); part of the run id.
        controller: controller name or module:Class.
        settings: run settings by name (fixed params plus this grid point).
        seed: the run seed.
        world_ref: what to load (``world`` resolved against the spec's folder); not part of
            the id.
        labels: the grid values of this run (for tables and plots), in grid order.
    """

    world: str
    controller: str
    settings: Mapping[str, Any]
    seed: int
    world_ref: str = ""
    labels: Mapping[str, Any] = field(default_factory=dict)

    @property
    def run_id(self) -> str:
        """The run's id (:func:`run_id`): runs that are the same by construction share it."""
        return run_id(self.world, self.controller, self.settings, self.seed, self.world_ref)

    def params(self) -> dict[str, Any]:
        """world, controller and settings as one flat dict (the table's parameter columns)."""
        return {"world": self.world, "controller": self.controller, **self.settings}

    def to_json(self) -> dict[str, Any]:
        return {"run_id": self.run_id, "world": self.world, "controller": self.controller,
                "settings": dict(self.settings), "seed": self.seed}


def _canonical(value: Any) -> Any:
    if isinstance(value, float) and value.is_integer():
        return int(value)
    return value


def run_id(world: str, controller: str, settings: Mapping[str, Any], seed: int,
           world_ref: str = "") -> str:
    """Stable 16-hex-digit id of a run's parameters and seed; the settings the controller
    names the run by canonically (:func:`same_run_settings`) in place of its own, so that runs
    that are the same by construction share one id. ``world_ref``: where the world loads from,
    if not ``world`` (RunSpec.world_ref); it is not part of the id."""
    given = {**settings, **same_run_settings(world_ref or world, controller, settings)}
    canon = {k: _canonical(v) for k, v in given.items()}
    if not canon.get("failures"):
        for key in INERT_WITHOUT_FAILURES:
            canon.pop(key, None)
    for key, default in LEFT_OUT_AT_DEFAULT.items():
        if key in canon and canon[key] == default:
            del canon[key]
    blob = json.dumps({"world": world, "controller": controller, "settings": canon,
                       "seed": int(seed)}, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(blob.encode()).hexdigest()[:16]


def same_run_settings(world: str, controller: str, settings: Mapping[str, Any]
                      ) -> dict[str, Any]:
    """The settings that the controller (a name or module:Class) names this run by instead of
    its own, because they make it tick for tick (ControllerInfo.same_run_settings, given the
    run's parameters as Simulation.check resolves them from ``world``, a name or path, and
    ``settings``); {} when it declares none, names this run so already, or when the world or
    the settings do not check (the run's own check reports that)."""
    try:
        key = json.dumps(dict(settings), sort_keys=True)
    except TypeError:  # not a setting a run can have: its check says so
        return {}
    return dict(_same_run_settings(world, controller, key))


@functools.lru_cache(maxsize=4096)
def _same_run_settings(world: str, controller: str, settings: str
                       ) -> tuple[tuple[str, Any], ...]:
    from swarmsim.engine.controller_info import describe
    from swarmsim.engine.sim import Simulation
    from swarmsim.registry import get_controller

    try:
        cls = get_controller(controller)
        if getattr(cls, "same_run_settings", None) is None:
            return ()
        config, params = Simulation.check(_loaded_world(world), controller=controller,
                                          settings=json.loads(settings))
        return tuple(sorted(describe(cls).same_run_settings(params, config).items()))
    except ConfigError:
        return ()


@functools.lru_cache(maxsize=32)
def _loaded_world(ref: str) -> Any:
    from swarmsim.world.world import load_world

    return load_world(ref)


@dataclass(frozen=True)
class SweepSpec:
    """A validated sweep: fixed params, grid and seeds for one world (or a grid of them)."""

    source: str
    world: str
    controller: str
    params: Mapping[str, Any]
    grid: Mapping[str, Sequence[Any]]
    seeds: tuple[int, ...]
    name: str = ""
    description: str = ""
    base_dir: str = ""

    def points(self) -> list[dict[str, Any]]:
        """The grid points (Cartesian product, file order, last key fastest)."""
        keys = list(self.grid)
        return [dict(zip(keys, combo, strict=True))
                for combo in itertools.product(*(self.grid[k] for k in keys))]

    def runs(self, unique: bool = True) -> list[RunSpec]:
        """Every run of the sweep: grid points x seeds (seeds innermost), each once (grid
        points that are the same run, e.g. failures = 0 in two failure phases, or two GGC rule
        sets that act alike in the run, share a run id: see :func:`run_id`). ``unique=False``
        keeps one RunSpec per grid point and seed, shared ids and all (for the aggregates,
        which show every grid point; a Sweep makes each id once)."""
        out: list[RunSpec] = []
        for point in self.points():
            world = str(point.get("world", self.world))
            controller = str(point.get("controller", self.controller))
            settings = {**self.params, **{k: v for k, v in point.items() if k not in RUN_KEYS}}
            for seed in self.seeds:
                out.append(RunSpec(world, controller, settings, seed,
                                   world_ref=resolve_world(world, self.base_dir),
                                   labels=dict(point)))
        return unique_runs(out) if unique else out


def resolve_world(world: str, base_dir: str) -> str:
    """A world path relative to the spec's folder, if it names a file there; else as given."""
    if base_dir and (world.endswith(".toml") or "/" in world):
        candidate = Path(base_dir) / world
        if candidate.is_file():
            return str(candidate)
    return world


def load_spec(path: str | Path) -> SweepSpec:
    """Read and validate a sweep spec TOML file."""
    path = Path(path)
    source = str(path)
    if not path.is_file():
        raise ConfigError(f"spec file not found: {source!r}", key="spec")
    data = read_toml(path)
    return spec_from_dict(data, source=source, base_dir=str(path.parent))


def spec_from_dict(data: Mapping[str, Any], source: str = "<spec>", base_dir: str = "",
                   check: bool = True) -> SweepSpec:
    """Validate a spec given as a dict (e.g. parsed TOML). ``check`` also checks that the
    world loads and that every setting name is known to its controller."""
    unknown = [k for k in data if k not in TOP_KEYS]
    if unknown:
        message = unknown_name("key", unknown[0], TOP_KEYS)
        raise ConfigError(f"{message} (value {data[unknown[0]]!r})", source=source,
                          key=unknown[0])
    name = _string(data, "name", "", source)
    description = _string(data, "description", "", source)
    params = _params(data.get("params", {}), source)
    grid = _grid(data.get("grid"), source)
    if "world" not in data and "world" not in grid:
        raise ConfigError("missing (the world to run: a name or a .toml path; or a list of "
                          "them as grid.world)", source=source, key="world")
    world = _string(data, "world", str(grid.get("world", [""])[0]), source)
    controller = _string(data, "controller", "ggc", source)
    for key in ("world", "controller"):
        if key in data and key in grid:
            raise ConfigError(f"set both as the top-level '{key}' ({data[key]!r}) and in [grid] "
                              f"({grid[key]!r}); give it once", source=source, key=f"grid.{key}")
    both = [k for k in grid if k in params]
    if both:
        raise ConfigError(f"set both in [params] ({params[both[0]]!r}) and in [grid] "
                          f"({grid[both[0]]!r})", source=source, key=f"grid.{both[0]}")
    seeds = _seeds(data, source)
    _check_run_count(grid, seeds, source)
    spec = SweepSpec(source, world, controller, params, grid, seeds, name, description,
                     base_dir)
    if check:
        check_settings(spec)
    return spec


def _string(data: Mapping[str, Any], key: str, default: str, source: str) -> str:
    value = data.get(key, default)
    if not isinstance(value, str) or (key in ("world", "controller") and not value.strip()):
        raise ConfigError(f"expected a non-empty string, got {value!r}", source=source, key=key)
    return value


def _params(value: Any, source: str) -> dict[str, Any]:
    if not isinstance(value, Mapping):
        raise ConfigError(f"expected a table of settings, got {value!r}", source=source,
                          key="params")
    out = {}
    for key, v in value.items():
        if key in ("seed", *RUN_KEYS):
            where = "'seeds' or 'reps'" if key == "seed" else f"top-level '{key}'"
            raise ConfigError(f"set the {key} with {where}, not in [params] (value {v!r})",
                              source=source, key=f"params.{key}")
        if not isinstance(v, SCALAR_TYPES):
            raise ConfigError(f"expected a number, boolean or string, got {v!r}",
                              source=source, key=f"params.{key}")
        out[key] = v
    return out


def _grid(value: Any, source: str) -> dict[str, list[Any]]:
    if value is None:
        return {}
    if not isinstance(value, Mapping):
        raise ConfigError(f"expected a table of lists, got {value!r}", source=source, key="grid")
    if not value:
        raise ConfigError("is empty: give lists of values (key = [v1, v2]) or leave [grid] out",
                          source=source, key="grid")
    out: dict[str, list[Any]] = {}
    for key, values in value.items():
        where = f"grid.{key}"
        if key == "seed":
            raise ConfigError(f"set seeds with 'seeds' or 'reps', not in [grid] (value "
                              f"{values!r})", source=source, key=where)
        if not isinstance(values, list):
            raise ConfigError(f"expected a list of values, got {values!r}", source=source,
                              key=where)
        if not values:
            raise ConfigError("empty list: a grid key needs at least one value", source=source,
                              key=where)
        for v in values:
            if not isinstance(v, SCALAR_TYPES):
                raise ConfigError(f"expected numbers, booleans or strings, got {v!r}",
                                  source=source, key=where)
        canon = [_canonical(v) for v in values]
        dup = next((v for i, v in enumerate(canon) if v in canon[:i]), None)
        if dup is not None:
            raise ConfigError(f"value {dup!r} is listed twice in {values!r}", source=source,
                              key=where)
        out[key] = list(values)
    return out


def _check_run_count(grid: Mapping[str, list[Any]], seeds: tuple[int, ...], source: str) -> None:
    """Refuse a sweep of more than MAX_RUNS runs (grid points x seeds), before listing them."""
    runs = math.prod(len(v) for v in grid.values()) * len(seeds)
    if runs > MAX_RUNS:
        sizes = " x ".join(f"{len(v)} {k}" for k, v in grid.items())
        raise ConfigError(f"{sizes} x {len(seeds)} seeds make {runs:,} runs, more than "
                          f"{MAX_RUNS:,} in one sweep", source=source, key="grid")


def _int(value: Any, source: str, key: str, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < minimum:
        raise ConfigError(f"expected an integer >= {minimum}, got {value!r}", source=source,
                          key=key)
    return value


def _seeds(data: Mapping[str, Any], source: str) -> tuple[int, ...]:
    if "seeds" in data:
        for key in ("reps", "seed_base"):
            if key in data:
                raise ConfigError(f"give either 'seeds' or 'reps' (with 'seed_base'), not both "
                                  f"(value {data[key]!r})", source=source, key=key)
        seeds = data["seeds"]
        if not isinstance(seeds, list) or not seeds:
            raise ConfigError(f"expected a non-empty list of integers, got {seeds!r}",
                              source=source, key="seeds")
        check_at_most("seeds", len(seeds), MAX_REPS, "seeds per grid point; this many seeds",
                      source)
        out = tuple(_int(s, source, "seeds", 0) for s in seeds)
        if len(set(out)) != len(out):
            raise ConfigError(f"seeds must be distinct, got {seeds!r}", source=source,
                              key="seeds")
        return out
    reps = _int(data.get("reps", 1), source, "reps", 1)
    check_at_most("reps", reps, MAX_REPS, "seeds per grid point", source)
    base = _int(data.get("seed_base", 0), source, "seed_base", 0)
    return tuple(range(base, base + reps))


def check_settings(spec: SweepSpec) -> None:
    """Every world loads and every setting name and value type suits its controller."""
    from swarmsim.controller import get_controller
    from swarmsim.world.world import load_world

    worlds = spec.grid.get("world", [spec.world])
    controllers = spec.grid.get("controller", [spec.controller])
    for w in worlds:
        key = "grid.world" if "world" in spec.grid else "world"
        _reraise(lambda w=w: load_world(resolve_world(str(w), spec.base_dir)), spec.source, key)
    for c in controllers:
        key = "grid.controller" if "controller" in spec.grid else "controller"
        cls = _reraise(lambda c=c: get_controller(str(c)), spec.source, key)
        known = {**field_defaults(SimConfig), **field_defaults(PhysicsConfig),
                 **field_defaults(cls.Params)}
        named = [(f"params.{k}", k, [v]) for k, v in spec.params.items()]
        named += [(f"grid.{k}", k, vs) for k, vs in spec.grid.items() if k not in RUN_KEYS]
        for where, k, values in named:
            if k not in known:
                hint = did_you_mean(k, known) or f"; see 'swarmsim params --controller {c}'"
                raise ConfigError(f"unknown setting for controller {c!r} (value {values[0]!r})"
                                  f"{hint}", source=spec.source, key=where)
            for v in values:
                _reraise(lambda v=v, k=k, d=known[k]: coerce(v, d, k), spec.source, where)
    check_runs(spec.runs(), spec.source)


def check_runs(runs: Iterable[RunSpec], source: str) -> None:
    """Check every distinct run setting (world, controller, settings, seed) as
    :meth:`Simulation.check` does, before any run starts: a bad value (``groups = 0``, an
    unknown mode, a negative distance) is one ConfigError naming the run's grid values, not a
    failed run per grid point."""
    from swarmsim.engine.sim import Simulation
    from swarmsim.world.world import load_world

    worlds: dict[str, Any] = {}
    for run in runs:
        ref = run.world_ref or run.world
        if ref not in worlds:
            worlds[ref] = _reraise(lambda ref=ref: load_world(ref), source, "world")
        try:
            Simulation.check(worlds[ref], controller=run.controller, seed=run.seed,
                             settings=dict(run.settings))
        except ConfigError as exc:
            where = ", ".join(f"{k}={v!r}" for k, v in {**run.labels, "seed": run.seed}.items())
            raise ConfigError(f"{exc} (in the run with {where})", source=source) from None


def _reraise(fn, source: str, key: str):
    try:
        return fn()
    except ConfigError as exc:
        text = str(exc)
        inner = f"key '{exc.key}': "
        if exc.source is None and exc.key and text.startswith(inner):
            text = text[len(inner):]
        raise ConfigError(text, source=source, key=key) from None


def drop_unused_groups(controller: str, settings: Mapping[str, Any]) -> dict[str, Any]:
    """``settings`` without ``groups`` when ``controller`` (a name or module:Class) with the
    settings' start has no use for groups (see ControllerInfo.uses_groups): such a run
    has one group, and asking it for more is an error. For figures and studies that set the
    same groups for every controller they compare."""
    from swarmsim.engine.controller_info import describe
    from swarmsim.registry import get_controller

    out = dict(settings)
    if "groups" in out and not describe(get_controller(controller)).uses_groups(
            str(out.get("start") or "")):
        del out["groups"]
    return out


def unique_runs(runs: Iterable[RunSpec]) -> list[RunSpec]:
    """``runs`` without repeats (same run id), in the order of each id's first occurrence.
    Of runs that share an id, the first whose own settings name it (see :func:`run_id`: the
    canonical one, e.g. GGC's run under the paper's rule set) is kept, else the first."""
    kept: dict[str, RunSpec] = {}
    for run in runs:
        rid = run.run_id
        if rid not in kept or (_renamed(kept[rid]) and not _renamed(run)):
            kept[rid] = run
    return list(kept.values())


def _renamed(run: RunSpec) -> bool:
    """The run's id is made from other settings than its own (same_run_settings)."""
    return bool(same_run_settings(run.world_ref or run.world, run.controller, run.settings))
