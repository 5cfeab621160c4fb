"""``swarmsim reproduce FIG``: the paper's Section 6 experiments (Figures 14, 17-24), resumably.

The registry (:data:`FIGURES`) says which runs each figure needs; :class:`PaperSetup` holds the
world, robot count and parameter values they share: change them there (or with the CLI's
``--world``, ``--robots`` and ``--set``). Figures that plot the same runs share them: a run's
id is a hash of its parameters and seed, and all figures keep their runs in one store
(``DIR/runs/<id>/``), so Figures 19/20/22 reuse the runs of 17/18/21, and the d_cover = 6,
3-group runs of Figure 18 are also Figure 21's K = 3 and Figure 23's 0-failure runs.

GGC is judged under each rule set of :meth:`PaperSetup.judged_rulesets` (its default and the
paper's): every figure's GGC runs are made once per rule set, and each output shows the rule
sets side by side (one column each, see :meth:`PaperSetup.columns`). A run that is the same
under two rule sets by construction (the controller's ``same_run_settings``, see
:func:`.spec.run_id`) has one id: it is made once and shown in each column, with the column's
own settings in the figure's results.csv.

Outputs, for each figure: ``DIR/<fig>/results.csv`` (one row per run), ``conditions.csv``
(mean, sd per condition), ``claims.csv`` (each claim's measurement and verdict),
``<fig>.png`` (mean curves with a min-max band, on a common tick
grid; runs that stopped early hold their last value; ``table3``, the paper's Table 3 measured
on Figure 24's runs, writes ``table.csv`` instead) and ``REPORT.md`` (the paper's claims next
to what was measured, with a verdict); ``DIR/REPORT.md`` collects every figure reproduced so
far in DIR (its code and run-time lines count every finished run in ``DIR/runs``, and each
figure's section names the setup and code it was made with), ``DIR/claims.csv`` every claim
of those figures, ``DIR/results.csv`` the runs of the figures asked for this time. How the
claims are judged: :mod:`.verdicts` and docs/reproduction/README.md.

Robot counts: the paper uses 603 robots on 'K' for every figure. At d_cover = 1, 2 or 4 a
lattice over K needs ~15,300 / ~3,800 / ~960 robots, so 603 cannot fill it; we keep 603 (the
world's default), report the coverage reached (the report lists the lattice capacity next
to it), and judge every d_cover claim only at the d_cover values the robots fill.

This module holds the registry and the entry point; the rest lives in :mod:`.figures` (the
setup, the figure types, the panel builders and the analysis of runs), :mod:`.verdicts` (the
paper's claims, judged) and :mod:`.report` (tables, plots and reports).
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from swarmsim.errors import ConfigError
from swarmsim.experiments.costs import claims_table3, table3
from swarmsim.experiments.figures import (
    PAPER,
    Condition,
    CondStats,
    Context,
    Figure,
    PaperSetup,
    comparison_panel,
    dcover_panel,
    failure_panels,
    groups_panel,
    num_text,
    panel_runs,
    random_start_panel,
)
from swarmsim.experiments.report import (
    store_totals,
    versions_line,
    write_figure,
    write_report,
)
from swarmsim.experiments.runner import DONE, RunStore, Sweep
from swarmsim.experiments.spec import RunSpec, check_runs, unique_runs
from swarmsim.experiments.startclaims import claims_fig14, junction_claims
from swarmsim.experiments.verdicts import (
    CONSISTENT,
    claims_fig17,
    claims_fig18,
    claims_fig19,
    claims_fig20,
    claims_fig21,
    claims_fig22,
    claims_fig23,
    claims_fig24,
    dcover_distance_claims,
)
from swarmsim.limits import MAX_REPS, MAX_TICKS, check_count


# ----------------------------------------------------------------------------- runs
def figure_runs(key: str, setup: PaperSetup = PAPER, reps: int = 3,
                max_ticks: int | None = None) -> list[RunSpec]:
    """Every run a figure needs, each once."""
    fig = get_figure(key)
    return unique_runs(run for panel in fig.build(setup)
                       for runs in panel_runs(panel, setup, reps, max_ticks) for run in runs)


def get_figure(key: str) -> Figure:
    if key not in FIGURES:
        raise ConfigError(f"unknown figure {key!r}; available: {', '.join(FIGURES)}, all",
                          key="FIG")
    return FIGURES[key]


def figure_keys(which: str | Sequence[str]) -> list[str]:
    """``"all"`` or figure names -> registry keys (validated)."""
    names = [which] if isinstance(which, str) else list(which)
    if "all" in names:
        return list(FIGURES)
    for n in names:
        get_figure(n)
    return names


# ----------------------------------------------------------------------------- registry
FIGURES: dict[str, Figure] = {
    "fig14": Figure("fig14", "Figure 14: grouping, aggregation and coverage from a random start",
                    random_start_panel, claims_fig14),
    "fig17": Figure("fig17", "Figure 17: coverage rate vs d_cover, not grouped",
                    lambda s: dcover_panel(s, 1, "coverage"), claims_fig17),
    "fig18": Figure("fig18", "Figure 18: coverage rate vs d_cover, 3 groups",
                    lambda s: dcover_panel(s, s.groups, "coverage"),
                    lambda ctx: claims_fig18(ctx) + junction_claims(ctx)),
    "fig19": Figure("fig19", "Figure 19: total distance vs d_cover, not grouped",
                    lambda s: dcover_panel(s, 1, "total_distance"), claims_fig19),
    "fig20": Figure("fig20", "Figure 20: total distance vs d_cover, 3 groups",
                    lambda s: dcover_panel(s, s.groups, "total_distance"), claims_fig20),
    "fig21": Figure("fig21", "Figure 21: coverage rate vs number of groups",
                    lambda s: groups_panel(s, "coverage"), claims_fig21),
    "fig22": Figure("fig22", "Figure 22: total distance vs number of groups",
                    lambda s: groups_panel(s, "total_distance"), claims_fig22),
    "fig23": Figure("fig23", "Figure 23: coverage with failed robots",
                    failure_panels, claims_fig23),
    "fig24": Figure("fig24", "Figure 24: comparison of coverage algorithms",
                    comparison_panel, claims_fig24),
    "table3": Figure("table3", "Table 3: communication and computing costs (Figure 24's runs)",
                     comparison_panel, claims_table3, table=table3),
}
"""The paper's Section 6 experiments, and Figure 14's run from a random start (Section 6.1).
Figures 19/20/22 plot the runs of 17/18/21; Figure 18 also judges the gaps where groups meet
(.startclaims), against Figure 17's runs; Table 3 measures Figure 24's runs
(swarmsim/experiments/costs.py)."""


# ----------------------------------------------------------------------------- entry point
@dataclass
class ReproduceResult:
    figures: list[str]
    report: Path | None
    sweep_line: str
    runs: int
    failed: int = 0


def plan(which: str | Sequence[str], setup: PaperSetup = PAPER, reps: int = 3,
         max_ticks: int | None = None) -> dict[str, list[RunSpec]]:
    """The runs of each requested figure (the registry expanded)."""
    check_count("--reps", reps, MAX_REPS, "seeds per condition")
    if max_ticks is not None:
        check_count("--max-ticks", max_ticks, MAX_TICKS, "ticks in one run")
    columns = setup.columns()
    runs = {k: unique_runs(r for col in columns for r in figure_runs(k, col, reps, max_ticks))
            for k in figure_keys(which)}
    check_runs(unique_runs(r for rs in runs.values() for r in rs), "reproduce")
    return runs


def reproduce(which: str | Sequence[str], out: str | Path, setup: PaperSetup = PAPER,
              reps: int = 3, max_ticks: int | None = None, workers: int | None = None,
              scheduler: Any = None, retry_failed: bool = False, progress: bool = True,
              on_result: Callable | None = None) -> ReproduceResult:
    """Run (or resume) the figures' runs, then write their tables, plots and reports."""
    out = Path(out)
    runs = plan(which, setup, reps, max_ticks)
    all_runs = unique_runs(r for rs in runs.values() for r in rs)
    sweep = Sweep(all_runs, out, runs_dir=out / "runs", table_path=out / "results.csv")
    report = sweep.run(workers, scheduler, retry_failed, progress, on_result)
    contexts = [Context(sweep, col, reps, max_ticks, get_figure) for col in setup.columns()]
    for key in runs:
        write_figure(FIGURES[key], contexts, out)
    versions, seconds = store_totals(out / "runs")  # every figure of the folder's runs
    path = write_report(out, list(FIGURES), setup, versions, seconds)
    return ReproduceResult(list(runs), path, report.line(), len(all_runs), report.failed)


