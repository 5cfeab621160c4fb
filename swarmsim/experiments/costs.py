"""The paper's Table 3, measured: each controller's communication and computing cost.

Table 3 rates methods qualitatively: CVT (and LFS, DD, CADT) communicate much and compute much;
GGC, DASH, FCDFS and Kilobot little. This figure ("table3") measures both on Figure 24's runs
(the same panel, :func:`.figures.comparison_panel`: no run of its own) from each run's cost
fields in summary.json (swarmsim/engine/costs.py, docs/outputs.md):

- communication: broadcasts heard per robot-tick, bytes per broadcast, and their product, the
  bytes a deciding robot receives per tick (:data:`COMMUNICATION`);
- computing: the controller's CPU milliseconds per robot-tick (:data:`COMPUTING`): a timing of
  this implementation on this machine, not an operation count.

A comparison is consistent only where it holds beyond the spread between seeds (significant
at 95 %: Welch's interval of the difference of means, :func:`.evidence.compare`), else "not
resolved at N runs".
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from swarmsim.experiments.evidence import CONTRADICTS, HOLDS, compare, less
from swarmsim.experiments.figures import Claim, Context, FigureTable, num_text, panel_runs
from swarmsim.experiments.runner import DONE
from swarmsim.experiments.verdicts import (
    CONSISTENT,
    NOT_CONSISTENT,
    NOT_MEASURED,
    PARTLY,
    not_resolved,
)

KEY = "table3"
"""The figure's key in the registry (swarmsim.experiments.reproduce.FIGURES)."""

HEARD, BYTES, COMMUNICATION, COMPUTING = (
    "messages_heard_per_robot_tick", "message_bytes", "bytes_heard_per_robot_tick",
    "controller_ms_per_robot_tick")
"""The measures: summary.json's fields, and bytes heard (their product, per run)."""


@dataclass(frozen=True)
class Measure:
    """One column of the table: a per-run value, its label and its number format."""

    key: str
    label: str
    digits: int


MEASURES = (Measure(HEARD, "messages heard / robot-tick", 2),
            Measure(BYTES, "bytes / broadcast", 0),
            Measure(COMMUNICATION, "bytes heard / robot-tick", 1),
            Measure(COMPUTING, "controller ms / robot-tick", 4))

SMALL_COMMUNICATION = ("dash", "fcdfs", "kilobot")
"""Table 3's other methods with small communication costs, besides GGC (and in Figure 24)."""
LARGE = "cvt"
"""Table 3's method with large communication and computing costs (in Figure 24)."""


def run_costs(summary: Mapping[str, Any]) -> dict[str, float] | None:
    """A run's value of each measure, or None for a run whose summary has no cost fields
    (made before they existed) or in which no robot decided."""
    heard, size, ms = (summary.get(k) for k in (HEARD, BYTES, COMPUTING))
    if heard is None or size is None or ms is None:
        return None
    return {HEARD: float(heard), BYTES: float(size), COMMUNICATION: float(heard) * float(size),
            COMPUTING: float(ms)}


@dataclass(frozen=True)
class ControllerCosts:
    """One controller's measures over its finished runs (one value per run that has them).

    Attributes:
        controller: its name (the condition's label).
        runs: runs asked for (its seeds).
        values: per measure key, the values of its runs that measured them, by seed.
    """

    controller: str
    runs: int
    values: Mapping[str, tuple[float, ...]]

    @property
    def measured(self) -> int:
        """How many runs measured the costs."""
        return len(self.values.get(HEARD, ()))

    def mean(self, key: str) -> float | None:
        vals = self.values.get(key, ())
        return sum(vals) / len(vals) if vals else None


def controller_costs(ctx: Context, key: str = KEY) -> list[ControllerCosts]:
    """Each condition's (controller's) costs in ``ctx``'s runs of figure ``key``."""
    store = ctx.sweep.store
    panel = ctx.panels(key)[0]
    out = []
    for cond, runs in zip(panel.conditions, panel_runs(panel, ctx.setup, ctx.reps,
                                                       ctx.max_ticks), strict=True):
        found = [run_costs(store.summary(r.run_id)) for r in runs
                 if store.status(r.run_id) == DONE]
        measured = [f for f in found if f is not None]
        out.append(ControllerCosts(str(cond.value), len(runs),
                                   {m.key: tuple(f[m.key] for f in measured) for m in MEASURES}))
    return out


