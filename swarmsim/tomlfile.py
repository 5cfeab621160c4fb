"""Reading the TOML files users write (worlds, sweep specs): one error line for any problem.

A UTF-8 byte-order mark (which some editors write first) is accepted: it is not part of the
TOML text. Every other problem (not TOML, not UTF-8, unreadable) is a ConfigError naming the
file.
"""

from __future__ import annotations

import codecs
import tomllib
from pathlib import Path
from typing import Any

from swarmsim.errors import ConfigError


def read_toml(path: str | Path) -> dict[str, Any]:
    """The parsed TOML file at ``path`` (a leading UTF-8 byte-order mark skipped)."""
    source = str(path)
    try:
        raw = Path(path).read_bytes()
    except OSError as exc:
        raise ConfigError(f"cannot read the file ({exc.strerror})", source=source) from None
    raw = raw.removeprefix(codecs.BOM_UTF8)
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        what = (" (it starts with a UTF-16 byte-order mark: save it as UTF-8)"
                if raw.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)) else "")
        raise ConfigError(f"not a UTF-8 text file (byte {exc.start}){what}: TOML files are "
                          "UTF-8", source=source) from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"not valid TOML: {exc}", source=source) from None
