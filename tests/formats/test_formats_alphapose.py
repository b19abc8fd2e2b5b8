"""Tests of the AlphaPose results reader (zedo_cli.formats.readers.alphapose)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from format_fixtures import alphapose, expected_xy, flat, write_json

from zedo_cli.data.skeleton import SKELETONS
from zedo_cli.errors import InputFormatError
from zedo_cli.formats import detect_format, read_keypoints, read_parsed


def test_halpe26_values_order_and_scores(tmp_path: Path) -> None:
    kp = read_keypoints(write_json(tmp_path / "alphapose-results.json", alphapose()))
    assert kp.format == "alphapose" and kp.skeleton.name == "halpe26" and len(kp) == 3
    # natural image order ("2.jpg" before "10.jpg"), persons of one image in file order
    assert kp.image_ids == ["2.jpg", "2.jpg", "10.jpg"] and kp.file_names == kp.image_ids
    assert kp.frame_indices == [2, 2, 10] and kp.scores == [1.5, 0.5, 2.875]
    np.testing.assert_array_equal(kp.xy[1], expected_xy(26, 3.0))
    np.testing.assert_array_equal(kp.xy[2], expected_xy(26, 1.0))
    assert kp.confidence[2, 0] == 1.0  # 1.5 clipped
    assert np.isnan(kp.xy[0, 4]).all() and kp.confidence[0, 4] == 0 and kp.confidence[0, 5] == 0.75
    assert np.isnan(kp.image_sizes).all()
    kp = read_keypoints(write_json(tmp_path / "a.json", alphapose()), image_size=(640, 480))
    np.testing.assert_array_equal(kp.image_sizes, [[640, 480]] * 3)


def test_halpe26_converts_like_motionbert() -> None:
    kp = read_parsed(alphapose(), "a.json").to_skeleton(SKELETONS["h36m17"])
    xy, h = expected_xy(26, 3.0), kp.skeleton
    expected = {"pelvis": xy[19], "thorax": xy[18], "head": xy[17], "neck": xy[0], "spine": (xy[18] + xy[19]) / 2,
                "right_ankle": xy[16], "left_wrist": xy[9]}  # fmt: skip
    for joint, value in expected.items():
        np.testing.assert_array_equal(kp.xy[1, h.index(joint)], value)
    syrip = read_parsed(alphapose(), "a.json").to_skeleton(SKELETONS["syrip12"])
    np.testing.assert_array_equal(syrip.xy[1, syrip.skeleton.index("right_hip")], xy[12])


def test_coco17_and_integer_ids(tmp_path: Path) -> None:
    data = alphapose(count=17)
    for n, entry in enumerate(data):
        entry["image_id"] = [7, 3, 3][n]
    kp = read_keypoints(write_json(tmp_path / "a.json", data), format="alphapose")
    assert kp.skeleton.name == "coco17" and kp.image_ids == [3, 3, 7] and kp.frame_indices == [3, 3, 7]
    assert kp.file_names == [None, None, None]


def test_detection() -> None:
    assert detect_format(alphapose()) == "alphapose"
    plain = [{"image_id": 1, "keypoints": flat(17, 1.0), "score": 0.5}]
    assert detect_format(plain) == "coco-results"
    assert detect_format([plain[0] | {"idx": 0}]) == "alphapose"
    assert detect_format([plain[0] | {"image_id": "1.jpg"}]) == "alphapose"


def test_companion_images_join_on_file_name(tmp_path: Path) -> None:
    images = write_json(tmp_path / "gt.json", {"images": [
        {"id": 0, "file_name": "test0.jpg", "original_file_name": "2.jpg", "width": 64, "height": 48},
        {"id": 1, "file_name": "10.jpg", "width": 32, "height": 24}]})  # fmt: skip
    kp = read_keypoints(write_json(tmp_path / "a.json", alphapose()), images=images)
    np.testing.assert_array_equal(kp.image_sizes, [[64, 48], [64, 48], [32, 24]])


def _entry(**changes: Any) -> list[dict[str, Any]]:
    return [{"image_id": "1.jpg", "keypoints": flat(26, 1.0), "score": 1.0, "idx": 0} | changes]


@pytest.mark.parametrize(
    ("data", "parts"),
    [
        (_entry(keypoints=flat(136, 1.0)), ("[0].keypoints", "unsupported joint count 136", "17 COCO or 26 Halpe")),
        (_entry(keypoints=flat(25, 1.0)), ("[0].keypoints", "unsupported joint count 25")),
        (_entry() + _entry(keypoints=flat(17, 1.0)), ("[1].keypoints", "expected 26 joints (halpe26)")),
        (_entry(keypoints=[math.nan, 1.0, 0.5, *flat(25, 1.0)]), ("[0].keypoints", "joint 0 (nose)")),
        (_entry(keypoints=flat(26, 1.0)[:-2]), ("[0].keypoints", "multiple of 3")),
        (_entry(image_id=1.5), ("[0].image_id", "integer or string")),
        (_entry(score="high"), ("[0].score", "expected a number")),
        ([{"image_id": "1.jpg", "idx": 0}], ("[0].keypoints", "missing required key")),
        ([{"image_id": "1.jpg", "keypoints": {}}], ("[0].keypoints", "expected a list")),
        ([], ("no instances found",)),
        ({"image_id": "1.jpg"}, ("expected a list, got an object",)),
    ],
)
def test_malformed_input_names_file_and_field(tmp_path: Path, data: Any, parts: tuple[str, ...]) -> None:
    path = write_json(tmp_path / "a.json", data)
    with pytest.raises(InputFormatError) as info:
        read_keypoints(path, format="alphapose")
    message = str(info.value)
    assert message.startswith(f"{path}: ") and all(part in message for part in parts), message
