"""Dropping the package's compiled-rule cache when any of its sources changes.

Numba's on-disk cache (``cache=True``) checks only the file that defines each function: the
driver in decide.py, compiled with the rules it calls, would keep an old rule's machine code
after rules/coverage.py changed, and a run would silently use the old rule. So the package
keeps a digest of all its sources next to the cache and drops every cached kernel of the
package when the digest changes (the next run compiles afresh, about a minute).
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

STAMP = "numba-sources.sha256"


def sources_digest(package: Path) -> str:
    """SHA-256 of every .py file under ``package`` (paths and contents)."""
    digest = hashlib.sha256()
    for path in sorted(package.rglob("*.py")):
        digest.update(str(path.relative_to(package)).encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()


def drop_stale_kernels(package: Path) -> bool:
    """Delete ``package``'s cached kernels (``__pycache__/*.nbi``, ``*.nbc``) unless they were
    compiled from the sources there now. True if they were dropped."""
    stamp = package / "__pycache__" / STAMP
    digest = sources_digest(package)
    try:
        if stamp.read_text() == digest:
            return False
    except OSError:
        pass
    for pattern in ("*.nbi", "*.nbc"):
        for cached in package.rglob(f"__pycache__/{pattern}"):
            cached.unlink(missing_ok=True)
    try:
        stamp.parent.mkdir(exist_ok=True)
        partial = stamp.with_name(f".{STAMP}.{os.getpid()}.tmp")
        partial.write_text(digest)
        partial.replace(stamp)
    except OSError:
        pass  # a read-only install: numba then caches nothing there either
    return True
