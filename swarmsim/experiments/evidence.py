"""Comparisons between conditions that weigh the spread between seeds.

A claim such as "3 groups complete sooner than 1" is judged on the runs of each condition
(one value per seed). :func:`compare` gives the difference of a statistic (mean or median)
between two conditions with a percentile bootstrap interval (each condition's seeds
resampled with replacement, a fixed generator: a report is the same every time it is
written). A comparison *holds* when the whole interval lies on the claimed side of zero,
*contradicts* when it lies wholly on the other side, and is *unresolved* otherwise, or when
either side has fewer than :data:`MIN_RUNS` values.

Completion ticks follow the paper's Definition 4: a run that never completes took forever.
They are compared with ``math.inf`` for such runs and the median as the statistic, which
orders "never" after every completion (two medians that are both "never" are equal).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

HOLDS, CONTRADICTS, UNRESOLVED = "holds", "contradicts", "unresolved"
"""The outcome of one comparison."""
MIN_RUNS = 2
"""Fewest values per side for a comparison to be resolved."""
LEVEL = 0.95
"""Two-sided level of the bootstrap intervals."""
BOOTSTRAPS = 4000
"""Bootstrap resamples per comparison."""


@dataclass(frozen=True)
class Comparison:
    """``stat(a) - stat(b)`` with its bootstrap interval.

    Attributes:
        diff: the difference of the two samples' statistics (may be +-inf).
        lo, hi: the interval's ends (``LEVEL`` two-sided).
        n_a, n_b: values on each side.
        stat: "mean" or "median".
    """

    diff: float
    lo: float
    hi: float
    n_a: int
    n_b: int
    stat: str

    @property
    def resolvable(self) -> bool:
        return min(self.n_a, self.n_b) >= MIN_RUNS

    def text(self, fmt: str = ".0f") -> str:
        """'d [lo, hi]' for a report (units those of the values)."""
        if not (self.n_a and self.n_b):
            return "n/a"
        return f"{_num(self.diff, fmt)} [{_num(self.lo, fmt)}, {_num(self.hi, fmt)}]"


def _num(x: float, fmt: str) -> str:
    if math.isinf(x):
        return "never" if x > 0 else "-never"
    return format(x, fmt)


def _stat(values: np.ndarray, stat: str) -> np.ndarray:
    """The statistic along the last axis."""
    if stat == "mean":
        return values.mean(axis=-1)
    return np.median(values, axis=-1)


def _differences(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a - b where "never minus never" (inf - inf) counts as equal (0)."""
    with np.errstate(invalid="ignore"):
        d = a - b
    return np.where(np.isnan(d), 0.0, d)


def compare(a: Sequence[float], b: Sequence[float], stat: str = "mean",
            seed: int = 0) -> Comparison:
    """``stat(a) - stat(b)`` with a percentile bootstrap interval over each side's values.

    ``math.inf`` is allowed (a run that never completed); use ``stat="median"`` then.
    """
    if stat not in ("mean", "median"):
        raise ValueError(f"stat must be 'mean' or 'median', got {stat!r}")
    xa, xb = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    if xa.size == 0 or xb.size == 0:
        return Comparison(math.nan, math.nan, math.nan, xa.size, xb.size, stat)
    diff = float(_differences(_stat(xa, stat), _stat(xb, stat)))
    rng = np.random.default_rng(seed)
    ra = xa[rng.integers(0, xa.size, (BOOTSTRAPS, xa.size))]
    rb = xb[rng.integers(0, xb.size, (BOOTSTRAPS, xb.size))]
    boot = _differences(_stat(ra, stat), _stat(rb, stat))
    tail = (1 - LEVEL) / 2
    lo, hi = np.quantile(boot, [tail, 1 - tail], method="inverted_cdf")
    return Comparison(diff, float(lo), float(hi), xa.size, xb.size, stat)


def less(c: Comparison) -> str:
    """Does ``a < b`` hold (the interval of a - b wholly below zero)?"""
    if not c.resolvable:
        return UNRESOLVED
    if c.hi < 0:
        return HOLDS
    return CONTRADICTS if c.lo > 0 else UNRESOLVED


def greater(c: Comparison) -> str:
    """Does ``a > b`` hold (the interval of a - b wholly above zero)?"""
    if not c.resolvable:
        return UNRESOLVED
    if c.lo > 0:
        return HOLDS
    return CONTRADICTS if c.hi < 0 else UNRESOLVED


def within(c: Comparison, margin: float) -> str:
    """Are a and b the same within ``margin`` (an equivalence test: the whole interval of
    a - b inside +-margin holds; wholly outside it contradicts)?"""
    if not c.resolvable:
        return UNRESOLVED
    if -margin < c.lo and c.hi < margin:
        return HOLDS
    return CONTRADICTS if c.lo > margin or c.hi < -margin else UNRESOLVED


def spread_text(values: Sequence[float], fmt: str = ".0f") -> str:
    """'median (min-max), n' of a condition's values, 'never' for math.inf."""
    xs = [float(v) for v in values]
    if not xs:
        return "n/a"
    med = float(np.median(xs)) if not all(math.isinf(x) for x in xs) else math.inf
    return f"{_num(med, fmt)} ({_num(min(xs), fmt)}-{_num(max(xs), fmt)}), n={len(xs)}"
