"""Command line: ``swarmsim run | view | replay | sweep | reproduce | study | worlds |
make-world | controllers | params``.

Every input error prints one line naming the file, key and value, and exits with status 2; a
controller's mistake, one line naming the controller, the robot and the tick (then, if the
controller raised, its own traceback), also status 2.
"""

from __future__ import annotations

import argparse
import contextlib
import math
import os
import signal
import sys
import tempfile
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from swarmsim.errors import ConfigError, ControllerError, interrupts_unwrapped
from swarmsim.limits import (
    MAX_COORDINATE,
    MAX_FPS,
    MAX_FRAME_SIDE,
    MAX_GROUPS,
    MAX_REPS,
    MAX_ROBOTS,
    MAX_TICKS,
    MAX_WORKERS_PER_CPU,
    check_count,
)
from swarmsim.results import runfolder
from swarmsim.results.runfolder import NewFolders
from swarmsim.world.worldinfo import LATTICE_SPACINGS, fit_number

if TYPE_CHECKING:  # the engine's modules load numba: only the commands that run import them
    from swarmsim.engine.config import SimConfig


VIEWER_CLOSED = "viewer_closed"
"""summary.json's stop_reason of a run `swarmsim view --out` wrote before it ended."""


def _parse_set(pairs: Sequence[str], **options: Any) -> dict[str, Any]:
    """The ``--set KEY=VALUE`` pairs as settings; see swarmsim.engine.config.settings_from_pairs."""
    from swarmsim.engine.config import settings_from_pairs

    return settings_from_pairs(pairs, options)


def _add_run_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("run", help="run one simulation",
                       description="Run one simulation and print a one-line summary.")
    _add_simulation_args(p, world_optional=True)
    _add_output_args(p, "")
    p.add_argument("--video", type=Path, metavar="FILE.mp4", help="write an MP4 of the run")
    p.add_argument("--fps", type=int, default=30,
                   help=f"video frames per second (default 30, at most {MAX_FPS})")
    p.add_argument("--frame-every", type=int, default=0, dest="frame_every", metavar="K",
                   help="a video frame every K ticks (default: max_ticks / 600, at least 1 "
                        "and at most 50)")
    p.add_argument("--color-by", default=None, dest="color_by", metavar="FIELD",
                   help="robot colouring in videos: status, or a field the controller offers "
                        "(GGC: gradient (default), group)")
    p.add_argument("--width", type=int, default=800,
                   help=f"video/snapshot width in px (default 800; even, 64 to {MAX_FRAME_SIDE:,})")
    p.add_argument("--highlight-contacts", action="store_true", dest="highlight_contacts",
                   help="ring robots that touch something (collision-realism videos)")
    p.add_argument("--snapshot", type=Path, metavar="FILE.png", help="PNG of the last frame")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.add_argument("--checkpoint-every", type=int, dest="checkpoint_every", metavar="N",
                   help="keep the run's latest checkpoint in OUT (checkpoint.swarmsim, replaced "
                        "every N ticks, removed when the run ends) for --resume; a run that "
                        "checkpoints is not the same run as one that does not, though as "
                        "deterministic (see docs/checkpoints.md)")
    p.add_argument("--resume", type=Path, metavar="DIR",
                   help="continue the run whose checkpoint DIR holds (after a kill), with the "
                        "options it was started with; writes the outputs it would have written")


def _add_output_args(p: argparse.ArgumentParser, when: str) -> None:
    """--out and --trajectories (run's and view's); ``when`` says when the files are written."""
    p.add_argument("--out", type=Path, help="write summary.json, timeseries.csv, robots.csv, "
                   f"coverage.npz and coverage.png there{when} (see docs/outputs.md)")
    p.add_argument("--trajectories", metavar="K",
                   help="also write OUT/trajectories.npz: every robot's position, status and "
                        "colouring fields, contacts and the coverage raster's changes every K "
                        "ticks, for 'swarmsim replay'; kept in memory until the run ends "
                        "(about N x 24 bytes per sample for GGC; docs/outputs.md) (needs --out)")


def _add_simulation_args(p: argparse.ArgumentParser, world_optional: bool = False) -> None:
    """The options that build a Simulation (run's and view's; see _run_arguments). With
    ``world_optional`` the world may be left out (run's --resume needs none)."""
    p.add_argument("world", nargs="?" if world_optional else None,
                   help="shipped world name (see 'swarmsim worlds') or a .toml path")
    p.add_argument("--controller",
                   help="controller name or module:Class (default: the world's, else ggc)")
    p.add_argument("--robots", type=int,
                   help=f"number of robots (default: the world's; at most {MAX_ROBOTS:,})")
    p.add_argument("--groups", type=int, help="number of groups K (default: the world's)")
    p.add_argument("--d-cover", type=float, dest="d_cover",
                   help="coverage distance d_cover, units (paper: 1, 2, 4, 6, 8, 10; default 6)")
    p.add_argument("--seed", type=int, help="run seed (default 0)")
    p.add_argument("--max-ticks", type=int, dest="max_ticks",
                   help=f"tick limit (default 100000, at most {MAX_TICKS:,})")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="any other parameter; see 'swarmsim params'")


def _add_view_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("view", help="watch one simulation live in a window",
                       description="Run one simulation in a window. Keys: space pause, . step, "
                       "+/- ticks per frame, c colouring, o coverage tint, s save PNG, 0 or r "
                       "reset the view, q quit; the mouse wheel zooms, a drag pans, a click "
                       "on a robot inspects it. Needs a display (or xvfb-run).")
    _add_simulation_args(p)
    p.add_argument("--color-by", default=None, dest="color_by", metavar="FIELD",
                   help="colouring to start with: status, or a field the controller offers "
                        "(c cycles them)")
    p.add_argument("--width", type=int,
                   help="frame width in px (default 800, or narrower so that the window fits "
                        f"the screen; even, 64 to {MAX_FRAME_SIDE:,})")
    _add_output_args(p, " when the window closes (the run as far as it went)")


