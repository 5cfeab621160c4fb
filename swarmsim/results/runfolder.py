"""A run's output folder: made only for a run that starts, removed again if the run ends early
and leaves it empty, locked while the run uses it, and holding one run's files.

- :func:`removed_if_left_empty` yields a :class:`NewFolders` that makes folders and
  remembers which it created (parents included); if the block ends with any exception
  (a refused option, a controller's error, Ctrl-C), the folders it created are removed
  again, deepest first, as far as they are empty. A folder that existed before is never
  removed, nor one that holds anything.
- :func:`locked` holds ``LOCK_FILE`` (an ``fcntl.flock`` on a file holding the run's pid) in
  the folder while the run writes there; a second run into a locked folder is refused with a
  ConfigError naming the folder and the other run's pid. The lock goes with the process (a
  killed run leaves no stale lock; its file is reused). Where there is no ``fcntl``
  (Windows), or the file system has no ``flock``, there is no lock.
- :func:`clear_run` removes the files a run writes (``RUN_FILES``, and the hidden temporary
  files of their atomic writes that a killed writer left), and only those: a user's own files
  in the folder are kept.
"""

from __future__ import annotations

import contextlib
import os
import socket
from collections.abc import Iterator
from pathlib import Path

from swarmsim.errors import ConfigError
from swarmsim.results.trajectories import FILE_NAME as TRAJECTORIES_FILE

RUN_FILES = ("summary.json", "timeseries.csv", "robots.csv", "coverage.npz", "coverage.png",
             TRAJECTORIES_FILE)
"""The files ``swarmsim run --out`` writes in its folder (docs/outputs.md)."""

LOCK_FILE = ".swarmsim-run.lock"
"""Held by the run writing into the folder (see :func:`locked`); removed when it ends."""


class NewFolders:
    """Makes folders and remembers the ones it created, so that they can be removed again."""

    def __init__(self) -> None:
        self.created: list[Path] = []
        """Folders this object created, in the order created (parents first)."""

    def make(self, folder: str | Path, attempts: int = 3) -> Path:
        """Create ``folder`` and the parents it lacks (OSError as ``Path.mkdir``); remember
        those created here (not one another process made meanwhile). Returns the folder.
        ``attempts``: tries, when a parent is removed meanwhile (another run's clean-up)."""
        folder = Path(folder)
        for path in reversed((folder, *folder.absolute().parents)):
            if path.is_dir():
                continue
            try:
                path.mkdir()
            except FileExistsError:
                continue  # made by someone else meanwhile (or a file: the next mkdir says so)
            except FileNotFoundError:
                if attempts <= 1:
                    raise
                return self.make(folder, attempts - 1)
            self.created.append(path)
        return folder

    def remove_empty(self) -> list[Path]:
        """Remove the folders created here that are empty, deepest first (a folder emptied by
        removing its empty children goes too). Returns those removed."""
        removed = []
        for path in reversed(self.created):
            with contextlib.suppress(OSError):  # not empty, or gone
                path.rmdir()
                removed.append(path)
        self.created = [p for p in self.created if p not in removed]
        return removed


@contextlib.contextmanager
def removed_if_left_empty() -> Iterator[NewFolders]:
    """Yield a :class:`NewFolders`; if the block raises anything (KeyboardInterrupt included),
    remove the folders it created that are empty, then re-raise."""
    made = NewFolders()
    try:
        yield made
    except BaseException:
        made.remove_empty()
        raise


def clear_run(folder: str | Path) -> None:
    """Remove from ``folder`` the files a run writes (RUN_FILES) and the temporary files of
    their atomic writes (``.NAME.*.tmp``, see swarmsim.results.output); nothing else."""
    folder = Path(folder)
    for name in RUN_FILES:
        (folder / name).unlink(missing_ok=True)
        for tmp in folder.glob(f".{name}.*.tmp"):
            tmp.unlink(missing_ok=True)


def holder(folder: str | Path) -> str | None:
    """Who holds the lock of ``folder`` (``"pid P on HOST"``), None if no run holds it.
    Only reads: a run started just after may still take it."""
    path = Path(folder) / LOCK_FILE
    try:
        fd = os.open(path, os.O_RDONLY)
    except OSError:
        return None
    try:
        return _holder_of(fd) if _is_locked(fd) else None
    finally:
        os.close(fd)


def check_free(folder: str | Path, key: str = "--out") -> None:
    """Refuse (ConfigError) a folder another run holds now: the quick check before a run is
    built; :func:`locked` is the one that counts."""
    who = holder(folder)
    if who is not None:
        raise _in_use(folder, who, key)


@contextlib.contextmanager
def locked(folder: str | Path, key: str = "--out") -> Iterator[None]:
    """Hold ``folder``'s lock (it must exist) while the block runs; ConfigError naming the
    folder and the holder's pid if another run holds it. The lock file is removed at the end."""
    try:
        import fcntl  # noqa: F401
    except ImportError:
        yield
        return
    path = Path(folder) / LOCK_FILE
    fd = _acquire(path, folder, key)
    try:
        yield
    finally:
        path.unlink(missing_ok=True)  # while still held: no other run has it
        os.close(fd)


def _acquire(path: Path, folder: str | Path, key: str) -> int:
    """Open and lock ``path`` (creating it), write this process's pid into it; the fd."""
    import fcntl

    while True:
        try:
            fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
        except OSError as exc:
            raise ConfigError(f"cannot write in the folder {str(folder)!r} ({exc.strerror})",
                              key=key) from None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            who = _holder_of(fd)
            os.close(fd)
            raise _in_use(folder, who, key) from None
        except OSError:  # a file system without flock (some network ones): no lock there
            break
        if _same_file(fd, path):
            break
        os.close(fd)  # the holder removed the file between our open and lock: take the next
    os.ftruncate(fd, 0)
    os.write(fd, f"pid {os.getpid()} on {socket.gethostname()}\n".encode())
    return fd


def _same_file(fd: int, path: Path) -> bool:
    try:
        return os.path.samestat(os.fstat(fd), os.stat(path))
    except FileNotFoundError:
        return False


def _is_locked(fd: int) -> bool:
    try:
        import fcntl
    except ImportError:
        return False
    try:
        fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
    except BlockingIOError:
        return True
    except OSError:  # no flock on this file system
        return False
    fcntl.flock(fd, fcntl.LOCK_UN)
    return False


def _holder_of(fd: int) -> str:
    text = os.pread(fd, 200, 0).decode(errors="replace").strip()
    return text or "pid unknown"


def _in_use(folder: str | Path, who: str, key: str) -> ConfigError:
    return ConfigError(f"the folder {str(folder)!r} is in use by another run ({who}); wait for "
                       "it to end or choose another folder", key=key)
