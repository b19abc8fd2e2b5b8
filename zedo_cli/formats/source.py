"""Reading input text from a file or stdin and parsing it as JSON, with file-level errors.

Kept apart from the readers so that every reader (and a directory of OpenPose files) turns a
missing, unreadable, non-UTF-8, empty or invalid file into the same `InputFormatError`.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any

from .validate import error

STDIN = "-"


def read_text(name: str) -> str:
    """The UTF-8 text of file `name` ("-" = stdin); a byte-order mark is dropped."""
    try:
        if name == STDIN:
            raw = sys.stdin.buffer.read()
        elif Path(name).is_dir():
            raise error(name, "", "is a directory, expected a JSON file")
        else:
            raw = Path(name).read_bytes()
    except FileNotFoundError:
        raise error(name, "", "file not found") from None
    except OSError as exc:
        raise error(name, "", f"cannot read file: {exc.strerror or exc}") from None
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise error(name, "", f"not UTF-8 text (invalid byte at offset {exc.start})") from None


def parse_json(text: str, name: str, where: str = "") -> Any:
    """`text` parsed as one JSON value; `where` prefixes the position (e.g. "line 3" of a JSONL file)."""
    if not text.strip():
        raise error(name, where, "file is empty" if not where else "empty line")
    try:
        return json.loads(text)
    except json.JSONDecodeError as exc:
        at = f"line {exc.lineno}, column {exc.colno}" if not where else f"column {exc.colno}"
        raise error(name, where, f"invalid JSON at {at}: {exc.msg}") from None
    except (ValueError, RecursionError) as exc:  # e.g. integers beyond Python's digit limit, deep nesting
        raise error(name, where, f"invalid JSON: {exc}") from None


def load_json(name: str) -> Any:
    """The parsed JSON of file `name` ("-" = stdin)."""
    return parse_json(read_text(name), name)
