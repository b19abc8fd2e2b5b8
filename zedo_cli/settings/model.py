"""The base of every command's settings model (`zedo lift`, `analyze`, `render`, `calibrate`, `norms`, `export`,
`adapt`, `fit-prior`, `fit-augmenter`, `augment`, `evaluate`, `benchmark`, `benchmark-symmetry`).

One field per long option, named as the option with underscores (`--min-confidence` ->
`min_confidence`), with its type, bounds, default and help. The command line, a `--config`
TOML file and the Python API (`zedo_cli.lift_file`, `zedo_cli.analyze`) all build the same
model, so a setting means the same wherever it is given. Types are strict (a TOML string is not
a number, a number is not a switch); a bad value is one line naming the option and what it
expects (`ConfigError`, exit code 2).
"""

from __future__ import annotations

import math
import types
from pathlib import Path
from typing import Any, ClassVar, Literal, TypeVar, Union, get_args, get_origin

import annotated_types as at
from pydantic import BaseModel, ConfigDict, ValidationError, model_validator

from ..errors import ConfigError

OptionsT = TypeVar("OptionsT", bound="Options")


def option_name(key: str) -> str:
    """`min_confidence` -> `--min-confidence`."""
    return "--" + key.replace("_", "-")


def show(value: Any) -> str:
    """A value as an error message quotes it: numbers compactly, strings quoted."""
    if isinstance(value, bool):
        return str(value).lower()
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return str(int(value)) if math.isfinite(value) and value.is_integer() and abs(value) < 1e16 else f"{value:g}"
    if isinstance(value, (list, tuple)):
        return " ".join(show(v) for v in value) or "none"
    return repr(str(value)) if isinstance(value, Path) else repr(value)


def _bounds(metadata: list[Any]) -> str:
    low = high = None
    for m in metadata:
        if isinstance(m, at.Ge):
            low = f"[{show(m.ge)}"
        elif isinstance(m, at.Gt):
            low = f"({show(m.gt)}"
        elif isinstance(m, at.Le):
            high = f"{show(m.le)}]"
        elif isinstance(m, at.Lt):
            high = f"{show(m.lt)})"
    if low and high:
        return f" in {low}, {high}"
    if low:
        return f" {'>=' if low[0] == '[' else '>'} {low[1:]}"
    if high:
        return f" {'<=' if high[-1] == ']' else '<'} {high[:-1]}"
    return ""


def _describe(annotation: Any) -> str:
    if get_origin(annotation) in (Union, types.UnionType):
        inner = [a for a in get_args(annotation) if a is not type(None)]
        return _describe(inner[0]) if len(inner) == 1 else " or ".join(_describe(a) for a in inner)
    if get_origin(annotation) is Literal:
        return "one of " + ", ".join(str(a) for a in get_args(annotation))
    if get_origin(annotation) is tuple:
        count = len(get_args(annotation))
        return f"{ {2: 'two', 3: 'three'}.get(count, count) } numbers"
    return {bool: "true or false", int: "an integer", float: "a number", str: "a string", Path: "a path"}.get(
        annotation, str(annotation)
    )


class Options(BaseModel):
    """A command's settings. Subclasses set `command` and declare one field per option."""

    model_config = ConfigDict(extra="forbid", strict=True, frozen=True, allow_inf_nan=False, populate_by_name=True)
    command: ClassVar[str] = ""

    @model_validator(mode="before")
    @classmethod
    def _lists_as_tuples(cls, data: Any) -> Any:
        """A TOML array or a Python list where the option takes several numbers (WIDTH HEIGHT)."""
        if isinstance(data, dict):
            return {k: tuple(v) if isinstance(v, list) else v for k, v in data.items()}
        return data

    @classmethod
    def keys(cls) -> dict[str, str]:
        """Option key (the long option's name with underscores) -> field name."""
        return {(f.alias or name): name for name, f in cls.model_fields.items()}

    @classmethod
    def help(cls, key: str) -> str:
        """The option's help text (the CLI's --help shows it)."""
        return cls.model_fields[cls.keys()[key]].description or ""

    @classmethod
    def default(cls, key: str) -> Any:
        return cls.model_fields[cls.keys()[key]].default

    @classmethod
    def expected(cls, key: str) -> str:
        """What the option takes, in words: "an integer in [1, 100000]", "one of m, mm"."""
        field = cls.model_fields[cls.keys()[key]]
        extra = field.json_schema_extra if isinstance(field.json_schema_extra, dict) else {}
        if "expected" in extra:
            return str(extra["expected"])
        return _describe(field.annotation) + _bounds(field.metadata)

    @classmethod
    def key_of(cls, loc: Any) -> str:
        """The option key of a pydantic error's location (a field name or its alias)."""
        name = str(loc)
        keys = cls.keys()
        return name if name in keys else next((k for k, n in keys.items() if n == name), name)

    @classmethod
    def bad_value(cls, exc: ValidationError) -> tuple[str, Any, str]:
        """The first error of `exc`: (option key, the value given, what the option expects)."""
        err = exc.errors()[0]
        key = cls.key_of(err["loc"][0]) if err["loc"] else ""
        return key, err.get("input"), cls.expected(key) if key in cls.keys() else err["msg"]

    @classmethod
    def validated(cls: type[OptionsT], values: dict[str, Any]) -> OptionsT:
        """The settings of `values` (option key -> value; missing keys take their defaults),
        their cross-option rules checked: a ConfigError naming the option otherwise."""
        try:
            options = cls.model_validate(values)
        except ValidationError as exc:
            err = exc.errors()[0]
            if err["type"] == "value_error":  # a field's own check (a validator): its message as it is
                raise ConfigError(str(err["msg"]).removeprefix("Value error, ")) from None
            key, value, expected = cls.bad_value(exc)
            value = values.get(key, value)  # the whole value, not the element of a pair that is wrong
            raise ConfigError(f"{option_name(key)} must be {expected}, got {show(value)}") from None
        options.check()
        return options

    def check(self) -> None:
        """Rules between options (a subclass's); a ConfigError naming them."""

    def values(self) -> dict[str, Any]:
        """Option key -> value, every option."""
        return {key: getattr(self, name) for key, name in self.keys().items()}

    def replace(self: OptionsT, **changes: Any) -> OptionsT:
        """A copy with `changes` (option keys), validated again."""
        return type(self).validated({**self.values(), **changes})
