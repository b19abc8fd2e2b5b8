"""Reading zedo's results back in every format lift writes, and refusing what is not one."""

from __future__ import annotations

import io
import json
import sys
from pathlib import Path

import numpy as np
import pytest
from analysis_results import kicking_poses, result_document, write_document
from writer_fixtures import INPUT_INFO, PARAMS, UNLIFTED, make_case

from zedo_cli.errors import InputFormatError
from zedo_cli.evaluation.result_scoring import read_result_file
from zedo_cli.formats.readers.result import read_result, read_result_bytes
from zedo_cli.formats.writers.outputs import write_result
from zedo_cli.formats.writers.result_csv import csv_text


@pytest.mark.parametrize("fmt", ["json", "jsonl", "csv", "npz"])
@pytest.mark.parametrize(("units", "frame"), [("m", "camera"), ("mm", "root")])
def test_every_format_reads_back_the_written_poses(tmp_path: Path, fmt: str, units: str, frame: str) -> None:
    kp, res, mats, sources = make_case()
    path = tmp_path / f"kp.zedo.{fmt}"
    write_result(path, kp, res, mats, sources, {**PARAMS, "fps": 25.0}, INPUT_INFO, units=units, frame=frame)
    got = read_result(path)
    want = res.poses_camera if frame == "camera" else res.poses_root_relative
    np.testing.assert_allclose(got.poses, want, atol=2e-6)  # metres whatever the file's unit
    assert got.format == fmt and got.skeleton.name == "syrip12" and got.coordinate_frame == frame
    assert got.fps == 25.0 and got.units_in_file == units
    assert got.frame_index.tolist() == [0, 0, 1, 2] and got.person.tolist() == [0, 1, 0, 0]
    assert got.image_ids == [10, 10, 11, 12] and got.file_names == ["a.jpg", "a.jpg", "b.jpg", None]
    assert got.lifted.tolist() == [i != UNLIFTED for i in range(4)]
    assert not got.observed[1, 2] and got.observed[0].all()
    assert got.uncertainty_m is None


@pytest.mark.parametrize("fmt", ["json", "jsonl", "csv", "npz"])
def test_every_format_reads_back_the_input_2d(tmp_path: Path, fmt: str) -> None:
    kp, res, mats, sources = make_case()
    kp.xy[2, 4] = np.nan  # a joint the input missed
    path = tmp_path / f"kp.zedo.{fmt}"
    write_result(path, kp, res, mats, sources, PARAMS, INPUT_INFO)
    got = read_result(path)
    assert got.keypoints_2d is not None and got.keypoints_2d.shape == (4, 12, 2)
    np.testing.assert_allclose(got.keypoints_2d, kp.xy, atol=1e-3)  # pixels, NaN where missing
    assert np.isnan(got.keypoints_2d[2, 4]).all() and np.isfinite(got.keypoints_2d[0]).all()


def test_a_result_without_2d_reads_as_none() -> None:
    rows = ["frame_index,image_id,file_name,person,joint,joint_index,x_cam_m,y_cam_m,z_cam_m,lifted"]
    rows += [f"0,0,f.png,0,{name},{j},{j},0,1,true" for j, name in enumerate(make_case()[0].skeleton.joints)]
    assert read_result_bytes("\n".join(rows).encode(), "old.csv").keypoints_2d is None


def test_csv_on_stdin_without_its_sidecar(monkeypatch: pytest.MonkeyPatch) -> None:
    kp, res, mats, sources = make_case()
    text = csv_text(kp, res, mats, sources, units="mm")
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(text.encode())))
    got = read_result("-")
    np.testing.assert_allclose(got.poses, res.poses_camera, atol=2e-6)
    assert got.skeleton.name == "syrip12" and got.fps is None and got.source == "-"


