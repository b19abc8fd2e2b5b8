"""The tidy table of an analysis held as columns (`Block`), and written as CSV or JSON lines a column at a time.

A block is `n` poses (or rows) by a few measures: its rows go pose by pose, each pose's measures in order. A
column shared by a pose's measures (frame_index, image_id, file_name, person) holds one value per pose; each
measure's own columns hold one value per pose or one for all. Rows (`Row`) are built only when asked for; the
writers turn each column into text once (a pose's shared cells once, a measure's constant cells once), so that a
10-minute clip's half a million rows cost seconds. The text is what `csv.writer` and `json.dumps` write for the
rows' values with numbers kept to `DECIMALS` decimals and at least `SIGNIFICANT` significant digits
(`formats.writers.common.rounded`), unknown values empty (CSV) or null (JSON).
"""

from __future__ import annotations

import csv
import io
import json
import math
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass, fields
from itertools import repeat
from typing import Any

import numpy as np

from ..formats.writers.common import SIGNIFICANT

COLUMNS = ("frame_index", "image_id", "file_name", "person", "measure", "value", "unit", "low", "high", "level",
           "call", "interval", "interval_note", "raw_value", "flag", "call_low", "call_high")  # fmt: skip
SHARED = COLUMNS[:4]  # one value per pose in a block
DECIMALS = 3  # at least; small values keep SIGNIFICANT digits
PART_POSES = 500  # poses turned into text at a time (a few MB)
# The `interval` column's codes: how `low` and `high` were obtained; `interval_note` says more (for "none": why)
INTERVAL_METHODS = {
    "calibrated": "split-conformal calibration of the measure on held-out lifts (docs/clinical.md)",
    "calibrated_filled": "the calibration's model of poses with a joint the prior filled (wider); the note names them",
    "median_of_frame_interval_ends": "a clip's median: the median of its frames' interval ends",
    "block_bootstrap_and_share_calibration": "a block bootstrap of the frames widened by the share calibration",
    "not_for_clip_features": "a clip's movement feature: no interval",
    "none": "no interval; the note says why",
}


def split_how(how: str) -> tuple[str, str]:
    """The `interval` code and `interval_note` of how an interval was obtained ("none: why", "calibrated", "code:
    note")."""
    method, _, note = how.partition(": ")
    return method, note


@dataclass
class Row:
    """One line of the tidy table (see COLUMNS): `low` and `high` hold the interval at `level` (NaN where none),
    `interval` how it was obtained (INTERVAL_METHODS), `interval_note` more about it."""

    frame_index: int | None
    image_id: int | str | None
    file_name: str | None
    person: int
    measure: str
    value: float
    unit: str
    low: float = np.nan
    high: float = np.nan
    level: float = np.nan
    call: str = ""
    interval: str = ""
    interval_note: str = ""
    raw_value: float = np.nan
    flag: str = ""
    call_low: float = np.nan
    call_high: float = np.nan

    def as_list(self) -> list[Any]:
        return [getattr(self, c) for c in COLUMNS]

    @property
    def how(self) -> str:
        """`interval` and `interval_note` in one line ("none: why")."""
        return f"{self.interval}: {self.interval_note}" if self.interval_note else self.interval


def clip_row(person: int, measure: str, value: float, unit: str, how: str, level: float, low: float = np.nan,
             high: float = np.nan, raw_value: float = np.nan) -> Row:  # fmt: skip
    """A row of a clip's measure, its interval at `level` obtained as `how` says ("none: why")."""
    method, note = split_how(how)
    return Row(None, None, None, person, measure, value, unit, low, high, float(level_where_known(low, high, level)),
               interval=method, interval_note=note, raw_value=raw_value)  # fmt: skip


def level_where_known(low: Any, high: Any, level: float) -> np.ndarray:
    """The `level` column: `level` where both interval ends are known, NaN elsewhere (arrays or numbers)."""
    known = np.isfinite(np.asarray(low, dtype=float)) & np.isfinite(np.asarray(high, dtype=float))
    return np.where(known, level, np.nan)


