"""What the engine's checks of a controller's actions cost, as a share of a run, in one run.

Times every call of the checks (swarmsim.engine.actioncheck: the forms of a batch controller's
ChunkActions, a list of Actions turned into columns, broadcasts converted; the ids written
and status codes checked by swarmsim.engine.tickrows.sign_rows) during a run, and prints their
seconds against the run's. The values checked inside the compiled passes that write the
actions (finite velocities, ranges not negative) cost a compare per robot and are not
counted. The timer's own cost (the wrapper, two perf_counter calls) is measured in the run,
by the same wrapper around a function that does nothing, called right before each check, and
taken off.

    python bench/bench_action_checks.py                       # K seed 0 (GGC), to the end
    python bench/bench_action_checks.py --controller dispersion --ticks 3000

A per-robot controller's Actions and broadcasts were converted before the checks too
(ChunkActions.of and sim.rows_to_array at e434d3b, copied below): each call is paired with
those conversions of the same inputs, the two taking turns at going first, and both totals
are printed.
"""

from __future__ import annotations

import argparse
import itertools
import time
from collections import Counter
from collections.abc import Callable
from typing import Any

import numpy as np

from swarmsim.controller import ChunkActions
from swarmsim.engine import actioncheck, sim, tickrows
from swarmsim.engine.sim import Simulation

SPENT: Counter[str] = Counter()
CALLS: Counter[str] = Counter()


def timed(name: str, fn: Callable[..., Any]) -> Callable[..., Any]:
    """``fn``, adding its seconds to SPENT[name]."""
    clock = time.perf_counter

    def wrapper(*args: Any, **kwargs: Any) -> Any:
        began = clock()
        try:
            return fn(*args, **kwargs)
        finally:
            SPENT[name] += clock() - began
            CALLS[name] += 1

    return wrapper


def columns_before(actions: list) -> ChunkActions:
    """ChunkActions.of as it was at e434d3b (no checks)."""
    velocities = np.array([a.velocity for a in actions], dtype=float).reshape(-1, 2)
    listen = np.array([np.nan if a.listen is None else a.listen for a in actions],
                      dtype=float)
    return ChunkActions(velocities, listen,
                        {k: a.message for k, a in enumerate(actions) if a.message is not None},
                        {k: a for k, a in enumerate(actions) if a.sleep})


def rows_before(rows: list[tuple], dtype: np.dtype) -> np.ndarray:
    """sim.rows_to_array as it was at e434d3b (no checks)."""
    out = np.empty(len(rows), dtype=dtype)
    for name, column in zip(dtype.names, zip(*rows, strict=True), strict=True):
        field = dtype[name]
        if field.shape and isinstance(column[0], np.ndarray):
            out[name] = np.concatenate(column).reshape(len(column), *field.shape)
        else:
            out[name] = np.asarray(column, dtype=field.base)
    return out


def paired(fn: Callable[..., Any], before: Callable[..., Any]) -> Callable[..., Any]:
    """``fn`` and ``before`` on the same inputs, taking turns at going first (the second
    finds the inputs in the cache)."""
    turn = itertools.cycle((True, False))

    def wrapper(*args: Any) -> Any:
        if next(turn):
            out = fn(*args)
            before(*args)
        else:
            before(*args)
            out = fn(*args)
        return out

    return wrapper


def with_null(fn: Callable[..., Any]) -> Callable[..., Any]:
    """``fn``, after a timed call of a function that does nothing (the timer's cost, there)."""
    null = timed("timer", lambda *args: None)

    def wrapper(*args: Any, **kwargs: Any) -> Any:
        null(*args)
        return fn(*args, **kwargs)

    return wrapper


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--world", default="K")
    ap.add_argument("--controller", default=None, help="default: the world's")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--ticks", type=int, default=None, help="stop here (default: the end)")
    args = ap.parse_args()
    sim.check_columns = with_null(timed("check_columns", actioncheck.check_columns))
    sim.columns_of = paired(timed("columns_of", actioncheck.columns_of),
                            timed("columns_of before", lambda actions, robots:
                                  columns_before(actions)))
    array = timed("Broadcasts.array", actioncheck.Broadcasts.array)
    as_before = timed("Broadcasts.array before", lambda broadcasts, rows:
                      rows_before(rows, broadcasts.dtype))
    actioncheck.Broadcasts.array = paired(array, as_before)
    tickrows.sign_rows = with_null(timed("sign_rows", tickrows.sign_rows))
    run = Simulation(args.world, controller=args.controller, seed=args.seed,
                     max_ticks=args.ticks)
    began = time.perf_counter()
    run.run()
    total = time.perf_counter() - began
    checks = SPENT["check_columns"] + SPENT["sign_rows"] - SPENT["timer"]
    print(f"{args.world} {run.controller_name} seed {args.seed}: {run.tick} ticks, "
          f"{total:.2f} s; decide phase {run.phase_seconds['decide']:.2f} s")
    names = ("check_columns", "columns_of", "columns_of before", "Broadcasts.array",
             "Broadcasts.array before", "sign_rows", "timer")
    for name in names:
        if CALLS[name]:
            print(f"  {name:24} {CALLS[name]:7} calls {SPENT[name]:8.4f} s "
                  f"({1e6 * SPENT[name] / CALLS[name]:6.2f} us a call)")
    print(f"  checks only (check_columns + sign_rows - timer): {checks:.4f} s = "
          f"{100 * checks / total:.3f} % of the run")
    for name in ("columns_of", "Broadcasts.array"):
        if CALLS[name]:
            extra = SPENT[name] - SPENT[f"{name} before"]
            print(f"  {name} now / before: {SPENT[name] / SPENT[f'{name} before']:.2f} "
                  f"({extra:+.3f} s = {100 * extra / total:+.2f} % of the run)")


if __name__ == "__main__":
    main()
