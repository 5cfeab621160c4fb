"""Comparisons between conditions that weigh the spread between seeds.

A claim such as "3 groups complete sooner than 1" is judged on the runs of each condition,
one value per seed. :func:`compare` tests the difference between two conditions at a 95 %
two-sided level, with few seeds in mind (the paper ran 30, a quick reproduction 3):

* **Finite values**: Welch's t interval of the difference of means (unequal variances;
  Student's t at Welch-Satterthwaite degrees of freedom). A percentile bootstrap was the
  first choice and was dropped: with 3 seeds a side it resamples only 10 distinct means and
  its interval is far too narrow (it "resolved" [1, 2, 5] against [4, 5, 6]).
* **Values with "never"** (``math.inf``: a run that never completed, slower than any that
  did, the paper's Definition 4): no mean exists, so the two samples are compared by ranks,
  with an exact permutation test of the Mann-Whitney statistic (all splits when there are at
  most :data:`EXACT_SPLITS`, else :data:`PERMUTATIONS` random ones from a fixed generator).
  With 3 runs a side no rank test reaches 2.5 % one-sided (the smallest p is 1/20): such a
  comparison is honestly "not resolved at 3 runs" however the runs fall.

A comparison *holds* when it is significant in the claimed direction, *contradicts* when it
is significant in the other, and is *unresolved* otherwise or with fewer than
:data:`MIN_RUNS` values a side. Every result is the same each time it is computed.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from itertools import combinations

import numpy as np
from scipy import stats as sps

HOLDS, CONTRADICTS, UNRESOLVED = "holds", "contradicts", "unresolved"
"""The outcome of one comparison."""
MIN_RUNS = 2
"""Fewest values per side for a comparison to be resolved."""
LEVEL = 0.95
"""Two-sided level: each direction is tested at (1 - LEVEL) / 2."""
EXACT_SPLITS = 20_000
"""Largest number of splits a rank test enumerates exactly."""
PERMUTATIONS = 20_000
"""Random splits of a rank test above :data:`EXACT_SPLITS`."""


@dataclass(frozen=True)
class Comparison:
    """``a`` against ``b``.

    Attributes:
        diff: mean(a) - mean(b) for finite values; median(a) - median(b) with "never"
            (may be +-inf; "never" against "never" is 0).
        lo, hi: the 95 % interval of the difference of means (NaN for a rank comparison).
        n_a, n_b: values on each side.
        method: "welch" or "ranks".
        p_less, p_greater: one-sided p values of a < b and a > b (rank comparison; NaN for
            Welch, which decides by its interval).
    """

    diff: float
    lo: float
    hi: float
    n_a: int
    n_b: int
    method: str = "welch"
    p_less: float = math.nan
    p_greater: float = math.nan

    @property
    def resolvable(self) -> bool:
        return min(self.n_a, self.n_b) >= MIN_RUNS

    def scaled(self, factor: float) -> Comparison:
        """The same comparison with its differences multiplied by ``factor`` (> 0)."""
        return Comparison(factor * self.diff, factor * self.lo, factor * self.hi, self.n_a,
                          self.n_b, self.method, self.p_less, self.p_greater)

    def shifted(self, by: float) -> Comparison:
        """The comparison of a + ``by`` with b (Welch only)."""
        return Comparison(self.diff + by, self.lo + by, self.hi + by, self.n_a, self.n_b,
                          self.method)

    def text(self, fmt: str = ".0f") -> str:
        """'d [lo, hi]' (Welch) or 'd (ranks, p = ...)' for a report, in the values' units."""
        if not (self.n_a and self.n_b):
            return "n/a"
        if self.method == "ranks":
            p = min(self.p_less, self.p_greater)
            return f"{_num(self.diff, fmt)} (medians; ranks, p = {p:.3f})"
        return f"{_num(self.diff, fmt)} [{_num(self.lo, fmt)}, {_num(self.hi, fmt)}]"


def _num(x: float, fmt: str) -> str:
    if math.isnan(x):
        return "n/a"
    if math.isinf(x):
        return "never" if x > 0 else "-never"
    return format(x, fmt)


def _median(x: np.ndarray) -> float:
    return float(np.median(x)) if x.size else math.nan


def compare(a: Sequence[float], b: Sequence[float]) -> Comparison:
    """``a`` against ``b``: Welch's interval for finite values, a rank test where either
    side holds ``math.inf`` (a run that never completed)."""
    xa, xb = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    if xa.size == 0 or xb.size == 0:
        return Comparison(math.nan, math.nan, math.nan, xa.size, xb.size)
    if np.isinf(xa).any() or np.isinf(xb).any():
        return _ranks(xa, xb)
    return _welch(xa, xb)


