"""Atomic result files."""

import os
import stat

from swarmsim.results.output import atomic_write_text, write_json


def test_atomic_files_get_the_permissions_of_a_plain_write(tmp_path):
    plain = tmp_path / "plain.txt"
    plain.write_text("x")
    atomic = tmp_path / "sub" / "summary.json"
    write_json(atomic, {"coverage": 0.99})
    assert stat.S_IMODE(os.stat(atomic).st_mode) == stat.S_IMODE(os.stat(plain).st_mode)
    atomic_write_text(atomic, "again")  # replacing keeps them, and leaves no temporary file
    assert atomic.read_text() == "again"
    assert stat.S_IMODE(os.stat(atomic).st_mode) == stat.S_IMODE(os.stat(plain).st_mode)
    assert sorted(p.name for p in atomic.parent.iterdir()) == ["summary.json"]
