"""Per phase, what a tick costs and what it costs per awake robot; and pymunk sleeping on vs off.

Two measurements:

``sizes`` (default): for each swarm size (600, 2,000, 10,000 robots) in bench_tick.py's
square world, in a fresh process (its peak resident memory is its own), after --warmup ticks it
times --ticks ticks per block and prints, as the median of --repeats blocks:

- ms per tick of each phase (sense, decide, physics, metrics) and of the whole tick;
- microseconds per awake robot of each phase: sense, decide and metrics per robot the engine
  decided (``awake``), physics per robot body awake in pymunk (``pm-awake``: not asleep);
- ``bare``: pymunk's bare step (Space.step, substeps a tick) of the same bodies right after
  each block;
- peak RSS of the process, MB;
- at the end, the log-log slope of the tick cost (and of the bare step) from the second-
  smallest size to the largest: log(cost ratio) / log(size ratio); 1.0 is linear.

With --pair, each size's process runs two simulations, pymunk sleeping on and off, taking
turns block by block (warm-up too), prints both and the ratios on / off; the peak memory is
then that of both runs together.

``compare``: one world and seed run twice in ONE process, pymunk sleeping on and off
(PhysicsConfig.physics_sleep), taking turns in blocks of --block ticks, so that both meet the
same machine. Prints each run's phases in ms per tick over the ticks both ran, and the ratio
on / off of the physics phase per tick, block by block (median and quartiles) and whole.
The two runs are the same physics but part ways after a few hundred ticks (contacts are
solved in another order), so they compare like two seeds, not tick by tick.

    python bench/bench_phases.py                                   # 600 2000 10000 robots
    python bench/bench_phases.py sizes --robots 600 2000 --ticks 50
    python bench/bench_phases.py compare --world house --ticks 3000
    python bench/bench_phases.py sizes --settings physics_sleep=false    # the default
    python bench/bench_phases.py sizes --pair        # sleeping on and off, taking turns

These machines are noisy (+-30 %): compare within one run of the script, not across runs.
"""

from __future__ import annotations

import argparse
import math
import multiprocessing
import resource
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_tick import square_world

from swarmsim import Simulation
from swarmsim.engine.sim import PHASES
from swarmsim.limits import MAX_TICKS


def parse_settings(pairs: list[str]) -> dict:
    """``key=value`` strings to a settings dict (true/false, ints and floats converted)."""
    out: dict = {}
    for pair in pairs:
        key, _, value = pair.partition("=")
        low = value.lower()
        if low in ("true", "false"):
            out[key] = low == "true"
            continue
        try:
            out[key] = int(value)
        except ValueError:
            try:
                out[key] = float(value)
            except ValueError:
                out[key] = value
    return out


def pymunk_awake(sim: Simulation) -> int:
    """Robot bodies not asleep in pymunk."""
    return int(sim.n - sim.physics.bodies_asleep().sum())


def measure(robots: int, controller: str, warmup: int, ticks: int, repeats: int,
            settings: dict, pair: bool = False) -> dict:
    """Phase costs (ms per tick), per-awake-robot costs (us) and the bare step, medians.

    With ``pair``, two runs in this process, pymunk sleeping on and off, take turns block by
    block (warm-up too); the result holds both, under "on" and "off".
    """
    variants = {"on": True, "off": False} if pair else {"": settings.get("physics_sleep", True)}
    sims = {name: Simulation(square_world(robots), controller=controller, robots=robots, seed=1,
                             max_ticks=MAX_TICKS, settings={**settings, "physics_sleep": sleep})
            for name, sleep in variants.items()}
    for _ in range(0, warmup, ticks):
        for sim in sims.values():
            for _ in range(min(ticks, warmup - sim.tick)):
                sim.step()
    blocks: dict[str, list[dict]] = {name: [] for name in sims}
    for _ in range(repeats):
        for name, sim in sims.items():
            blocks[name].append(_block(sim, ticks))
    out = {name: {k: statistics.median(b[k] for b in blocks[name]) for k in blocks[name][0]}
           for name in sims}
    for r in out.values():
        r["robots"] = robots
    return out if pair else out[""]


def _block(sim: Simulation, ticks: int) -> dict:
    """One measured block of ``ticks`` ticks, then as many bare steps."""
    before = dict(sim.phase_seconds)
    awake = pm_awake = 0
    start = time.perf_counter()
    for _ in range(ticks):
        sim.step()
        awake += sim.metrics.rows[-1]["awake"] if sim.metrics.rows else sim.n
        pm_awake += pymunk_awake(sim)
    wall = time.perf_counter() - start
    ms = {k: (sim.phase_seconds[k] - before[k]) / ticks * 1e3 for k in PHASES}
    ms["tick"] = wall / ticks * 1e3
    ms["awake"], ms["pm_awake"] = awake / ticks, pm_awake / ticks
    space, substeps = sim.physics.space, sim.physics.config.substeps
    bare_start = time.perf_counter()
    for _ in range(ticks * substeps):
        space.step(1.0 / substeps)  # the same bodies, the same drive commands
    ms["bare"] = (time.perf_counter() - bare_start) / ticks * 1e3
    return ms


