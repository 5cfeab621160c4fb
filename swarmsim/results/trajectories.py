"""Trajectories: what a run looked like every K ticks, saved as one npz file that
``swarmsim replay`` draws again without simulating (swarmsim.replay).

Python API::

    from swarmsim import Simulation
    from swarmsim.results.trajectories import Trajectories, load_trajectories

    sim = Simulation("corridor", seed=1)
    tracks = Trajectories(sim, every=10)        # samples the start state now
    sim.run(on_tick=tracks.on_tick)
    tracks.save("out/trajectories.npz")         # adds the final state; atomic
    data = load_trajectories("out/trajectories.npz")
    data["positions"][-1]                        # (N, 2) where the robots ended

Per sample (T samples: tick 0 or the tick sampling began, every multiple of K, the last tick):

- ``ticks`` (T,) int64.
- ``positions`` (T, N, 2) float64, units: the engine's own numbers, so that a replayed frame
  puts every robot on exactly the pixel the live frame did (float32 moves a robot whose
  centre falls near a pixel's edge by one pixel).
- ``statuses`` (T, N) int8: the index into the controller's STATUSES, -1 for a robot that
  has not broadcast yet; the names in ``status_names`` (S,).
- ``field_NAME`` (T, N) in the broadcast's own dtype, for every colouring the controller
  offers (``colouring_names`` / ``colouring_kinds``: "scale" or "category") and its leader and
  group fields (``leader_field`` / ``group_field``, "" for none): GGC's ``field_gradient``,
  ``field_group``, ``field_leader``.
- ``in_contact_bits``, ``failed_bits``, ``asleep_bits`` (T, ceil(N / 8)) uint8: the (N,)
  bool flags (touching something, failed, asleep) packed with ``np.packbits``
  (``np.unpackbits(row, count=N)`` reads them).
- ``headings`` (T, N) float64, radians in the world frame: each robot's heading, only for a
  run whose drive has one (``Snapshot.headings``); absent otherwise.
- ``coverage`` (T,) float64: coverage P(t).
- ``covered_changes`` (C,) uint16 (uint32 when the raster has more than 65,535 cells) and
  ``covered_change_offsets`` (T + 1,) int64: the flat indices (row-major, as ``grid_inside``)
  of the raster cells whose covered state flipped since the previous sample (since an
  uncovered raster for the first): sample t's are
  ``covered_changes[offsets[t]:offsets[t + 1]]``. A cell is covered while a robot is within
  r of it, so cells are uncovered again when robots leave: a change goes either way.

Once per run, to draw it again: ``format`` (FORMAT), ``controller``, ``radius`` (robot body
radius, units), ``start_groups`` (N,) int32 and ``start_leaders`` (N,) bool (the roles the
run gave the robots at the start), the world (``world_name``, ``world_arena`` (4,),
``world_target``, ``world_spawns``, ``world_obstacles`` as WKB bytes (uint8), ``world_beacon``
(2,) or (0,)), the coverage raster (``grid_inside`` (rows, cols) bool, ``grid_x0``,
``grid_y0``, ``grid_dx``, ``grid_dy``, ``grid_radius``).

Samples are kept in memory until saved. A sample costs, per robot, 16 bytes (position) + 1
(status) + the fields' bytes (GGC: gradient 4, group 2, leader 1) + 3 bits (contact, failure,
sleep): 24.375 bytes for GGC (:func:`sample_cost`), 8 more with headings; and per sample 71
bytes (the tick and coverage objects, the flags' rounding) and at most 136 for each of its
arrays (numpy's header and a list slot; 9 arrays for GGC, one more with headings), plus the
changed raster cells, at most the raster's cells or two robot stencils per
robot, 2 or 4 bytes each (``memory_bytes`` counts this bound; :func:`check_memory` refuses
more than MAX_TRAJECTORY_BYTES). Files written before ``format`` 2 hold only ``ticks``,
``positions`` (float32), ``statuses`` and ``status_names``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import shapely

from swarmsim.errors import ConfigError
from swarmsim.limits import MAX_TICKS, MAX_TRAJECTORY_BYTES, check_at_most
from swarmsim.results.output import write_npz

FILE_NAME = "trajectories.npz"
FORMAT = 2
"""The layout this module writes (``format`` in the file); files without it are from before
replay (positions and statuses only)."""
POSITION_BYTES = 16  # float64 x, y
STATUS_BYTES = 1
FLAG_BYTES = 3 / 8  # in_contact, failed and asleep, one bit each
BYTES_PER_ROBOT = POSITION_BYTES + STATUS_BYTES + FLAG_BYTES
"""A sample's bytes per robot without the controller's fields: the least any run keeps."""
ARRAY_BYTES = 128 + 8
"""What each array a sample keeps costs beside its data: numpy's header (sys.getsizeof of an
empty 2-D array; 112 for 1-D) and its slot in a list."""
FIXED_ARRAYS = 6  # position, status, three flags, changed cells; plus one per field
HEADING_BYTES = 8  # float64, only for a drive with a heading (plus one array)
SAMPLE_BYTES = 28 + 24 + 2 * 8 + 3  # the tick (int) and coverage (float) objects, their
# slots, and the three flag arrays' last bytes (packbits rounds N / 8 up)
FIELD_PREFIX = "field_"


def check_every(value: Any, key: str = "trajectories_every") -> int:
    """``value`` as a sampling interval in ticks: a positive integer, else ConfigError."""
    if isinstance(value, bool):
        raise ConfigError(f"must be a positive integer (ticks), got {value!r}", key=key)
    if isinstance(value, str):
        try:
            value = int(value.strip())
        except ValueError:
            raise ConfigError(f"must be a positive integer (ticks), got {value!r}",
                              key=key) from None
    if not isinstance(value, (int, np.integer)) or value <= 0:
        raise ConfigError(f"must be a positive integer (ticks), got {value!r}", key=key)
    check_at_most(key, value, MAX_TICKS, "ticks in one run")
    return int(value)


@dataclass(frozen=True)
class SampleCost:
    """What one sample keeps in memory: ``per_robot`` bytes for each robot, ``per_sample``
    bytes once, and at most ``max_changes`` changed raster cells of ``change_bytes`` each."""

    per_robot: float = BYTES_PER_ROBOT
    per_sample: int = SAMPLE_BYTES + FIXED_ARRAYS * ARRAY_BYTES
    max_changes: int = 0
    change_bytes: int = 2

    def bytes(self, robots: int) -> int:
        """Bytes of one sample of ``robots`` robots (the changed cells at their bound)."""
        return math.ceil(robots * self.per_robot) + self.per_sample \
            + self.max_changes * self.change_bytes


def memory_bytes(every: int, robots: int, max_ticks: int, cost: SampleCost = SampleCost()
                 ) -> int:
    """Bytes the samples of a run of ``robots`` robots and at most ``max_ticks`` ticks, sampled
    every ``every`` ticks, hold in memory at most: ``cost.bytes(robots)`` a sample,
    (ticks / every + 2) samples. The default cost is the least any run has (no fields)."""
    return cost.bytes(robots) * (max_ticks // every + 2)


def check_memory(every: int, robots: int, max_ticks: int,
                 key: str = "trajectories_every", cost: SampleCost = SampleCost()) -> None:
    """Refuse a sampling interval whose samples would exceed MAX_TRAJECTORY_BYTES in memory."""
    need = memory_bytes(every, robots, max_ticks, cost)
    if need > MAX_TRAJECTORY_BYTES:
        sample = cost.bytes(robots)
        least = sample * max_ticks // (MAX_TRAJECTORY_BYTES - 2 * sample) + 1
        raise ConfigError(f"{every} ticks would keep {need / 2**30:,.1f} GiB of samples in "
                          f"memory ({robots:,} robots, up to {max_ticks:,} ticks), more than "
                          f"{MAX_TRAJECTORY_BYTES / 2**30:g} GiB: sample every {least:,} ticks "
                          "or more", key=key)


def recorded_fields(sim: Any) -> tuple[str, ...]:
    """The broadcast fields besides ``status`` that drawing ``sim`` reads: its colourings,
    leader and group fields, in the order of its message dtype."""
    info = sim.info
    wanted = {*info.colourings, info.leader_field, info.group_field}
    return tuple(n for n in (sim.messages.dtype.names or ()) if n in wanted and n != "status")


def sample_cost(sim: Any, headings: bool = False) -> SampleCost:
    """What one sample of ``sim`` keeps in memory (see the module docstring); ``headings``:
    its snapshots carry headings."""
    fields = sum(sim.messages.dtype[n].itemsize for n in recorded_fields(sim))
    fields += HEADING_BYTES if headings else 0
    grid = sim.grid
    rows, cols = grid.shape
    stencil = (2 * math.ceil(grid.radius / grid.dy) + 3) * (2 * math.ceil(grid.radius / grid.dx)
                                                            + 3)
    arrays = FIXED_ARRAYS + len(recorded_fields(sim)) + int(headings)
    return SampleCost(per_robot=BYTES_PER_ROBOT + fields,
                      per_sample=SAMPLE_BYTES + arrays * ARRAY_BYTES,
                      max_changes=min(rows * cols, 2 * sim.n * stencil),
                      change_bytes=np.dtype(change_dtype(rows * cols)).itemsize)


def change_dtype(cells: int) -> type:
    """The dtype of ``covered_changes`` for a raster of ``cells`` cells."""
    return np.uint16 if cells <= np.iinfo(np.uint16).max else np.uint32


class Trajectories:
    """Samples ``sim`` every ``every`` ticks (tick 0, or whatever tick it is at now, included).

    Pass :meth:`on_tick` to ``Simulation.run``; :meth:`save` adds the final state (if it is not
    a sample already) and writes the npz. Sampling only reads the run: it changes nothing.
    """

    def __init__(self, sim: Any, every: int):
        self.sim = sim
        self.every = check_every(every)
        first = sim.snapshot()
        check_memory(self.every, sim.n, sim.config.max_ticks,
                     cost=sample_cost(sim, headings=first.headings is not None))
        self._fields = recorded_fields(sim)
        self._change_dtype = change_dtype(sim.grid.inside.size)
        self._ticks: list[int] = []
        self._positions: list[np.ndarray] = []
        self._statuses: list[np.ndarray] = []
        self._field_values: dict[str, list[np.ndarray]] = {n: [] for n in self._fields}
        self._in_contact: list[np.ndarray] = []
        self._failed: list[np.ndarray] = []
        self._asleep: list[np.ndarray] = []
        self._headings: list[np.ndarray] = []
        self._coverage: list[float] = []
        self._changes: list[np.ndarray] = []
        self._covered = np.zeros(sim.grid.inside.size, dtype=bool)
        self._sample(first)

    def _sample(self, snap: Any = None) -> None:
        """Keep the state now (``snap``: the run's snapshot now, if already taken)."""
        sim = self.sim
        if self._ticks and self._ticks[-1] == sim.tick:
            return
        if snap is None:
            snap = sim.snapshot()  # what a live frame draws: the same copy, the same raster
        self._ticks.append(int(snap.tick))
        self._positions.append(np.array(snap.positions, dtype=np.float64))
        self._statuses.append(snap.messages["status"].astype(np.int8))
        for name in self._fields:
            self._field_values[name].append(snap.messages[name].copy())
        self._in_contact.append(np.packbits(np.asarray(snap.in_contact, dtype=bool)))
        self._failed.append(np.packbits(np.asarray(snap.failed, dtype=bool)))
        self._asleep.append(np.packbits(np.asarray(sim.asleep, dtype=bool)))
        if snap.headings is not None:
            self._headings.append(np.array(snap.headings, dtype=np.float64))
        self._coverage.append(float(snap.coverage))
        covered = np.asarray(snap.covered, dtype=bool).ravel()
        self._changes.append(np.flatnonzero(covered != self._covered).astype(self._change_dtype))
        self._covered = covered

    def on_tick(self, sim: Any) -> None:
        """Called after every tick: samples on multiples of ``every``."""
        if sim.tick % self.every == 0:
            self._sample()

    @property
    def samples(self) -> int:
        return len(self._ticks)

    def arrays(self) -> dict[str, np.ndarray]:
        """The samples so far plus the current state, as the npz file's arrays."""
        self._sample()
        sizes = [len(c) for c in self._changes]
        out = {"format": np.int64(FORMAT),
               "ticks": np.asarray(self._ticks, dtype=np.int64),
               "positions": np.stack(self._positions),
               "statuses": np.stack(self._statuses),
               "status_names": np.asarray(self.sim.statuses, dtype=str),
               **{FIELD_PREFIX + n: np.stack(v) for n, v in self._field_values.items()},
               "in_contact_bits": np.stack(self._in_contact),
               "failed_bits": np.stack(self._failed),
               "asleep_bits": np.stack(self._asleep),
               **({"headings": np.stack(self._headings)} if self._headings else {}),
               "coverage": np.asarray(self._coverage, dtype=np.float64),
               "covered_changes": np.concatenate(self._changes),
               "covered_change_offsets": np.concatenate(([0], np.cumsum(sizes))).astype(np.int64)}
        return {**out, **self._run_arrays()}

    def _run_arrays(self) -> dict[str, np.ndarray]:
        """What stays the same all run: controller, roles at the start, world and raster."""
        sim = self.sim
        info = sim.info
        return {"controller": np.asarray(sim.controller_name, dtype=str),
                "colouring_names": np.asarray(list(info.colourings), dtype=str),
                "colouring_kinds": np.asarray(list(info.colourings.values()), dtype=str),
                "leader_field": np.asarray(info.leader_field or "", dtype=str),
                "group_field": np.asarray(info.group_field or "", dtype=str),
                "radius": np.float64(sim.physics_config.radius),
                "start_groups": np.asarray(sim.start_groups, dtype=np.int32),
                "start_leaders": np.asarray(sim.start_leaders, dtype=bool),
                **world_arrays(sim.world), **grid_arrays(sim.grid)}

    def save(self, path: str | Path) -> Path:
        """Write the npz (compressed, atomically) at ``path``; returns the path."""
        path = Path(path)
        write_npz(path, self.arrays())
        return path


def _wkb(geometries: Any) -> np.ndarray:
    return np.frombuffer(shapely.to_wkb(geometries), dtype=np.uint8)


def world_arrays(world: Any) -> dict[str, np.ndarray]:
    """The world's drawn parts as arrays (see the module docstring)."""
    collection = shapely.geometrycollections
    return {"world_name": np.asarray(world.name, dtype=str),
            "world_arena": np.asarray(world.arena, dtype=np.float64),
            "world_target": _wkb(world.target),
            "world_spawns": _wkb(collection(list(world.spawns))),
            "world_obstacles": _wkb(collection(list(world.obstacles))),
            "world_beacon": np.asarray(world.beacon if world.beacon is not None else (),
                                       dtype=np.float64)}


def grid_arrays(grid: Any) -> dict[str, np.ndarray]:
    """The coverage raster's geometry as arrays (see the module docstring)."""
    return {"grid_inside": np.asarray(grid.inside, dtype=bool),
            **{f"grid_{k}": np.float64(getattr(grid, k)) for k in ("x0", "y0", "dx", "dy")},
            "grid_radius": np.float64(grid.radius)}


def load_trajectories(path: str | Path) -> dict[str, np.ndarray]:
    """The arrays of a trajectories file (see the module docstring)."""
    with np.load(Path(path), allow_pickle=False) as data:
        return {k: data[k] for k in data.files}
