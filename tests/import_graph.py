"""Test helper: import circles in a module graph."""

from __future__ import annotations


def assert_no_circles(edges: dict[str, set[str]]) -> None:
    """Fail naming the first import circle found in ``edges`` (module -> modules it imports;
    only modules that are keys count)."""
    state: dict[str, int] = {}

    def visit(m: str, path: list[str]) -> None:
        state[m] = 1
        for d in sorted(edges[m]):
            if d not in edges:
                continue
            if state.get(d) == 1:
                raise AssertionError(" -> ".join([*path[path.index(d):], d]))
            if d not in state:
                visit(d, [*path, d])
        state[m] = 2

    for m in sorted(edges):
        if m not in state:
            visit(m, [m])
