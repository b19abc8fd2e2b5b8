"""Small versioned JSON files that ship with the package (calibrations): `{"format": ..., "format_version":
..., <key>: [items]}`, each item a pydantic model, read with one error naming the file and field and written whole."""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any, TypeVar

from pydantic import BaseModel, ConfigDict, TypeAdapter, ValidationError

from .errors import WeightsError
from .strict_json import loads

M = TypeVar("M", bound=BaseModel)


class FileModel(BaseModel):
    """An item of a shipped file, or a part of one: strict types (an int is a float, nothing else converts),
    no field the file format does not name."""

    model_config = ConfigDict(strict=True, extra="forbid", frozen=True)


class PlainEntry(FileModel):
    """An item that the code computes with as it is read: `value()` is the item itself and `of(value)` takes it
    back (for `ShippedFile`)."""

    def value(self) -> Any:
        return self

    @classmethod
    def of(cls, value: Any) -> Any:
        return value


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


def read_models(path: str | Path, fmt: str, version: int, key: str, what: str, model: type[M]) -> list[M]:
    """The items of `read_items`, each validated as `model`; a malformed item is the same one-line
    WeightsError naming `what` and the first bad field (`calibrations[0].measures.x.center: ...`)."""
    items = read_items(path, fmt, version, key, what)
    try:
        return TypeAdapter(list[model]).validate_python(items)  # type: ignore[valid-type]
    except ValidationError as exc:
        e = exc.errors()[0]
        where = key + "".join(f"[{p}]" if isinstance(p, int) else f".{p}" for p in e["loc"])
        msg = e["msg"].removeprefix("Value error, ")
        raise WeightsError(f"{path}: unreadable {what} ({where}: {msg})") from None


def write_models(path: str | Path, fmt: str, version: int, key: str, models: Sequence[BaseModel]) -> None:
    """The file of `models` under `key` (JSON, one space indent; a NaN is written as NaN, as json writes it)."""
    doc = {"format": fmt, "format_version": version, key: [m.model_dump() for m in models]}
    Path(path).write_text(json.dumps(doc, indent=1) + "\n")


@dataclass(frozen=True)
class ShippedFile:
    """One kind of shipped file: its name in `zedo_cli/weights`, format, version, the key of its items, what it
    holds (for errors) and the model of an item, whose `value()` is what the code computes with and whose
    `of(value)` makes an item of it."""

    name: str
    fmt: str
    version: int
    key: str
    what: str
    model: type[Any]

    def bundled_path(self) -> Path:
        return Path(str(resources.files("zedo_cli") / "weights" / self.name))

    def read(self, path: str | Path) -> list[Any]:
        return [e.value() for e in read_models(path, self.fmt, self.version, self.key, self.what, self.model)]

    def read_bundled(self) -> tuple[Any, ...]:
        """The bundled file's values (none when the file is absent)."""
        path = self.bundled_path()
        return tuple(self.read(path)) if path.exists() else ()

    def write(self, path: str | Path, values: Sequence[Any]) -> None:
        write_models(path, self.fmt, self.version, self.key, [self.model.of(v) for v in values])
