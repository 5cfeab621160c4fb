"""`swarmsim params`: every parameter's default and meaning, read from the dataclasses'
docstrings and wrapped to the terminal.

A parameter's meaning is its entry in the class docstring's ``Attributes:`` section (Google
style): a line ``name: text`` at the section's own indentation starts an entry; deeper-indented
lines continue it (a blank line between them starts a new paragraph). A continuation line that
happens to read ``word: ...`` is therefore still part of the entry before it.
"""

from __future__ import annotations

import dataclasses
import inspect
import shutil
import textwrap
from collections.abc import Iterable, Mapping

MAX_WIDTH = 100
MIN_WIDTH = 60
NAME_COLUMN = 22
DEFAULT_COLUMN = 12


def help_width() -> int:
    """Line width for help text: the terminal's, at most MAX_WIDTH, at least MIN_WIDTH."""
    columns = shutil.get_terminal_size((MAX_WIDTH, 24)).columns
    return max(MIN_WIDTH, min(MAX_WIDTH, columns))


def attribute_docs(cls: type) -> dict[str, list[str]]:
    """Each attribute's description in ``cls``'s docstring, as a list of paragraphs (each
    paragraph one line of text, whitespace collapsed). Empty when there is no ``Attributes:``
    section."""
    lines = inspect.cleandoc(cls.__doc__ or "").splitlines()
    starts = [i for i, line in enumerate(lines) if line.strip() == "Attributes:"]
    if not starts:
        return {}
    out: dict[str, list[list[str]]] = {}
    current: str | None = None
    indent: int | None = None
    for line in lines[starts[0] + 1:]:
        text = line.strip()
        if not text:
            if current is not None and out[current][-1]:
                out[current].append([])  # a paragraph break
            continue
        depth = len(line) - len(line.lstrip())
        if indent is None:
            indent = depth
        if depth < indent:  # the section ended
            break
        if depth == indent:
            name, _, rest = text.partition(":")
            current = name.split()[0] if name.split() else name
            out[current] = [[rest.strip()] if rest.strip() else []]
        elif current is not None:
            out[current][-1].append(text)
    return {name: [" ".join(p) for p in paras if p] for name, paras in out.items()}


def format_params(sections: Iterable[tuple[str, type]], width: int) -> list[str]:
    """The listing's lines: per ``(title, dataclass)`` a ``[title]`` line, then per field its
    name, default and whole description, wrapped at ``width`` characters."""
    lines: list[str] = []
    desc_col = 2 + NAME_COLUMN + 3 + DEFAULT_COLUMN + 1
    if width - desc_col < 40:  # a narrow terminal: every description below its name
        desc_col = 6
    for title, klass in sections:
        lines.append(f"[{title}]")
        docs = attribute_docs(klass)
        for f in dataclasses.fields(klass):
            default = f.default if f.default is not dataclasses.MISSING else "(required)"
            head = f"  {f.name:<{NAME_COLUMN}} = {default!r:<{DEFAULT_COLUMN}} "
            paragraphs = _with_bound(docs.get(f.name, []), f) or [""]
            if len(head) > desc_col:  # a long name or default (or narrow): description below
                lines.append(head.rstrip())
                head = ""
            for k, para in enumerate(paragraphs):
                first = head if k == 0 and head else " " * desc_col
                wrapped = textwrap.wrap(para, width=width, initial_indent=first,
                                        subsequent_indent=" " * desc_col,
                                        break_long_words=True, break_on_hyphens=False)
                lines.extend(wrapped or [first.rstrip()])
    return lines


def format_choices(title: str, choices: Mapping[str, str], width: int) -> list[str]:
    """A ``[title]`` line, then per choice its name and meaning, wrapped at ``width``
    characters (e.g. a controller's failure modes)."""
    lines = [f"[{title}]"]
    desc_col = 2 + NAME_COLUMN + 1
    for name, meaning in choices.items():
        lines.extend(textwrap.wrap(meaning, width=width,
                                   initial_indent=f"  {name:<{NAME_COLUMN}} ",
                                   subsequent_indent=" " * desc_col, break_long_words=True,
                                   break_on_hyphens=False))
    return lines


def _with_bound(paragraphs: list[str], f: dataclasses.Field) -> list[str]:
    """The field's paragraphs, the last one ending with its upper bound if it declares one
    (swarmsim.limits.at_most)."""
    from swarmsim.limits import BOUND, format_bound

    if BOUND not in f.metadata:
        return paragraphs
    note = f"At most {format_bound(f.metadata[BOUND])}."
    if not paragraphs:
        return [note]
    return [*paragraphs[:-1], f"{paragraphs[-1]} {note}"]
