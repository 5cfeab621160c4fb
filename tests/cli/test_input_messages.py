"""Messages that say what is wrong: missing glyphs, TOML strings, byte-order marks, holes
touching the outline, "did you mean", settings given twice, an unreachable scheduler, and
what each controller and subcommand is."""

from __future__ import annotations

import codecs
import socket
import subprocess
import sys
import tomllib
from pathlib import Path
from types import SimpleNamespace

import pytest

from swarmsim import ConfigError, Simulation
from swarmsim.cli import build_parser, main
from swarmsim.controller import available_controllers, get_controller
from swarmsim.engine.config import build_configs
from swarmsim.experiments.spec import load_spec, spec_from_dict
from swarmsim.world.makeworld import toml_string
from swarmsim.world.world import load_world, world_from_dict
from tests.errlines import one_error_line

REPO = Path(__file__).parents[2]


# ----------------------------------------------------------------------------- make-world text
@pytest.mark.parametrize("text, missing", [
    ("日本", ["'日' (U+65E5)", "'本' (U+672C)"]),
    ("GG\U000e0001C", ["U+E0001"]),  # a tag character
    ("A\ue000", ["U+E000"]),  # private use
    ("K\u0378", ["U+0378"]),  # unassigned
])
def test_characters_the_font_lacks_are_refused_by_name(text, missing, tmp_path, capsys):
    out = tmp_path / "w.toml"
    assert main(["make-world", "--text", text, "--out", str(out)]) == 2
    err = one_error_line(capsys)
    assert "key '--text'" in err and "DejaVuSans-Bold.ttf" in err
    assert all(m in err for m in missing), err
    assert not out.exists()


@pytest.mark.parametrize("text", ["😀", 'quote " and \\ backslash', "tab\tnew\nline\x01\x7f",
                                  "Ж日本", "", "'single' \"\"\" triple"])
def test_toml_strings_round_trip(text):
    assert tomllib.loads(f"k = {toml_string(text)}")["k"] == text


def test_an_emoji_the_font_has_makes_a_valid_world(tmp_path, capsys):
    out = tmp_path / "e.toml"
    assert main(["make-world", "--text", "😀", "--name", 'smile "😀"', "--out", str(out)]) == 0
    assert load_world(out).name == 'smile "😀"'


# ----------------------------------------------------------------------------- byte-order marks
@pytest.mark.parametrize("kind", ["world", "spec"])
def test_a_utf8_byte_order_mark_is_accepted(kind, tmp_path):
    source = (REPO / "worlds" / "corridor.toml" if kind == "world"
              else None)
    text = (source.read_text() if source else
            'world = "tiny"\ncontroller = "dispersion"\n[params]\nmax_ticks = 5\n')
    plain, marked = tmp_path / "plain.toml", tmp_path / "marked.toml"
    plain.write_text(text, encoding="utf-8")
    marked.write_bytes(codecs.BOM_UTF8 + text.encode())
    load = load_world if kind == "world" else load_spec
    a, b = load(plain), load(marked)
    assert (a.target.equals(b.target) if kind == "world" else a.params == b.params)


def test_a_utf16_file_is_named_as_such(tmp_path):
    path = tmp_path / "w.toml"
    path.write_text((REPO / "worlds" / "corridor.toml").read_text(), encoding="utf-16")
    with pytest.raises(ConfigError, match="UTF-16 byte-order mark: save it as UTF-8"):
        load_world(path)


# ----------------------------------------------------------------------------- holes
OUTLINE = [[0, 0], [50, 0], [50, 50], [0, 50]]
GOOD_HOLE = [[10, 10], [20, 10], [20, 20], [10, 20]]


