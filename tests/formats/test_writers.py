"""3D result writers: values per format and per units/frame, missing values, metadata,
atomic and non-clobbering writes, stdout, and one end-to-end lift with the tiny prior."""

from __future__ import annotations

import csv
import io
import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from writer_fixtures import INPUT_INFO, MISSING, PARAMS, UNLIFTED, make_case

from zedo_cli.errors import ConfigError
from zedo_cli.formats.readers.result import RESULT_FORMATS
from zedo_cli.formats.writers.common import rounded
from zedo_cli.formats.writers.outputs import default_output_name, output_format, write_result
from zedo_cli.formats.writers.result_csv import coordinate_columns, sidecar_path
from zedo_cli.formats.writers.result_json import build_result_document
from zedo_cli.formats.writers.result_jsonl import JsonlWriter
from zedo_cli.lifting.config import LiftConfig
from zedo_cli.lifting.solver import lift
from zedo_cli.prior.weights import Prior

EXT = {"json": "json", "jsonl": "jsonl", "csv": "csv", "npz": "npz"}
OPTIONS = [("m", "camera"), ("mm", "camera"), ("m", "root"), ("mm", "root")]


def expected_poses(units: str, frame: str) -> np.ndarray:
    _, res, _, _ = make_case()
    poses = res.poses_camera if frame == "camera" else res.poses_root_relative
    return poses * (1000.0 if units == "mm" else 1.0)


def _json_poses(persons: list[dict[str, Any]], joints: int) -> np.ndarray:
    out = np.full((len(persons), joints, 3), np.nan)
    for p, person in enumerate(persons):
        if person["keypoints_3d"] is not None:
            out[p] = np.array(person["keypoints_3d"], dtype=float)
    return out


def read_back(path: Path, fmt: str, joints: int = 12) -> tuple[np.ndarray, dict[str, Any]]:
    """Poses `(N, J, 3)` in input instance order and the metadata, from a written file."""
    if fmt == "json":
        doc = json.loads(path.read_text())
        persons = [p for f in doc["frames"] for p in f["persons"]]
        return _json_poses(sorted(persons, key=lambda p: p["instance_index"]), joints), doc
    if fmt == "jsonl":
        lines = [json.loads(line) for line in path.read_text().splitlines()]
        persons = [p for line in lines if line["type"] == "frame" for p in line["persons"]]
        return _json_poses(sorted(persons, key=lambda p: p["instance_index"]), joints), lines[0]
    if fmt == "csv":
        meta = json.loads(sidecar_path(path).read_text())
        rows = list(csv.DictReader(path.open()))
        cols = coordinate_columns(meta["units"], meta["coordinate_frame"])
        n = 1 + max(int(r["instance_index"]) for r in rows)
        out = np.full((n, joints, 3), np.nan)
        for r in rows:
            out[int(r["instance_index"]), int(r["joint_index"])] = [float(r[c]) if r[c] else np.nan for c in cols]
        return out, meta
    with np.load(path) as z:  # allow_pickle=False: nothing may need pickle
        meta = {**json.loads(str(z["metadata"])), "npz_units": str(z["units"]), "npz_frame": str(z["coordinate_frame"])}
        return z["poses"], meta


@pytest.mark.parametrize("fmt", RESULT_FORMATS)
@pytest.mark.parametrize(("units", "frame"), OPTIONS)
def test_values_round_trip_per_format_units_and_frame(tmp_path: Path, fmt: str, units: str, frame: str) -> None:
    kp, res, mats, sources = make_case()
    out = tmp_path / f"r.{EXT[fmt]}"
    write_result(out, kp, res, mats, sources, PARAMS, INPUT_INFO, units=units, frame=frame)
    poses, meta = read_back(out, fmt)
    want = expected_poses(units, frame)
    # Written to a micrometre in either unit: mm = 1000 x m, root = camera minus root point.
    np.testing.assert_allclose(poses, want, atol=1.5e-6 * (1000.0 if units == "mm" else 1.0))
    assert np.isnan(poses[UNLIFTED]).all() and np.isfinite(poses[:UNLIFTED]).all()
    assert meta["units"] == units and meta["coordinate_frame"] == frame
    assert meta["axes"] == {"x": "right", "y": "down", "z": "forward (away from the camera)"}
    assert meta["skeleton"]["name"] == "syrip12" and meta["params"] == PARAMS and meta["input"] == INPUT_INFO
    assert ("origin" in meta) == (frame == "root")
    if frame == "root":
        assert np.allclose(poses[:UNLIFTED].reshape(-1, 12, 3)[:, [0, 3]].mean(1), 0.0, atol=1e-5)