_DEFAULTS = {f.name: f.default for f in fields(Row) if f.name not in SHARED}
_FLOATS = frozenset(c for c, d in _DEFAULTS.items() if isinstance(d, float)) | {"value"}


@dataclass(frozen=True)
class Block:
    """Rows of the tidy table as columns: `shared` maps SHARED columns to one value per pose `(n,)`; `cells` holds
    per measure its columns (each `(n,)` or one value for all); a column a measure lacks takes Row's default. A
    measure's `how` ("none: why", "calibrated", ...) gives its `interval` and `interval_note`, and its `level` is
    the block's where `low` and `high` are known."""

    n: int
    shared: dict[str, np.ndarray]
    cells: tuple[dict[str, Any], ...]
    level: float = np.nan

    def parts(self, poses: int) -> Iterator[Block]:
        """The block in parts of at most `poses` poses, in order."""
        if self.n <= poses:
            yield self
            return
        for start in range(0, self.n, poses):
            part = slice(start, start + poses)
            yield Block(len(range(self.n)[part]), {c: v[part] for c, v in self.shared.items()},
                        tuple({c: v[part] if isinstance(v, np.ndarray) else v for c, v in cell.items()}
                              for cell in self.cells), self.level)  # fmt: skip

    def columns(self, cell: dict[str, Any]) -> dict[str, Any]:
        """A measure's own columns, `level`, `interval` and `interval_note` made from its intervals and `how`."""
        out = {c: v for c, v in cell.items() if c != "how"}
        if "how" in cell:
            how = cell["how"]
            if isinstance(how, np.ndarray):
                split = {h: split_how(h) for h in set(how.tolist())}
                out["interval"] = np.array([split[h][0] for h in how.tolist()], dtype=object)
                out["interval_note"] = np.array([split[h][1] for h in how.tolist()], dtype=object)
            else:
                out["interval"], out["interval_note"] = split_how(how)
        if "level" not in out and "low" in out and "high" in out:
            out["level"] = level_where_known(out["low"], out["high"], self.level)
        return out

    def rows(self) -> Iterator[Row]:
        shared = [self.shared[c].tolist() for c in SHARED]
        columns = [{c: (v.tolist() if isinstance(v, np.ndarray) else repeat(v, self.n))
                    for c, v in self.columns(cell).items()} for cell in self.cells]  # fmt: skip
        per_measure = [[dict(zip(cell, values, strict=False)) for values in zip(*cell.values(), strict=False)]
                       for cell in columns]  # fmt: skip
        for k, key in enumerate(zip(*shared, strict=True)):
            for measure in per_measure:
                yield Row(*key, **{**_DEFAULTS, **measure[k]})


def rows_block(rows: Sequence[Row]) -> Block:
    """Rows already built (the clip features) as a block of one measure per row."""
    columns = {c: [getattr(r, c) for r in rows] for c in COLUMNS}
    shared = {c: np.array(columns[c], dtype=object) for c in SHARED}
    cell = {c: np.array(v, dtype=float if c in _FLOATS else object) for c, v in columns.items() if c not in SHARED}
    return Block(len(rows), shared, (cell,))


def number_texts(values: np.ndarray, empty: str) -> list[str]:
    """Each number as `str` writes its rounded value (`formats.writers.common.rounded`), a whole number as an
    integer; `empty` where not finite."""
    x = np.asarray(values, dtype=float).reshape(-1)
    out = np.full(len(x), empty, dtype=object)
    finite = np.isfinite(x)
    whole = finite & (x == np.trunc(np.where(finite, x, 0.0)))
    out[whole] = list(map(str, map(int, x[whole].tolist())))
    rest = finite & ~whole
    r = x[rest]
    magnitude = np.abs(r)
    digits = np.where(magnitude >= 10.0 ** (SIGNIFICANT - 1 - DECIMALS), DECIMALS,
                      SIGNIFICANT - 1 - np.floor(np.log10(magnitude)).astype(int))  # fmt: skip
    out[rest] = list(map(repr, map(round, r.tolist(), digits.tolist())))
    return out.tolist()