def shared_runs(which: str | Sequence[str], setup: PaperSetup = PAPER, reps: int = 3,
                max_ticks: int | None = None) -> dict[str, int]:
    """Per figure, how many of its runs more than one column (rule set) needs: one run id,
    because the runs are the same by construction (spec.run_id), made once and shown in
    each column."""
    out = {}
    for key in figure_keys(which):
        asked = Counter(r.run_id for col in setup.columns()
                        for r in figure_runs(key, col, reps, max_ticks))
        out[key] = sum(n > 1 for n in asked.values())
    return out


def describe_plan(runs: Mapping[str, list[RunSpec]], out: str | Path | None = None,
                  retry_failed: bool = False, shared: Mapping[str, int] | None = None) -> str:
    """One line per figure: runs, and how many are already done in ``out`` (and, given
    ``shared`` from :func:`shared_runs`, how many of them several columns share); with
    ``out``, how many failed and a rough estimate of the CPU time still to go (failed runs
    count as to run only with ``retry_failed``, as in :func:`reproduce`)."""
    store = RunStore(Path(out) / "runs") if out else None
    lines = []
    for key, rs in runs.items():
        done = sum(store.status(r.run_id) == DONE for r in rs) if store else 0
        labels = dict.fromkeys(num_text(v) for r in rs for v in r.labels.values())
        both = (shared or {}).get(key, 0)
        lines.append(f"{key}: {len(rs)} runs ({done} done) over {', '.join(labels)}"
                     + (f"; {both} of them made once for more than one column" if both else ""))
    total = unique_runs(r for rs in runs.values() for r in rs)
    lines.append(f"total: {len(total)} distinct runs"
                 + (_time_to_go(Sweep(total, out, runs_dir=store.dir), retry_failed)
                    if store else ""))
    return "\n".join(lines)