def test_json_default_is_metres_camera_frame_and_keeps_its_layout() -> None:
    kp, res, mats, sources = make_case()
    doc = build_result_document(kp, res, mats, sources, params=PARAMS, input_info=INPUT_INFO)
    assert list(doc) == ["schema", "zedo_version", "created", "skeleton", "units", "coordinate_frame", "axes",
                         "camera", "input", "params", "frames", "summary"]  # fmt: skip
    assert doc["units"] == "m" and doc["coordinate_frame"] == "camera"
    assert [f["image_id"] for f in doc["frames"]] == [10, 11, 12]
    assert [len(f["persons"]) for f in doc["frames"]] == [2, 1, 1]
    assert doc["frames"][1]["camera"] == {
        "K": mats[2].tolist(),
        "image_size": [640.0, 480.0],
        "source": "file",
        "model": "pinhole",
        "dist": [],
    }
    assert doc["frames"][2]["camera"]["image_size"] is None and doc["camera"]["source"] == "mixed"
    person = doc["frames"][0]["persons"][1]
    assert person["keypoints_3d"][0] == [rounded(float(v), 6) for v in res.poses_camera[1, 0]]
    assert person["observed"][2] is False and person["keypoints_2d"][2] is None
    assert person["reprojection_error_px"][2] is None and person["joint_confidence"][2] is None
    unlifted = doc["frames"][2]["persons"][0]
    assert unlifted["keypoints_3d"] is None and unlifted["root_translation"] is None
    assert doc["summary"]["instances_lifted"] == 3 and doc["summary"]["frames_total"] == 3


def test_root_translation_stays_in_the_camera_frame_in_the_chosen_units() -> None:
    kp, res, mats, sources = make_case()
    doc = build_result_document(kp, res, mats, sources, params=PARAMS, input_info=INPUT_INFO, units="mm", frame="root")
    person = doc["frames"][1]["persons"][0]
    np.testing.assert_allclose(person["root_translation"], res.root_translation[2] * 1000.0, atol=1e-3)
    camera = np.array(person["keypoints_3d"]) + np.array(person["root_translation"])
    np.testing.assert_allclose(camera, res.poses_camera[2] * 1000.0, atol=2e-3)


def test_jsonl_is_header_frames_summary_and_joins_into_the_json_document(tmp_path: Path) -> None:
    kp, res, mats, sources = make_case()
    write_result(tmp_path / "r.jsonl", kp, res, mats, sources, PARAMS, INPUT_INFO)
    lines = [json.loads(line) for line in (tmp_path / "r.jsonl").read_text().splitlines()]
    assert [line.pop("type") for line in lines] == ["header", "frame", "frame", "frame", "summary"]
    joined = {**lines[0], "frames": lines[1:-1], "summary": lines[-1]}
    doc = build_result_document(kp, res, mats, sources, params=PARAMS, input_info=INPUT_INFO)
    joined.pop("created"), doc.pop("created")
    assert joined == json.loads(json.dumps(doc))


def test_csv_rows_columns_missing_values_and_sidecar(tmp_path: Path) -> None:
    kp, res, mats, sources = make_case()
    written = write_result(tmp_path / "r.csv", kp, res, mats, sources, PARAMS, INPUT_INFO, units="mm")
    assert written == [tmp_path / "r.csv", tmp_path / "r.meta.json"]
    text = (tmp_path / "r.csv").read_text()
    assert not text.startswith("#")  # plain CSV: the first line is the column header
    rows = list(csv.DictReader(io.StringIO(text)))
    assert len(rows) == 4 * 12 and rows[0]["x_cam_mm"] and "x_cam_m" not in rows[0]
    missing = next(r for r in rows if r["instance_index"] == "1" and r["joint_index"] == "2")
    assert missing["observed"] == "false" and missing["u_px"] == "" and missing["reprojection_error_px"] == ""
    assert missing["confidence"] == "" and missing["x_cam_mm"] != ""  # filled by the prior
    assert missing["status"] == "lifted"
    for r in (r for r in rows if r["instance_index"] == str(UNLIFTED)):
        assert r["lifted"] == "false" and r["x_cam_mm"] == r["y_cam_mm"] == r["z_cam_mm"] == ""
        assert r["status"] == "too_few_observed_joints"  # why, as JSON's flag and NPZ's status say
        assert r["k_source"] == "pseudo" and r["file_name"] == "" and r["frame_index"] == "2"
    frame1 = next(r for r in rows if r["image_id"] == "11")
    assert (frame1["fx_px"], frame1["cx_px"], frame1["k_source"]) == ("1500.0", "320.0", "file")
    assert {r["person"] for r in rows if r["image_id"] == "10"} == {"0", "1"}
    meta = json.loads((tmp_path / "r.meta.json").read_text())
    assert meta["data_file"] == "r.csv" and meta["units"] == "mm" and "x_cam_mm, y_cam_mm, z_cam_mm" in meta["columns"]
    assert [f["camera"]["K"][0][0] for f in meta["frames"]] == [1000.0, 1500.0, 1000.0]
    assert meta["summary"]["instances_skipped"] == 1


