"""What a batch controller's swarm reads from a DecideBatch, the same way for every one: the
floor probes of a chunk in one query, and columns in the dtype its compiled kernel takes."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

from swarmsim.controller import DecideBatch


def probe_many_of(batch: DecideBatch) -> Callable[[np.ndarray, np.ndarray], np.ndarray]:
    """The batch's ``probe_many``, or its robots' probes asked one by one (a batch made by
    hand may have none): ``f(ks, offsets)`` -> (M,) bool, entry j robot ``ks[j]``'s floor
    probe at ``offsets[j]`` (units)."""
    if batch.probe_many is not None:
        return batch.probe_many

    def one_by_one(ks: np.ndarray, offsets: np.ndarray) -> np.ndarray:
        return np.array([bool(batch.probe(int(k))(o)) for k, o in zip(ks, offsets, strict=True)],
                        dtype=np.bool_)

    return one_by_one


def column(a: Any, dtype: type) -> np.ndarray:
    """``a`` as a C-contiguous array of ``dtype`` (a copy only when it is not one already)."""
    return np.require(a, dtype=dtype, requirements=("C",))


def sensed_columns(robots: np.ndarray, batch: DecideBatch, fields: Mapping[str, type]
                   ) -> dict[str, Any]:
    """A chunk's sensing as a compiled kernel's columns, by name: the tick, the chunk's robot
    ``rows``, each robot's first neighbour row (``starts``), the neighbours' ``offsets`` (P, 2)
    and ``distances``, their broadcasts' ``sender`` (the ``id`` field) and each of ``fields``
    (name -> dtype), the floor sensors (``on_target``), the odometry (``moved``, (R, 2)), the
    beacon bearings (``beacons``, (R, 2): zeros without a beacon) and ``has_beacon``."""
    messages = batch.neighbours.messages
    has_beacon = batch.beacons is not None
    out: dict[str, Any] = {
        "tick": int(batch.tick), "rows": column(robots, np.int64),
        "starts": column(batch.neighbours.starts, np.int64),
        "offsets": column(batch.offsets, np.float64).reshape(-1, 2),
        "distances": column(batch.neighbours.distances, np.float64),
        "sender": column(messages["id"], np.int64),
        "on_target": column(batch.on_target, np.bool_),
        "moved": column(batch.moved, np.float64).reshape(-1, 2),
        "beacons": (column(batch.beacons, np.float64).reshape(-1, 2) if has_beacon
                    else np.zeros((len(robots), 2))),
        "has_beacon": has_beacon}
    out.update({name: column(messages[name], dtype) for name, dtype in fields.items()})
    return out


__all__ = ["column", "probe_many_of", "sensed_columns"]
