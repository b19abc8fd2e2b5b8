"""The input's keypoints that are not lifted (nose, eyes, ears, feet, ...): kept by name through
the conversion to the prior's joint set and person selection, written by every result format
and read back; results written before zedo kept them still read."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest
from format_fixtures import coco_annotations, expected_xy, openpose_frame, zedo_2d
from helpers import write_coco
from typer.testing import CliRunner
from writer_fixtures import INPUT_INFO, PARAMS, make_case

from zedo_cli.cli import app
from zedo_cli.data.keypoints import Keypoints2D, OtherKeypoints
from zedo_cli.data.skeleton import SKELETONS
from zedo_cli.errors import InputFormatError
from zedo_cli.formats.readers.inputs import read_keypoints, read_parsed
from zedo_cli.formats.readers.result import RESULT_FORMATS, read_result
from zedo_cli.formats.writers.outputs import write_result

SYRIP = SKELETONS["syrip12"]
FACE = ("nose", "left_eye", "right_eye", "left_ear", "right_ear")


def test_coco17_keeps_the_face_by_name_with_pixels_and_confidence() -> None:
    doc = coco_annotations()
    doc["annotations"][0]["keypoints"][3 * 3 + 2] = 0  # left_ear: v = 0, missing
    kp = read_parsed(doc, "a.json").to_skeleton(SYRIP)
    assert kp.skeleton is SYRIP and kp.other is not None
    assert kp.other.names == FACE
    want = expected_xy(17, 1.0)[:5]
    np.testing.assert_array_equal(kp.other.xy[0, [0, 1, 2, 4]], want[[0, 1, 2, 4]])
    assert np.isnan(kp.other.xy[0, 3]).all() and kp.other.confidence[0, 3] == 0.0
    assert kp.other.confidence[0, 0] == 1.0  # v = 2


def test_body25_keeps_face_feet_and_its_midpoints() -> None:
    kp = read_parsed(openpose_frame(0.0), "f_keypoints.json").to_skeleton(SYRIP)
    assert kp.other is not None
    assert kp.other.names == (
        "nose", "thorax", "pelvis", "right_eye", "left_eye", "right_ear", "left_ear", "left_big_toe",
        "left_small_toe", "left_heel", "right_big_toe", "right_small_toe", "right_heel",
    )  # fmt: skip
    body25 = SKELETONS["body25"].joints
    want = expected_xy(25, 0.0)[[body25.index(n) for n in kp.other.names]]
    np.testing.assert_array_equal(kp.other.xy[0], want)


def test_an_input_without_other_joints_keeps_an_empty_record() -> None:
    kp = read_parsed(zedo_2d(), "z.json").to_skeleton(SYRIP)
    assert kp.other is not None and kp.other.names == () and kp.other.xy.shape == (1, 0, 2)


def test_person_selection_keeps_the_other_points_with_their_instance() -> None:
    kp = read_parsed(openpose_frame(0.0, 300.0), "f_keypoints.json")
    chosen = kp.subset([1]).to_skeleton(SYRIP)
    assert chosen.other is not None
    np.testing.assert_array_equal(chosen.other.xy[0, 0], expected_xy(25, 300.0)[0])  # the second person's nose


def test_a_second_conversion_keeps_what_the_first_left_out() -> None:
    kp = read_parsed(coco_annotations(), "a.json")
    twice = kp.to_skeleton(SKELETONS["h36m17"]).to_skeleton(SYRIP)
    assert twice.other is not None
    assert twice.other.names[:5] == FACE  # then the h36m joints syrip12 lacks (pelvis, spine, ...)
    assert "pelvis" in twice.other.names and len(set(twice.other.names)) == len(twice.other.names)


def _case_with_others() -> tuple[Keypoints2D, object, np.ndarray, list[str]]:
    kp, res, mats, sources = make_case()
    n = len(kp)
    xy = np.arange(n * 5 * 2, dtype=float).reshape(n, 5, 2) * 1.25 + 100.0
    conf = np.full((n, 5), 0.75)
    xy[1, 2], conf[1, 2] = np.nan, 0.0  # instance 1's right eye missing
    return dataclasses.replace(kp, other=OtherKeypoints(FACE, xy, conf)), res, mats, sources


@pytest.mark.parametrize("fmt", RESULT_FORMATS)
@pytest.mark.parametrize("frame", ["camera", "root"])
def test_every_format_round_trips_the_other_keypoints(tmp_path: Path, fmt: str, frame: str) -> None:
    kp, res, mats, sources = _case_with_others()
    out = tmp_path / f"r.{fmt}"
    write_result(out, kp, res, mats, sources, PARAMS, INPUT_INFO, frame=frame, units="mm")
    back = read_result(out)
    assert back.other_keypoint_names == FACE
    assert back.other_keypoints_2d is not None and back.other_keypoint_confidence is not None
    np.testing.assert_allclose(back.other_keypoints_2d, kp.other.xy, atol=1e-3)  # pixels whatever the units
    np.testing.assert_allclose(back.other_keypoint_confidence, kp.other.confidence, atol=1e-4)
    assert np.isnan(back.other_keypoints_2d[1, 2]).all() and back.other_keypoint_confidence[1, 2] == 0.0
    np.testing.assert_allclose(back.poses, res.poses_camera if frame == "camera" else res.poses_root_relative,
                               atol=2e-6)  # the lifted joints are read as before  # fmt: skip


def test_json_names_them_in_the_header_and_lists_them_per_person(tmp_path: Path) -> None:
    kp, res, mats, sources = _case_with_others()
    out = tmp_path / "r.json"
    write_result(out, kp, res, mats, sources, PARAMS, INPUT_INFO)
    doc = json.loads(out.read_text())
    assert doc["other_keypoints"]["joints"] == list(FACE)
    person = doc["frames"][0]["persons"][1]
    assert person["other_keypoints_2d"][2] is None and person["other_keypoint_confidence"][2] is None
    assert person["other_keypoints_2d"][0] == [112.5, 113.75]  # (1 * 5 + 0) * 2 * 1.25 + 100


def test_csv_rows_have_no_joint_index_and_no_3d(tmp_path: Path) -> None:
    kp, res, mats, sources = _case_with_others()
    out = tmp_path / "r.csv"
    write_result(out, kp, res, mats, sources, PARAMS, INPUT_INFO)
    lines = out.read_text().splitlines()
    header = lines[0].split(",")
    rows = [dict(zip(header, line.split(","), strict=False)) for line in lines[1:]]
    nose = [r for r in rows if r["joint"] == "nose"]
    assert len(nose) == len(kp) and all(r["joint_index"] == "" and r["x_cam_m"] == "" for r in nose)
    assert nose[0]["u_px"] == "100.0" and nose[0]["confidence"] == "0.75"
    assert len(rows) == len(kp) * (SYRIP.num_joints + len(FACE))


@pytest.mark.parametrize("fmt", RESULT_FORMATS)
def test_an_input_without_other_keypoints_reads_back_empty(tmp_path: Path, fmt: str) -> None:
    kp, res, mats, sources = make_case()
    kp = dataclasses.replace(kp, other=OtherKeypoints.empty(len(kp)))
    out = tmp_path / f"r.{fmt}"
    write_result(out, kp, res, mats, sources, PARAMS, INPUT_INFO)
    back = read_result(out)
    assert back.other_keypoint_names == () and back.other_keypoints_2d is not None
    assert back.other_keypoints_2d.shape == (len(kp), 0, 2)


def test_results_without_the_field_still_read(tmp_path: Path) -> None:
    kp, res, mats, sources = make_case()  # a caller's own record: no other keypoints
    for fmt in RESULT_FORMATS:
        out = tmp_path / f"old.{fmt}"
        write_result(out, kp, res, mats, sources, PARAMS, INPUT_INFO)
        back = read_result(out)
        assert back.other_keypoints_2d is None and back.other_keypoint_names == (), fmt
    assert "other_keypoints" not in json.loads((tmp_path / "old.json").read_text())


def test_a_person_list_of_the_wrong_length_names_the_field(tmp_path: Path) -> None:
    kp, res, mats, sources = _case_with_others()
    out = tmp_path / "r.json"
    write_result(out, kp, res, mats, sources, PARAMS, INPUT_INFO)
    doc = json.loads(out.read_text())
    doc["frames"][0]["persons"][0]["other_keypoints_2d"].pop()
    out.write_text(json.dumps(doc))
    with pytest.raises(InputFormatError, match=r"frames\[0\]\.persons\[0\]\.other_keypoints_2d: expected 5"):
        read_result(out)


def test_lift_writes_the_inputs_face_points_as_given(tiny_prior_path: Path, tmp_path: Path) -> None:
    src = write_coco(tmp_path / "kp.json")
    doc = json.loads(src.read_text())
    for a, ann in enumerate(doc["annotations"]):  # a face for each person; the second's ears missing
        face = [[300.0 + a, 100.5], [290.0, 95.25], [310.0, 95.25], [280.0, 99.0], [320.0, 99.0]]
        for e, (x, y) in enumerate(face):
            ann["keypoints"][3 * e : 3 * e + 3] = [x, y, 0 if (a == 1 and e >= 3) else 2]
    src.write_text(json.dumps(doc))
    out = tmp_path / "kp.zedo.jsonl"
    result = CliRunner().invoke(app, ["lift", "--prior", str(tiny_prior_path), "--steps", "5", "-q", str(src),
                                      "-o", str(out)])  # fmt: skip
    assert result.exit_code == 0, result.output
    back = read_result(out)
    assert back.other_keypoint_names == FACE
    kp = read_keypoints(src)
    np.testing.assert_allclose(back.other_keypoints_2d, kp.xy[:, :5], atol=1e-3)
    assert np.isnan(back.other_keypoints_2d[1, 3:]).all()
