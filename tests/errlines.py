"""What a refused command prints: the lines tests read."""

from __future__ import annotations

import re

from swarmsim.kernels.kernelbuild import PREFIX

_NOTICE = re.compile(rf"^({re.escape(PREFIX)}|swarmsim: compiled |  \d+/\d+ )")
"""A line of the first run's build notice (swarmsim.kernels.kernelbuild), which a run that compiles
kernels prints before anything else: on a cold cache (a fresh clone's CI) it comes first."""


def error_lines(err: str) -> list[str]:
    """stderr's lines without the kernels' build notice."""
    return [line for line in err.strip().splitlines() if not _NOTICE.match(line)]


def one_error_line(capsys) -> str:
    """stderr of the command just run, asserted to be one ``swarmsim: error: ...`` line with
    no traceback (beside a build notice); returned stripped."""
    lines = error_lines(capsys.readouterr().err)
    assert len(lines) == 1 and lines[0].startswith("swarmsim: error: "), lines
    assert "Traceback" not in lines[0]
    return lines[0]
