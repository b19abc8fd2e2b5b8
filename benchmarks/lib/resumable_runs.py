"""Benchmark runs recorded one JSON line each, so an interrupted sweep resumes where it stopped
(shared by adapt_table.py, adapt_validation.py, norms_false_alarms.py and share_calibration.py)."""

from __future__ import annotations

import json
from collections.abc import Callable, Iterator
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path


def read_rows(path: Path) -> list[dict]:
    """The runs already recorded in `path` (none when it does not exist)."""
    if not path.exists():
        return []
    return [json.loads(line) for line in path.read_text().splitlines() if line.strip()]


def append_row(path: Path, row: dict) -> None:
    """Record one finished run as a JSON line at the end of `path`."""
    with path.open("a") as fh:
        fh.write(json.dumps(row) + "\n")


def run_and_record(run_one: Callable[[dict], dict], jobs: list[dict], out: Path, workers: int) -> Iterator[dict]:
    """Run `jobs` in `workers` processes; append each result to `out` as soon as it finishes, then yield it."""
    with ProcessPoolExecutor(max_workers=workers) as pool:
        for future in as_completed([pool.submit(run_one, job) for job in jobs]):
            row = future.result()
            append_row(out, row)
            yield row