def _add_replay_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("replay", help="draw a recorded run again, without simulating it",
                       description="Draw a run recorded with 'swarmsim run ... --out DIR "
                       "--trajectories K' again from DIR/trajectories.npz: one frame per "
                       "recorded sample, in any colouring the run recorded, width and frame "
                       "rate (see docs/replay.md).")
    p.add_argument("run_dir", metavar="RUN_DIR", type=Path,
                   help="the run's --out folder (or its trajectories.npz)")
    what = p.add_mutually_exclusive_group(required=True)
    what.add_argument("--video", type=Path, metavar="FILE.mp4", help="write an MP4")
    what.add_argument("--snapshot", type=Path, metavar="FILE.png",
                      help="write a PNG of one recorded sample (--tick; default the last)")
    what.add_argument("--view", action="store_true",
                      help="step through the samples in the live viewer (keys as in 'view'; "
                           ". steps one sample; needs a display)")
    p.add_argument("--tick", type=int, help="the recorded tick --snapshot draws")
    p.add_argument("--fps", type=int, default=30,
                   help=f"video frames per second (default 30, at most {MAX_FPS})")
    p.add_argument("--color-by", default=None, dest="color_by", metavar="FIELD",
                   help="robot colouring: status, or a field the run recorded (default: the "
                        "controller's first)")
    p.add_argument("--width", type=int,
                   help="frame width in px (default 800; --view: narrower if the window would "
                        f"not fit the screen; even, 64 to {MAX_FRAME_SIDE:,})")
    p.add_argument("--highlight-contacts", action="store_true", dest="highlight_contacts",
                   help="ring robots that touch something")
    p.add_argument("--quiet", action="store_true", help="no progress bar")


def _add_executor_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("--workers", type=int, help="local worker processes (default: all CPUs; "
                   f"1 = in this process; at most {MAX_WORKERS_PER_CPU} per CPU)")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="run on a Dask cluster, e.g. tcp://host:8786 (pip install 'swarmsim[dask]')")
    p.add_argument("--retry-failed", action="store_true", dest="retry_failed",
                   help="run again the runs that failed before")
    p.add_argument("--quiet", action="store_true", help="no progress bar")


def _add_sweep_parsers(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("sweep", help="run a sweep spec (params x grid x seeds), resumably",
                       description="Run every run of a TOML sweep spec once; run again with the "
                       "same --out to resume. The same command started in a second terminal, or "
                       "on a machine sharing the folder, shares the runs left (each run is "
                       "claimed in runs/<id>/claim.json while it runs). Writes runs/<id>/ (each "
                       "run's files), results.csv (a row per run) and aggregate/ (mean and "
                       "spread per grid point over seeds: conditions.csv, curves.csv, "
                       "coverage.png); docs/outputs.md describes every file.")
    p.add_argument("spec", type=Path, help="sweep spec (.toml)")
    p.add_argument("--out", type=Path, required=True, help="output folder")
    _add_executor_args(p)
    r = sub.add_parser("reproduce", help="run the paper's Section 6 figures (fig14, "
                       "fig17..fig24, table3, all)",
                       description="Run (or resume) the runs of the paper's figures and write "
                       "tables, plots and REPORT.md.")
    r.add_argument("fig", nargs="+",
                   help="fig14, fig17 .. fig24, table3 (Figure 24's runs' costs), or all; "
                        "several figures share one report and one run store")
    r.add_argument("--reps", type=int, default=3,
                   help=f"seeds per condition (default 3, at most {MAX_REPS:,})")
    r.add_argument("--out", type=Path, default=Path("results/reproduce"),
                   help="output folder (default results/reproduce)")
    r.add_argument("--max-ticks", type=int, dest="max_ticks", help="tick limit of every run")
    r.add_argument("--world", help="world instead of the paper's 'K'")
    r.add_argument("--robots", type=int, help="robot count (default: the world's; K: 603)")
    r.add_argument("--rulesets", type=_names, metavar="A,B",
                   help="GGC's rule sets judged side by side (default: its default rule set, "
                        "then paper)")
    r.add_argument("--ghost", action="store_true",
                   help="add a column of point robots that pass through each other (mode "
                        "ghost, as in the paper's NetLogo model) under the first rule set")
    r.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="another setting for every run")
    r.add_argument("--dry-run", action="store_true", dest="dry_run",
                   help="list the runs each figure needs, how many are done in --out and "
                        "a rough guess of the CPU time left, and exit")
    _add_executor_args(r)


STUDY_GROUPS = 3  # a study's groups when neither --groups nor --set groups= is given
STUDIES = ("collisions", "realism")
REALISM_DRIVES = ("holonomic", "diff", "kilobot")  # as swarmsim.experiments.realism.DRIVES
REALISM_MESSAGES = ("uniform", "logistic")  # as swarmsim.experiments.realism.MESSAGES
REALISM_ONLY = ("drives", "messages")  # study options only realism has