def _csv_quoted(text: str) -> str:
    buffer = io.StringIO()
    csv.writer(buffer, lineterminator="\n").writerow([text, ""])
    return buffer.getvalue()[:-2]


@dataclass(frozen=True)
class _Format:
    """How a file writes a cell: its text for an unknown value and for a string, and how a row's cells join."""

    empty: str
    string: Callable[[str], str]
    join: Callable[[Sequence[str]], str]

    def one(self, value: Any) -> str:
        if value is None:
            return self.empty
        if isinstance(value, str):
            return self.string(value)
        if isinstance(value, bool | np.bool_):
            return str(bool(value))
        if isinstance(value, int | np.integer):
            return str(int(value))
        return number_texts(np.array([value]), self.empty)[0]

    def strings(self, values: list[Any]) -> list[str]:
        cache: dict[Any, str] = {}
        return [cache[v] if v in cache else cache.setdefault(v, self.one(v)) for v in values]


_JSON_OBJECT = "{{" + ", ".join(json.dumps(c).replace("{", "{{").replace("}", "}}") + ": {}" for c in COLUMNS) + "}}"

CSV = _Format("", _csv_quoted, ",".join)
JSON = _Format("null", json.dumps, lambda cells: _JSON_OBJECT.format(*cells))


def _column(values: Any, n: int, formats: Sequence[_Format]) -> list[Iterable[str]]:
    """Per format, the texts of a column of `n` cells (an array, or one value for all); numbers formatted once."""
    if not isinstance(values, np.ndarray):
        return [repeat(f.one(values), n) for f in formats]
    if values.dtype.kind == "f":
        texts = number_texts(values, "")
        return [texts if not f.empty else [t or f.empty for t in texts] for f in formats]
    if values.dtype.kind in "iu":
        return [list(map(str, values.tolist()))] * len(formats)
    listed = values.tolist()
    return [f.strings(listed) for f in formats]


def _lines(block: Block, formats: Sequence[_Format]) -> list[list[str]]:
    """Per format, the block's rows as text lines (its `join` of a row's cells in COLUMNS order), in row order."""
    n = block.n
    shared = [_column(block.shared[c], n, formats) for c in SHARED]
    per_measure: list[list[list[str]]] = [[] for _ in formats]
    for cell in map(block.columns, block.cells):
        own = [_column(cell[c] if c in cell else _default(c), n, formats) for c in COLUMNS[len(SHARED) :]]
        for f, fmt in enumerate(formats):
            columns = [column[f] for column in (*shared, *own)]
            per_measure[f].append(list(map(fmt.join, zip(*columns, strict=False))))
    return [lines[0] if len(lines) == 1 else [line for row in zip(*lines, strict=True) for line in row]
            for lines in per_measure]  # fmt: skip


def _default(column: str) -> Any:
    value = _DEFAULTS[column]
    return None if isinstance(value, float) and math.isnan(value) else value


CSV_HEADER = ",".join(COLUMNS) + "\n"


def csv_lines(blocks: Iterable[Block]) -> Iterator[str]:
    """The tidy CSV, header first, a part of a block at a time (each line ends in a newline)."""
    yield CSV_HEADER
    for block in blocks:
        for part in block.parts(PART_POSES):
            (lines,) = _lines(part, (CSV,))
            yield "".join(line + "\n" for line in lines)


def json_rows(blocks: Iterable[Block]) -> Iterator[list[str]]:
    """The rows, a part at a time: each row the text of `json.dumps` of its dict (COLUMNS -> value)."""
    for block in blocks:
        for part in block.parts(PART_POSES):
            (rows,) = _lines(part, (JSON,))
            yield rows


def csv_and_json(blocks: Iterable[Block]) -> Iterator[tuple[str, list[str]]]:
    """`csv_lines` (without the header) and `json_rows` side by side, a part at a time, each number formatted
    once for both."""
    for block in blocks:
        for part in block.parts(PART_POSES):
            lines, rows = _lines(part, (CSV, JSON))
            yield "".join(line + "\n" for line in lines), rows
