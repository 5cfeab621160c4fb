"""Run a list of runs once each, resumably, on any executor; write results as they finish.

Layout of an output folder::

    DIR/runs/<run_id>/run.json         the run's world, controller, settings and seed
    DIR/runs/<run_id>/timeseries.csv   its time series
    DIR/runs/<run_id>/robots.csv       per robot: final state, distance moved, contacts, ...
    DIR/runs/<run_id>/coverage.npz     the final coverage raster and the target mask
    DIR/runs/<run_id>/summary.json     its summary: written last, it marks the run as done
    DIR/runs/<run_id>/error.txt        instead, when the run raised (message and traceback)
    DIR/runs/<run_id>/claim.json       while a sweep process runs it (see claims.py)
    DIR/results.csv                    one row per run (rewritten after each completion)
    DIR/aggregate/                     per condition over seeds, by run_sweep: conditions.csv,
                                       curves.csv, coverage.png (see aggregate.py)

Every file is written atomically. Running the same sweep again skips runs that are done (and,
unless ``retry_failed``, runs that failed), so an interrupted sweep resumes where it stopped
without redoing or losing a finished run. Two sweeps may share an output folder: each claims
the runs it is about to run, and leaves the runs another live process has claimed to it.
"""

from __future__ import annotations

import concurrent.futures as cf
import json
import shutil
import sys
import traceback
from collections import Counter
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures.process import BrokenProcessPool
from contextlib import nullcontext
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from swarmsim.errors import ControllerError, interrupt_within
from swarmsim.experiments import claims
from swarmsim.experiments.executors import check_workers, open_pool
from swarmsim.experiments.spec import RunSpec, unique_runs
from swarmsim.experiments.table import read_table, run_row, write_table
from swarmsim.results.output import write_csv, write_json, write_npz
from swarmsim.results.runfolder import NewFolders, removed_if_left_empty

DONE, FAILED = "done", "failed"


def run_cost(summary: Mapping[str, Any]) -> float:
    """A finished run's cost, s: its CPU time in the tick loop, or for a run made before
    summaries recorded that, its wall time."""
    return float(summary.get("cpu_seconds") or summary.get("wall_seconds") or 0.0)


class SweepError(RuntimeError):
    """The sweep itself broke (e.g. a worker process died); finished runs are saved."""


def execute_run(run: RunSpec) -> dict[str, Any]:
    """Run one simulation (in a worker). Never raises for a bad run: returns its error."""
    try:
        from swarmsim.engine.sim import Simulation

        sim = Simulation(run.world_ref or run.world, controller=run.controller, seed=run.seed,
                         settings=dict(run.settings))
        sim.summary_sources.add("sweep", lambda: {"run_id": run.run_id})
        result = sim.run(progress=False)
        return {"summary": result.summary, "timeseries": result.timeseries,
                "robots": result.robots, "coverage": sim.grid.arrays(sim.positions)}
    except Exception as exc:  # a failing run is recorded, the sweep goes on
        if interrupt_within(exc):  # Ctrl-C inside compiled code: not the run's failure
            raise KeyboardInterrupt from exc
        if isinstance(exc, ControllerError):  # its line, and the controller's own frames
            return {"error": str(exc), "traceback": exc.user_traceback()}
        return {"error": one_line(exc), "traceback": traceback.format_exc()}


def one_line(exc: BaseException) -> str:
    text = " ".join(str(exc).split())
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


class RunStore:
    """The per-run folders of an output directory."""

    def __init__(self, runs_dir: str | Path):
        self.dir = Path(runs_dir)

    def path(self, run_id: str) -> Path:
        return self.dir / run_id

    def status(self, run_id: str) -> str | None:
        p = self.path(run_id)
        if (p / "summary.json").is_file():
            return DONE
        if (p / "error.txt").is_file():
            return FAILED
        return None

    def summary(self, run_id: str) -> dict[str, Any]:
        return json.loads((self.path(run_id) / "summary.json").read_text())

    def error(self, run_id: str) -> str:
        text = (self.path(run_id) / "error.txt").read_text()
        return text.splitlines()[0] if text else "error"

    def timeseries(self, run_id: str) -> list[dict[str, str]]:
        return read_table(self.path(run_id) / "timeseries.csv")

    def write_result(self, run: RunSpec, summary: dict, timeseries: Sequence[dict],
                     robots: Sequence[dict] = (),
                     coverage: Mapping[str, Any] | None = None) -> None:
        p = self.path(run.run_id)
        write_json(p / "run.json", run.to_json())
        write_csv(p / "timeseries.csv", timeseries)
        if robots:
            write_csv(p / "robots.csv", robots)
        if coverage:
            write_npz(p / "coverage.npz", coverage)
        write_json(p / "summary.json", summary)  # last: marks the run done
        (p / "error.txt").unlink(missing_ok=True)

    def write_error(self, run: RunSpec, message: str, details: str = "") -> None:
        from swarmsim.results.output import atomic_write_text

        p = self.path(run.run_id)
        write_json(p / "run.json", run.to_json())
        atomic_write_text(p / "error.txt", message + "\n\n" + details)

    def clear(self, run_id: str) -> None:
        shutil.rmtree(self.path(run_id), ignore_errors=True)


