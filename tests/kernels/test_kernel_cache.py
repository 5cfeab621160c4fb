"""Compiled kernels are cached by code (swarmsim/kernels/kernelcache.py), and the first run says that
it compiles them (swarmsim/kernels/kernelbuild.py)."""

from __future__ import annotations

import io
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from swarmsim.kernels import kernelcache

RULE = '''\
"""Rules."""
from numba import njit


@njit(cache=True)
def rule(x):
    """The rule."""
    return x + 1  # one more
'''

DRIVER = '''\
from numba import njit

from .rules import rule


@njit(cache=True)
def driver(x):
    return rule(x) * 10
'''

RUN = '''\
import sys
from pathlib import Path

from swarmsim import kernelcache

kernelcache.register_tree(Path(sys.argv[1]) / "pkg", whole=True)
kernelcache.install()
sys.path.insert(0, sys.argv[1])
from numba.core import event

from swarmsim.kernels.kernelbuild import build_notice

with event.install_recorder("numba:compile") as compiles, build_notice(detail=False):
    from pkg.driver import driver
    value = driver(1)
names = {ev.data["dispatcher"].py_func.__name__ for _, ev in compiles.buffer if ev.is_start}
print(value, ",".join(sorted(names)))
'''


@pytest.mark.parametrize("edited", [
    '"""Rules, reworded."""\n' + RULE.split("\n", 1)[1],            # the module's docstring
    RULE.replace('"""The rule."""', '"""The rule,\n    reworded."""'),  # a function's docstring
    RULE.replace("# one more", "# add one"),                          # a comment
    "\n\n# a header\n" + RULE,                                        # lines added above
    RULE.replace('    """The rule."""\n', ""),                         # a docstring dropped
])
def test_the_code_digest_ignores_docstrings_comments_and_positions(edited):
    assert kernelcache.code_digest(edited) == kernelcache.code_digest(RULE)


@pytest.mark.parametrize("edited", [
    RULE.replace("x + 1", "x + 2"),                    # a constant
    RULE.replace("x + 1", "x - 1"),                    # an operator
    RULE.replace("return x + 1", "y = x + 1\n    return y"),  # a statement
    RULE.replace("cache=True", "cache=False"),         # a decorator's argument
])
def test_the_code_digest_changes_with_the_code(edited):
    assert kernelcache.code_digest(edited) != kernelcache.code_digest(RULE)


def test_ggc_kernels_are_stamped_by_the_whole_package():
    """A change to any rule's code recompiles GGC's driver (it is compiled with the rules)."""
    import controllers.ggc
    from controllers.ggc.rules import coverage

    package = Path(controllers.ggc.__file__).parent
    assert kernelcache.source_stamp(Path(coverage.__file__)) == kernelcache.tree_digest(package)
    assert kernelcache.source_stamp(Path(kernelcache.__file__)) == kernelcache.file_digest(
        Path(kernelcache.__file__))


def _run(tmp_path: Path, cache: Path) -> tuple[str, str, str]:
    """(value, kernels compiled, stderr) of RUN on tmp_path's package, numba's cache in
    ``cache``."""
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache))
    done = subprocess.run([sys.executable, "-c", RUN, str(tmp_path)], env=env,
                          capture_output=True, text=True, timeout=300, check=True)
    value, _, names = done.stdout.strip().partition(" ")
    return value, names, done.stderr


@pytest.mark.slow
def test_a_docstring_edit_keeps_the_compiled_kernels_and_a_code_edit_recompiles(tmp_path):
    pkg = tmp_path / "pkg"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "rules.py").write_text(RULE)
    (pkg / "driver.py").write_text(DRIVER)
    cache = tmp_path / "cache"
    value, compiled, notice = _run(tmp_path, cache)
    assert (value, compiled) == ("20", "driver,rule")
    assert notice.startswith("swarmsim: compiling kernels (first run only) ... done in ")
    assert notice.count("\n") == 1  # --quiet's one line
    # docstrings, comments and lines above the rule: loaded from the cache, nothing printed
    (pkg / "rules.py").write_text('"""Rules, reworded."""\n\n\n# more\n' + textwrap.dedent(
        RULE.split("\n", 1)[1]).replace("# one more", "# add one"))
    assert _run(tmp_path, cache) == ("20", "", "")
    # the rule's code, in another file than the driver's: both compiled again
    (pkg / "rules.py").write_text(RULE.replace("x + 1", "x + 2"))
    value, compiled, _ = _run(tmp_path, cache)
    assert (value, compiled) == ("30", "driver,rule")


def test_the_detailed_notice_names_each_step_that_compiled():
    """Off a terminal: the first compile announces the build, each step that compiled gets a
    line (k of n, kernels, seconds), and the end says how long it took; a step that compiled
    nothing gets no line."""
    from numba import njit

    from swarmsim.kernels.kernelbuild import PREFIX, build_notice, step

    @njit  # not cached: compiled on every call of this test
    def add_one(x):  # pragma: no cover - compiled
        return x + 1

    stream = io.StringIO()
    with build_notice(stream, detail=True):
        with step("nothing", 1, 3):
            pass
        with step("a tiny kernel", 2, 3):
            add_one(1)
        with step("loaded", 3, 3):
            add_one(2)  # compiled already
    lines = stream.getvalue().splitlines()
    assert lines[0] == f"{PREFIX} ..."
    assert lines[1].startswith("  2/3 a tiny kernel: 1 kernel, ")
    assert lines[2].startswith("swarmsim: compiled 1 kernel in ")
    assert len(lines) == 3


def test_nothing_is_printed_when_nothing_compiles():
    from swarmsim.kernels.kernelbuild import build_notice, step

    stream = io.StringIO()
    with build_notice(stream, detail=True), step("loaded", 1, 1):
        pass
    assert stream.getvalue() == ""
