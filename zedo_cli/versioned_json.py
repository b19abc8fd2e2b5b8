"""Small versioned JSON files that ship with the package (calibrations): `{"format": ..., "format_version":
..., <key>: [items]}`, read with one error naming the file and written whole."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

from .errors import WeightsError
from .strict_json import loads

T = TypeVar("T")


def read_items(path: str | Path, fmt: str, version: int, key: str, what: str) -> list[dict[str, Any]]:
    """The items under `key` of a `fmt` version `version` file; WeightsError naming `what` otherwise."""
    path = Path(path)
    try:
        doc = loads(path.read_text())
        if not isinstance(doc, dict) or doc.get("format") != fmt or doc.get("format_version") != version:
            raise WeightsError(f"{path}: not a {fmt} version {version} file")
        items = doc[key]
        if not isinstance(items, list) or not all(isinstance(d, dict) for d in items):
            raise TypeError(f"{key}: expected a list of objects")
        return items
    except (OSError, ValueError, KeyError, TypeError, AttributeError, RecursionError) as exc:
        raise WeightsError(f"{path}: unreadable {what} ({exc})") from None


def read_models(
    path: str | Path, fmt: str, version: int, key: str, what: str, parse: Callable[[dict[str, Any]], T]
) -> list[T]:
    """The items of `read_items`, each made into a model by `parse`; a malformed item is the same
    one-line WeightsError naming `what`."""
    items = read_items(path, fmt, version, key, what)
    try:
        return [parse(d) for d in items]
    except (ValueError, KeyError, TypeError, AttributeError) as exc:
        raise WeightsError(f"{path}: unreadable {what} ({exc})") from None


def write_items(path: str | Path, fmt: str, version: int, key: str, items: list[dict[str, Any]]) -> None:
    doc = {"format": fmt, "format_version": version, key: items}
    Path(path).write_text(json.dumps(doc, indent=1) + "\n")
