"""numba's on-disk kernel cache, stamped by code: comments and docstrings never recompile.

numba keys each cached kernel (``cache=True``) on its source file's modification time and
size, and names the cache files after the function's first line number: an edited comment or
docstring, or a line added above a kernel, drops the machine code and the next run compiles
again. And it checks only the file that defines each function: a driver compiled with rules
from other files keeps the old rules' machine code after those files changed.

:func:`install` puts a locator in front of numba's own for the files of registered source
trees (:func:`register_tree`). Their cache is found where numba's would be (beside the
sources in ``__pycache__``, or under ``NUMBA_CACHE_DIR``, or numba's per-user folder), but

* its freshness stamp is a digest of the code: the abstract syntax tree without docstrings,
  comments or positions (:func:`code_digest`), of the file alone or, for a tree registered
  ``whole``, of every .py file of the tree (a change to any of its code recompiles all its
  kernels, as a driver that calls rules from other files needs);
* its file names carry a digest of the function's bytecode instead of its first line
  number, so moving a kernel down a file keeps its cache.

Importing swarmsim installs it without importing numba: the locators go in front of numba's
list when numba loads its caching module (at once if it did already); numba's own locators
serve every other file. (numba's ``NUMBA_CACHE_LOCATOR_CLASSES``, when set, replaces the list:
numba's stamps then apply.)
"""

from __future__ import annotations

import ast
import hashlib
import importlib.abc
import importlib.util
import json
import os
import sys
from pathlib import Path
from typing import Any

_TREES: dict[Path, bool] = {}
"""Registered source trees (resolved) -> whole (one stamp for all their files)."""

_BASES = ("UserProvidedCacheLocator", "InTreeCacheLocator", "UserWideCacheLocator")
"""numba's locators (numba.core.caching) that get a code-stamped twin, in numba's order."""


def register_tree(root: Path, whole: bool = False) -> None:
    """Stamp the kernels of the .py files under ``root`` by code (``whole``: by the code of
    every file under ``root``). Call it before the tree's kernels are decorated; the deepest
    registered tree that holds a file decides."""
    _TREES[Path(root).resolve()] = whole


def code_digest(source: str) -> str:
    """SHA-256 of Python ``source``'s code: its syntax tree without docstrings, comments,
    line or column numbers. Raises SyntaxError for source that does not parse."""
    tree = ast.parse(source)
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            body = node.body
            if (body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant)
                    and isinstance(body[0].value.value, str)):
                node.body = body[1:] or [ast.Pass()]
    return hashlib.sha256(ast.dump(tree, include_attributes=False).encode()).hexdigest()


MEMO = "kernel-code-digests.json"
"""Each directory's memo of its files' code digests (in its ``__pycache__``): a process
parses only the files changed since (a warm run would otherwise parse every kernel file)."""
_MEMOS: dict[Path, dict[str, list]] = {}


def _memo(folder: Path) -> dict[str, list]:
    """``folder``'s memo: file name -> [mtime_ns, size, digest] (empty if none is readable)."""
    if folder not in _MEMOS:
        try:
            memo = json.loads((folder / "__pycache__" / MEMO).read_text())
            _MEMOS[folder] = memo if isinstance(memo, dict) else {}
        except (OSError, ValueError):
            _MEMOS[folder] = {}
    return _MEMOS[folder]


def _save_memo(folder: Path) -> None:
    """Write ``folder``'s memo (atomically; not at all where the folder is read-only)."""
    cache = folder / "__pycache__"
    try:
        cache.mkdir(exist_ok=True)
        partial = cache / f".{MEMO}.{os.getpid()}.tmp"
        partial.write_text(json.dumps(_memo(folder)))
        partial.replace(cache / MEMO)
    except OSError:
        pass


def file_digest(path: Path) -> str:
    """:func:`code_digest` of the file ``path``, remembered (also on disk, :data:`MEMO`)
    while its mtime and size stay."""
    st = path.stat()
    memo = _memo(path.parent)
    known = memo.get(path.name)
    if known is not None and known[:2] == [st.st_mtime_ns, st.st_size]:
        return str(known[2])
    digest = code_digest(path.read_text(encoding="utf-8"))
    memo[path.name] = [st.st_mtime_ns, st.st_size, digest]
    _save_memo(path.parent)
    return digest