@dataclass
class SweepReport:
    """What a sweep did.

    Attributes:
        total: runs in the sweep.
        skipped: runs already done (or failed, without retry) before this call.
        ran: runs executed now.
        failed: runs whose latest attempt failed (now or before).
        table: path of the results table.
        versions: finished runs per code version (more than one: the table mixes code).
        busy: runs not run now because another live process has claimed them.
        done: runs with a result.
    """

    total: int
    skipped: int
    ran: int
    failed: int
    table: Path
    versions: Mapping[str, int] = field(default_factory=dict)
    busy: int = 0
    done: int = 0
    others: int = 0

    def line(self) -> str:
        text = (f"{self.total} runs: {self.done} done ({self.ran} run now, {self.skipped} already "
                f"there), {self.failed} failed -> {self.table}")
        if self.busy:
            text += (f"\n{self.busy} runs are claimed by another process (runs/<id>/"
                     f"{claims.CLAIM_FILE}) and were left to it: run again once it has ended")
        if len(self.versions) > 1:
            listed = ", ".join(f"{v} ({n})" for v, n in sorted(self.versions.items()))
            text += f"\nwarning: the table mixes runs made by different code: {listed}"
        if self.others:
            text += (f"\nnote: {self.others} other runs in the runs folder (another spec's?) "
                     "are not in this table: it holds the runs of this command")
        return text


