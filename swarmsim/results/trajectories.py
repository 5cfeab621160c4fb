"""Trajectories: every robot's position (and status) every K ticks, saved as one npz file.

Python API::

    from swarmsim import Simulation
    from swarmsim.results.trajectories import Trajectories, load_trajectories

    sim = Simulation("corridor", seed=1)
    tracks = Trajectories(sim, every=10)        # samples the start state now
    sim.run(on_tick=tracks.on_tick)
    tracks.save("out/trajectories.npz")         # adds the final state; atomic
    data = load_trajectories("out/trajectories.npz")
    data["positions"][-1]                        # (N, 2) where the robots ended

The file holds ``ticks`` (T,) int64, ``positions`` (T, N, 2) float32 (units) and, when the
controller's broadcasts have a ``status`` field, ``statuses`` (T, N) int8 (the index into
the controller's STATUSES, -1 for a failed or silent robot) with the names in
``status_names`` (S,). Samples are kept in memory until saved: N x 9 bytes a sample (8 for
the position, 1 for the status), (ticks / every + 2) samples.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from swarmsim.errors import ConfigError
from swarmsim.limits import MAX_TICKS, MAX_TRAJECTORY_BYTES, check_at_most
from swarmsim.results.output import write_npz

FILE_NAME = "trajectories.npz"
BYTES_PER_ROBOT = 9  # a sample's bytes per robot: float32 x, y and an int8 status


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


def memory_bytes(every: int, robots: int, max_ticks: int) -> int:
    """Bytes the samples of a run of ``robots`` robots and at most ``max_ticks`` ticks, sampled
    every ``every`` ticks, hold in memory: N x BYTES_PER_ROBOT a sample, (ticks / every + 2)
    samples."""
    return robots * BYTES_PER_ROBOT * (max_ticks // every + 2)


def check_memory(every: int, robots: int, max_ticks: int,
                 key: str = "trajectories_every") -> None:
    """Refuse a sampling interval whose samples would exceed MAX_TRAJECTORY_BYTES in memory."""
    need = memory_bytes(every, robots, max_ticks)
    if need > MAX_TRAJECTORY_BYTES:
        least = robots * BYTES_PER_ROBOT * max_ticks // (MAX_TRAJECTORY_BYTES
                                                          - 2 * robots * BYTES_PER_ROBOT) + 1
        raise ConfigError(f"{every} ticks would keep {need / 2**30:,.1f} GiB of samples in "
                          f"memory ({robots:,} robots, up to {max_ticks:,} ticks), more than "
                          f"{MAX_TRAJECTORY_BYTES / 2**30:g} GiB: sample every {least:,} ticks "
                          "or more", key=key)


class Trajectories:
    """Samples ``sim`` every ``every`` ticks (tick 0, or whatever tick it is at now, included).

    Pass :meth:`on_tick` to ``Simulation.run``; :meth:`save` adds the final state (if it is not
    a sample already) and writes the npz. Sampling only reads the run: it changes nothing.
    """

    def __init__(self, sim: Any, every: int):
        self.sim = sim
        self.every = check_every(every)
        check_memory(self.every, sim.n, sim.config.max_ticks)
        names = sim.messages.dtype.names or ()
        self._with_status = "status" in names
        self._ticks: list[int] = []
        self._positions: list[np.ndarray] = []
        self._statuses: list[np.ndarray] = []
        self._sample()

    def _sample(self) -> None:
        sim = self.sim
        if self._ticks and self._ticks[-1] == sim.tick:
            return
        self._ticks.append(int(sim.tick))
        self._positions.append(sim.positions.astype(np.float32))
        if self._with_status:
            self._statuses.append(sim.messages["status"].astype(np.int8))

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
        out = {"ticks": np.asarray(self._ticks, dtype=np.int64),
               "positions": np.stack(self._positions)}
        if self._with_status:
            out["statuses"] = np.stack(self._statuses)
            out["status_names"] = np.asarray(self.sim.statuses, dtype=str)
        return out

    def save(self, path: str | Path) -> Path:
        """Write the npz (compressed, atomically) at ``path``; returns the path."""
        path = Path(path)
        write_npz(path, self.arrays())
        return path


def load_trajectories(path: str | Path) -> dict[str, np.ndarray]:
    """The arrays of a trajectories file (see the module docstring)."""
    with np.load(Path(path), allow_pickle=False) as data:
        return {k: data[k] for k in data.files}

