"""The README stays a user's page: short, with the two commands CI relies on."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
README = (ROOT / "README.md").read_text(encoding="utf-8")


def test_readme_is_at_most_250_lines() -> None:
    assert len(README.splitlines()) <= 250


def test_the_two_commands_are_there_as_ci_runs_them() -> None:
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    test_command = ".venv/bin/python -m pytest -q -n auto --dist loadfile"
    assert test_command in README and test_command in ci
    assert (".venv/bin/pip install -e '.[test]' && .venv/bin/swarmsim run K --out runs/K "
            "--video runs/K/K.mp4") in README


def test_links_and_picture_exist() -> None:
    targets = re.findall(r"\]\(([^)#]+)\)", README)
    assert targets
    missing = [t for t in targets if not t.startswith("http") and not (ROOT / t).exists()]
    assert not missing, missing


def test_controller_section_keeps_the_marker_for_the_api() -> None:
    section = README.split("## Writing a controller", 1)[1].split("\n## ", 1)[0]
    assert "<!-- controller-api" in section and "<!-- /controller-api -->" in section
    assert "examples/my_controller.py" in section
    assert len(section.splitlines()) <= 45  # one screen
