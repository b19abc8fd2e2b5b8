"""The tidy table as columns (`analysis.table`): its CSV and JSON text is what `csv.writer` and `json.dumps` write
for the rows a cell at a time, with every number rounded by `formats.writers.common.rounded`."""

from __future__ import annotations

import csv
import io
import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from analysis_results import kicking_poses, result_document, write_document

from zedo_cli.analysis.analyse import analyse
from zedo_cli.analysis.outputs import analysis_document, csv_text, write_csv, write_csv_and_json, write_json
from zedo_cli.analysis.pose.symmetry import symmetry_band, symmetry_bands, symmetry_call, symmetry_calls
from zedo_cli.analysis.table import COLUMNS, Block, Row, csv_and_json, csv_lines, json_rows, number_texts
from zedo_cli.formats.readers.result import read_result
from zedo_cli.formats.writers.common import rounded


def _num(value: Any) -> Any:
    """A cell's value as the row-at-a-time writer wrote it."""
    if isinstance(value, float):
        if not math.isfinite(value):
            return None
        return int(value) if value.is_integer() else rounded(value, 3)
    return value


def csv_of_rows(rows: list[Row]) -> str:
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(COLUMNS)
    for row in rows:
        writer.writerow(["" if (v := _num(x)) is None else v for x in row.as_list()])
    return buffer.getvalue()


def json_of_rows(rows: list[Row]) -> list[str]:
    return [json.dumps({c: _num(v) for c, v in zip(COLUMNS, row.as_list(), strict=True)}) for row in rows]


def awkward_numbers(rng: np.random.Generator, n: int) -> np.ndarray:
    """Numbers of every magnitude and sign, whole ones, the rounding edges of `rounded`, and the unknown."""
    spread = rng.uniform(-1, 1, n) * 10.0 ** rng.integers(-8, 18, n)
    edges = np.array([0.0, -0.0, 1.0, -3.0, 99.99995, 99.999949, 100.0005, 0.03875, 1e-5, 123456789.0, 2.675, 1e16,
                      1.5e300, np.nan, np.inf, -np.inf, 0.1 + 0.2, 45.12345650000001])  # fmt: skip
    return np.concatenate([spread, np.round(spread[: n // 4]), edges])


def test_numbers_are_written_as_the_row_writer_wrote_them() -> None:
    x = awkward_numbers(np.random.default_rng(0), 4000)
    assert number_texts(x, "") == [str(v) if (v := _num(float(f))) is not None else "" for f in x]
    assert number_texts(np.array([np.nan, np.inf, -np.inf, 0.5]), "null") == ["null"] * 3 + ["0.5"]


def awkward_block(n: int = 7) -> Block:
    rng = np.random.default_rng(1)
    image_ids = np.empty(n, object)
    image_ids[:] = [i if i % 2 else f"img,{i}" for i in range(n)]
    names = np.empty(n, object)
    names[:] = [None if i % 3 else f'a "quoted"\nname {i} \u00e9' for i in range(n)]
    keys = {"frame_index": np.arange(n, dtype=np.int64), "image_id": image_ids, "file_name": names,
            "person": np.zeros(n, dtype=np.int64)}  # fmt: skip
    how = np.array(["calibrated", "none: a reason, with a comma", "", 'say "x"', "calibrated", "c", "d"][:n], object)
    cells = (
        {"measure": "first_deg", "value": awkward_numbers(rng, n)[:n], "unit": "deg", "low": rng.normal(size=n),
         "interval": how, "call": np.array(["symmetric", "", "uncertain", "", "", "", ""][:n], object)},
        {"measure": "second", "value": np.round(rng.normal(size=n) * 5), "unit": "band", "flag": "too_fast"},
    )  # fmt: skip
    return Block(n, keys, cells)


def test_a_block_writes_as_its_rows_do() -> None:
    block = awkward_block()
    rows = list(block.rows())
    assert [r.measure for r in rows[:4]] == ["first_deg", "second", "first_deg", "second"]  # pose by pose
    assert rows[1].call == "" and np.isnan(rows[1].low) and rows[1].flag == "too_fast"
    assert "".join(csv_lines([block])) == csv_of_rows(rows)
    assert [row for part in json_rows([block]) for row in part] == json_of_rows(rows)
    both = list(csv_and_json([block]))
    assert "".join(lines for lines, _ in both) == csv_of_rows(rows).split("\n", 1)[1]
    assert [row for _, part in both for row in part] == json_of_rows(rows)


def test_a_block_in_parts_writes_the_same() -> None:
    block = awkward_block()
    parts = list(block.parts(3))
    assert [p.n for p in parts] == [3, 3, 1]
    assert [r for p in parts for r in p.rows()] == list(block.rows())
    assert "".join(csv_lines(parts)) == "".join(csv_lines([block]))


def test_vectorised_calls_and_bands_match_one_at_a_time() -> None:
    values = np.array([np.nan, 10.0, 40.0, 28.0, 28.0, 20.0, 35.0, 35.0, 50.0, 70.0])
    low = np.array([np.nan, 5.0, 30.0, 27.0, np.nan, 10.0, 30.0, 29.0, np.nan, 60.0])
    high = np.array([np.nan, 15.0, 50.0, 30.0, np.nan, np.nan, 32.0, 27.0, np.nan, 80.0])
    expected = ["" if not np.isfinite(v) else symmetry_call(v, 28.0, lo, hi) if np.isfinite(lo) else "uncertain"
                for v, lo, hi in zip(values, low, high, strict=True)]  # fmt: skip
    assert symmetry_calls(values, 28.0, low, high).tolist() == expected
    bands = symmetry_bands(values)
    assert np.array_equal(bands, [symmetry_band(v) for v in values], equal_nan=True)


@pytest.fixture()
def kick(tmp_path: Path) -> Path:
    return write_document(tmp_path / "kick.zedo.json", result_document(kicking_poses(40), fps=30.0))


def test_an_analysis_writes_its_rows(kick: Path, tmp_path: Path) -> None:
    a = analyse(read_result(kick))
    rows = a.rows
    assert rows[-1].frame_index is None and rows[0].measure == "symmetry_upper_arm_deg"
    assert csv_text(a) == csv_of_rows(rows)
    assert analysis_document(a)["rows"] == [json.loads(r) for r in json_of_rows(rows)]
    write_csv(a, tmp_path / "a.csv")
    write_json(a, tmp_path / "a.json")
    write_csv_and_json(a, tmp_path / "b.csv", tmp_path / "b.json")
    assert (tmp_path / "b.csv").read_text() == (tmp_path / "a.csv").read_text()
    first, second = (json.loads((tmp_path / f"{k}.json").read_text()) for k in "ab")
    assert {**first, "created": ""} == {**second, "created": ""}
