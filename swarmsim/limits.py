"""Upper bounds on every size a user can type, declared once, with the reason for each.

A number that sizes an allocation (a raster, a frame, a robot array, samples kept in memory)
or a loop (ticks, substeps, runs) is refused above its bound with one line naming the key,
the bound and the value, before anything is allocated. ``swarmsim params`` prints each
parameter's bound (dataclass fields declare it with :func:`at_most`); docs/input-checks.md
lists them all.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

from swarmsim.errors import ConfigError

MAX_ROBOTS = 50_000
"""Robots in one run: 5x the largest swarm measured (10,000 robots, docs/performance.md)."""
MAX_GROUPS = 256
"""Groups in one run (``groups``: run, a world's defaults, make-world's --groups): a group
per 200 robots (the shipped K's 603 in 3, make-world's default) at MAX_ROBOTS is 250. Groups
cost nothing per robot in formation starts; a scattered GGC start keeps 16 bytes per group in
each robot's state and broadcasts 8, and its gathering robots read every group's entries of
each neighbour every tick: memory and the first ticks' time grow with robots x groups
(50,000 x 256: 307 MB of per-group values; measured: docs/input-checks.md)."""
GROUPS_SIZE = "groups in one run"
"""What :data:`MAX_GROUPS` bounds, as its refusals say it."""
MAX_TICKS = 10_000_000
"""Ticks in one run: 100x the default limit."""
MAX_RECORD_ROWS = 1_000_000
"""Time-series rows a run keeps in memory until it ends (max_ticks / record_every); a row's
size, and so this bound's memory: docs/input-checks.md."""
MAX_GRID_SIZE = 2_000
"""Coverage raster side, cells (paper: 100): grid_size^2 cells, 4 million at the bound."""
MAX_SUBSTEPS = 100
"""pymunk steps per tick (default 6): each is a full physics step."""
MAX_ITERATIONS = 100
"""Contact solver iterations per step (default 5)."""
MAX_COORDINATE = 1e6
"""|x| and |y| of any point of a world, units: 2.5 million robot radii (0.4). Beyond, the
coverage raster's cells and the arena are absurd for robots of this size."""
MAX_FRAME_SIDE = 7_680
"""Video, snapshot and preview frame width or height, pixels (8K)."""
MAX_FPS = 240
"""Video frames per second."""
MAX_REPS = 1_000
"""Seeds per condition (sweep ``reps``, ``reproduce --reps``, ``study --reps``)."""
MAX_RUNS = 1_000_000
"""Runs in one sweep (grid points x seeds)."""
MAX_TRAJECTORY_BYTES = 4 * 2**30
"""Trajectory samples kept in memory until a run ends (``--trajectories``), bytes (4 GiB)."""
MAX_WORKERS_PER_CPU = 4
"""Local worker processes per CPU (``--workers``)."""

BOUND = "at_most"
"""The dataclass field metadata key of a parameter's upper bound (see :func:`at_most`)."""
WHAT = "at_most_sizes"
"""The field metadata key of what the bounded value sizes (for the error message)."""


def at_most(bound: float, what: str = "") -> dict[str, Any]:
    """Field metadata declaring ``bound`` as the parameter's largest value (``what``: what the
    value sizes, for the error): ``robots: int = field(default=100,
    metadata=at_most(MAX_ROBOTS))``."""
    return {BOUND: bound, WHAT: what}


def field_bounds(cls: type) -> dict[str, tuple[float, str]]:
    """(bound, what it sizes) of each field of dataclass ``cls`` that declares a bound."""
    return {f.name: (f.metadata[BOUND], f.metadata.get(WHAT, ""))
            for f in dataclasses.fields(cls) if BOUND in f.metadata}


def check_fields(config: Any) -> None:
    """Refuse a field of dataclass instance ``config`` above its declared bound."""
    check_values(type(config), {f.name: getattr(config, f.name)
                                for f in dataclasses.fields(config)})


def check_values(cls: type, values: Mapping[str, Any]) -> None:
    """Refuse a value of ``values`` (keyword arguments for dataclass ``cls``) above the bound
    its field declares."""
    bounds = field_bounds(cls)
    for name, value in values.items():
        if name in bounds:
            check_at_most(name, value, *bounds[name])


def check_at_most(key: str, value: Any, bound: float, what: str = "",
                  source: str | None = None) -> None:
    """Refuse ``value`` > ``bound`` with one line naming ``key`` (and ``source``); ``what``
    says what the value sizes. Non-numbers are left to the type checks."""
    if isinstance(value, (int, float)) and not isinstance(value, bool) and value > bound:
        why = f" ({what})" if what else ""
        raise ConfigError(f"must be at most {format_bound(bound)}{why}, got {value!r}",
                          source=source, key=key)


def check_count(key: str, value: Any, bound: float, what: str = "") -> None:
    """Refuse ``value`` unless it is an integer from 1 to ``bound`` (one line naming ``key``)."""
    if isinstance(value, bool) or not isinstance(value, int):
        raise ConfigError(f"must be an integer >= 1, got {value!r}", key=key)
    if value < 1:
        raise ConfigError(f"must be >= 1, got {value!r}", key=key)
    check_at_most(key, value, bound, what)


def format_bound(bound: float) -> str:
    """``bound`` with thousands separators (50,000; 1,000,000)."""
    return f"{bound:,.0f}" if float(bound).is_integer() else f"{bound:g}"


def require_positive(params: Any, *names: str) -> None:
    """For a parameter dataclass's ``__post_init__``: ValueError "NAME must be positive, got
    VALUE" for the first of the fields ``names`` of ``params`` whose value is not > 0 (NaN
    is not). A run turns it into a ConfigError naming that setting."""
    for name in names:
        value = getattr(params, name)
        if not value > 0:
            raise ValueError(f"{name} must be positive, got {value!r}")


def require_non_negative(params: Any, *names: str) -> None:
    """As :func:`require_positive`, for fields that must be >= 0 ("NAME must be >= 0")."""
    for name in names:
        value = getattr(params, name)
        if not value >= 0:
            raise ValueError(f"{name} must be >= 0, got {value!r}")