def _welch(xa: np.ndarray, xb: np.ndarray) -> Comparison:
    diff = float(xa.mean() - xb.mean())
    if min(xa.size, xb.size) < 2:
        return Comparison(diff, math.nan, math.nan, xa.size, xb.size)
    va, vb = xa.var(ddof=1) / xa.size, xb.var(ddof=1) / xb.size
    se = math.sqrt(va + vb)
    if se == 0:
        return Comparison(diff, diff, diff, xa.size, xb.size)
    df = (va + vb) ** 2 / (va ** 2 / (xa.size - 1) + vb ** 2 / (xb.size - 1))
    half = float(sps.t.ppf(1 - (1 - LEVEL) / 2, df)) * se
    return Comparison(diff, diff - half, diff + half, xa.size, xb.size)


def _u(xa: np.ndarray, xb: np.ndarray) -> np.ndarray:
    """The Mann-Whitney count of pairs with a below b (ties a half), along the last axis
    of stacked samples."""
    below = (xa[..., :, None] < xb[..., None, :]).sum(axis=(-2, -1))
    ties = (xa[..., :, None] == xb[..., None, :]).sum(axis=(-2, -1))
    return below + 0.5 * ties


def _ranks(xa: np.ndarray, xb: np.ndarray) -> Comparison:
    both, na = np.concatenate([xa, xb]), xa.size
    splits = math.comb(both.size, na)
    if splits <= EXACT_SPLITS:
        picks = np.array(list(combinations(range(both.size), na)))
    else:
        rng = np.random.default_rng(0)
        picks = np.argsort(rng.random((PERMUTATIONS, both.size)), axis=1)[:, :na]
    chosen = np.zeros((len(picks), both.size), dtype=bool)
    np.put_along_axis(chosen, picks, True, axis=1)
    order = np.argsort(~chosen, axis=1, kind="stable")  # each split: a's first, then b's
    shuffled = both[order]
    u_all = _u(shuffled[:, :na], shuffled[:, na:])
    u = float(_u(xa, xb))
    diff = _median(xa) - _median(xb) if not (np.isinf(_median(xa)) and np.isinf(_median(xb))) \
        else 0.0
    return Comparison(diff, math.nan, math.nan, xa.size, xb.size, "ranks",
                      p_less=float(np.mean(u_all >= u)), p_greater=float(np.mean(u_all <= u)))


def _significant(p: float) -> bool:
    return p <= (1 - LEVEL) / 2


def less(c: Comparison) -> str:
    """Does ``a < b`` hold (significant at the module's level)?"""
    if not c.resolvable:
        return UNRESOLVED
    if c.method == "ranks":
        return (HOLDS if _significant(c.p_less) else
                CONTRADICTS if _significant(c.p_greater) else UNRESOLVED)
    if c.hi < 0:
        return HOLDS
    return CONTRADICTS if c.lo > 0 else UNRESOLVED


def greater(c: Comparison) -> str:
    """Does ``a > b`` hold?"""
    flipped = {HOLDS: CONTRADICTS, CONTRADICTS: HOLDS}
    return flipped.get(less(c), UNRESOLVED)


def within(c: Comparison, margin: float) -> str:
    """Are a and b the same within ``margin`` (an equivalence test: the whole interval
    inside +-margin holds, wholly outside contradicts)? A rank comparison ("never" on a
    side) contradicts when it is significant and its medians differ by more than the
    margin, else is unresolved: no interval bounds it."""
    if not c.resolvable:
        return UNRESOLVED
    if c.method == "ranks":
        apart = _significant(min(c.p_less, c.p_greater)) and abs(c.diff) > margin
        return CONTRADICTS if apart else UNRESOLVED
    if -margin < c.lo and c.hi < margin:
        return HOLDS
    return CONTRADICTS if c.lo > margin or c.hi < -margin else UNRESOLVED


def spread_text(values: Sequence[float], fmt: str = ".0f") -> str:
    """'median (min-max), n=N' of a condition's values, 'never' for math.inf."""
    xs = [float(v) for v in values]
    if not xs:
        return "n/a"
    med = float(np.median(xs))
    return f"{_num(med, fmt)} ({_num(min(xs), fmt)}-{_num(max(xs), fmt)}), n={len(xs)}"
