"""Where runs execute: in this process, in local worker processes, or on a Dask cluster.

All three are ``concurrent.futures`` executors (``submit`` returns a Future; results are
collected with :func:`concurrent.futures.wait`), so the sweep runner has one code path:

* ``workers == 1``: :class:`InProcessExecutor`, runs each task when its result is collected,
  in submission order (easy to debug, no pickling).
* ``workers > 1`` (default ``os.cpu_count()``): ``ProcessPoolExecutor`` with fresh interpreter
  processes ("forkserver", else "spawn"): no state leaks from the parent into the runs.
* ``scheduler = "tcp://host:8786"`` (or a ``dask.distributed`` Client / cluster object): the
  Client's own ``concurrent.futures`` executor (``Client.get_executor``). Needs the optional
  extra: ``pip install 'swarmsim[dask]'``; the workers need swarmsim installed too.
"""

from __future__ import annotations

import concurrent.futures as cf
import multiprocessing
import os
import socket
from collections.abc import Callable, Collection
from contextlib import contextmanager
from typing import Any

from swarmsim.errors import ConfigError
from swarmsim.limits import MAX_WORKERS_PER_CPU, check_count


class InProcessExecutor(cf.Executor):
    """Runs tasks in this process, lazily: a task runs when :meth:`as_completed` reaches it.

    Lazy so that a sweep writes each run's result before the next run starts (resume works
    the same as with worker processes).
    """

    def __init__(self) -> None:
        self._pending: list[tuple[cf.Future, Callable, tuple, dict]] = []
        self._shutdown = False

    def submit(self, fn, /, *args, **kwargs) -> cf.Future:
        if self._shutdown:
            raise RuntimeError("cannot schedule new futures after shutdown")
        future: cf.Future = cf.Future()
        self._pending.append((future, fn, args, kwargs))
        return future

    def run_pending(self, future: cf.Future) -> None:
        """Run the task of ``future`` now (if not already done or cancelled)."""
        for i, (f, fn, args, kwargs) in enumerate(self._pending):
            if f is future:
                del self._pending[i]
                if f.set_running_or_notify_cancel():
                    try:
                        f.set_result(fn(*args, **kwargs))
                    except BaseException as exc:
                        f.set_exception(exc)
                        if not isinstance(exc, Exception):
                            raise
                return

    def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
        self._shutdown = True
        if cancel_futures:
            for f, *_ in self._pending:
                f.cancel()
            self._pending.clear()


class Pool:
    """A concurrent.futures executor plus how to wait on its futures."""

    def __init__(self, executor: cf.Executor, kind: str, workers: int | None,
                 close: Callable[[], None] | None = None):
        self.executor = executor
        self.kind = kind
        self.workers = workers
        self._close = close

    def submit(self, fn: Callable, *args: Any) -> cf.Future:
        return self.executor.submit(fn, *args)

    def window(self, tasks: int) -> int:
        """How many tasks to keep submitted at once: one per local worker (so that a task is
        claimed only when a worker is free for it), every task on a Dask cluster."""
        return tasks if self.kind == "dask" else max(1, self.workers or 1)

    def next_completed(self, futures: Collection[cf.Future]) -> cf.Future:
        """Wait for one of ``futures`` to finish and return it (in process: run the first)."""
        if isinstance(self.executor, InProcessExecutor):
            first = next(iter(futures))
            self.executor.run_pending(first)
            return first
        done, _ = cf.wait(futures, return_when=cf.FIRST_COMPLETED)
        return next(f for f in futures if f in done)  # submission order among the finished

    def shutdown(self, cancel: bool) -> None:
        """Wait for running tasks, or (``cancel``) drop pending ones and stop workers now."""
        if self.kind == "dask":
            self.executor.shutdown(wait=not cancel)
        else:
            # Runs in flight are lost either way: stop the workers rather than let them finish
            # the tasks already queued to them (Python < 3.14 has no terminate_workers()).
            procs = list((getattr(self.executor, "_processes", None) or {}).values())
            self.executor.shutdown(wait=not cancel, cancel_futures=cancel)
            for proc in procs if cancel else ():
                proc.terminate()
        if self._close is not None:
            self._close()

    def describe(self) -> str:
        if self.kind == "dask":
            return "dask cluster"
        return "in-process" if self.kind == "inprocess" else f"{self.workers} worker processes"