def _add_study_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("study", help="realism studies: ghost vs rigid robots (collisions); "
                       "drives x noise x message models against ideal robots (realism)",
                       description="collisions: run the same scenarios with robots that pass "
                       "through each other (ghost, the paper's points) and rigid discs (and "
                       "optionally noise levels). realism: run them under every drive x mode x "
                       "noise level x message model, plus the baseline (holonomic ghost discs, "
                       "noise 0, uniform messages without loss), and compare each with the "
                       "baseline (docs/realism-study.md). Both write runs/, results.csv, "
                       "conditions.csv, a figure and REPORT.md in --out; resumable (run the same "
                       "command again), local workers or Dask.")
    p.add_argument("what", choices=STUDIES, help="the study to run")
    p.add_argument("--world", default="K", help="world (default K)")
    p.add_argument("--controller", default="ggc", help="controller (default ggc)")
    p.add_argument("--robots", type=int, help="robot count (default: the world's)")
    p.add_argument("--groups", type=int, help=f"number of groups K (default {STUDY_GROUPS})")
    p.add_argument("--d-cover", type=float, dest="d_cover", help="d_cover (default: 6)")
    p.add_argument("--reps", type=int, default=5,
                   help=f"seeds per condition (default 5, at most {MAX_REPS:,})")
    p.add_argument("--max-ticks", type=int, dest="max_ticks",
                   help="tick limit of every run (default 100000)")
    p.add_argument("--modes", nargs="+", choices=("ghost", "rigid"),
                   help="physics modes to compare (default: ghost rigid for collisions, rigid "
                   "for realism, whose baseline is ghost)")
    p.add_argument("--noise", nargs="+", type=float, metavar="LEVEL",
                   help="noise levels: LEVEL sets speed, heading (rad), distance and bearing "
                   "(rad) noise to LEVEL; realism also makes the floor sensor misread within 1 "
                   "unit of the target's edge with probability 2 x LEVEL, so LEVEL <= 0.5 "
                   "(default: 0 for collisions, 0 0.05 for realism)")
    p.add_argument("--drives", nargs="+", metavar="DRIVE",
                   help="realism only: drives to compare, as --set drive=DRIVE (default: "
                   f"{' '.join(REALISM_DRIVES)})")
    p.add_argument("--messages", nargs="+", choices=REALISM_MESSAGES,
                   help="realism only: message models to compare: uniform (no loss) and "
                   "logistic (success falls with distance: 50 %% at 0.8 x the sensing range, "
                   "fall-off 1.5 units) (default: uniform logistic)")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="another setting for every run (e.g. message_loss=0.1 for collisions); "
                   "not one the study varies")
    p.add_argument("--out", type=Path,
                   help="output folder (default results/collisions or results/realism)")
    _add_executor_args(p)


def _add_make_world_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("make-world", help="build a world file from text or a black-and-white "
                       "image", description="Build a world from glyph outlines (--text) or an "
                       "image's dark shapes (--image): the target scaled and joined into one "
                       "polygon, holes kept, a spawn band below it, the beacon inside it and "
                       "the robot count from the lattice capacity at --d-cover.")
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--text", help='the target\'s text, e.g. "GGC"')
    src.add_argument("--image", type=Path, metavar="FILE.png",
                     help="a black-and-white image: its dark shapes become the target")
    p.add_argument("--out", type=Path, required=True, metavar="FILE.toml",
                   help="the world file to write")
    p.add_argument("--size", type=float, help="the target's height, units (default: the "
                   "height at which its area is the K world's, 13,280 units^2); refused when "
                   f"the target would take more than {MAX_ROBOTS:,} robots or span more than "
                   f"+-{MAX_COORDINATE:,.0f} units")
    p.add_argument("--font", help="font family or .ttf file for --text (default DejaVu Sans "
                   "Bold)")
    p.add_argument("--invert", action="store_true",
                   help="trace the image's light shapes instead of its dark ones")
    p.add_argument("--robots", type=int, help="robot count (default: the lattice capacity at "
                   f"--d-cover / 0.7, as the shipped worlds; at most {MAX_ROBOTS:,})")
    p.add_argument("--groups", type=int, help="groups (default: one per 200 robots, 1..10; at "
                   f"most {MAX_GROUPS}, as a run takes)")
    p.add_argument("--d-cover", type=float, default=6.0, dest="d_cover",
                   help="d_cover the robot count is sized for (default 6)")
    p.add_argument("--name", help="the world's name (default: the text, or the image's name)")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="swarmsim",
        description="Physics-based 2-D swarm-robotics simulator (GGC area coverage).")
    sub = parser.add_subparsers(dest="command", required=True)
    _add_run_parser(sub)
    _add_view_parser(sub)
    _add_replay_parser(sub)
    _add_sweep_parsers(sub)
    _add_study_parser(sub)
    wp = sub.add_parser("worlds", help="list shipped worlds, or describe your own world files",
                        description="Without WORLD: the shipped worlds with their target area "
                        "and lattice capacity. With WORLD (a .toml path or a shipped name): its "
                        "free target floor (net of holes and obstacles), lattice capacity per "
                        "d_cover, spawn room, beacon and warnings.")
    wp.add_argument("world", nargs="*", help="world file(s) (.toml) or shipped names")
    wp.add_argument("--preview", type=Path, metavar="FILE.png",
                    help="draw the world (one WORLD) with its robots at the start, without "
                    "running it")
    wp.add_argument("--width", type=int, default=800,
                    help=f"preview width in px (default 800; even, 64 to {MAX_FRAME_SIDE:,})")
    _add_make_world_parser(sub)
    sub.add_parser("controllers", help="list registered controllers",
                   description="List the registered controllers (swarmsim's and those other "
                   "packages install by entry point), each with a line on what it does. Give one "
                   "to run with --controller NAME, or any class as --controller module:Class.")
    pp = sub.add_parser("params", help="list every parameter with its default and meaning",
                        description="List every parameter a run takes, by section (engine, "
                        "physics, the controller's own), with its default, meaning and upper "
                        "bound. Set any with --set KEY=VALUE (run, reproduce, study) or in a "
                        "sweep spec's [params] and [grid].")
    pp.add_argument("--controller", default="ggc",
                    help="the controller whose parameters to list (default ggc)")
    return parser


def cmd_worlds(args: argparse.Namespace) -> int:
    if not args.world:
        if args.preview:
            raise ConfigError("needs a WORLD to draw (e.g. swarmsim worlds my.toml --preview "
                              "my.png)", key="--preview")
        return cmd_list_worlds()
    return cmd_describe_worlds(args.world, args.preview, args.width)