# ----------------------------------------------------------------------------- verdicts
def less_beyond_spread(small: Sequence[float], large: Sequence[float]) -> str:
    """Is ``small`` below ``large`` beyond the spread between seeds (significant at 95 %, as
    :mod:`.verdicts` judges: :func:`.evidence.compare`)? CONSISTENT,
    NOT_CONSISTENT when it lies wholly above, else "not resolved at N runs" (N: the fewer
    values of the two; also with fewer than 2 a side); NOT_MEASURED without values."""
    if not small or not large:
        return NOT_MEASURED
    outcome = less(compare(small, large))
    return {HOLDS: CONSISTENT, CONTRADICTS: NOT_CONSISTENT}.get(
        outcome, not_resolved(min(len(small), len(large))))


def combine(verdicts: Sequence[str]) -> str:
    """All comparisons consistent: consistent; some contradicted: partly (if others hold) or
    not consistent; none contradicted but some not resolved: the least resolved's verdict
    ("not resolved at N runs", smallest N); anything not measured: not measured."""
    if not verdicts or NOT_MEASURED in verdicts:
        return NOT_MEASURED
    if all(v == CONSISTENT for v in verdicts):
        return CONSISTENT
    if NOT_CONSISTENT in verdicts:
        return PARTLY if CONSISTENT in verdicts else NOT_CONSISTENT
    unresolved = [v for v in verdicts if v != CONSISTENT]
    return min(unresolved, key=lambda v: int(v.split()[-2]))


def _spread_text(c: ControllerCosts, m: Measure) -> str:
    """'mean [min, max]' of a measure over a controller's runs ('n/a' without any)."""
    vals = c.values.get(m.key, ())
    if not vals:
        return "n/a"
    fmt = f"{{:.{m.digits}f}}"
    if min(vals) == max(vals):
        return fmt.format(vals[0])
    return f"{fmt.format(sum(vals) / len(vals))} [{fmt.format(min(vals))}, {fmt.format(max(vals))}]"


def _ratio(c: ControllerCosts, base: ControllerCosts | None, key: str) -> float | None:
    """Mean of ``c`` over the mean of ``base`` (None when either is missing or base is 0)."""
    a, b = c.mean(key), None if base is None else base.mean(key)
    return None if a is None or not b else a / b


def _versus(costs: Sequence[ControllerCosts], pivot: str, rivals: Sequence[str],
             measure: Measure, rivals_below: bool) -> tuple[str, list[str]]:
    """Measured text and verdicts of "each of ``rivals`` is below (``rivals_below``) or
    above ``pivot``" on ``measure``, beyond the spread between seeds."""
    by = {c.controller: c for c in costs}
    names = [*rivals, pivot] if rivals_below else [pivot, *rivals]  # the smaller side first
    text = "; ".join(f"{n} {_spread_text(by[n], measure)}" for n in names if n in by)
    verdicts = []
    for name in rivals:
        if pivot not in by or name not in by:
            verdicts.append(NOT_MEASURED)
            continue
        mine, theirs = by[pivot].values[measure.key], by[name].values[measure.key]
        verdicts.append(less_beyond_spread(theirs, mine) if rivals_below
                        else less_beyond_spread(mine, theirs))
    return f"{measure.label}, mean [min, max] over seeds: {text}", verdicts


def communication_claim(costs: Sequence[ControllerCosts], study: str = "ggc") -> Claim:
    """Table 3's communication cost: the controller under study and DASH, FCDFS, Kilobot each
    hear fewer bytes per robot-tick than CVT, beyond the spread between seeds (:func:`combine`
    of the comparisons; not consistent whenever the controller under study's is
    contradicted, whatever the baselines')."""
    by = {c.controller: c for c in costs}
    small = [study, *(n for n in SMALL_COMMUNICATION if n in by and n != study)]
    measure = next(m for m in MEASURES if m.key == COMMUNICATION)
    text, verdicts = _versus(costs, LARGE, small, measure, rivals_below=True)
    ratio = _ratio(by[LARGE], by.get(study), COMMUNICATION) if LARGE in by else None
    measured = text + ("" if ratio is None else f"; {LARGE}/{study} {ratio:.2f}")
    verdict = NOT_CONSISTENT if verdicts[0] == NOT_CONSISTENT else combine(verdicts)
    return Claim(
        "GGC's communication cost is small (like DASH, FCDFS, Kilobot) and CVT's large",
        measured, verdict,
        test=(f"bytes a deciding robot hears per tick (broadcasts heard x bytes per broadcast) "
              f"of each of {', '.join(small)} below {LARGE}'s beyond the spread between seeds "
              f"(Welch's 95% interval); {study} above {LARGE} is not consistent, a baseline above "
              "it partly"),
        where=("Figure 24's runs (the paper's setup); swarmsim's CVT senses its neighbours' "
               "positions and a local floor map instead of asking for them, so its broadcasts "
               "carry only id, status and moving"),
        paper=("Table 3: CVT, LFS, DD, CADT: communication delay exists; DASH, FCDFS, Kilobot, "
               "GGC: not; Section 6.8: 'a large amount of communication between each other' "
               "vs 'small communication costs'"))


