"""Tests of the MMPose readers (zedo_cli.formats.readers.mmpose): the three layouts of FORMATS.md 3.5."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from format_fixtures import (
    MMPOSE_COCO_NAMES,
    MMPOSE_HALPE_NAMES,
    expected_xy,
    mmpose_demo,
    mmpose_image,
    mmpose_instance,
    mmpose_video,
    write_json,
)

from zedo_cli.data.skeleton import SKELETONS
from zedo_cli.errors import InputFormatError
from zedo_cli.formats import detect_format, read_keypoints, read_parsed

MMPOSE_H36M_NAMES = ["root", "right_hip", "right_knee", "right_foot", "left_hip", "left_knee", "left_foot", "spine",
                     "thorax", "neck_base", "head", "left_shoulder", "left_elbow", "left_wrist", "right_shoulder",
                     "right_elbow", "right_wrist"]  # fmt: skip


def test_image_layout_round_trips(tmp_path: Path) -> None:
    kp = read_keypoints(write_json(tmp_path / "baby01.json", mmpose_image()))
    assert kp.format == "mmpose-image" and kp.skeleton.name == "coco17" and len(kp) == 2
    assert kp.image_ids == ["baby01", "baby01"] and kp.frame_indices is None
    assert kp.scores == [0.875, 0.25]  # bbox_score
    np.testing.assert_array_equal(kp.xy[1], expected_xy(17, 2.0))
    present = [j for j in range(17) if j != 3]
    np.testing.assert_array_equal(kp.xy[0, present], expected_xy(17, 1.0)[present])
    assert np.isnan(kp.xy[0, 3]).all() and kp.confidence[0, 3] == 0 and kp.confidence[0, 0] == 0.5


def test_video_layout_frames_and_halpe_by_count(tmp_path: Path) -> None:
    kp = read_keypoints(write_json(tmp_path / "clip.json", mmpose_video(count=26)))
    assert kp.format == "mmpose-video" and kp.skeleton.name == "halpe26"
    assert kp.image_ids == [0, 0, 2] and kp.frame_indices == [0, 0, 2]
    np.testing.assert_array_equal(kp.xy[2, 1:], expected_xy(26, 3.0)[1:])
    assert kp.confidence[2, 0] == 0 and np.isnan(kp.xy[2, 0]).all()
    h36m = kp.to_skeleton(SKELETONS["h36m17"])
    xy = expected_xy(26, 1.0)  # Halpe: head 17, neck 18 (= thorax), hip 19 (= pelvis)
    for joint, index in (("head", 17), ("thorax", 18), ("pelvis", 19), ("neck", 0)):
        np.testing.assert_array_equal(h36m.xy[0, h36m.skeleton.index(joint)], xy[index])


def test_demo_video_is_one_based_and_names_the_skeleton(tmp_path: Path) -> None:
    kp = read_keypoints(write_json(tmp_path / "results_clip.json", mmpose_demo()))
    assert kp.format == "mmpose-demo" and kp.skeleton.name == "coco17"
    assert kp.image_ids == [1, 2, 2] and kp.frame_indices == [0, 1, 1]
    np.testing.assert_array_equal(kp.xy[2], expected_xy(17, 3.0))
    assert read_parsed(mmpose_demo(start=0), "r.json").frame_indices == [0, 1, 1]


@pytest.mark.parametrize(
    ("names", "dataset", "skeleton"),
    [(MMPOSE_H36M_NAMES, "h36m", "h36m17"), (MMPOSE_HALPE_NAMES, "halpe26", "halpe26"),
     (MMPOSE_H36M_NAMES, "coco", "h36m17")],
)  # fmt: skip
def test_demo_meta_info_names_the_skeleton(names: list[str], dataset: str, skeleton: str) -> None:
    """keypoint_id2name decides (before dataset_name); the reason is recorded."""
    kp = read_parsed(mmpose_demo(names, dataset), "r.json")
    assert kp.skeleton.name == skeleton
    assert kp.source_skeleton == {"name": skeleton, "reason": "meta_info.keypoint_id2name names"}
    np.testing.assert_array_equal(kp.xy[0], expected_xy(len(names), 1.0))


@pytest.mark.parametrize("dataset", ["h36m", "other"])
def test_demo_unknown_joint_names_are_an_error_unless_skeleton_is_given(dataset: str) -> None:
    """17 unknown names were silently read as h36m17 (dataset_name) or COCO-17 (count)."""
    doc = mmpose_demo([f"j{k}" for k in range(17)], dataset)
    with pytest.raises(InputFormatError, match=r"r\.json: meta_info\.keypoint_id2name: unknown joint names \('j0'"):
        read_parsed(doc, "r.json")
    kp = read_parsed(doc, "r.json", skeleton="h36m17")
    assert kp.skeleton.name == "h36m17" and kp.source_skeleton["reason"].startswith("--skeleton")
    np.testing.assert_array_equal(kp.xy[0], expected_xy(17, 1.0))


def test_demo_without_names_uses_dataset_name_then_count() -> None:
    doc = mmpose_demo()
    del doc["meta_info"]["keypoint_id2name"]
    doc["meta_info"]["dataset_name"] = "h36m"
    kp = read_parsed(doc, "r.json")
    assert kp.source_skeleton == {"name": "h36m17", "reason": "meta_info.dataset_name 'h36m'"}
    del doc["meta_info"]
    assert read_parsed(doc, "r.json").source_skeleton == {"name": "coco17", "reason": "joint count 17"}


def test_demo_permuted_keypoint_id2name_gives_the_standard_order() -> None:
    """The same 17 joints listed in another order, the points permuted to match, read the same."""
    standard = read_parsed(mmpose_demo(), "r.json")
    perm = np.random.default_rng(3).permutation(17)
    doc = mmpose_demo([MMPOSE_COCO_NAMES[k] for k in perm])
    for frame in doc["instance_info"]:
        for inst in frame["instances"]:
            inst["keypoints"] = [inst["keypoints"][k] for k in perm]
            inst["keypoint_scores"] = [inst["keypoint_scores"][k] for k in perm]
    permuted = read_parsed(doc, "r.json")
    assert permuted.skeleton.name == "coco17"
    assert permuted.source_skeleton["reason"] == "meta_info.keypoint_id2name names, in the file's order"
    np.testing.assert_array_equal(permuted.xy, standard.xy)
    np.testing.assert_array_equal(permuted.confidence, standard.confidence)


def test_demo_image_is_a_flat_instance_list(tmp_path: Path) -> None:
    doc = {"meta_info": {"dataset_name": "coco"}, "instance_info": mmpose_image()}
    kp = read_keypoints(write_json(tmp_path / "results_baby02.json", doc))
    assert kp.format == "mmpose-demo" and kp.image_ids == ["baby02", "baby02"] and kp.frame_indices is None
    np.testing.assert_array_equal(kp.xy[1], expected_xy(17, 2.0))


def test_detection_and_the_umbrella_format(tmp_path: Path) -> None:
    assert detect_format(mmpose_image()) == "mmpose-image"
    assert detect_format(mmpose_video()) == "mmpose-video"
    assert detect_format(mmpose_demo()) == "mmpose-demo"
    layouts = ((mmpose_image(), "mmpose-image"), (mmpose_video(), "mmpose-video"), (mmpose_demo(), "mmpose-demo"))
    for doc, fmt in layouts:
        assert read_keypoints(write_json(tmp_path / "m.json", doc), format="mmpose").format == fmt
    with pytest.raises(InputFormatError, match="not an MMPose prediction file"):
        read_parsed({"people": []}, "m.json", format="mmpose")


def test_scores_above_one_are_clipped() -> None:
    inst = mmpose_instance(1.0)
    inst["keypoint_scores"][0] = 7.5  # RTMPose SimCC
    assert read_parsed([inst], "m.json").confidence[0, 0] == 1.0


def _inst(**changes: Any) -> dict[str, Any]:
    return mmpose_instance(1.0) | changes


@pytest.mark.parametrize(
    ("doc", "fmt", "parts"),
    [
        ([_inst(keypoints=[[1.0, 2.0, 3.0]] * 17)], "mmpose-image", ("[0].keypoints[0]", "3D keypoints")),
        ([_inst(keypoint_scores=[0.5] * 16)], "mmpose-image", ("[0].keypoint_scores", "expected 17 scores")),
        ([{"keypoints": [[1.0, 2.0]] * 17}], "mmpose-image", ("[0].keypoint_scores", "missing required key")),
        ([_inst(keypoints=[[1.0, 2.0]] * 14)], "mmpose-image", ("[0].keypoints", "unsupported joint count 14")),
        ([_inst(keypoints=[[math.nan, 2.0]] * 17)], "mmpose-image", ("[0].keypoints", "joint 0 (nose)")),
        ([_inst(keypoints=[["1", 2.0]] * 17)], "mmpose-image", ("[0].keypoints[0][0]", "expected a number")),
        ([_inst(bbox_score=math.inf)], "mmpose-image", ("[0].bbox_score", "finite")),
        ([_inst(), mmpose_instance(1.0, count=26)], "mmpose-image", ("[1].keypoints", "expected 17 joints (coco17)")),
        ([], "mmpose-image", ("no instances found",)),
        ([{"frame_id": -1, "instances": []}], "mmpose-video", ("[0].frame_id", ">= 0")),
        ([{"frame_id": True, "instances": []}], "mmpose-video", ("[0].frame_id", "frame number")),
        ([{"frame_id": 0}], "mmpose-video", ("[0].instances", "missing required key")),
        ([{"frame_id": 0, "instances": [[]]}], "mmpose-video", ("[0].instances[0]", "expected an object")),
        ({"instance_info": {}}, "mmpose-demo", ("instance_info", "expected a list")),
        ({"meta_info": [], "instance_info": []}, "mmpose-demo", ("meta_info", "expected an object")),
        ({"meta_info": {"keypoint_id2name": {"a": "nose"}}, "instance_info": []}, "mmpose-demo",
         ("meta_info.keypoint_id2name.a", "joint id")),
        ({"meta_info": {"keypoint_id2name": {"0": 5}}, "instance_info": []}, "mmpose-demo",
         ("meta_info.keypoint_id2name[0]", "joint name")),
        (mmpose_demo(MMPOSE_H36M_NAMES) | {"instance_info": [{"frame_id": 1, "instances": [
            mmpose_instance(1.0, count=26)]}]}, "mmpose-demo",
         ("instance_info[0].instances[0].keypoints", "expected 17 joints (h36m17)")),
    ],
)  # fmt: skip
def test_malformed_input_names_file_and_field(tmp_path: Path, doc: Any, fmt: str, parts: tuple[str, ...]) -> None:
    path = write_json(tmp_path / "m.json", doc)
    for format in (fmt, "mmpose") if doc else (fmt,):
        with pytest.raises(InputFormatError) as info:
            read_keypoints(path, format=format)
        message = str(info.value)
        assert message.startswith(f"{path}: ") and all(part in message for part in parts), message


def test_demo_unknown_dataset_name_without_names_is_an_error() -> None:
    doc = mmpose_demo()
    doc["meta_info"] = {"dataset_name": "crowdpose"}
    with pytest.raises(InputFormatError, match=r"r\.json: meta_info\.dataset_name: 'crowdpose' is not a joint set"):
        read_parsed(doc, "r.json")
    assert read_parsed(doc, "r.json", skeleton="coco17").source_skeleton == {"name": "coco17", "reason": "--skeleton"}