def cmd_describe_worlds(names: Sequence[str], preview: Path | None, width: int) -> int:
    """Describe each world; with ``preview``, draw the one world into that PNG."""
    from swarmsim.world.world import load_world
    from swarmsim.world.worldinfo import describe_world, format_report

    if preview is not None:
        if len(names) != 1:
            raise ConfigError(f"draws one world, got {len(names)}: {' '.join(names)}",
                              key="--preview")
        if preview.suffix.lower() != ".png":
            raise ConfigError(f"must be a .png file, got {str(preview)!r}", key="--preview")
        _check_width(width)
    reports = [describe_world(load_world(name)) for name in names]
    if preview is not None:
        _check_width(width, reports[0].world.arena)
    for k, report in enumerate(reports):
        if k:
            print()
        print("\n".join(format_report(report)))
    if preview is not None:
        from swarmsim.render.preview import save_preview

        with runfolder.removed_if_left_empty() as made:  # if drawing fails
            _make_folder("--preview", preview.parent, made)
            print(f"preview: {save_preview(reports[0], preview, width)}")
    return 0


def cmd_make_world(args: argparse.Namespace) -> int:
    from swarmsim.world.makeworld import WorldSpec, build_world, describe_built, write_world
    from swarmsim.world.shapes import image_shape, text_shape

    if args.out.suffix.lower() != ".toml":
        raise ConfigError(f"must be a .toml file, got {str(args.out)!r}", key="--out")
    if args.out.is_dir():
        raise ConfigError(f"{str(args.out)!r} is a folder; give a file name", key="--out")
    if args.text is not None:
        shape = text_shape(args.text, args.font)
        name = args.name or args.text.strip()
        how = f"the text {args.text.strip()!r}" + (f" in {args.font}" if args.font else "")
    else:
        if args.font:
            raise ConfigError("is for --text only", key="--font")
        shape = image_shape(args.image, invert=args.invert)
        name = args.name or args.image.stem
        how = f"the {'light' if args.invert else 'dark'} shapes of {args.image.name}"
    spec = WorldSpec(name=name, description=f"Made by swarmsim make-world from {how}",
                     size=args.size, d_cover=args.d_cover, robots=args.robots,
                     groups=args.groups)
    built = build_world(shape, spec)
    header = (f"Made by `swarmsim make-world` from {how}.\n"
              "Edit freely: `swarmsim worlds THIS.toml` describes it, --preview draws it.")
    with runfolder.removed_if_left_empty() as made:  # if writing fails
        _make_folder("--out", args.out.parent, made)
        path = write_world(built, args.out, header)
    d = built.data["defaults"]
    print(f"wrote {path}: {built.world.target_area:,.0f} units^2, {d['robots']} robots, "
          f"{d['groups']} group(s), d_cover {d['d_cover']:g}")
    for note in built.notes:
        print(f"  {note}")
    for warning in describe_built(built):
        print(f"  warning: {warning}")
    print(f"run it: swarmsim run {path}   describe it: swarmsim worlds {path} --preview "
          f"{path.with_suffix('.png')}")
    return 0


def cmd_list_worlds() -> int:
    from swarmsim.engine.config import SimConfig
    from swarmsim.world.floor import travel_floor_ticks
    from swarmsim.world.world import available_worlds, load_world

    v_max = SimConfig().v_max
    head = f"{'world':<10} {'area':>9} " + " ".join(f"{'cap@' + str(d):>8}"
                                                   for d in LATTICE_SPACINGS)
    print(head + f" {'robots':>7} {'groups':>6} {'floor':>7}")
    for name in available_worlds():
        w = load_world(name)
        caps = " ".join(fit_number(w.lattice_capacity(d), 8) for d in LATTICE_SPACINGS)
        print(f"{name:<10} {fit_number(w.target_area, 9)} {caps} "
              f"{w.defaults.get('robots', '-'):>7} {w.defaults.get('groups', '-'):>6} "
              f"{_floor_text(travel_floor_ticks(w, v_max)):>7}")
    print("cap@d = robots a hexagonal lattice of spacing d holds: area / (0.866 d^2)")
    print(f"floor = ticks a robot at v_max {v_max:g} needs from the spawn areas to the "
          "farthest target point")
    return 0


def _floor_text(ticks: float) -> str:
    """A travel floor for the worlds list: ticks, or "-" when no path reaches the target."""
    return fit_number(ticks, 7).strip() if math.isfinite(ticks) else "-"


def cmd_controllers() -> int:
    from swarmsim.controller import available_controllers, get_controller

    for name in available_controllers():
        cls = get_controller(name)
        doc = (cls.__doc__ or "").strip().splitlines()[0] if cls.__doc__ else ""
        print(f"{name:<12} {doc}")
    return 0


def cmd_params(controller: str) -> int:
    from swarmsim.controller import get_controller
    from swarmsim.engine.config import DEAD, SimConfig
    from swarmsim.engine.controller_info import describe
    from swarmsim.engine.paramhelp import format_choices, format_params, help_width
    from swarmsim.physics.physics import PhysicsConfig

    cls = get_controller(controller)
    sections = (("engine", SimConfig), ("physics", PhysicsConfig),
                (f"controller {controller}", cls.Params))
    width = help_width()
    print("\n".join(format_params(sections, width)))
    modes = {DEAD: "stops moving and communicating, stays in the way (every controller's)",
             **describe(cls, controller).failure_modes}
    print("\n".join(format_choices(f"failure_mode of controller {controller}", modes, width)))
    return 0