@pytest.mark.parametrize("hole, index, what", [
    ([[0, 20], [10, 20], [10, 30], [0, 30]], 1, "touches the outline at (0, 30) to (0, 20)"),
    ([[0, 20], [10, 25], [0, 30]], 1, "touches the outline at"),
    ([[30, 50], [40, 40], [40, 50]], 1, "touches the outline at"),
    ([[-5, 20], [10, 20], [10, 30], [-5, 30]], 1, "crosses the outline at"),
    ([[60, 60], [70, 60], [70, 70]], 1, "lies outside the outline"),
    ([[30, 30], [40, 30], [30, 40], [40, 40]], 1, "is not a simple polygon"),
    ([[15, 15], [25, 15], [25, 25], [15, 25]], 1, "overlaps or touches hole 0"),
    ([[20, 10], [30, 10], [30, 20], [20, 20]], 1, "overlaps or touches hole 0 at (20, 10) to"),
])
def test_a_bad_hole_is_named_with_what_is_wrong(hole, index, what):
    data = {"name": "h", "target": {"outline": OUTLINE, "holes": [GOOD_HOLE, hole]},
            "spawn": [{"outline": [[0, -30], [20, -30], [20, -10], [0, -10]]}]}
    with pytest.raises(ConfigError) as info:
        world_from_dict(data, source="h.toml")
    message = str(info.value)
    assert f"key 'target.holes[{index}]': hole {index} {hole!r}" in message, message
    assert what in message, message
    assert "Self-intersection" not in message or "simple" in message


def test_a_hole_touching_the_outline_at_one_point_is_fine():
    data = {"name": "h", "target": {"outline": OUTLINE, "holes": [[[0, 25], [10, 20],
                                                                   [10, 30]]]},
            "spawn": [{"outline": [[0, -30], [20, -30], [20, -10], [0, -10]]}]}
    assert len(world_from_dict(data).target.interiors) == 1


# ----------------------------------------------------------------------------- did you mean
def _world_with(**extra) -> dict:
    data = {"name": "w", "target": {"outline": OUTLINE},
            "spawn": [{"outline": [[0, -30], [20, -30], [20, -10], [0, -10]]}]}
    data.update(extra)
    return data


def _recorder_color_by(name: str) -> None:
    sim = SimpleNamespace(info=SimpleNamespace(colourings={"gradient": "scale",
                                                           "group": "category"}),
                          controller_name="ggc")
    Simulation.offered_colourings(sim, name)  # what Recorder and the viewer ask


@pytest.mark.parametrize("refuse, suggestion", [
    (lambda: build_configs({"robot": 5}, get_controller("ggc").Params), "'robots'"),
    (lambda: build_configs({"d_covr": 5}, get_controller("ggc").Params), "'d_cover'"),
    (lambda: build_configs({"grid_sise": 5}, get_controller("ggc").Params), "'grid_size'"),
    (lambda: spec_from_dict({"world": "tiny", "controler": "ggc"}), "'controller'"),
    (lambda: spec_from_dict({"world": "tiny", "controller": "dispersion",
                             "params": {"max_tick": 5}}), "'max_ticks'"),
    (lambda: spec_from_dict({"world": "tiny", "controller": "dispersion",
                             "grid": {"robot": [5, 6]}}), "'robots'"),
    (lambda: world_from_dict(_world_with(obstacle=[])), "'obstacles'"),
    (lambda: world_from_dict(_world_with(defaults={"robot": 5})), "'robots'"),
    (lambda: world_from_dict(_world_with(target={"outline": OUTLINE, "hole": []})), "'holes'"),
    (lambda: world_from_dict(_world_with(defaults={"controller": "gcc"})), "'ggc'"),
    (lambda: get_controller("dispersal"), "'dispersion'"),
    (lambda: load_world("corridr"), "'corridor'"),
    (lambda: _recorder_color_by("grup"), "'group'"),
])
def test_an_unknown_name_gets_the_closest_known_ones(refuse, suggestion):
    with pytest.raises(ConfigError) as info:
        refuse()
    message = str(info.value)
    assert f"did you mean {suggestion}" in message or (
        "did you mean" in message and suggestion in message), message
    assert len(message) < 300, message  # not every known name


def test_an_unknown_setting_on_the_command_line_is_short(capsys):
    assert main(["run", "K", "--set", "robot=7"]) == 2
    err = one_error_line(capsys)
    assert "did you mean 'robots'" in err and len(err) < 200, err