def computing_claim(costs: Sequence[ControllerCosts], study: str = "ggc") -> Claim:
    """Table 3's computing cost: the controller under study spends less controller CPU time
    per robot-tick than CVT, beyond the spread between seeds."""
    by = {c.controller: c for c in costs}
    measure = next(m for m in MEASURES if m.key == COMPUTING)
    text, verdicts = _versus(costs, study, [LARGE], measure, rivals_below=False)
    ratio = _ratio(by[LARGE], by.get(study), COMPUTING) if LARGE in by else None
    measured = text + ("" if ratio is None else f"; {LARGE}/{study} {ratio:.1f}")
    return Claim(
        "GGC's computing cost is small and CVT's large", measured, combine(verdicts),
        test=(f"{study}'s controller CPU ms per robot-tick below {LARGE}'s beyond the spread "
              "between seeds (Welch's 95% interval)"),
        where=("Figure 24's runs; CPU time of this implementation on this machine (every "
               "method decides a chunk of robots in one compiled call), not an operation "
               "count"),
        paper="Table 3: computing cost CVT large, GGC small; Section 6.8: 'minimal computation'")


def claims_table3(ctx: Context) -> list[Claim]:
    """Table 3's claims judged on ``ctx``'s runs of Figure 24."""
    costs = controller_costs(ctx)
    study = ctx.setup.controller
    return [communication_claim(costs, study), computing_claim(costs, study)]


# ----------------------------------------------------------------------------- the table
def cost_rows(costs: Sequence[ControllerCosts], study: str) -> tuple[dict[str, Any], ...]:
    """table.csv's rows: per controller, each measure's mean, min, max and ratio to the
    controller under study's mean."""
    base = next((c for c in costs if c.controller == study), None)
    rows = []
    for c in costs:
        row: dict[str, Any] = {"controller": c.controller, "runs": c.runs,
                               "measured": c.measured}
        for m in MEASURES:
            vals = c.values.get(m.key, ())
            ratio = _ratio(c, base, m.key)
            row |= {f"{m.key}_mean": None if not vals else round(sum(vals) / len(vals), 6),
                    f"{m.key}_min": min(vals, default=None),
                    f"{m.key}_max": max(vals, default=None),
                    f"{m.key}_vs_{study}": None if ratio is None else round(ratio, 4)}
        rows.append(row)
    return tuple(rows)


def cost_markdown(costs: Sequence[ControllerCosts], study: str) -> str:
    """The table per controller: each measure as 'mean [min, max]' over seeds, and the
    ratios of the communication and computing means to the controller under study's."""
    base = next((c for c in costs if c.controller == study), None)
    head = ["controller", "runs measured", *(m.label for m in MEASURES),
            f"bytes heard, x {study}", f"controller ms, x {study}"]
    lines = ["| " + " | ".join(head) + " |", "|" + "|".join("---" for _ in head) + "|"]
    for c in costs:
        ratios = [_ratio(c, base, k) for k in (COMMUNICATION, COMPUTING)]
        cells = [c.controller, f"{c.measured}/{c.runs}",
                 *(_spread_text(c, m) for m in MEASURES),
                 *("n/a" if r is None else num_text(round(r, 2)) for r in ratios)]
        lines.append("| " + " | ".join(cells) + " |")
    note = ("Per robot-tick: per robot deciding in a tick (not asleep, not failed); "
            "mean [min, max] over seeds; docs/outputs.md defines each field.")
    return "\n".join(lines) + "\n\n" + note


def table3(ctx: Context) -> FigureTable:
    """The figure's table (a :class:`.figures.FigureTable`) for ``ctx``'s rule set."""
    costs = controller_costs(ctx)
    study = ctx.setup.controller
    return FigureTable(cost_rows(costs, study), cost_markdown(costs, study))


__all__ = ["COMMUNICATION", "COMPUTING", "KEY", "MEASURES", "ControllerCosts", "Measure",
           "claims_table3", "combine", "communication_claim", "computing_claim",
           "controller_costs", "cost_markdown", "cost_rows", "less_beyond_spread",
           "not_resolved", "run_costs", "table3"]
