"""Each kept reproduction (docs/reproduction/<folder>/) is auditable: its REPORT.md's verdicts
and tally follow from its claims.csv, and it names its code and command."""

from pathlib import Path

import pytest

from swarmsim.experiments.report import claims_summary_text
from swarmsim.experiments.table import read_table

KEPT = Path(__file__).resolve().parents[2] / "docs" / "reproduction"
FOLDERS = sorted(p for p in KEPT.iterdir() if (p / "REPORT.md").is_file())


def test_at_least_one_full_reproduction_is_kept():
    assert FOLDERS, f"no kept reproduction in {KEPT}"


@pytest.mark.parametrize("folder", FOLDERS, ids=[p.name for p in FOLDERS])
def test_a_kept_reports_verdicts_follow_from_its_claims_csv(folder):
    rows = read_table(folder / "claims.csv")
    report = (folder / "REPORT.md").read_text()
    assert rows and claims_summary_text(rows) in report
    names_code = "Code: " in report or "code versions: " in report  # one version, or several
    assert names_code and "swarmsim reproduce" in (folder / "COMMAND.md").read_text()
