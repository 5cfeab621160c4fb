"""code_version names the commit in a git checkout (summary.json and checkpoints carry it)."""

from __future__ import annotations

import subprocess

import pytest

from swarmsim.results import provenance


def _head() -> str:
    try:
        done = subprocess.run(["git", "-C", str(provenance.CHECKOUT), "rev-parse", "--short",
                               "HEAD"], capture_output=True, text=True, timeout=10, check=False)
    except (OSError, subprocess.SubprocessError):
        return ""
    return done.stdout.strip() if done.returncode == 0 else ""


def test_the_checkout_is_the_folder_holding_the_package():
    assert (provenance.CHECKOUT / "swarmsim" / "results" / "provenance.py").is_file()


@pytest.mark.skipif(not (provenance.CHECKOUT / ".git").exists() or not _head(),
                    reason="not a git checkout (an installed package has no commit to name)")
def test_code_version_names_the_commit_in_a_checkout():
    assert f"+g{_head()}" in provenance.code_version()