def tree_digest(root: Path) -> str:
    """SHA-256 of the code (:func:`file_digest`) of every .py file under ``root`` and of
    their paths relative to it."""
    digest = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        if "__pycache__" not in path.parts:
            digest.update(str(path.relative_to(root)).encode())
            digest.update(file_digest(path).encode())
    return digest.hexdigest()


def source_stamp(path: Path) -> str | None:
    """The code stamp of source file ``path``, or None when no registered tree holds it."""
    path = Path(path).resolve()
    for root in sorted(_TREES, key=lambda r: len(r.parts), reverse=True):
        if path.is_relative_to(root):
            return tree_digest(root) if _TREES[root] else file_digest(path)
    return None


def function_digest(py_func: Any) -> str:
    """A short digest of ``py_func``'s bytecode, names and nested code: the same while only
    its docstring, comments or position change (line numbers live apart from the bytecode)."""
    digest = hashlib.sha256()

    def add(code: Any) -> None:
        digest.update(code.co_code)
        digest.update(repr((code.co_names, code.co_varnames, code.co_freevars)).encode())
        for const in code.co_consts:
            if hasattr(const, "co_code"):
                add(const)

    add(py_func.__code__)
    return digest.hexdigest()[:12]


def _code_stamped(base: type) -> type:
    """``base`` (one of numba's locators) stamped by code for the registered trees' files;
    it declines (None) every other file."""

    class Locator(base):
        _code_stamp: str
        _disambiguator: str

        @classmethod
        def from_function(cls, py_func: Any, py_file: str) -> Any:
            stamp = source_stamp(Path(py_file)) if os.path.isfile(py_file) else None
            if stamp is None:
                return None
            self = super().from_function(py_func, py_file)
            if self is not None:
                self._code_stamp = stamp
                self._disambiguator = function_digest(py_func)
            return self

        def get_source_stamp(self) -> str:
            return self._code_stamp

        def get_disambiguator(self) -> str:
            return self._disambiguator

    Locator.__name__ = Locator.__qualname__ = f"CodeStamped{base.__name__}"
    Locator.__module__ = __name__
    return Locator


_LOCATORS: dict[str, type] = {}


def _locators(caching: Any) -> list[type]:
    """The code-stamped twins of numba's locators in ``caching`` (numba.core.caching)."""
    if not _LOCATORS:
        for base in _BASES:
            _LOCATORS[f"CodeStamped{base}"] = _code_stamped(getattr(caching, base))
    return list(_LOCATORS.values())


def _patch(caching: Any) -> None:
    """Put the code-stamped locators in front of numba's in ``caching``, once."""
    impl = getattr(caching, "CacheImpl", None) or caching._CacheImpl  # _CacheImpl in older numba
    mine = _locators(caching)
    if impl._locator_classes[:len(mine)] != mine:
        impl._locator_classes[:0] = mine


class _PatchWhenLoaded(importlib.abc.MetaPathFinder):
    """Patches numba.core.caching as soon as numba has loaded it (then leaves sys.meta_path)."""

    def find_spec(self, name: str, path: Any, target: Any = None) -> Any:
        if name != "numba.core.caching":
            return None
        sys.meta_path.remove(self)
        spec = importlib.util.find_spec(name)
        if spec is not None and spec.loader is not None:
            run = spec.loader.exec_module

            def exec_module(module: Any) -> None:
                run(module)
                _patch(module)

            # this one loader object runs our exec_module (mypy refuses assigning a method)
            spec.loader.exec_module = exec_module  # type: ignore[method-assign]
        return spec


def install() -> None:
    """Make numba stamp the registered trees' kernels by code (idempotent; see the module)."""
    if "numba.core.caching" in sys.modules:
        _patch(sys.modules["numba.core.caching"])
    elif not any(isinstance(f, _PatchWhenLoaded) for f in sys.meta_path):
        sys.meta_path.insert(0, _PatchWhenLoaded())
