"""summary.json assembled in one place: named sources of fields, collected in order.

Each part of a run that reports figures (the run's identity, the metrics, the fault plan, the
controller) adds one source; :meth:`SummaryCollector.collect` calls them in the order they were
added and refuses a field that two sources both write, so no part can overwrite another's.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

Source = Callable[[], Mapping[str, Any]]
"""A source of summary fields: called once when the summary is made."""


class SummaryCollector:
    """Named sources of summary fields, in order."""

    def __init__(self) -> None:
        self._sources: dict[str, Source] = {}

    def add(self, name: str, source: Source) -> None:
        """Add a source (ValueError if the name is taken)."""
        if name in self._sources:
            raise ValueError(f"summary source {name!r} added twice")
        self._sources[name] = source

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(self._sources)

    def collect(self) -> dict[str, Any]:
        """Every source's fields, in the order the sources were added (ValueError if two
        sources write the same field)."""
        out: dict[str, Any] = {}
        owner: dict[str, str] = {}
        for name, source in self._sources.items():
            for key, value in source().items():
                if key in owner:
                    raise ValueError(f"summary field {key!r} written by both {owner[key]!r} "
                                     f"and {name!r}")
                owner[key] = name
                out[key] = value
        return out


__all__ = ["Source", "SummaryCollector"]