# ----------------------------------------------------------------------------- given twice
@pytest.mark.parametrize("argv, key", [
    (["run", "K", "--robots", "5", "--set", "robots=7"], "robots"),
    (["run", "K", "--groups", "2", "--set", "groups=1"], "groups"),
    (["run", "K", "--seed", "1", "--set", "seed=2"], "seed"),
    (["run", "K", "--max-ticks", "10", "--set", "max_ticks=20"], "max_ticks"),
    (["run", "K", "--d-cover", "4", "--set", "d-cover=3"], "d_cover"),
    (["run", "K", "--set", "eps0=0.1", "--set", "eps0=0.2"], "eps0"),
    (["study", "collisions", "--robots", "5", "--set", "robots=6", "--out", "OUT"], "robots"),
    (["study", "collisions", "--groups", "2", "--set", "groups=2", "--out", "OUT"], "groups"),
    (["study", "collisions", "--set", "mode=ghost", "--out", "OUT"], "mode"),
    (["study", "collisions", "--set", "speed_noise=0.1", "--out", "OUT"], "speed_noise"),
    (["reproduce", "fig17", "--max-ticks", "5", "--set", "max_ticks=6", "--dry-run"],
     "max_ticks"),
])
def test_a_setting_given_twice_is_refused(argv, key, tmp_path, capsys):
    out = tmp_path / "out"
    assert main([a.replace("OUT", str(out)) for a in argv]) == 2
    err = one_error_line(capsys)
    assert f"key '{key}'" in err and ("given twice" in err or "--modes" in err
                                      or "--noise" in err), err
    assert not out.exists()


@pytest.mark.parametrize("key, top, grid", [("world", "tiny", ["corridor"]),
                                            ("controller", "dispersion", ["cvt"])])
def test_a_spec_key_set_at_the_top_and_in_the_grid_is_refused(key, top, grid):
    data = {"world": "tiny", "controller": "dispersion", "params": {"max_ticks": 5}}
    data.update({key: top, "grid": {key: grid}})
    with pytest.raises(ConfigError, match=rf"key 'grid.{key}': set both as the top-level"):
        spec_from_dict(data)


def test_a_setting_given_twice_in_the_python_api():
    with pytest.raises(ConfigError, match=r"key 'robots': given twice: robots=5 and settings "
                                          r"robots=7"):
        Simulation.check("K", robots=5, settings={"robots": 7})
    config, _ = Simulation.check("K", settings={"seed": 3})  # once is fine
    assert config.seed == 3


# ----------------------------------------------------------------------------- scheduler
@pytest.mark.slow
def test_a_refused_scheduler_port_is_refused_at_once(tmp_path):
    pytest.importorskip("dask.distributed")
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]  # closed again: nothing listens there
    spec = tmp_path / "spec.toml"
    spec.write_text('world = "tiny"\ncontroller = "dispersion"\n[params]\nmax_ticks = 5\n')
    done = subprocess.run([sys.executable, "-m", "swarmsim", "sweep", str(spec), "--out",
                           str(tmp_path / "out"), "--scheduler", f"tcp://127.0.0.1:{port}",
                           "--quiet"], capture_output=True, text=True, timeout=60, check=False)
    assert done.returncode == 2, done.stderr
    err = done.stderr.strip()
    assert err.count("\n") == 0 and "key '--scheduler'" in err and "refused" in err, err
    assert not (tmp_path / "out").exists()


# ----------------------------------------------------------------------------- descriptions
@pytest.mark.parametrize("name", available_controllers())
def test_each_controller_says_what_it_does(name, capsys):
    assert main(["controllers"]) == 0
    line = next(x for x in capsys.readouterr().out.splitlines() if x.split()[0] == name)
    text = line[len(name):].strip()
    assert len(text.split()) >= 5 and "declarations only" not in text, line


def test_every_subcommand_has_a_description():
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    for name, command in sub.choices.items():
        assert command.description and len(command.description) > 40, name
        assert all(a.help for a in command._actions if a.dest != "help"), name