def _frame_every(args: argparse.Namespace, max_ticks: int) -> int:
    if args.frame_every:
        check_count("--frame-every", args.frame_every, MAX_TICKS, "ticks in one run")
    return args.frame_every or max(1, min(50, max_ticks // 600))


def _trajectories_every(args: argparse.Namespace) -> int:
    """--trajectories K as ticks (0 when not given); it needs --out."""
    if args.trajectories is None:
        return 0
    from swarmsim.results.trajectories import check_every

    every = check_every(args.trajectories, key="--trajectories")
    if not args.out:
        raise ConfigError(f"{args.trajectories!r} needs --out (the folder for "
                          "trajectories.npz)", key="--trajectories")
    return every


def _check_width(width: int | None,
                 arena: tuple[float, float, float, float] | None = None) -> None:
    """Refuse a frame width the renderer cannot draw (and, given the ``arena``, a frame height
    it would make), before the run rather than at its first frame. None (the viewer's: fitted
    to the screen) passes."""
    from swarmsim.render.frame import check_width, frame_size

    if width is None:
        return
    try:
        check_width(width) if arena is None else frame_size(arena, width)
    except ValueError as exc:
        raise ConfigError(str(exc).removeprefix("width "), key="--width") from None


def _make_folder(key: str, folder: str | Path, made: NewFolders | None = None) -> None:
    """Create ``folder`` (and its parents) now, so that a path that cannot be written is one
    error naming the option before any work, not a traceback after it. With ``made``, the
    folders created are remembered there (to be removed if the command ends early)."""
    try:
        (made or NewFolders()).make(folder)
    except OSError as exc:
        raise ConfigError(f"cannot create the folder {str(folder)!r} ({exc.strerror})",
                          key=key) from None
    try:
        with tempfile.TemporaryFile(dir=folder):
            pass
    except OSError as exc:
        raise ConfigError(f"cannot write in the folder {str(folder)!r} ({exc.strerror})",
                          key=key) from None


def _check_folder(key: str, folder: str | Path) -> None:
    """Refuse a folder that cannot be made or written, without making it: the folder is a
    file, or the nearest folder that exists above it is a file or not writable."""
    path = Path(folder)
    above = next(p for p in (path, *path.absolute().parents) if p.exists())
    if not above.is_dir():
        raise ConfigError(f"cannot create the folder {str(folder)!r} ({str(above)!r} is a "
                          "file)", key=key)
    if not os.access(above, os.W_OK | os.X_OK):
        verb = "write in" if above == path else "create"
        raise ConfigError(f"cannot {verb} the folder {str(folder)!r} (permission denied on "
                          f"{str(above)!r})", key=key)


def _output_folders(args: argparse.Namespace) -> list[tuple[str, Path]]:
    """(option, folder) that run's --out, --video and --snapshot write to."""
    out = [("--out", Path(args.out))] if args.out else []
    return out + [(key, Path(path).parent) for key, path in
                  (("--video", args.video), ("--snapshot", args.snapshot)) if path]


def _check_output_paths(args: argparse.Namespace) -> None:
    """Refuse run's --out, --video and --snapshot paths that cannot be written, before the
    run and without making anything (the folders are made once the run is valid:
    _make_output_folders)."""
    if args.snapshot and Path(args.snapshot).suffix.lower() != ".png":
        raise ConfigError(f"must be a .png file, got {str(args.snapshot)!r}", key="--snapshot")
    if args.video and Path(args.video).suffix.lower() != ".mp4":
        raise ConfigError(f"must be an .mp4 file, got {str(args.video)!r}", key="--video")
    for key, folder in _output_folders(args):
        _check_folder(key, folder)
    if args.out:
        runfolder.check_free(args.out)  # quick: another run writing there (locked: cmd_run)
    for key, path in (("--video", args.video), ("--snapshot", args.snapshot)):
        if path and Path(path).is_dir():
            raise ConfigError(f"{str(path)!r} is a folder; give a file name", key=key)


def _make_output_folders(args: argparse.Namespace, made: NewFolders) -> None:
    """Make the folders run writes to (and find them writable), remembered in ``made``."""
    for key, folder in _output_folders(args):
        _make_folder(key, folder, made)


def _check_run_sizes(args: argparse.Namespace, world: Any, config: SimConfig, every: int) -> None:
    """Refuse what the run's outputs would make too large, before the run is built: frames
    (the height follows the arena) and trajectory samples kept in memory."""
    if args.video or args.snapshot:
        _check_width(args.width, world.arena)
    if every:
        _check_trajectory_memory(every, config)


def _run_arguments(args: argparse.Namespace) -> dict[str, Any]:
    """Simulation's keyword arguments from run's options (an option that --set gives again
    is refused: swarmsim.engine.config.settings_from_pairs)."""
    given = {"robots": args.robots, "groups": args.groups, "seed": args.seed,
             "d_cover": args.d_cover, "max_ticks": args.max_ticks}
    return {"controller": args.controller, **given, "settings": _parse_set(args.set, **given)}


def cmd_run(args: argparse.Namespace) -> int:
    from swarmsim.engine.sim import Simulation
    from swarmsim.kernels.kernelbuild import build_notice
    from swarmsim.world.world import load_world

    if args.resume is not None:
        return _resume_run(args)
    if args.world is None:
        raise ConfigError("give the WORLD to run (or --resume DIR)", key="world")
    check_count("--fps", args.fps, MAX_FPS, "video frames per second")
    _frame_every(args, MAX_TICKS)
    if args.video or args.snapshot:
        _check_width(args.width)
    every = _trajectories_every(args)
    _check_checkpoint_every(args)
    _check_output_paths(args)
    run = _run_arguments(args)
    world = load_world(args.world)
    _check_run_sizes(args, world, Simulation.check(world, **run)[0], every)
    with build_notice(detail=not args.quiet):  # the first run compiles kernels: say so
        sim = Simulation(world, **run)
    recorder = _recorder(sim, args, every)
    return _run_to_end(args, sim, recorder, resumed=False)


def _recorder(sim: Any, args: argparse.Namespace, every: int) -> Any:
    """The run's swarmsim.recording.Recorder (checks --color-by and the frame's options)."""
    from swarmsim.recording import Recorder

    return Recorder(sim, video=args.video, snapshot=args.snapshot, fps=args.fps,
                    frame_every=_frame_every(args, sim.config.max_ticks),
                    color_by=args.color_by, width=args.width,
                    highlight_contacts=args.highlight_contacts, trajectories_every=every)


def _run_to_end(args: argparse.Namespace, sim: Any, recorder: Any, resumed: bool) -> int:
    """Run ``sim`` to its end with ``recorder`` (checkpointing every --checkpoint-every
    ticks), write the outputs in --out and print the one-line summary. A new run (not
    ``resumed``) removes a checkpoint an earlier run left in --out; a run that ends normally
    removes its own."""
    from swarmsim.engine.checkpoint import FILE_NAME

    checkpoint = Path(args.out) / FILE_NAME if args.out else None
    try:
        result = _run_in_folder(args, sim, recorder, checkpoint, resumed)
    except KeyboardInterrupt:  # Ctrl-C, SIGTERM: say how to go on, if there is a way
        if not (args.checkpoint_every and checkpoint.is_file()):
            raise
        print(f"swarmsim: interrupted; 'swarmsim run --resume {args.out}' continues the run "
              "from its last checkpoint", file=sys.stderr)
        return 130
    s = result.summary
    done = f"complete at tick {s['completion_tick']}" if s["completion_tick"] else s["stop_reason"]
    if s.get("floor_ratio") is not None:
        done += f", {s['floor_ratio']:.2f}x the travel floor"
    print(f"{s['world']} {s['controller']} robots={s['robots']} groups={s['groups']} "
          f"seed={s['seed']}: coverage {100 * s['coverage']:.1f}% ({done}), ticks {s['ticks']}, "
          f"distance {s['total_distance']:.0f}, contacts {s['collisions_robot_robot']}, "
          f"{s['wall_seconds']:.1f}s")
    return 0


def _run_in_folder(args: argparse.Namespace, sim: Any, recorder: Any, checkpoint: Path | None,
                   resumed: bool) -> Any:
    """_run_to_end's run: the folders made and locked, the run, its outputs; the RunResult."""
    # only now the folders; a run that ends early in any way removes those it made
    with runfolder.removed_if_left_empty() as made:
        _make_output_folders(args, made)
        with runfolder.locked(args.out) if args.out else contextlib.nullcontext():
            if checkpoint is not None and not resumed:
                _remove_checkpoint(checkpoint)  # an earlier run's: not this one's
            on_tick = (_checkpointing(args, recorder, checkpoint) if args.checkpoint_every
                       else recorder.on_tick)
            with recorder:
                result = sim.run(progress=not args.quiet, on_tick=on_tick)
            if checkpoint is not None:
                recorder.write_outputs(args.out, result)
                _remove_checkpoint(checkpoint)  # the outputs hold the whole run now
    return result


def _remove_checkpoint(path: Path) -> None:
    """Remove the checkpoint at ``path`` and the temporary files of its atomic writes
    (``.NAME.*.tmp``) that a kill during a write left."""
    path.unlink(missing_ok=True)
    for tmp in path.parent.glob(f".{path.name}.*.tmp"):
        tmp.unlink(missing_ok=True)


def _check_checkpoint_every(args: argparse.Namespace) -> None:
    """Refuse --checkpoint-every that is not a tick count, has no --out to keep the
    checkpoint in, or comes with --video (a video cannot be resumed)."""
    if args.checkpoint_every is None:
        return
    check_count("--checkpoint-every", args.checkpoint_every, MAX_TICKS, "ticks in one run")
    if not args.out:
        raise ConfigError(f"{args.checkpoint_every!r} needs --out (the folder that keeps the "
                          "checkpoint)", key="--checkpoint-every")
    if args.video:
        raise ConfigError("a video cannot be resumed after a kill, so it cannot come with "
                          "--checkpoint-every: record --trajectories K and make the video with "
                          "'swarmsim replay'", key="--video")


def _checkpointing(args: argparse.Namespace, recorder: Any, path: Path) -> Any:
    """The run's on_tick: the recorder's, then every --checkpoint-every ticks (unless the
    run ends at this tick) a checkpoint at ``path`` holding the run, its options and its
    trajectory samples. Saving re-seats the run on the file (swarmsim/engine/checkpoint.py),
    and the recorder goes on with the samples loaded back, as a resume does."""
    from swarmsim.engine import checkpoint

    options = _resume_options(args)
    every = args.checkpoint_every

    def on_tick(sim: Any) -> None:
        recorder.on_tick(sim)
        if sim.tick % every == 0 and sim.finished() is None:
            extra = checkpoint.save(sim, path, {"options": options,
                                                "trajectories": recorder.trajectories})
            recorder.trajectories = extra["trajectories"]

    return on_tick


def _resume_options(args: argparse.Namespace) -> dict[str, Any]:
    """The run options a checkpoint keeps for --resume (all of run's, less --resume and
    --quiet)."""
    return {k: v for k, v in vars(args).items() if k not in ("resume", "quiet")}


def _resume_run(args: argparse.Namespace) -> int:
    """``swarmsim run --resume DIR``: continue the run whose checkpoint DIR holds, with the
    options it was started with (--out is DIR), to the outputs it would have written."""
    from swarmsim.engine import checkpoint
    from swarmsim.engine.sim import Simulation

    defaults = vars(build_parser().parse_args(["run"]))
    given = [k for k, v in _resume_options(args).items() if v != defaults.get(k)]
    if given:
        flag = given[0] if given[0] == "world" else "--" + given[0].replace("_", "-")
        raise ConfigError(f"continues the run with the options it was started with; got "
                          f"{flag} too", key="--resume")
    folder = Path(args.resume)
    path = folder / checkpoint.FILE_NAME
    if not path.is_file():
        if (folder / "summary.json").is_file():
            raise ConfigError(f"the run in {str(folder)!r} has ended (summary.json is "
                              "written): nothing to resume", key="--resume")
        raise ConfigError(f"no checkpoint in {str(folder)!r} ({checkpoint.FILE_NAME}): "
                          "only a run started with --out DIR --checkpoint-every N can be "
                          "resumed", key="--resume")
    runfolder.check_free(folder, key="--resume")
    sim, extra = checkpoint.load(path, Simulation)
    options = argparse.Namespace(**{**extra["options"], "out": folder, "quiet": args.quiet,
                                    "resume": folder})
    recorder = _recorder(sim, options, 0)
    recorder.trajectories = extra["trajectories"]  # the samples taken before the checkpoint
    return _run_to_end(options, sim, recorder, resumed=True)


def cmd_view(args: argparse.Namespace) -> int:
    """Open the live viewer (swarmsim.render.viewer) on the run the options describe."""
    from swarmsim.render.viewer import display_problem

    problem = display_problem(os.environ, sys.platform)  # before the run is built
    if problem:
        raise ConfigError(problem)
    from swarmsim.engine.sim import Simulation
    from swarmsim.kernels.kernelbuild import build_notice
    from swarmsim.render.viewer import view
    from swarmsim.world.world import load_world

    _check_width(args.width)
    every = _trajectories_every(args)
    if args.out:
        _check_folder("--out", args.out)
        runfolder.check_free(args.out)
    run = _run_arguments(args)
    world = load_world(args.world)
    _check_width(args.width, world.arena)
    if every:
        _check_trajectory_memory(every, Simulation.check(world, **run)[0])
    with build_notice(detail=True):
        sim = Simulation(world, **run)
    recorder = _view_recorder(sim, args, every)
    viewer = view(sim, width=args.width, color_by=args.color_by,
                  on_tick=recorder.on_tick if recorder else None)
    written = _write_viewed_run(args.out, sim, recorder) if recorder else None
    print(f"{sim.world.name} {sim.controller_name}: stopped at tick {sim.tick}"
          + "".join(f"; saved {p}" for p in viewer.saved)
          + (f"; wrote {written}" if written else ""))
    return 0


def _check_trajectory_memory(every: int, config: SimConfig) -> None:
    """Refuse --trajectories K whose samples would not fit in memory (run's and view's)."""
    from swarmsim.results.trajectories import check_memory

    check_memory(every, config.robots, config.max_ticks, key="--trajectories")


def _view_recorder(sim: Any, args: argparse.Namespace, every: int) -> Any:
    """The viewed run's Recorder when --out is given (its trajectory samples with
    --trajectories), else None."""
    from swarmsim.recording import Recorder

    return Recorder(sim, trajectories_every=every) if args.out else None


def _write_viewed_run(out: Path, sim: Any, recorder: Any) -> Path:
    """Write the viewed run's outputs in ``out`` as far as it went (a run the window closed
    before it ended has stop_reason VIEWER_CLOSED in summary.json)."""
    result = sim.result()
    if result.summary["stop_reason"] is None:
        result.summary["stop_reason"] = VIEWER_CLOSED
    with runfolder.removed_if_left_empty() as made:
        _make_folder("--out", out, made)
        with runfolder.locked(out):
            return recorder.write_outputs(out, result)


def _check_replay_output(key: str, path: Path, suffix: str) -> None:
    """Refuse replay's output file: another suffix, a folder, a folder that cannot be made."""
    if path.suffix.lower() != suffix:
        raise ConfigError(f"must be a {suffix} file, got {str(path)!r}", key=key)
    if path.is_dir():
        raise ConfigError(f"{str(path)!r} is a folder; give a file name", key=key)
    _check_folder(key, path.parent)


def _replay_recording(args: argparse.Namespace) -> Any:
    """The recording replay's options ask for, its frame width and colouring checked."""
    from swarmsim.replay import Recording

    recording = Recording.load(args.run_dir)
    _check_width(args.width, recording.world.arena)
    recording.offered_colourings(args.color_by)
    return recording


def _replay_view(args: argparse.Namespace) -> int:
    """``replay --view``: the live viewer stepping through the recorded samples."""
    from swarmsim.render.viewer import display_problem

    if display_problem(os.environ, sys.platform):  # before reading the recording
        run = str(args.run_dir)
        raise ConfigError("no display to open the viewer on (DISPLAY and WAYLAND_DISPLAY are "
                          f"unset): write a video with 'swarmsim replay {run} --video "
                          f"FILE.mp4', or run the viewer under a virtual X server: xvfb-run "
                          f"swarmsim replay {run} --view")
    from swarmsim.replay import replay_view

    recording = _replay_recording(args)
    viewer = replay_view(recording, width=args.width, color_by=args.color_by)
    print(f"{args.run_dir}: stopped at tick {viewer.sim.tick}"
          + "".join(f"; saved {p}" for p in viewer.saved))
    return 0


def cmd_replay(args: argparse.Namespace) -> int:
    """Draw a recorded run again (swarmsim.replay): its video, one sample as a PNG, or the
    samples in the live viewer."""
    check_count("--fps", args.fps, MAX_FPS, "video frames per second")
    _check_width(args.width)
    if args.tick is not None and not args.snapshot:
        raise ConfigError("draws one sample for --snapshot; --video and --view show them all",
                          key="--tick")
    if args.view:
        if args.highlight_contacts:
            raise ConfigError("is for --video and --snapshot; the viewer draws no contact "
                              "rings", key="--highlight-contacts")
        return _replay_view(args)
    key, path = ("--video", args.video) if args.video else ("--snapshot", args.snapshot)
    _check_replay_output(key, path, ".mp4" if args.video else ".png")
    recording = _replay_recording(args)
    if args.snapshot and args.tick is not None:
        recording.index_of(args.tick)
    with runfolder.removed_if_left_empty() as made:
        _make_folder(key, path.parent, made)
        print(_replay_write(args, recording, path))
    return 0


def _replay_write(args: argparse.Namespace, recording: Any, path: Path) -> str:
    """Write replay's --video or --snapshot at ``path``; the line that says what it wrote."""
    from swarmsim.render.frame import DEFAULT_WIDTH
    from swarmsim.replay import replay_png, replay_video

    options = {"color_by": args.color_by, "width": args.width or DEFAULT_WIDTH,
               "highlight_contacts": args.highlight_contacts}
    ticks = recording.ticks
    if args.video:
        frames = replay_video(recording, path, fps=args.fps, progress=not args.quiet, **options)
        return f"{path}: {frames} frames, ticks {int(ticks[0])} to {int(ticks[-1])}"
    replay_png(recording, path, tick=args.tick, **options)
    return f"{path}: tick {args.tick if args.tick is not None else int(ticks[-1])}"


def cmd_sweep(args: argparse.Namespace) -> int:
    from swarmsim.experiments import load_spec, run_sweep
    from swarmsim.experiments.executors import check_workers

    check_workers(args.workers)
    _check_folder("--out", args.out)  # made by the sweep once the runs and executor are valid
    runs = load_spec(args.spec).runs(unique=False)  # the sweep makes each run id once
    report = run_sweep(runs, args.out, workers=args.workers, scheduler=args.scheduler,
                       retry_failed=args.retry_failed, progress=not args.quiet)
    print(report.line())
    print(f"per condition: {args.out / 'aggregate'}")
    return 1 if report.failed else 0


def _names(text: str) -> list[str]:
    """A comma-separated list of names (``a,b``), spaces stripped."""
    return [n.strip() for n in text.split(",")]


def cmd_reproduce(args: argparse.Namespace) -> int:
    from swarmsim.experiments import reproduce as rp
    from swarmsim.experiments.executors import check_workers

    check_workers(args.workers)
    setup = rp.setup_with(rp.PAPER, args.world, args.robots,
                          _parse_set(args.set, robots=args.robots, max_ticks=args.max_ticks),
                          args.rulesets, args.ghost)
    if args.dry_run:
        print(rp.describe_plan(rp.plan(args.fig, setup, args.reps, args.max_ticks), args.out,
                               args.retry_failed,
                               rp.shared_runs(args.fig, setup, args.reps, args.max_ticks)))
        return 0
    _check_folder("--out", args.out)  # made by the sweep once every run is checked
    result = rp.reproduce(args.fig, args.out, setup, args.reps, args.max_ticks, args.workers,
                          args.scheduler, args.retry_failed, progress=not args.quiet)
    print(f"{result.sweep_line}\nreport: {result.report}")
    return 1 if result.failed else 0


def cmd_study(args: argparse.Namespace) -> int:
    from swarmsim.experiments.executors import check_workers

    if args.max_ticks is not None and args.max_ticks < 1:
        raise ConfigError(f"must be >= 1, got {args.max_ticks!r}", key="--max-ticks")
    if args.what != "realism":
        for name in REALISM_ONLY:
            if getattr(args, name) is not None:
                raise ConfigError(f"is an option of study realism, not {args.what}",
                                  key=f"--{name}")
    check_workers(args.workers)
    out = args.out = args.out if args.out is not None else Path("results") / args.what
    _check_folder("--out", out)  # made by the sweep once every run is checked
    extra = _parse_set(args.set, robots=args.robots, groups=args.groups, d_cover=args.d_cover,
                       max_ticks=args.max_ticks)
    groups = args.groups if args.groups is not None else extra.pop("groups", STUDY_GROUPS)
    common = {"world": args.world, "controller": args.controller, "robots": args.robots,
              "groups": groups, "d_cover": args.d_cover, "max_ticks": args.max_ticks,
              "extra": extra}
    if args.what == "realism":
        from swarmsim.experiments.realism import RealismSetup, study_realism

        setup = RealismSetup(**common, **_given(args, ("drives", "modes", "noise", "messages")))
        result = study_realism(setup, out, args.reps, args.workers, args.scheduler,
                               args.retry_failed, progress=not args.quiet)
    else:
        from swarmsim.experiments.collisions import StudySetup, study_collisions

        setup = StudySetup(**common, **_given(args, ("modes", "noise")))
        result = study_collisions(setup, out, args.reps, args.workers, args.scheduler,
                                  args.retry_failed, progress=not args.quiet)
    print(f"{result.sweep_line}\nreport: {result.report}")
    return 1 if result.failed else 0


def _given(args: argparse.Namespace, names: Sequence[str]) -> dict[str, tuple]:
    """The axis options among ``names`` given on the command line, as tuples without repeats
    (those not given keep the study's defaults)."""
    return {name: tuple(dict.fromkeys(getattr(args, name))) for name in names
            if getattr(args, name) is not None}


def _dispatch(args: argparse.Namespace) -> int:
    from swarmsim.experiments.runner import SweepError

    commands = {"sweep": cmd_sweep, "reproduce": cmd_reproduce, "study": cmd_study}
    try:
        with interrupts_unwrapped():
            return commands[args.command](args)
    except SweepError as exc:
        print(f"swarmsim: error: {exc}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        saved = (f"finished runs are saved in {args.out}" if Path(args.out).is_dir()
                 else "no run had finished (nothing is left behind)")
        print(f"swarmsim: interrupted; {saved}: run the same command again to resume",
              file=sys.stderr)
        return 130


@contextlib.contextmanager
def _terminate_as_interrupt() -> Iterator[None]:
    """Treat SIGTERM (``kill``, a batch system's time limit) like Ctrl-C while a command runs,
    so that it ends the same way: partial video files are removed, a sweep keeps its finished
    runs and says how to resume. Only in the main thread (where Python allows handlers)."""
    try:
        # Python's own Ctrl-C handler: raises KeyboardInterrupt
        previous = signal.signal(signal.SIGTERM, signal.default_int_handler)
    except ValueError:  # not the main thread
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    with _terminate_as_interrupt():
        try:
            return _main(args)
        except BrokenPipeError:  # the reader went away (swarmsim worlds | head): no traceback
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
            return 1


def _main(args: argparse.Namespace) -> int:
    try:
        with interrupts_unwrapped():
            return _command(args)
    except ConfigError as exc:
        print(f"swarmsim: error: {exc}", file=sys.stderr)
        return 2
    except ControllerError as exc:  # the line, then the controller's own traceback if it raised
        print(f"swarmsim: error: {exc}\n{exc.user_traceback()}".rstrip(), file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("swarmsim: interrupted", file=sys.stderr)
        return 130


def _command(args: argparse.Namespace) -> int:
    if args.command == "worlds":
        return cmd_worlds(args)
    if args.command == "make-world":
        return cmd_make_world(args)
    if args.command == "controllers":
        return cmd_controllers()
    if args.command == "params":
        return cmd_params(args.controller)
    if args.command in ("sweep", "reproduce", "study"):
        return _dispatch(args)
    if args.command == "view":
        return cmd_view(args)
    if args.command == "replay":
        return cmd_replay(args)
    return cmd_run(args)


if __name__ == "__main__":
    sys.exit(main())
