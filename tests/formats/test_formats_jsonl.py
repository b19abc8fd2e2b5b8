"""Tests of the zedo JSON Lines reader (zedo_cli.formats.readers.jsonl): files, stdin, detection, errors."""

from __future__ import annotations

import io
import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from format_fixtures import coco_results, expected_xy, jsonl_records, jsonl_text

from zedo_cli.errors import InputFormatError
from zedo_cli.formats import detect_format, read_keypoints, read_keypoints_text


def _stdin(monkeypatch: pytest.MonkeyPatch, text: str) -> None:
    monkeypatch.setattr("sys.stdin", type("Stdin", (), {"buffer": io.BytesIO(text.encode())})())


def _check_values(kp: Any) -> None:
    assert kp.format == "zedo-jsonl" and kp.skeleton.name == "coco17" and len(kp) == 3
    assert kp.frame_indices == [0, 0, 2] and kp.image_ids == [0, 0, "f2.png"]
    assert kp.file_names == [None, None, "f2.png"] and kp.scores == [0.75, None, None]
    np.testing.assert_array_equal(kp.image_sizes, [[640, 480]] * 3)  # line 3 has none: the first line's serves
    np.testing.assert_array_equal(kp.xy[1], expected_xy(17, 2.0))
    np.testing.assert_array_equal(kp.xy[2], expected_xy(17, 3.0))
    assert np.isnan(kp.xy[0, 2]).all() and kp.confidence[0, 2] == 0  # null
    assert kp.confidence[0, 1] == 1.0 and kp.confidence[0, 0] == 0.5  # [x, y] and [x, y, c]


def test_file_round_trips(tmp_path: Path) -> None:
    path = tmp_path / "kp.jsonl"
    path.write_text(jsonl_text(jsonl_records()) + "\n   \n")  # blank lines are skipped
    _check_values(read_keypoints(path))
    _check_values(read_keypoints(path, format="zedo-jsonl"))


def test_stdin(monkeypatch: pytest.MonkeyPatch) -> None:
    _stdin(monkeypatch, jsonl_text(jsonl_records()))
    kp = read_keypoints("-")
    assert kp.path == "-"
    _check_values(kp)


def test_stdin_still_takes_a_json_document(monkeypatch: pytest.MonkeyPatch) -> None:
    _stdin(monkeypatch, json.dumps(coco_results(), indent=2))
    assert read_keypoints("-").format == "coco-results"


def test_detected_by_content_and_one_record_is_a_document(tmp_path: Path) -> None:
    path = tmp_path / "stream.txt"
    path.write_text(jsonl_text(jsonl_records()))
    _check_values(read_keypoints(path))
    one = jsonl_records()[2]
    assert detect_format(one) == "zedo-jsonl"
    assert len(read_keypoints_text(json.dumps(one), "one.json")) == 1


def test_named_skeleton_and_raw_line_separators() -> None:
    line = {"frame": 4, "skeleton": "syrip12", "file_name": "a\u2028b.png", "persons": [{"keypoints": [[1, 2]] * 12}]}
    text = json.dumps(line, ensure_ascii=False) + "\n" + json.dumps({"frame": 5, "persons": []})
    kp = read_keypoints_text(text, "s.jsonl")
    assert kp.skeleton.name == "syrip12" and kp.file_names == ["a\u2028b.png"] and kp.frame_indices == [4]


@pytest.mark.parametrize(
    ("lines", "parts"),
    [
        (['{"frame": 0, "persons": []}', "{oops"], ("line 2", "invalid JSON at column 2")),
        (['{"persons": []}'], ("line 1: frame", "missing required key")),
        (['{"frame": 0}'], ("line 1: persons", "missing required key")),
        (['{"frame": -2, "persons": []}'], ("line 1: frame", ">= 0")),
        (['{"frame": 0.5, "persons": []}'], ("line 1: frame", "frame number")),
        (["[1, 2]"], ("line 1", "expected an object, got a list")),
        (['{"frame": 0, "persons": [{"keypoints": [[1, 2]]}]}'], ("line 1: persons[0].keypoints", "joint count 1")),
        (['{"frame": 0, "persons": [{}]}'], ("line 1: persons[0].keypoints", "missing required key")),
        ([json.dumps({"frame": 0, "persons": [{"keypoints": [[1, 2]] * 17}]}),
          json.dumps({"frame": 1, "persons": [{"keypoints": [[1, 2]] * 18}]})],
         ("line 2: persons[0].keypoints", "expected 17 joints (coco17)")),
        ([json.dumps({"frame": 0, "persons": [{"keypoints": [[1, 2, 3]] * 17}]})],
         ("line 1: persons[0].keypoints[0][2]", "confidence in [0, 1]")),
        ([json.dumps({"frame": 0, "persons": [{"keypoints": [[1, "2"]] * 17}]})],
         ("line 1: persons[0].keypoints[0][1]", "expected a number")),
        ([json.dumps({"frame": 0, "persons": [{"keypoints": [[float("nan"), 2]] * 17}]})], ("joint 0 (nose)",)),
        ([json.dumps({"frame": 0, "skeleton": "coco17", "persons": []}),
          json.dumps({"frame": 1, "skeleton": "h36m17", "persons": []})], ("line 2: skeleton", "expected coco17")),
        (['{"frame": 0, "skeleton": "nope", "persons": []}'], ("line 1: skeleton", "unknown skeleton")),
        (['{"frame": 0, "image_size": [0, 1], "persons": []}'], ("line 1: image_size[0]", "positive")),
        (['{"frame": 0, "file_name": 3, "persons": []}'], ("line 1: file_name", "expected a string")),
        ([json.dumps({"frame": 0, "persons": [{"keypoints": [[1, 2]] * 17, "score": "x"}]})],
         ("line 1: persons[0].score", "expected a number")),
        (['{"frame": 0, "persons": []}'] * 2, ("no instances found",)),
        (["", "  "], ("file is empty",)),
    ],
)  # fmt: skip
def test_malformed_lines_name_file_line_and_field(tmp_path: Path, lines: list[str], parts: tuple[str, ...]) -> None:
    path = tmp_path / "kp.jsonl"
    path.write_text("\n".join(lines))
    with pytest.raises(InputFormatError) as info:
        read_keypoints(path)
    message = str(info.value)
    assert message.startswith(f"{path}: ") and all(part in message for part in parts), message