def test_uncertainty_is_read_from_json_jsonl_csv_and_npz(tmp_path: Path) -> None:
    doc = result_document(kicking_poses(4), fps=30.0, radius=0.02)
    doc["frames"][1]["persons"][0]["uncertainty_m"][3] = None
    got = read_result(write_document(tmp_path / "u.zedo.json", doc))
    assert got.uncertainty_m is not None and got.uncertainty_m.shape == (4, 12)
    assert np.isnan(got.uncertainty_m[1, 3]) and np.nansum(got.uncertainty_m) == pytest.approx(0.02 * 47)
    header = {k: v for k, v in doc.items() if k not in ("frames", "summary")}
    lines = [json.dumps({"type": "header", **header})] + [json.dumps({"type": "frame", **f}) for f in doc["frames"]]
    lines.append(json.dumps({"type": "summary", **doc["summary"]}))
    got = read_result_bytes("\n".join(lines).encode(), "u.jsonl")
    assert got.format == "jsonl" and np.isnan(got.uncertainty_m[1, 3])
    # CSV: an uncertainty_m column; NPZ: an (N, J) array
    rows = ["frame_index,image_id,file_name,person,joint,joint_index,x_cam_m,y_cam_m,z_cam_m,lifted,uncertainty_m"]
    for j, name in enumerate(got.skeleton.joints):
        rows.append(f"0,0,f.png,0,{name},{j},{j},0,1,true,{'' if j == 0 else 0.01}")
    csv_got = read_result_bytes("\n".join(rows).encode(), "u.csv")
    assert np.isnan(csv_got.uncertainty_m[0, 0]) and csv_got.uncertainty_m[0, 1] == 0.01
    buf = io.BytesIO()
    np.savez(buf, poses=got.poses, joint_names=np.array(got.skeleton.joints), units=np.array("m"),
             frame_index=got.frame_index, person=got.person, uncertainty_m=np.full((4, 12), 0.03))  # fmt: skip
    assert read_result_bytes(buf.getvalue(), "u.npz").uncertainty_m[2, 5] == 0.03


def test_read_result_file_keeps_the_first_lifted_person_per_frame(tmp_path: Path) -> None:
    kp, res, mats, sources = make_case()
    for fmt in ("json", "npz"):
        path = tmp_path / f"kp.zedo.{fmt}"
        write_result(path, kp, res, mats, sources, PARAMS, INPUT_INFO)
        pred = read_result_file(path)
        assert pred.keys == ["a.jpg", "b.jpg"] and pred.poses.shape == (2, 12, 3)


@pytest.mark.parametrize(
    ("content", "message"),
    [
        (b"", "empty file"),
        (b"   \n", "empty file"),
        (b"\xff\xfe\x00garbage", "neither UTF-8 text nor a NPZ archive"),
        (b'{"images": [], "annotations": []}', "schema: expected a zedo result file"),
        (b"[1, 2, 3]", "not a zedo result"),
        (b"hello,world\n1,2\n", "not a zedo result"),
        (b'{"schema": "zedo.pose3d/1", "skeleton": {"name": "syrip12"}, "frames": []}', "zedo_version: field required"),
        (b"frame_index,image_id,person,joint,joint_index,lifted\n", "no coordinate columns"),
        (b"PK\x03\x04broken zip", "not a readable NPZ archive"),
    ],
)
def test_what_is_not_a_result_is_refused_with_the_file_named(content: bytes, message: str) -> None:
    with pytest.raises(InputFormatError, match=message) as err:
        read_result_bytes(content, "bad.json")
    assert str(err.value).startswith("bad.json")


def test_missing_file_and_folder(tmp_path: Path) -> None:
    with pytest.raises(InputFormatError, match="nope.json: file not found"):
        read_result(tmp_path / "nope.json")
    with pytest.raises(InputFormatError, match="is a folder"):
        read_result(tmp_path)


def _set(doc: dict, path: str, value: object) -> dict:
    """`doc` with the field at `path` (dots and [i]) set to `value` (`...` deletes it)."""
    keys = [int(k) if k.isdigit() else k for k in path.replace("[", ".").replace("]", "").split(".")]
    target = doc
    for key in keys[:-1]:
        target = target[key]
    if value is ...:
        del target[keys[-1]]
    else:
        target[keys[-1]] = value
    return doc


