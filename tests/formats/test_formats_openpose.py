"""Tests of the OpenPose reader (zedo_cli.formats.readers.openpose): single files, directories, skeletons, errors."""

from __future__ import annotations

import hashlib
import io
import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from format_fixtures import expected_xy, flat, openpose_frame, write_json

from zedo_cli.data.skeleton import SKELETONS
from zedo_cli.errors import InputFormatError
from zedo_cli.formats import detect_format, input_sha256, read_keypoints


def assert_error(path: Path | str, *parts: str, **kwargs: Any) -> str:
    with pytest.raises(InputFormatError) as info:
        read_keypoints(path, **kwargs)
    message = str(info.value)
    for part in parts:
        assert part in message, message
    return message


def test_single_body25_file_round_trips_every_person(tmp_path: Path) -> None:
    path = write_json(tmp_path / "clip_000000000007_keypoints.json", openpose_frame(1.0, 2.0, missing=(4, 24)))
    kp = read_keypoints(path)
    assert kp.format == "openpose" and kp.skeleton.name == "body25" and len(kp) == 2
    assert kp.image_ids == ["clip_000000000007"] * 2 and kp.frame_indices == [7, 7]
    assert kp.scores == [None, None] and kp.file_names == [None, None] and np.isnan(kp.image_sizes).all()
    for n, offset in enumerate((1.0, 2.0)):
        want = expected_xy(25, offset)
        present = [j for j in range(25) if j not in (4, 24)]
        np.testing.assert_array_equal(kp.xy[n, present], want[present])
        assert np.isnan(kp.xy[n, [4, 24]]).all() and (kp.confidence[n, [4, 24]] == 0).all()
        assert (kp.confidence[n, present] == 0.75).all()


def test_coco18_file_and_conversion_by_name(tmp_path: Path) -> None:
    kp = read_keypoints(write_json(tmp_path / "x.json", openpose_frame(5.0, count=18)), format="openpose")
    assert kp.skeleton.name == "coco18" and kp.frame_indices == [0] and kp.image_ids == ["x"]
    h36m = kp.to_skeleton(SKELETONS["h36m17"])
    xy = expected_xy(18, 5.0)
    # OpenPose's Neck (joint 1) is H36M's thorax; the pelvis is the hip midpoint (COCO-18 hips 8, 11).
    np.testing.assert_array_equal(h36m.xy[0, h36m.skeleton.index("thorax")], xy[1])
    np.testing.assert_array_equal(h36m.xy[0, h36m.skeleton.index("pelvis")], (xy[8] + xy[11]) / 2)
    np.testing.assert_array_equal(h36m.xy[0, h36m.skeleton.index("neck")], xy[0])
    syrip = kp.to_skeleton(SKELETONS["syrip12"])
    np.testing.assert_array_equal(syrip.xy[0, syrip.skeleton.index("left_ankle")], xy[13])
    assert h36m.frame_indices == [0]


def test_body25_to_h36m17_uses_midhip_neck_and_lowest_confidence(tmp_path: Path) -> None:
    doc = openpose_frame(3.0)
    doc["people"][0]["pose_keypoints_2d"][3 * 16 + 2] = 0.25  # left eye less sure
    kp = read_keypoints(write_json(tmp_path / "f_keypoints.json", doc)).to_skeleton(SKELETONS["h36m17"])
    xy, h = expected_xy(25, 3.0), kp.skeleton
    np.testing.assert_array_equal(kp.xy[0, h.index("pelvis")], xy[8])
    np.testing.assert_array_equal(kp.xy[0, h.index("thorax")], xy[1])
    np.testing.assert_array_equal(kp.xy[0, h.index("spine")], (xy[8] + xy[1]) / 2)
    np.testing.assert_array_equal(kp.xy[0, h.index("head")], (xy[15] + xy[16]) / 2)
    assert kp.confidence[0, h.index("head")] == 0.25
    coco = read_keypoints(write_json(tmp_path / "f_keypoints.json", doc)).to_skeleton(SKELETONS["coco17"])
    np.testing.assert_array_equal(coco.xy[0, coco.skeleton.index("right_ear")], xy[17])


def test_directory_is_read_in_natural_frame_order(tmp_path: Path) -> None:
    for frame, offsets in ((10, (10.0,)), (2, (2.0, 2.5)), (9, ())):
        write_json(tmp_path / f"clip_{frame:012d}_keypoints.json", openpose_frame(*offsets))
    (tmp_path / "notes.txt").write_text("not a frame")
    write_json(tmp_path / "settings.json", {"unrelated": True})  # ignored: *_keypoints.json files exist
    kp = read_keypoints(tmp_path)
    assert kp.path == str(tmp_path) and kp.format == "openpose"
    assert kp.frame_indices == [2, 2, 10]
    assert kp.image_ids == ["clip_000000000002", "clip_000000000002", "clip_000000000010"]
    np.testing.assert_array_equal(kp.xy[1], expected_xy(25, 2.5))
    np.testing.assert_array_equal(kp.xy[2], expected_xy(25, 10.0))
    kp = read_keypoints(tmp_path, format="openpose", image_size=(1920, 1080))
    np.testing.assert_array_equal(kp.image_sizes, [[1920, 1080]] * 3)


