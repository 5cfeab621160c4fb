"""The README stays a user's page: short, with the two commands CI relies on."""

from __future__ import annotations

import re
import sys
import types
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text(encoding="utf-8")


def test_readme_is_at_most_250_lines() -> None:
    assert len(README.splitlines()) <= 250


def test_the_two_commands_are_there_as_ci_runs_them() -> None:
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    test_command = ".venv/bin/python -m pytest -q -n auto --dist loadfile"
    assert test_command in README and ci.rstrip().endswith(test_command)
    assert '`-m "not slow"`' in README  # the fast subset ([tool.pytest.ini_options] markers)
    checks = [".venv/bin/ruff check .", ".venv/bin/mypy"]  # before the tests, in this order
    assert [ci.index(line) for line in checks] < [ci.index(test_command)] * 2
    assert ci.index(checks[0]) < ci.index(checks[1])
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


def controller_snippet() -> str:
    """The Python code of the README's section "Writing a controller"."""
    section = README.split("## Writing a controller", 1)[1].split("\n## ", 1)[0]
    return section.split("```python\n", 1)[1].split("```", 1)[0]


def test_the_controller_snippet_runs_as_printed() -> None:
    """The README's controller, imports and all, is a working controller: robots reach the
    target and stop there."""
    from swarmsim import Simulation

    code = controller_snippet()
    module = types.ModuleType("readme_snippet")
    sys.modules[module.__name__] = module  # dataclasses looks its module up
    try:
        exec(compile(code, "README.md", "exec", dont_inherit=True), module.__dict__)  # noqa: S102
    finally:
        del sys.modules[module.__name__]
    sim = Simulation("tiny", controller=module.GoToLight, robots=6, max_ticks=1500)
    result = sim.run()
    assert result.summary["robots_on_target"] == 6
    assert {row["status"] for row in result.robots} == {"Arrived"}


def test_the_controller_snippet_type_checks(tmp_path: Path) -> None:
    """The README's controller passes mypy against the controller API's types, as a user
    would check it (unannotated arguments allowed): a type the README uses as the docs say
    and the API declares otherwise fails here."""
    mypy = pytest.importorskip("mypy.api")
    snippet = tmp_path / "readme_controller.py"
    snippet.write_text(controller_snippet(), encoding="utf-8")
    out, err, status = mypy.run([str(snippet), "--config-file", str(ROOT / "pyproject.toml"),
                                 "--cache-dir", str(ROOT / ".mypy_cache")])
    assert status == 0, out + err