def _time_to_go(sweep: Sweep, retry_failed: bool = False) -> str:
    """', N done, F failed, M to run: about H CPU-hours at the mean of the finished runs'
    wall time' (runs of different conditions differ a lot: a rough guide)."""
    done = sweep.done_count()
    failed = sweep.failed_count()
    left = len(sweep.pending(retry_failed))
    text = f", {done} done" + (f", {failed} failed" if failed else "") + f", {left} to run"
    if failed and not retry_failed:
        text += " (--retry-failed runs the failed ones again)"
    if done and left:
        mean = sweep.run_seconds() / done
        text += (f": about {left * mean / 3600:.1f} CPU-hours at the finished runs' mean "
                 f"({mean:.0f} s a run)")
    return text


def setup_with(setup: PaperSetup = PAPER, world: str | None = None, robots: int | None = None,
               extra: Mapping[str, Any] | None = None,
               rulesets: Sequence[str] | None = None, ghost: bool = False) -> PaperSetup:
    """A copy of ``setup`` with another world, robot count, rule sets judged side by side,
    a ghost column or extra settings (``robots`` among them counts as the robot count: the
    claims judge it; ``ruleset`` as the one rule set judged)."""
    extra = dict(extra or {})
    changes: dict[str, Any] = {"ghost": True} if ghost else {}
    if ghost and "mode" in extra:
        raise ConfigError(f"adds a column of point robots beside rigid ones; it cannot go "
                          f"with --set mode={extra['mode']}", key="--ghost")
    if "ruleset" in extra:
        given = str(extra.pop("ruleset"))
        if rulesets is not None and list(rulesets) != [given]:
            raise ConfigError(f"--rulesets {','.join(rulesets)} and --set ruleset={given} "
                              "disagree", key="ruleset")
        rulesets = [given]
    if rulesets is not None:
        if not rulesets or len(set(rulesets)) < len(rulesets) or not all(rulesets):
            raise ConfigError(f"must name each rule set once, got {','.join(rulesets)!r}",
                              key="--rulesets")
        changes["rulesets"] = tuple(rulesets)
    if "robots" in extra:
        given = extra.pop("robots")
        if robots is not None and robots != given:
            raise ConfigError(f"--robots {robots} and --set robots={given} disagree",
                              key="robots")
        robots = given
    if world is not None:
        changes["world"] = world
    if robots is not None:
        if isinstance(robots, bool) or not isinstance(robots, int) or robots < 1:
            raise ConfigError(f"must be an integer >= 1, got {robots!r}", key="robots")
        changes["robots"] = robots
    if extra:
        changes["extra"] = {**setup.extra, **extra}
    return replace(setup, **changes)


# CONSISTENT, CondStats, Condition, dcover_distance_claims and versions_line are re-exported
# (from .figures, .verdicts and .report) for the CLI and the tests.
__all__ = ["CONSISTENT", "FIGURES", "PAPER", "CondStats", "Condition", "PaperSetup",
           "ReproduceResult", "dcover_distance_claims", "describe_plan", "figure_keys",
           "figure_runs", "get_figure", "plan", "reproduce", "setup_with", "shared_runs",
           "versions_line"]