@pytest.mark.parametrize(
    ("path", "value", "message"),
    [
        ("skeleton.name", "nope", "skeleton.name: unknown"),
        ("skeleton.joints[0]", "hip", "skeleton.joints: not the joints of syrip12"),
        ("units", "cm", "units: input should be 'm' or 'mm'"),
        ("params.fps", -1, "params.fps: input should be greater than 0"),
        (
            "frames[1].persons[0].keypoints_3d",
            [[0, 0, 1]],
            r"frames\[1\].persons\[0\].keypoints_3d: expected 12 entries",
        ),
        ("frames[1].persons[0].keypoints_3d[2]", [0, 1], r"keypoints_3d\[2\]: list should have at least 3 items"),
        ("frames[1].persons[0].keypoints_3d[2][0]", "0.1", r"keypoints_3d\[2\]\[0\]: input should be a valid number"),
        (
            "frames[1].persons[0].observed[0]",
            1,
            r"frames\[1\].persons\[0\].observed\[0\]: input should be a valid bool",
        ),
        ("frames[1].persons[0].uncertainty_m[0]", -0.1, r"uncertainty_m\[0\]: input should be greater than or equal"),
        ("frames[1].camera.K", [[1, 0, 0]], r"frames\[1\].camera.K: list should have at least 3 items"),
        ("frames[1].camera.model", "orthographic", r"frames\[1\].camera.model: input should be 'pinhole' or 'fisheye'"),
        ("frames[1].frame_index", "1", r"frames\[1\].frame_index: input should be a valid integer"),
        ("frames[1].persons[0].flags", ..., r"frames\[1\].persons\[0\].flags: field required"),
        ("frames[1].persons[0].colour", "red", r"frames\[1\].persons\[0\].colour: extra inputs are not permitted"),
        ("summary.frames_total", 7, "summary: 7 frames and 4 people, but the file has 4 and 4"),
        ("summary", ..., "summary: field required"),
    ],
)
def test_a_result_that_does_not_fit_the_schema_is_refused_naming_the_field(
    tmp_path: Path, path: str, value: object, message: str
) -> None:
    doc = _set(result_document(kicking_poses(4), fps=30.0, radius=0.02), path, value)
    with pytest.raises(InputFormatError, match=message) as err:
        read_result(write_document(tmp_path / "bad.zedo.json", doc))
    assert str(err.value).startswith(str(tmp_path / "bad.zedo.json")) and "\n" not in str(err.value)
    if path != "summary":  # the same in JSON Lines, with the line named
        header = {k: v for k, v in doc.items() if k not in ("frames", "summary")}
        lines = [{"type": "header", **header}, *({"type": "frame", **f} for f in doc["frames"])]
        lines.append({"type": "summary", **doc["summary"]})
        with pytest.raises(InputFormatError, match=r"bad.jsonl: (line \d+: )?.*" + message.split(": ")[-1][:20]):
            read_result_bytes("\n".join(json.dumps(line) for line in lines).encode(), "bad.jsonl")


def test_camera_lens_fields_and_new_flags_fit_the_schema(tmp_path: Path) -> None:
    doc = result_document(kicking_poses(3), fps=30.0)
    doc["frames"][0]["camera"].update(model="fisheye", dist=[0.1, -0.02, 0.0, 0.0])
    doc["frames"][1]["camera"].update(model="pinhole", dist=[-0.3, 0.1, 0.0, 0.0, 0.0])
    doc["frames"][2]["persons"][0]["flags"] = ["implausible_distance: 75.0 m", "keypoints_outside_image"]
    assert len(read_result(write_document(tmp_path / "ok.zedo.json", doc))) == 3


def test_jsonl_without_its_summary_line_is_incomplete() -> None:
    doc = result_document(kicking_poses(2))
    header = {k: v for k, v in doc.items() if k not in ("frames", "summary")}
    lines = [{"type": "header", **header}, *({"type": "frame", **f} for f in doc["frames"])]
    with pytest.raises(InputFormatError, match="no summary line: the file is incomplete"):
        read_result_bytes("\n".join(json.dumps(line) for line in lines).encode(), "cut.jsonl")
    with pytest.raises(InputFormatError, match="line 5: a line after the summary line"):
        text = "\n".join(json.dumps(line) for line in [*lines, {"type": "summary", **doc["summary"]}, lines[1]])
        read_result_bytes(text.encode(), "late.jsonl")
