"""Where a run's walking goes: distance by final status, and where the last robots arrived.

    python examples/where_distance_goes.py                      # 'tiny', a few seconds
    python examples/where_distance_goes.py K --seed 0 --late-from 13000   # minutes

Runs GGC (or --controller) like ``swarmsim run`` and keeps, per robot, the distance it moved
(units) and the tick it settled. Prints the distance of the robots in each status at the end
(did the walking go to robots that found a place, or to robots that never did?) and every
robot that settled after ``--late-from`` (tick, id, group, position, coverage then). On K with
3 groups this is how the interior holes that end a run were found
(docs/reports/ggc-findings-journal.md).
It also splits the distance by the status each robot had as it moved, and by whether it was
driven (a velocity commanded that tick) or pushed (moved by contacts with none commanded):
travel in formation shows as Initial, walking to a place as Coverage.
"""

from __future__ import annotations

import argparse

import numpy as np

from swarmsim import Simulation
from swarmsim.errors import ConfigError


def parse_args() -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("world", nargs="?", default="tiny", help="world name or .toml path")
    parser.add_argument("--controller", default="ggc")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--groups", type=int, default=None, help="default: the world's")
    parser.add_argument("--late-from", type=int, default=0, metavar="TICK",
                        help="list the robots that settle after this tick (default 0: all)")
    return parser.parse_args()


class Ledger:
    """Per-robot distance (units) and the tick each robot first settled, kept tick by tick
    through ``Simulation.run(on_tick=...)``."""

    def __init__(self, sim: Simulation, late_from: int):
        self.settled_codes = sim.settled_codes()
        self.distance = np.zeros(sim.n)
        self.settled_at = np.full(sim.n, -1)
        self.late_from = late_from
        self.late: list[tuple[int, int, np.ndarray, float]] = []
        self._last = sim.positions
        self._status = sim.messages["status"].copy()
        n_status = len(sim.statuses) + 1  # the last row: no status (-1)
        self.driven = np.zeros(n_status)  # units moved, by status during the move
        self.pushed = np.zeros(n_status)

    def __call__(self, sim: Simulation) -> None:
        step = np.hypot(*(sim.positions - self._last).T)
        self.distance += step
        self._last = sim.positions
        driven = sim.velocities.any(axis=1)  # what the robots were told this tick
        # the status each robot decided this tick with (its broadcast of the tick before)
        np.add.at(self.driven, self._status[driven], step[driven])
        np.add.at(self.pushed, self._status[~driven], step[~driven])
        self._status = sim.messages["status"].copy()
        settled = np.isin(sim.messages["status"], self.settled_codes)
        for i in np.flatnonzero(settled & (self.settled_at < 0)).tolist():
            self.settled_at[i] = sim.tick
            if sim.tick > self.late_from:
                self.late.append((sim.tick, i, sim.positions[i], sim.metrics.coverage))


def report(sim: Simulation, ledger: Ledger, summary: dict) -> None:
    distance = ledger.distance
    status = np.array([sim.statuses[int(s)] for s in sim.messages["status"]])
    print(f"{sim.world.name}: ended at tick {summary['ticks']} ({summary['stop_reason']}), "
          f"coverage {summary['coverage']:.4f}, total distance {distance.sum():.0f}")
    for name in sorted(set(status.tolist())):
        mine = status == name
        share = 100 * distance[mine].sum() / max(distance.sum(), 1e-12)
        print(f"  {name:<10} {int(mine.sum()):5d} robots  {distance[mine].sum():10.0f} units"
              f"  ({share:4.1f} %)")
    print("by the status robots moved in (driven: velocity commanded; pushed: none):")
    names = [*sim.statuses, "none"]
    for k in np.flatnonzero(ledger.driven + ledger.pushed).tolist():
        print(f"  {names[k]:<10} driven {ledger.driven[k]:10.0f}  pushed {ledger.pushed[k]:8.0f}")
    print(f"settled after tick {ledger.late_from}: {len(ledger.late)}")
    fields = sim.messages.dtype.names or ()
    for tick, i, (x, y), coverage in ledger.late:
        group = f" group {int(sim.messages['group'][i])}" if "group" in fields else ""
        print(f"  tick {tick:6d}  robot {i:4d}{group}  at ({x:6.1f}, {y:6.1f})  "
              f"coverage {coverage:.4f}")


def main() -> None:
    args = parse_args()
    try:
        sim = Simulation(args.world, controller=args.controller, groups=args.groups,
                         seed=args.seed)
    except ConfigError as err:  # a bad world, controller or group count: say which
        raise SystemExit(f"where_distance_goes: error: {err}") from None
    ledger = Ledger(sim, args.late_from)
    result = sim.run(progress=True, on_tick=ledger)
    report(sim, ledger, result.summary)


if __name__ == "__main__":
    main()
