"""``run_sweep``: run a sweep's pending runs, then write its aggregate.

The runs themselves are :class:`swarmsim.experiments.runner.Sweep`'s; the aggregate over seeds
is :mod:`swarmsim.experiments.aggregate`'s.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from swarmsim.experiments.aggregate import AGGREGATE_DIR, write_aggregate
from swarmsim.experiments.runner import Sweep, SweepReport
from swarmsim.experiments.spec import RunSpec


def run_sweep(runs: Sequence[RunSpec], out_dir: str | Path, *, workers: int | None = None,
              scheduler: Any = None, retry_failed: bool = False, progress: bool = True,
              on_result: Callable[[RunSpec, str], None] | None = None,
              runs_dir: str | Path | None = None,
              table_path: str | Path | None = None) -> SweepReport:
    """Run every run not yet done, writing each one as it finishes, and the table.

    Args:
        runs: the runs (e.g. ``load_spec(path).runs()``).
        out_dir: output folder.
        workers: local worker processes (default os.cpu_count(); 1 = in this process).
        scheduler: a Dask scheduler address (or Client/cluster): run there instead.
        retry_failed: run again the runs that failed before.
        progress: tqdm progress bar on stderr.
        on_result: called as ``on_result(run, "done" | "failed")`` after each run is written.
        runs_dir, table_path: see :class:`Sweep`.

    Then it writes ``out_dir/aggregate/`` from every finished run of ``runs`` (see
    :mod:`.aggregate`), one condition per grid point of ``runs`` (a run whose id several
    grid points share, made once, counts in each). A KeyboardInterrupt (also raised from ``on_result``) cancels what has
    not finished; what has finished is on disk and the next call resumes (and aggregates).
    """
    sweep = Sweep(runs, out_dir, runs_dir, table_path)
    report = sweep.run(workers, scheduler, retry_failed, progress, on_result)
    write_aggregate(sweep.store, runs, sweep.out / AGGREGATE_DIR)
    return report


__all__ = ["run_sweep"]