def test_npz_arrays_nan_for_missing_and_metadata(tmp_path: Path) -> None:
    kp, res, mats, sources = make_case()
    write_result(tmp_path / "r.npz", kp, res, mats, sources, PARAMS, INPUT_INFO)
    with np.load(tmp_path / "r.npz") as z:
        assert z["poses"].shape == (4, 12, 3) and z["K"].shape == (4, 3, 3) and z["observed"].dtype == bool
        np.testing.assert_array_equal(z["lifted"], [True, True, True, False])
        assert not z["observed"][MISSING] and np.isnan(z["keypoints_2d"][MISSING]).all()
        assert np.isnan(z["confidence"][MISSING]) and np.isnan(z["reprojection_error_px"][MISSING])
        assert np.isnan(z["root_translation"][UNLIFTED]).all() and not (z["poses"][UNLIFTED] == 0).any()
        assert z["image_ids"].tolist() == [10, 10, 11, 12] and z["file_names"].tolist()[-1] == ""
        assert z["frame_index"].tolist() == [0, 0, 1, 2] and z["person"].tolist() == [0, 1, 0, 0]
        assert z["k_source"].tolist() == sources and z["K"][2, 0, 0] == 1500.0
        assert z["joint_names"].tolist() == list(kp.skeleton.joints) and z["bones"].shape[1] == 2
        assert str(z["units"]) == "m" and str(z["coordinate_frame"]) == "camera" and str(z["axes"][1]) == "down"
        assert json.loads(str(z["metadata"]))["summary"]["instances_total"] == 4


def test_string_image_ids_are_kept_as_strings_in_npz(tmp_path: Path) -> None:
    kp, res, mats, sources = make_case()
    kp.image_ids[3] = "clip/frame_0012"
    write_result(tmp_path / "r.npz", kp, res, mats, sources, PARAMS, INPUT_INFO)
    with np.load(tmp_path / "r.npz") as z:
        assert z["image_ids"].tolist() == ["10", "10", "11", "clip/frame_0012"]


@pytest.mark.parametrize("fmt", RESULT_FORMATS)
def test_never_overwrites_without_permission_and_leaves_no_temp_file(tmp_path: Path, fmt: str) -> None:
    kp, res, mats, sources = make_case()
    out = tmp_path / f"r.{EXT[fmt]}"
    out.write_text("precious")
    with pytest.raises(ConfigError, match=str(out)):
        write_result(out, kp, res, mats, sources, PARAMS, INPUT_INFO)
    assert out.read_text() == "precious"
    write_result(out, kp, res, mats, sources, PARAMS, INPUT_INFO, overwrite=True)
    assert out.read_bytes() != b"precious"
    expected = {out.name} | ({"r.meta.json"} if fmt == "csv" else set())
    assert {p.name for p in tmp_path.iterdir()} == expected  # no .tmp left behind


def test_csv_sidecar_blocks_the_write_too(tmp_path: Path) -> None:
    kp, res, mats, sources = make_case()
    (tmp_path / "r.meta.json").write_text("{}")
    with pytest.raises(ConfigError, match="r.meta.json"):
        write_result(tmp_path / "r.csv", kp, res, mats, sources, PARAMS, INPUT_INFO)
    assert not (tmp_path / "r.csv").exists()


def test_failed_write_leaves_nothing_behind(tmp_path: Path) -> None:
    kp, res, mats, sources = make_case()
    bad = {"seed": float("nan")}  # not valid JSON: the write fails part-way
    for fmt in RESULT_FORMATS:
        with pytest.raises(ValueError):
            write_result(tmp_path / f"r.{EXT[fmt]}", kp, res, mats, sources, bad, INPUT_INFO)
    with pytest.raises(KeyError), JsonlWriter(tmp_path / "s.jsonl") as writer:
        writer.write_header({"schema": "x"})
        raise KeyError("boom")
    assert list(tmp_path.iterdir()) == []


