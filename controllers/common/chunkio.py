"""What a batch controller's swarm reads from a DecideBatch, the same way for every one: the
floor probes of a chunk in one query, and columns in the dtype its compiled kernel takes."""

from __future__ import annotations

from collections.abc import Callable
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


__all__ = ["column", "probe_many_of"]
