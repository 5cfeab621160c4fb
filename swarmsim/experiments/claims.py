"""Claim files: which process is running a run, so that two sweeps sharing a store (two
``reproduce`` processes on overlapping figures, say) never simulate the same run twice.

A claim is ``runs/<run_id>/claim.json`` holding the claiming process's host, pid and start
time, created atomically (one process wins). A claim whose process is gone (same host, pid no
longer alive: a killed sweep) is stale and taken over. A claim made on another host cannot be
checked from here and is respected; delete the file by hand if that sweep is dead.
"""

from __future__ import annotations

import json
import os
import socket
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

CLAIM_FILE = "claim.json"
TAKEOVER_LOCK = ".takeover.lock"


def _process_key(pid: int) -> str | None:
    """Boot id and start time of a process (Linux /proc), so that a pid reused after a
    restart is not taken for the process that made a claim; None where /proc is missing or
    the process is gone."""
    try:
        boot = Path("/proc/sys/kernel/random/boot_id").read_text().strip()
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    return f"{boot}:{stat.rsplit(')', 1)[1].split()[19]}"  # field 22: starttime


def _me() -> dict[str, Any]:
    pid = os.getpid()
    return {"host": socket.gethostname(), "pid": pid, "process": _process_key(pid),
            "started": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())}


def _alive(pid: int, key: str | None) -> bool:
    """Is the process that made a claim (pid, process key) still running on this host?"""
    if key is not None and Path("/proc").is_dir():
        return _process_key(pid) == key
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # alive, but another user's
        return True
    return True


def holder(run_dir: Path) -> dict[str, Any] | None:
    """The claim on a run folder if it is live (this process, a live process on this host,
    or any process on another host), None if there is none or it is stale."""
    try:
        found = json.loads((run_dir / CLAIM_FILE).read_text())
        host, pid, key = str(found["host"]), int(found["pid"]), found.get("process")
    except FileNotFoundError:
        return None
    except (ValueError, KeyError, TypeError, OSError):
        return None  # unreadable or half-written: treat as stale
    if host != socket.gethostname() or _alive(pid, key):
        return found
    return None


def claim(run_dir: Path) -> bool:
    """Claim a run folder for this process: True if it is now ours (taking over a stale
    claim), False if another live process holds it.

    The claim is written whole to a private file, then hard-linked to its name, which fails
    if the name exists: no process ever reads a half-written claim.
    """
    path = run_dir / CLAIM_FILE
    mine = run_dir / f".claim.{os.getpid()}.tmp"
    for attempt in range(3):
        run_dir.mkdir(parents=True, exist_ok=True)
        try:
            mine.write_text(json.dumps(_me()))
            break
        except FileNotFoundError:  # an interrupted sweep removed the empty folder meanwhile
            if attempt == 2:
                raise
    try:
        try:
            _link(mine, path)
            return True
        except FileExistsError:
            pass
        with _takeover_lock(run_dir.parent):  # judge and replace as one step
            if holder(run_dir) is not None:
                return False
            path.unlink(missing_ok=True)  # stale: the process that made it is gone
            try:
                _link(mine, path)
                return True
            except FileExistsError:  # another process claimed it in between (not stale)
                return False
    finally:
        mine.unlink(missing_ok=True)


@contextmanager
def _takeover_lock(runs_dir: Path) -> Iterator[None]:
    """An exclusive lock (flock on ``runs_dir/.takeover.lock``) while a process judges a
    claim stale and replaces it: without it two processes could both judge the same stale
    claim, the second deleting the first one's fresh claim, and both run the run. Claims
    are taken over only from processes on this host, so a host-local lock suffices; where
    there is no fcntl (Windows) there is no lock."""
    try:
        import fcntl
    except ImportError:
        yield
        return
    with open(runs_dir / TAKEOVER_LOCK, "a") as fh:
        fcntl.flock(fh, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(fh, fcntl.LOCK_UN)


def _link(src: Path, dst: Path) -> None:
    """Hard-link src to dst (FileExistsError if dst exists). Where the file system has no
    hard links, create dst exclusively and copy src in (a reader may then, rarely, see it
    half-written and take it for stale)."""
    try:
        os.link(src, dst)
    except FileExistsError:
        raise
    except OSError:
        fd = os.open(dst, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
        with os.fdopen(fd, "w") as f:
            f.write(src.read_text())


def release(run_dir: Path) -> None:
    """Drop this process's claim on a run folder (another process's is left alone)."""
    path = run_dir / CLAIM_FILE
    try:
        claim = json.loads(path.read_text())
    except (FileNotFoundError, ValueError, OSError):
        return
    if claim.get("process", "") == _process_key(os.getpid()) and claim.get("pid") == os.getpid():
        path.unlink(missing_ok=True)