def test_a_missing_folder_is_made_and_a_file_in_its_place_is_a_config_error(tmp_path: Path) -> None:
    kp, res, mats, sources = make_case()
    write_result(tmp_path / "new" / "deeper" / "r.json", kp, res, mats, sources, PARAMS, INPUT_INFO)
    assert (tmp_path / "new" / "deeper" / "r.json").is_file()
    (tmp_path / "plain").write_text("x")
    with pytest.raises(ConfigError, match="is not a folder"):
        write_result(tmp_path / "plain" / "sub" / "r.json", kp, res, mats, sources, PARAMS, INPUT_INFO)


@pytest.mark.parametrize("fmt", ["json", "jsonl", "csv"])
def test_stdout(capsys: pytest.CaptureFixture[str], fmt: str) -> None:
    kp, res, mats, sources = make_case()
    assert write_result("-", kp, res, mats, sources, PARAMS, INPUT_INFO, fmt=None if fmt == "json" else fmt) == []
    text = capsys.readouterr().out
    if fmt == "json":
        assert json.loads(text)["schema"] == "zedo.pose3d/1"
    elif fmt == "jsonl":
        lines = [json.loads(line) for line in text.splitlines()]
        assert lines[0]["type"] == "header" and lines[-1]["type"] == "summary" and len(lines) == 5
    else:
        assert text.startswith("frame_index,") and "x_cam_m" in text.splitlines()[0]


def test_npz_to_stdout_is_refused(capsys: pytest.CaptureFixture[str]) -> None:
    kp, res, mats, sources = make_case()
    with pytest.raises(ConfigError, match="stdout"):
        write_result("-", kp, res, mats, sources, PARAMS, INPUT_INFO, fmt="npz")
    assert capsys.readouterr().out == ""


def test_jsonl_writer_streams_in_order(capsys: pytest.CaptureFixture[str]) -> None:
    with JsonlWriter("-") as writer:
        with pytest.raises(RuntimeError):
            writer.write_frame({"frame_index": 0})
        writer.write_header({"units": "m"})
        writer.write_frame({"frame_index": 0, "x": None})
        assert capsys.readouterr().out.count("\n") == 2  # flushed line by line
    assert json.loads(capsys.readouterr().out) == {"type": "summary", "frames_total": 1}


def test_output_format_choice() -> None:
    assert output_format("a.JSON") == "json" and output_format("a.ndjson") == "jsonl" and output_format("-") == "json"
    assert output_format("a.txt", "csv") == "csv" and output_format("-", "jsonl") == "jsonl"
    assert default_output_name("data/kp.json", "npz") == Path("data/kp.zedo.npz")
    for out, fmt, needle in [("a.txt", None, "extension"), ("a.json", "csv", "says json"), ("a.csv", "xls", "unknown")]:
        with pytest.raises(ConfigError, match=needle):
            output_format(out, fmt)


@pytest.mark.parametrize(("units", "frame", "needle"), [("cm", "camera", "units"), ("m", "world", "frame")])
def test_bad_options_are_config_errors(tmp_path: Path, units: str, frame: str, needle: str) -> None:
    kp, res, mats, sources = make_case()
    with pytest.raises(ConfigError, match=needle):
        write_result(tmp_path / "r.json", kp, res, mats, sources, PARAMS, INPUT_INFO, units=units, frame=frame)
    assert list(tmp_path.iterdir()) == []


def test_real_lift_result_agrees_across_formats(tiny_prior: Prior, tmp_path: Path) -> None:
    kp, _, mats, sources = make_case()
    res = lift(kp.xy, kp.confidence, mats, tiny_prior, LiftConfig(init_steps=5, steps=5))
    assert res.lifted.tolist() == [True, True, True, False]
    poses = {}
    for fmt in RESULT_FORMATS:
        write_result(tmp_path / f"r.{EXT[fmt]}", kp, res, mats, sources, PARAMS, INPUT_INFO, units="mm", frame="root")
        poses[fmt] = read_back(tmp_path / f"r.{EXT[fmt]}", fmt)[0]
    for fmt in RESULT_FORMATS:
        np.testing.assert_allclose(poses[fmt], res.poses_root_relative * 1000.0, atol=1.5e-3)


def test_numbers_keep_six_significant_digits_whatever_their_size() -> None:
    assert rounded(0.03875, 3) == 0.03875  # three decimals would write 0.039
    assert rounded(0.000123456789, 6) == 0.000123457
    assert rounded(1.23456789, 6) == 1.234568  # never fewer decimals than the unit's
    assert rounded(1234.56789, 3) == 1234.568
    assert rounded(-0.0123456789, 3) == -0.0123457
    assert rounded(0.0, 3) == 0.0 and np.isnan(rounded(np.nan, 3)) and rounded(np.inf, 3) == np.inf