def test_directory_without_frame_numbers_uses_positions(tmp_path: Path) -> None:
    for name in ("b.json", "a.json"):
        write_json(tmp_path / name, openpose_frame(1.0, count=18))
    kp = read_keypoints(tmp_path)
    assert kp.image_ids == ["a", "b"] and kp.frame_indices == [0, 1]


def test_stdin_openpose_frame(monkeypatch: pytest.MonkeyPatch) -> None:
    raw = io.BytesIO(json.dumps(openpose_frame(4.0)).encode())
    monkeypatch.setattr("sys.stdin", type("Stdin", (), {"buffer": raw})())
    kp = read_keypoints("-")
    assert kp.format == "openpose" and kp.path == "-"
    np.testing.assert_array_equal(kp.xy[0], expected_xy(25, 4.0))


def test_detection() -> None:
    assert detect_format(openpose_frame(1.0)) == "openpose"
    assert detect_format({"version": 1.3, "people": []}) == "openpose"


def _person(values: list[float]) -> dict[str, Any]:
    return {"version": 1.3, "people": [{"pose_keypoints_2d": values}]}


@pytest.mark.parametrize(
    ("doc", "parts"),
    [
        (_person(flat(24, 1.0)), ("people[0].pose_keypoints_2d", "unsupported joint count 24")),
        (_person(flat(25, 1.0)[:-1]), ("people[0].pose_keypoints_2d", "multiple of 3")),
        (_person([math.nan, 1.0, 0.5] + flat(24, 1.0)), ("joint 0 (nose)", "not marked missing")),
        (_person([math.inf, 1.0, 0.5] + flat(24, 1.0)), ("people[0].pose_keypoints_2d", "joint 0")),
        (_person([1.0, 1.0, math.nan] + flat(24, 1.0)), ("people[0].pose_keypoints_2d[2]", "NaN")),
        (_person(["1"] + flat(25, 1.0)[1:]), ("people[0].pose_keypoints_2d[0]", "expected a number")),
        ({"people": [{"face_keypoints_2d": []}]}, ("people[0].pose_keypoints_2d", "missing required key")),
        ({"people": {}}, ("people", "expected a list")),
        ({"people": [[]]}, ("people[0]", "expected an object")),
        ({"version": 1.3, "people": []}, ("no instances found",)),
        ({"version": 1.3}, ("people", "missing required key")),
        ({"people": [{"pose_keypoints_2d": flat(25, 1.0)}, {"pose_keypoints_2d": flat(18, 1.0)}]},
         ("people[1].pose_keypoints_2d", "expected 25 joints (body25)", "got 18")),
    ],
)  # fmt: skip
def test_malformed_frames_name_the_field(tmp_path: Path, doc: Any, parts: tuple[str, ...]) -> None:
    path = write_json(tmp_path / "f_keypoints.json", doc)
    message = assert_error(path, *parts, format="openpose")
    assert message.startswith(f"{path}: ")


def test_directory_errors_name_the_file(tmp_path: Path) -> None:
    empty = tmp_path / "empty"
    empty.mkdir()
    assert_error(empty, "is a directory without OpenPose")
    clip = tmp_path / "clip"
    clip.mkdir()
    write_json(clip / "c_000000000001_keypoints.json", openpose_frame(1.0))
    write_json(clip / "c_000000000002_keypoints.json", openpose_frame(1.0, count=18))
    assert_error(clip, "c_000000000002_keypoints.json: people[0].pose_keypoints_2d", "expected 25 joints")
    (clip / "c_000000000002_keypoints.json").write_text("{not json")
    assert_error(clip, "c_000000000002_keypoints.json: invalid JSON at line 1")
    (clip / "c_000000000002_keypoints.json").write_text("")
    assert_error(clip, "c_000000000002_keypoints.json: file is empty")
    write_json(clip / "c_000000000002_keypoints.json", openpose_frame())
    write_json(clip / "d_000000000001_keypoints.json", openpose_frame(1.0))
    assert_error(clip, "frame 1 also comes from")
    assert_error(clip, "only OpenPose or LabelMe files are read from a directory", format="coco-results")
    nobody = tmp_path / "nobody"
    nobody.mkdir()
    write_json(nobody / "n_000000000000_keypoints.json", openpose_frame())
    assert_error(nobody, f"{nobody}: no instances found")


def test_input_sha256_of_files_directories_and_stdin(tmp_path: Path) -> None:
    clip = tmp_path / "clip"
    clip.mkdir()
    write_json(clip / "c_000000000001_keypoints.json", openpose_frame(1.0))
    first = input_sha256(clip)
    assert first is not None and len(first) == 64 and input_sha256(clip) == first
    write_json(clip / "c_000000000001_keypoints.json", openpose_frame(2.0))
    assert input_sha256(clip) != first
    single = write_json(tmp_path / "f.json", openpose_frame(1.0))
    assert input_sha256(single) == hashlib.sha256(single.read_bytes()).hexdigest()
    assert input_sha256("-") is None
    with pytest.raises(InputFormatError, match="cannot read file"):
        input_sha256(tmp_path / "missing.json")
