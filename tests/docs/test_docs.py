"""docs/ reads as today: current pages dated by commit, links that resolve, outputs.md naming
every field a run writes, and no measured figure in the README (they live in docs/)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
CURRENT = sorted(p for p in DOCS.glob("*.md") if p.name != "README.md")
"""The current pages: each describes one commit, in the present tense."""
REPORTS = sorted((DOCS / "reports").glob("*.md"))
"""The dated journals: provenance, not updated as the code changes."""
EXTERNAL = {"docs/riport.md"}
"""docs/ paths of other repositories that the code cites (controllers/fcdfs/controller.py:
Kristofy/uniform-dispersion-problem)."""

MEASURED = re.compile(
    r"\d[\d,.]*\s*(?:ticks?|s|ms|sec|seconds|min|minutes|hours?|CPU[- ]?(?:s|seconds|hours))\b"
    r"|\b(?:at|since)\s+[0-9a-f]{7,40}\b")
"""A measured figure: a number of ticks or a time, or a figure pinned to a commit."""


def _prose(markdown: str) -> str:
    """``markdown`` without its fenced code blocks (commands hold options, not figures)."""
    return re.sub(r"```.*?```", "", markdown, flags=re.DOTALL)


def test_the_readme_quotes_no_measured_figure() -> None:
    """Tick counts and timings go stale with the next change: they belong in docs/
    (performance.md, results.md, each with its commit), and the README links there."""
    readme = _prose((ROOT / "README.md").read_text(encoding="utf-8"))
    found = [m.group(0) for m in MEASURED.finditer(readme)]
    assert not found, f"measured figures in README.md (move them to docs/): {found}"


def test_the_scan_finds_what_it_is_meant_to() -> None:
    found = [m.group(0) for m in MEASURED.finditer(
        "K in 13,726 ticks (since 9db3722); ~20 s, 67 s of CPU, 5 min 24 s, 1.5 hours")]
    assert found == ["13,726 ticks", "since 9db3722", "20 s", "67 s", "5 min", "24 s",
                     "1.5 hours"]
    assert not MEASURED.findall("time in ticks; `--max-ticks T`; 100 x 100 raster; r = 4")


@pytest.mark.parametrize("page", CURRENT, ids=lambda p: p.name)
def test_a_current_page_names_its_commit_and_counts_no_sessions(page: Path) -> None:
    text = page.read_text(encoding="utf-8")
    head = "\n".join(text.splitlines()[:6])
    assert re.search(r"Describes the code at [0-9a-f]{7,40} \(\d{4}-\d\d-\d\d\)", head), page
    assert not re.search(r"\b\d+(?:st|nd|rd|th) session", text), page


@pytest.mark.parametrize("report", REPORTS, ids=lambda p: p.name)
def test_a_report_says_it_is_dated_and_points_to_the_current_page(report: Path) -> None:
    head = "\n".join(report.read_text(encoding="utf-8").splitlines()[:4])
    assert "A dated report, not the current state." in head
    targets = re.findall(r"\]\(\.\./([^)#]+)\)", head)
    assert targets and all((DOCS / t).exists() for t in targets), report


def test_links_in_docs_resolve() -> None:
    missing = []
    for page in [*DOCS.glob("*.md"), *REPORTS]:
        for target in re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", page.read_text("utf-8")):
            if not target.startswith(("http", "mailto:")) and not (page.parent / target).exists():
                missing.append(f"{page.relative_to(ROOT)}: {target}")
    assert not missing, missing


def test_docs_paths_named_in_the_code_exist() -> None:
    """A docstring, comment or help text that names a page under docs/ names one that exists."""
    missing = []
    for folder in ("swarmsim", "controllers", "bench", "examples", "tests"):
        for source in (ROOT / folder).rglob("*.py"):
            for name in re.findall(r"docs/[\w/.-]+\.md", source.read_text(encoding="utf-8")):
                if name not in EXTERNAL and not (ROOT / name).exists():
                    missing.append(f"{source.relative_to(ROOT)}: {name}")
    assert not missing, missing


def _named(page: str) -> set[str]:
    """Every `backquoted` name of a docs page."""
    return set(re.findall(r"`([^`\s]+)`", (DOCS / page).read_text(encoding="utf-8")))


def test_outputs_md_names_every_field_and_column_a_run_writes() -> None:
    """summary.json's fields, timeseries.csv's and robots.csv's columns as a run writes them
    today are each named in docs/outputs.md (a controller's own summary fields, added by its
    ``summarize``, are listed there too; this run's controller adds none)."""
    from swarmsim import Simulation

    result = Simulation("tiny", controller="dispersion", seed=0, max_ticks=30).run()
    written = {*result.summary, *result.timeseries[0], *result.robots[0]}
    written |= {"run_id", "fault_tick"}  # a sweep's, and a run with failures'
    assert not written - _named("outputs.md"), sorted(written - _named("outputs.md"))
