"""`--json` reports are strict JSON: unknown figures (NaN, infinities) become null."""

from __future__ import annotations

import json

import numpy as np
import pytest

from zedo_cli.cli.common import finite_or_null, print_json_report


def _strict(text: str) -> object:
    def refuse(name: str) -> None:
        raise AssertionError(f"non-standard JSON constant {name}")

    return json.loads(text, parse_constant=refuse)


def test_nan_and_infinities_become_null_at_any_depth() -> None:
    doc = {"a": float("nan"), "b": [1.5, float("inf"), {"c": np.float64("nan"), "d": np.float32(2.0)}],
           "e": (np.float32("-inf"), 3), "f": "NaN", "g": None, "h": True}  # fmt: skip
    out = finite_or_null(doc)
    assert out == {"a": None, "b": [1.5, None, {"c": None, "d": 2.0}], "e": [None, 3], "f": "NaN", "g": None, "h": True}


def test_finite_values_are_kept_as_they_are() -> None:
    doc = {"mpjpe_mm": 39.43, "count": 100, "per_joint": {"left_hip": 12.0}, "empty": []}
    assert finite_or_null(doc) == doc


def test_print_json_report_writes_strict_json(capsys: pytest.CaptureFixture[str]) -> None:
    print_json_report({"accuracy": [{"preset": "fast", "mpjpe_mm": float("nan"), "count": 0}]})
    assert _strict(capsys.readouterr().out) == {"accuracy": [{"preset": "fast", "mpjpe_mm": None, "count": 0}]}
