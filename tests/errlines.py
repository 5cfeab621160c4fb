"""What a refused command prints: the one line tests read."""

from __future__ import annotations


def one_error_line(capsys) -> str:
    """stderr of the command just run, asserted to be one ``swarmsim: error: ...`` line with
    no traceback; returned stripped."""
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and err.startswith("swarmsim: error: "), err
    assert "Traceback" not in err
    return err
