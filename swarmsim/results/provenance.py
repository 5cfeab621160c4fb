"""Which code made a result: the package version plus, in a git checkout, the commit.

Every run's summary carries :func:`code_version`, so a results table that mixes runs made by
different code (a sweep resumed after the controller changed) shows it, and
``swarmsim reproduce`` says so in its report instead of averaging them silently.
"""

from __future__ import annotations

import functools
import subprocess
from importlib.metadata import version
from pathlib import Path

GIT_TIMEOUT_S = 5.0


CHECKOUT = Path(__file__).resolve().parents[2]
"""The folder that holds the swarmsim package (this file is swarmsim/results/provenance.py):
in a git checkout, the checkout."""


@functools.cache
def code_version() -> str:
    """``"0.1.0"``, or ``"0.1.0+g1a2b3c4"`` in a git checkout (``".dirty"`` appended when
    tracked files under the checkout differ from that commit). The version is the installed
    package's (pyproject.toml): read here, not from the package above (no arrow back up)."""
    __version__ = version("swarmsim")
    commit = _git("rev-parse", "--short", "HEAD")
    if not commit:
        return __version__
    dirty = _git("status", "--porcelain", "--untracked-files=no")
    return f"{__version__}+g{commit}" + (".dirty" if dirty else "")


def _git(*args: str) -> str:
    """Output of a git command run in the package's checkout; "" if there is none."""
    root = CHECKOUT
    if not (root / ".git").exists():
        return ""
    try:
        done = subprocess.run(["git", "-C", str(root), *args], capture_output=True, text=True,
                              timeout=GIT_TIMEOUT_S, check=False)
    except (OSError, subprocess.SubprocessError):
        return ""
    return done.stdout.strip() if done.returncode == 0 else ""
