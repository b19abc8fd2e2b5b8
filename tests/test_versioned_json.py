"""The shipped calibration files through their pydantic entries: read and written again unchanged, and a bad
field one line naming the file and the field."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from zedo_cli.analysis.uncertainty import calibration, head_calibration
from zedo_cli.errors import WeightsError
from zedo_cli.lifting import uncertainty

SHIPPED: dict[str, tuple[Path, Callable[[Path], list[Any]], Callable[[Path, list[Any]], None]]] = {
    "measures.json": (calibration.bundled_path(), calibration.read_calibrations, calibration.write_calibrations),
    "head.json": (head_calibration.bundled_path(), head_calibration.read_head_calibrations,
                  head_calibration.write_head_calibrations),
    "uncertainty.json": (uncertainty.bundled_calibrations_path(), uncertainty.read_calibrations,
                         uncertainty.write_calibrations),
}  # fmt: skip


@pytest.mark.parametrize("name", SHIPPED)
def test_a_shipped_file_written_again_through_its_models_is_the_same(tmp_path: Path, name: str) -> None:
    shipped, read, write = SHIPPED[name]
    assert shipped.exists()
    again = tmp_path / name
    write(again, read(shipped))
    assert json.loads(again.read_text()) == json.loads(shipped.read_text())
    assert again.read_text() == shipped.read_text()  # byte for byte: the same keys in the same order, the same digits


def test_a_quantile_of_too_few_cases_is_null_in_the_file_and_nan_when_read(tmp_path: Path) -> None:
    shipped = calibration.read_calibrations(calibration.bundled_path())[0]
    name, model = next(iter(shipped.measures.items()))
    q = {lv: (np.nan, *v[1:]) for lv, v in model.q_high.items()}
    changed = calibration.MeasureCalibration(**{**vars(shipped), "measures": {name: type(model)(
        model.center, model.weight, model.edges, model.q_low, q, model.circular)}})  # fmt: skip
    path = tmp_path / "m.json"
    calibration.write_calibrations(path, [changed])
    entry = json.loads(path.read_text())["calibrations"][0]["measures"][name]
    assert all(v[0] is None for v in entry["q_high"].values())
    back = calibration.read_calibrations(path)[0].measures[name]
    assert all(np.isnan(v[0]) for v in back.q_high.values()) and back.q_low == model.q_low


@pytest.mark.parametrize(
    ("name", "spoil", "message"),
    [
        ("measures.json", lambda d: d["calibrations"][1].update(prior_sha256=1),
         r"unreadable measure calibration \(calibrations\[1\]\.prior_sha256: Input should be a valid string\)"),
        ("measures.json", lambda d: d["calibrations"][3]["domain"].update(focal_px=[600.0]),
         r"\(calibrations\[3\]\.domain\.focal_px: List should have at least 2 items"),
        ("measures.json", lambda d: d["calibrations"][0].update(scope="poses"), r"\(calibrations\[0\]\.scope: "),
        ("measures.json", lambda d: d["calibrations"][0].update(weights=1),
         r"\(calibrations\[0\]\.weights: Extra inputs are not permitted\)"),
        ("head.json", lambda d: d["calibrations"][0]["measures"]["head_tilt_median_deg"].update(error=True),
         r"unreadable head interval calibration \(calibrations\[0\]\.measures\.head_tilt_median_deg\.error: "),
        ("uncertainty.json", lambda d: d["models"][0]["scale"].__setitem__(2, "0.1"),
         r"unreadable uncertainty calibration \(models\[0\]\.scale\[2\]: Input should be a valid number\)"),
    ],
)  # fmt: skip
def test_a_bad_field_is_one_line_naming_the_file_and_the_field(
    tmp_path: Path, name: str, spoil: Callable[[dict], None], message: str
) -> None:
    shipped, read, _ = SHIPPED[name]
    doc = json.loads(shipped.read_text())
    spoil(doc)
    path = tmp_path / name
    path.write_text(json.dumps(doc))
    with pytest.raises(WeightsError, match=rf"{name}: .*{message}") as err:
        read(path)
    assert "\n" not in str(err.value)