class Sweep:
    """A list of runs bound to an output folder.

    Args:
        runs: the runs (repeats of the same run id are run once).
        out_dir: output folder (``runs/`` and ``results.csv`` inside unless given).
        runs_dir: where run folders live (share one among sweeps to share runs).
        table_path: where the results table goes.
    """

    def __init__(self, runs: Sequence[RunSpec], out_dir: str | Path,
                 runs_dir: str | Path | None = None, table_path: str | Path | None = None):
        self.runs = unique_runs(runs)
        self.out = Path(out_dir)
        self.store = RunStore(runs_dir or self.out / "runs")
        self.table_path = Path(table_path or self.out / "results.csv")
        self._results: dict[str, tuple[dict[str, Any] | None, str | None]] = {}

    def pending(self, retry_failed: bool = False) -> list[RunSpec]:
        """Runs still to do: not done, and not failed unless ``retry_failed``."""
        todo = []
        for run in self.runs:
            status = self.store.status(run.run_id)
            if status is None or (status == FAILED and retry_failed):
                todo.append(run)
        return todo

    def row(self, run: RunSpec) -> dict[str, Any] | None:
        """The table row of a finished (or failed) run, None if it has not run yet. Its
        parameters are ``run``'s own, also when another run of the same id (the same run by
        construction, see spec.run_id) made the result."""
        rid = run.run_id
        if rid not in self._results:
            status = self.store.status(rid)
            if status == DONE:
                self._results[rid] = (self.store.summary(rid), None)
            elif status == FAILED:
                self._results[rid] = (None, self.store.error(rid))
            else:
                return None
        summary, error = self._results[rid]
        return run_row(run, summary, error)

    def write_table(self) -> None:
        rows = [r for r in (self.row(run) for run in self.runs) if r is not None]
        lead = list(run_row(self.runs[0])) if self.runs else []
        write_table(self.table_path, rows, lead)

    def _finished_rows(self) -> list[dict[str, Any]]:
        """Table rows of the runs that finished without error."""
        rows = (self.row(run) for run in self.runs)
        return [r for r in rows if r is not None and not r.get("error")]

    def code_versions(self) -> Counter[str]:
        """How many finished runs each code version made (see swarmsim.results.provenance)."""
        return Counter(str(r.get("code_version") or "unrecorded") for r in self._finished_rows())

    def run_seconds(self) -> float:
        """Seconds the finished runs took, summed (each run's ``cpu_seconds``, or its
        ``wall_seconds`` if it predates them: report.run_cost)."""
        return sum(run_cost(r) for r in self._finished_rows())

    def done_count(self) -> int:
        """Runs that finished without error."""
        return len(self._finished_rows())

    def failed_count(self) -> int:
        return sum(self.store.status(r.run_id) == FAILED for r in self.runs)

    def record(self, run: RunSpec, outcome: dict[str, Any]) -> str:
        """Write a run's outcome; returns DONE or FAILED."""
        self._results.pop(run.run_id, None)
        if "summary" in outcome:
            self.store.write_result(run, outcome["summary"], outcome["timeseries"],
                                    outcome.get("robots", ()), outcome.get("coverage"))
            status = DONE
        else:
            self.store.write_error(run, outcome["error"], outcome.get("traceback", ""))
            status = FAILED
        self.write_table()
        return status

    def run(self, workers: int | None = None, scheduler: Any = None,
            retry_failed: bool = False, progress: bool = True,
            on_result: Callable[[RunSpec, str], None] | None = None) -> SweepReport:
        """Run every pending run once; see :func:`run_sweep`. The executor is opened (a bad
        worker count or scheduler refused) before anything is written.

        A sweep that ends early (interrupted, a worker died) leaves nothing behind but its
        finished runs: the folders it made (the output folder, ``runs/``, ``runs/<id>/``) are
        removed again as far as they are empty once the claims of the runs in flight are
        dropped; a folder that existed before is kept, as is any that holds a file."""
        check_workers(workers)
        todo = self.pending(retry_failed)
        tally: Counter[str] = Counter()
        pool = open_pool(workers, scheduler, tasks=len(todo)) if todo else nullcontext()
        in_flight: dict[cf.Future, RunSpec] = {}
        with removed_if_left_empty() as made:
            try:
                with pool as opened:
                    made.make(self.out)
                    if todo:
                        self._execute(opened, todo, in_flight, progress, on_result, tally, made)
                    self.write_table()  # after each run too (record): here for a sweep with none
            finally:  # interrupted: the pool has stopped its workers; only now free their runs
                for run in in_flight.values():
                    claims.release(self.store.path(run.run_id))
        return SweepReport(len(self.runs), len(self.runs) - len(todo) + tally["elsewhere"],
                           tally["ran"], self.failed_count(), self.table_path,
                           self.code_versions(), busy=tally["busy"],
                           done=self.done_count(), others=self.other_runs())

    def other_runs(self) -> int:
        """Finished or failed runs in the store that are not this sweep's."""
        mine = {run.run_id for run in self.runs}
        return sum(1 for p in self.store.dir.glob("*") if p.name not in mine
                   and ((p / "summary.json").is_file() or (p / "error.txt").is_file()))

    def _execute(self, pool, todo: list[RunSpec], in_flight: dict[cf.Future, RunSpec],
                 progress: bool, on_result, tally: Counter[str], made: NewFolders) -> None:
        """Run ``todo`` on ``pool``, claiming each run just before it is submitted (see
        claims.py) and keeping one run per worker in flight, so that other processes can share
        the rest. ``in_flight`` holds the runs submitted and not finished (the caller frees
        their claims once the pool has stopped); ``made`` remembers the run folders made."""
        from tqdm import tqdm

        bar = tqdm(total=len(todo), unit="run", desc="sweep", file=sys.stderr,
                   disable=not progress, dynamic_ncols=True)
        queue = iter(todo)
        try:
            window = pool.window(len(todo))
            self._submit_more(pool, queue, in_flight, window, tally, bar, made)
            while in_flight:
                future = pool.next_completed(in_flight)
                run = in_flight.pop(future)
                self._finish(run, _outcome(future), tally, bar, on_result)
                self._submit_more(pool, queue, in_flight, window, tally, bar, made)
        finally:
            bar.close()

    def _submit_more(self, pool, queue, in_flight: dict, window: int, tally: Counter[str],
                     bar, made: NewFolders) -> None:
        """Claim and submit runs until ``window`` are in flight; runs another process has
        claimed, or has finished meanwhile, are passed over. The run folders made for the
        claims are remembered in ``made``."""
        while len(in_flight) < window:
            run = next(queue, None)
            if run is None:
                return
            path = made.make(self.store.path(run.run_id))
            if not claims.claim(path):
                tally["busy"] += 1
            elif self.store.status(run.run_id) == DONE:  # another process finished it
                claims.release(path)
                tally["elsewhere"] += 1
            else:
                in_flight[pool.submit(execute_run, run)] = run
                continue
            bar.update(1)
            bar.set_postfix_str(f"{tally['busy'] + tally['elsewhere']} left to another process")

    def _finish(self, run: RunSpec, outcome: dict[str, Any], tally: Counter[str], bar,
                on_result) -> None:
        status = self.record(run, outcome)
        claims.release(self.store.path(run.run_id))
        tally["ran"] += 1
        tally["failed"] += status == FAILED
        bar.update(1)
        if tally["failed"]:
            bar.set_postfix_str(f"{tally['failed']} failed")
        if on_result is not None:
            on_result(run, status)


def _outcome(future: cf.Future) -> dict[str, Any]:
    """The worker's result, or an error outcome when the executor itself failed."""
    if future.cancelled():
        raise KeyboardInterrupt
    exc = future.exception()
    if exc is None:
        return future.result()
    if not isinstance(exc, Exception):  # KeyboardInterrupt / SystemExit in a worker
        raise KeyboardInterrupt
    if isinstance(exc, BrokenProcessPool):  # the pool broke, not this run
        raise SweepError(f"a worker process died ({one_line(exc)}); finished runs are saved, "
                           "run again to resume") from exc
    details = "".join(traceback.format_exception(exc))
    return {"error": one_line(exc), "traceback": details}