def _measure_with_memory(*args) -> dict:
    out = measure(*args)
    out = {"runs": out} if "on" in out else out
    out["peak_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # KB on Linux
    return out


def sizes(args: argparse.Namespace) -> None:
    settings = parse_settings(args.settings)
    print(f"{args.controller} {settings or ''}: ms per tick per phase, median of {args.repeats}"
          f" blocks of {args.ticks} ticks after {args.warmup}; us per awake robot (physics: "
          "per robot awake in pymunk); bare = pymunk's step of the same bodies"
          + ("; pymunk sleeping on and off, two runs in one process taking turns"
             if args.pair else ""))
    print(f"{'robots':>9}{'awake':>7}{'pm-awake':>9}" + "".join(f"{p:>8}" for p in PHASES)
          + f"{'tick':>8}{'bare':>8}  |" + "".join(f"{p[:6] + ' us':>10}" for p in PHASES)
          + f"{'peak MB':>9}")
    ctx = multiprocessing.get_context("spawn")
    results: dict[str, list[dict]] = {}
    for n in sorted(args.robots):
        with ctx.Pool(1) as pool:
            out = pool.apply(_measure_with_memory, (n, args.controller, args.warmup, args.ticks,
                                                    args.repeats, settings, args.pair))
        for name, r in (out["runs"].items() if args.pair else [("", out)]):
            r["peak_mb"] = out["peak_mb"]
            results.setdefault(name, []).append(r)
            _print_row(r, f"{n} {name}".strip())
        if args.pair:
            on, off = out["runs"]["on"], out["runs"]["off"]
            print(f"{'':>9}physics phase on / off {on['physics'] / off['physics']:.2f}, tick "
                  f"{on['tick'] / off['tick']:.2f}, bare step {on['bare'] / off['bare']:.2f}")
    for name, rows in results.items():
        if len(rows) >= 2:
            a, b = rows[-2] if len(rows) > 2 else rows[0], rows[-1]
            span = math.log(b["robots"] / a["robots"])
            slope = {k: math.log(b[k] / a[k]) / span for k in ("tick", "bare", "physics")}
            print(f"log-log slope {a['robots']} -> {b['robots']} robots{' ' + name if name else ''}"
                  f": tick {slope['tick']:.2f}, physics phase {slope['physics']:.2f}, "
                  f"bare step {slope['bare']:.2f}")


def _print_row(r: dict, label: str) -> None:
    per = [r[p] * 1e3 / max(r["pm_awake" if p == "physics" else "awake"], 1.0) for p in PHASES]
    print(f"{label:>9}{r['awake']:>7.0f}{r['pm_awake']:>9.0f}"
          + "".join(f"{r[p]:>8.2f}" for p in PHASES) + f"{r['tick']:>8.2f}{r['bare']:>8.2f}"
          + "  |" + "".join(f"{u:>10.2f}" for u in per) + f"{r['peak_mb']:>9.0f}", flush=True)


def compare(args: argparse.Namespace) -> None:
    settings = parse_settings(args.settings)
    sims = {name: Simulation(args.world, seed=args.seed, max_ticks=args.ticks or None,
                             settings={**settings, "physics_sleep": name == "on"})
            for name in ("off", "on")}
    ratios: list[float] = []
    while not any(sim.stop_reason is not None for sim in sims.values()):
        spent = {}
        for name, sim in sims.items():  # taking turns
            before, start = sim.phase_seconds["physics"], sim.tick
            while sim.tick < start + args.block and sim.stop_reason is None:
                sim.advance()
            spent[name] = (sim.phase_seconds["physics"] - before, sim.tick - start)
        if spent["on"][1] == spent["off"][1] == args.block:
            ratios.append(spent["on"][0] / spent["off"][0])
    both = min(sim.tick for sim in sims.values())
    print(f"{args.world} seed {args.seed}: pymunk sleeping on vs off in one process, blocks of "
          f"{args.block} ticks taking turns; off ran {sims['off'].tick} ticks"
          f"{' (ended)' if sims['off'].stop_reason else ''}, on {sims['on'].tick}"
          f"{' (ended)' if sims['on'].stop_reason else ''}")
    for name, sim in sims.items():
        cells = ", ".join(f"{p} {sim.phase_seconds[p] / sim.tick * 1e3:.2f}" for p in PHASES)
        print(f"  {name:>3}: ms per tick over its {sim.tick} ticks: {cells}; asleep now "
              f"{int(sim.physics.bodies_asleep().sum())} of {sim.n}")
    per_tick = {k: sims[k].phase_seconds["physics"] / sims[k].tick for k in sims}
    q = statistics.quantiles(ratios, n=4) if len(ratios) > 1 else ratios * 3
    print(f"  physics phase per tick, on / off: {per_tick['on'] / per_tick['off']:.3f} whole;"
          f" block by block median {statistics.median(ratios):.3f} (quartiles {q[0]:.3f}-"
          f"{q[2]:.3f}, {len(ratios)} blocks of both runs before tick {both})")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="what")
    s = sub.add_parser("sizes", help="per-phase costs at several swarm sizes (default)")
    s.add_argument("--robots", type=int, nargs="+", default=[600, 2000, 10000])
    s.add_argument("--controller", default="ggc")
    s.add_argument("--warmup", type=int, default=600, help="ticks before measuring")
    s.add_argument("--ticks", type=int, default=100, help="ticks per measured block")
    s.add_argument("--repeats", type=int, default=3, help="measured blocks (median)")
    s.add_argument("--settings", nargs="*", default=[], help="key=value run settings")
    s.add_argument("--pair", action="store_true",
                   help="pymunk sleeping on and off: two runs in one process taking turns")
    c = sub.add_parser("compare", help="pymunk sleeping on vs off, one process, taking turns")
    c.add_argument("--world", default="house")
    c.add_argument("--seed", type=int, default=0)
    c.add_argument("--ticks", type=int, default=3000, help="stop here (0: run to the end)")
    c.add_argument("--block", type=int, default=250, help="ticks per turn")
    c.add_argument("--settings", nargs="*", default=[], help="key=value run settings")
    args = parser.parse_args(sys.argv[1:] or ["sizes"])
    if args.what == "compare":
        compare(args)
    else:
        sizes(args)


if __name__ == "__main__":
    main()