def _mp_context():
    methods = multiprocessing.get_all_start_methods()
    return multiprocessing.get_context("forkserver" if "forkserver" in methods else "spawn")


CONNECT_TIMEOUT = 5.0
"""Seconds the probe of a scheduler address waits for a TCP connection (see probe_scheduler)."""


def probe_scheduler(address: str, timeout: float = CONNECT_TIMEOUT) -> None:
    """Refuse a ``tcp://host:port`` scheduler address that cannot be reached, at once: a TCP
    connection is tried (for at most ``timeout`` seconds) before Dask's Client, which retries
    for its whole timeout. Other schemes (tls://, ucx://, ...) are left to Dask."""
    from urllib.parse import urlsplit

    parts = urlsplit(address if "://" in address else f"tcp://{address}")
    if parts.scheme != "tcp":
        return
    try:
        host, port = parts.hostname, parts.port
    except ValueError:
        raise ConfigError(f"{address!r} has no valid port (expected tcp://host:port)",
                          key="--scheduler") from None
    if not host or port is None:
        raise ConfigError(f"expected tcp://host:port, got {address!r}", key="--scheduler")
    try:
        with socket.create_connection((host, port), timeout=timeout):
            pass
    except socket.gaierror:
        raise ConfigError(f"cannot connect to the Dask scheduler {address!r}: unknown host "
                          f"{host!r}", key="--scheduler") from None
    except TimeoutError:
        raise ConfigError(f"cannot connect to the Dask scheduler {address!r}: no answer within "
                          f"{timeout:g} s", key="--scheduler") from None
    except OSError as exc:
        reason = exc.strerror or type(exc).__name__
        raise ConfigError(f"cannot connect to the Dask scheduler {address!r}: {reason.lower()}"
                          f" (is a scheduler running there? start one with 'dask scheduler')",
                          key="--scheduler") from None


def dask_client(scheduler: Any):
    """A dask.distributed Client for an address, a Client or a cluster object; an address
    that cannot be reached is refused at once (probe_scheduler)."""
    try:
        from dask.distributed import Client
    except ImportError:
        raise ConfigError("running on a Dask cluster needs dask.distributed: "
                          "pip install 'swarmsim[dask]' (or 'dask[distributed]')",
                          key="--scheduler") from None
    if isinstance(scheduler, Client):
        return scheduler, False
    if isinstance(scheduler, str):
        probe_scheduler(scheduler)
    try:
        return Client(scheduler, timeout="20s"), True
    except (OSError, TimeoutError, ValueError) as exc:
        raise ConfigError(f"cannot connect to the Dask scheduler {scheduler!r}: {exc}",
                          key="--scheduler") from None


def max_workers() -> int:
    """The most local worker processes a sweep starts: MAX_WORKERS_PER_CPU per CPU."""
    return MAX_WORKERS_PER_CPU * (os.cpu_count() or 1)


def check_workers(workers: int | None) -> None:
    """Refuse a worker count below 1 or above max_workers() (None = one per CPU)."""
    if workers is not None:
        check_count("--workers", workers, max_workers(),
                    f"{MAX_WORKERS_PER_CPU} processes per CPU on this machine")


@contextmanager
def open_pool(workers: int | None = None, scheduler: Any = None, tasks: int | None = None):
    """Open an executor: Dask when ``scheduler`` is given, else ``workers`` local processes.

    Args:
        workers: local worker processes (None = os.cpu_count(); 1 = in this process).
        scheduler: Dask scheduler address (str), Client or cluster; overrides ``workers``.
        tasks: number of tasks to come (no more processes than tasks are started).

    Yields a :class:`Pool`; on an exception (e.g. KeyboardInterrupt) pending tasks are
    cancelled.
    """
    check_workers(workers)
    if scheduler is not None:
        client, owned = dask_client(scheduler)
        pool = Pool(client.get_executor(pure=False), "dask", None,
                    close=client.close if owned else None)
    else:
        n = workers or os.cpu_count() or 1
        if tasks is not None:
            n = max(1, min(n, tasks))
        if n == 1:
            pool = Pool(InProcessExecutor(), "inprocess", 1)
        else:
            pool = Pool(cf.ProcessPoolExecutor(n, mp_context=_mp_context()), "processes", n)
    try:
        yield pool
    except BaseException:
        pool.shutdown(cancel=True)
        raise
    pool.shutdown(cancel=False)
