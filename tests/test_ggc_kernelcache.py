"""GGC's compiled-rule cache is dropped when any source of the package changes (numba checks
only each function's own file)."""

from pathlib import Path

from controllers.ggc.kernelcache import STAMP, drop_stale_kernels


def _package(tmp_path: Path) -> tuple[Path, Path]:
    pkg = tmp_path / "pkg"
    (pkg / "rules" / "__pycache__").mkdir(parents=True)
    (pkg / "__pycache__").mkdir()
    (pkg / "decide.py").write_text("def driver(): pass\n")
    (pkg / "rules" / "coverage.py").write_text("def rule(): return 1\n")
    return pkg, pkg / "__pycache__" / "decide.driver-1.py311.nbi"


def test_kernels_are_kept_while_the_sources_stay_the_same(tmp_path):
    pkg, kernel = _package(tmp_path)
    assert drop_stale_kernels(pkg)  # no stamp yet: compiled from who knows what
    kernel.write_bytes(b"index")
    assert not drop_stale_kernels(pkg)
    assert kernel.exists() and (pkg / "__pycache__" / STAMP).exists()


def test_changing_a_rule_in_another_file_drops_every_kernel(tmp_path):
    pkg, kernel = _package(tmp_path)
    drop_stale_kernels(pkg)
    kernel.write_bytes(b"index")
    rule_kernel = pkg / "rules" / "__pycache__" / "coverage.rule-1.py311.1.nbc"
    rule_kernel.write_bytes(b"code")
    (pkg / "rules" / "coverage.py").write_text("def rule(): return 2\n")
    assert drop_stale_kernels(pkg)
    assert not kernel.exists() and not rule_kernel.exists()
    assert not drop_stale_kernels(pkg)  # stamped anew
