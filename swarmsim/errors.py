"""Errors that swarmsim reports to users.

Every problem with user input (world files, parameters, sweep specs) is raised as a
:class:`ConfigError` whose message names the file (when there is one), the key and the
offending value, so that the command line can print one clear line instead of a traceback.
"""

from __future__ import annotations


class ConfigError(ValueError):
    """Bad user input: a world file, a parameter or a spec that cannot be used."""

    def __init__(self, message: str, *, source: str | None = None, key: str | None = None):
        self.source = source
        self.key = key
        where = ""
        if source:
            where += f"{source}: "
        if key:
            where += f"key '{key}': "
        super().__init__(f"{where}{message}")
