"""`swarmsim params`: whole descriptions, wrapped, and no run results in the engine's help."""

from __future__ import annotations

import dataclasses
import re

import pytest

from swarmsim.cli import main
from swarmsim.controller import available_controllers, get_controller
from swarmsim.engine.config import SimConfig
from swarmsim.engine.paramhelp import attribute_docs, format_params
from swarmsim.physics.physics import PhysicsConfig

SENTENCE_ENDS = (".", ")", '"', "!", "?")


def _classes() -> list[type]:
    return [SimConfig, PhysicsConfig] + [get_controller(n).Params
                                         for n in available_controllers()]


@dataclasses.dataclass(frozen=True)
class _Documented:
    """A test class.

    Attributes:
        alpha: the first value (a
            check: this line reads like an entry but continues alpha).

            A second paragraph of alpha.
        beta: the second value.
    Not an attribute: the section ended.
    """

    alpha: int = 1
    beta: str = "b"


def test_continuation_lines_that_look_like_entries_stay_in_their_entry() -> None:
    docs = attribute_docs(_Documented)
    assert set(docs) == {"alpha", "beta"}
    first = ("the first value (a check: this line reads like an entry but "
             "continues alpha).")
    assert docs["alpha"] == [first, "A second paragraph of alpha."]
    assert docs["beta"] == ["the second value."]


@pytest.mark.parametrize("cls", _classes(), ids=lambda c: c.__name__)
def test_every_field_has_a_whole_description(cls: type) -> None:
    docs = attribute_docs(cls)
    for f in dataclasses.fields(cls):
        paragraphs = docs.get(f.name)
        assert paragraphs, f"{cls.__name__}.{f.name} has no description"
        assert paragraphs[-1].rstrip().endswith(SENTENCE_ENDS), (
            f"{cls.__name__}.{f.name} ends mid-sentence: ...{paragraphs[-1][-60:]!r}")


def test_the_six_descriptions_once_cut_are_whole() -> None:
    ggc = get_controller("ggc").Params
    sim, params = attribute_docs(SimConfig), attribute_docs(ggc)
    assert "drawn in index order" in sim["decide_order"][-1]
    assert "(at failure_tick)" in sim["failure_phase"][-1]
    for name in ("gradient_reach", "boundary_probe", "surplus_stop", "lattice_stop"):
        text = " ".join(params[name])
        assert text.count("(") == text.count(")"), f"{name}: {text[-80:]!r}"
        assert text.rstrip().endswith((".", ")")), f"{name}: {text[-80:]!r}"


@pytest.mark.parametrize("width", [100, 80, 60])
@pytest.mark.parametrize("controller", available_controllers())
def test_no_help_line_exceeds_the_width(controller: str, width: int) -> None:
    sections = (("engine", SimConfig), ("physics", PhysicsConfig),
                (f"controller {controller}", get_controller(controller).Params))
    lines = format_params(sections, width)
    too_long = [ln for ln in lines if len(ln) > width]
    assert not too_long, too_long[:3]
    for f in dataclasses.fields(SimConfig):
        assert any(ln.lstrip().startswith(f"{f.name} ") for ln in lines)


def test_params_command_wraps_at_100(capsys: pytest.CaptureFixture[str],
                                     monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("COLUMNS", "200")
    assert main(["params"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0] == "[engine]"
    assert max(len(ln) for ln in out) <= 100
    assert any("drawn in index order" in ln for ln in out)


def test_engine_help_quotes_no_run_results() -> None:
    """Run figures go stale: seeds, tick counts and timings belong in docs/, not help text."""
    pattern = re.compile(r"\bseed \d|\d,\d{3} ticks|\d+(\.\d+)? ?(s|ms)\b|K seed|house")
    for name, paragraphs in attribute_docs(SimConfig).items():
        for text in paragraphs:
            assert not pattern.search(text), f"SimConfig.{name}: {text}"


def test_params_lists_the_controllers_failure_modes(capsys: pytest.CaptureFixture[str],
                                                    monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("COLUMNS", "200")
    assert main(["params", "--controller", "ggc"]) == 0
    out = capsys.readouterr().out.splitlines()
    modes = out[out.index("[failure_mode of controller ggc]") + 1:]
    assert [ln.split()[0] for ln in modes if not ln.startswith("   ")] == ["dead", "no_gradient"]
    assert max(len(ln) for ln in out) <= 100
    assert main(["params", "--controller", "dispersion"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[-2:][0] == "[failure_mode of controller dispersion]" and "dead" in out[-1]
