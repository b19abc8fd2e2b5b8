"""TRC and C3D marker files: the exact header bytes, the NaN rules, the axes, one file per track,
and the refusals (stdout, no frame numbers). ezc3d (the test extra) reads the C3D back."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from writer_fixtures import INPUT_INFO, MISSING, PARAMS, UNLIFTED, make_case

from zedo_cli.data.skeleton import get_skeleton
from zedo_cli.errors import ConfigError
from zedo_cli.formats.writers.markers import MARKER_AXES, MarkerTracks, marker_name
from zedo_cli.formats.writers.outputs import output_format, write_result
from zedo_cli.formats.writers.result_trc import write_trc

POSE2SIM_COCO = "RHip LHip RKnee LKnee RAnkle LAnkle RShoulder LShoulder RElbow LElbow RWrist LWrist".split()
FPS = {**PARAMS, "fps": 30.0}


def numbered_case(frames: list[int] = [0, 0, 1, 3]):  # noqa: B006 (never mutated)
    """make_case with frame numbers: frame 0 holds two persons (tracks 0 and 1), frame 2 is empty,
    frame 3's person is not lifted, instance 1 (track 1) has a joint filled by the prior."""
    kp, res, mats, sources = make_case()
    return replace(kp, frame_indices=frames), res, mats, sources


def read_trc(path: Path) -> tuple[list[str], np.ndarray]:
    """The header lines and the data rows (frame, time, x1, y1, z1, ...) of a TRC, split on tabs only."""
    lines = path.read_text(encoding="utf-8").split("\n")
    assert lines[-1] == "" and all(line for line in lines[:-1])
    rows = [[float(v) for v in line.split("\t")] for line in lines[5:-1]]
    return lines[:5], np.array(rows)


def to_markers(poses_camera: np.ndarray, axes: str = "level") -> np.ndarray:
    return poses_camera @ MARKER_AXES[axes].T


def test_marker_names_are_pose2sims_coco_names() -> None:
    names = {marker_name(j) for j in get_skeleton("syrip12").joints}
    assert names == set(POSE2SIM_COCO)
    assert marker_name("left_big_toe") == "LBigToe" and marker_name("nose") == "Nose"


def test_axes_are_rotations_with_y_up() -> None:
    for rot in MARKER_AXES.values():
        np.testing.assert_allclose(rot @ rot.T, np.eye(3))
        assert np.linalg.det(rot) == pytest.approx(1.0)
    up_in_camera = {"level": [0.0, -1.0, 0.0], "overhead": [0.0, 0.0, -1.0]}  # towards the sky
    for axes, up in up_in_camera.items():
        np.testing.assert_allclose(MARKER_AXES[axes] @ np.array(up), [0.0, 1.0, 0.0])


def test_trc_header_bytes() -> None:
    tracks = MarkerTracks(("RHip", "LHip"), np.array([4, 5, 6]), np.array([4, 5, 6]) / 25.0, 25.0, 25.0, "level",
                          [np.zeros((3, 2, 3))])  # fmt: skip
    from zedo_cli.formats.writers.result_trc import trc_header

    assert trc_header("a.trc", tracks) == (
        "PathFileType\t4\t(X/Y/Z)\ta.trc\n"
        "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\tOrigDataStartFrame\tOrigNumFrames\n"
        "25\t25\t3\t2\tm\t25\t5\t3\n"
        "Frame#\tTime\tRHip\t\t\tLHip\n"
        "\t\tX1\tY1\tZ1\tX2\tY2\tZ2\n"
    )


def test_trc_rows_values_nan_rules_and_tracks(tmp_path: Path) -> None:
    kp, res, mats, sources = numbered_case()
    written = write_result(tmp_path / "clip.trc", kp, res, mats, sources, FPS, INPUT_INFO)
    assert written == [tmp_path / "clip_P1.trc", tmp_path / "clip_P2.trc"]  # two tracks: one file each
    assert sorted(p.name for p in tmp_path.iterdir()) == ["clip_P1.trc", "clip_P2.trc"]
    header, rows = read_trc(tmp_path / "clip_P1.trc")
    assert header[0] == "PathFileType\t4\t(X/Y/Z)\tclip_P1.trc"
    assert header[2] == "30\t30\t4\t12\tm\t30\t1\t4"
    assert header[3] == "Frame#\tTime\t" + "\t\t\t".join(marker_name(j) for j in kp.skeleton.joints)
    text = (tmp_path / "clip_P1.trc").read_text()
    assert "\t\n" not in text and "\n\t\n" not in text  # no trailing tab, no empty last field
    assert rows.shape == (4, 2 + 36)
    np.testing.assert_array_equal(rows[:, 0], [1, 2, 3, 4])  # frame_index 0..3, counted from 1
    np.testing.assert_allclose(rows[:, 1], np.arange(4) / 30.0, atol=1e-6)
    assert (np.diff(rows[:, 1]) > 0).all()
    xyz = rows[:, 2:].reshape(4, 12, 3)
    expected = to_markers(res.poses_camera)
    np.testing.assert_allclose(xyz[0], expected[0], atol=1e-6)  # track 0: instance 0, then 2 in frame 1
    np.testing.assert_allclose(xyz[1], expected[2], atol=1e-6)
    assert np.isnan(xyz[2]).all()  # frame 2: no person
    assert np.isnan(xyz[3]).all()  # frame 3: instance UNLIFTED, not lifted
    assert UNLIFTED == 3 and "NaN\tNaN\tNaN" in text and "\t0.000000\t0.000000\t0.000000" not in text
    _, rows2 = read_trc(tmp_path / "clip_P2.trc")
    xyz2 = rows2[:, 2:].reshape(4, 12, 3)
    np.testing.assert_allclose(xyz2[0], expected[1], atol=1e-6)  # the joint filled by the prior is kept
    assert np.isfinite(xyz2[0][MISSING[1]]).all() and np.isnan(xyz2[1:]).all()


def test_trc_without_fps_is_rate_1_and_time_is_the_frame_number(tmp_path: Path) -> None:
    kp, res, mats, sources = numbered_case([5, 5, 6, 9])
    write_result(tmp_path / "c.trc", kp, res, mats, sources, PARAMS, INPUT_INFO, frame="root", marker_axes="overhead")
    header, rows = read_trc(tmp_path / "c_P1.trc")
    assert header[2] == "1\t1\t5\t12\tm\t1\t6\t5"
    np.testing.assert_array_equal(rows[:, 0], [6, 7, 8, 9, 10])
    np.testing.assert_array_equal(rows[:, 1], [5, 6, 7, 8, 9])
    np.testing.assert_allclose(rows[0, 2:].reshape(12, 3), to_markers(res.poses_root_relative, "overhead")[0],
                               atol=1e-6)  # fmt: skip


def test_no_frame_numbers_needs_fps(tmp_path: Path) -> None:
    kp, res, mats, sources = make_case()  # COCO-like image ids, no frame numbers
    for fmt in ("trc", "c3d"):
        with pytest.raises(ConfigError, match="no frame numbers.*--fps"):
            write_result(tmp_path / f"r.{fmt}", kp, res, mats, sources, PARAMS, INPUT_INFO)
    assert list(tmp_path.iterdir()) == []
    write_result(tmp_path / "r.trc", kp, res, mats, sources, FPS, INPUT_INFO)  # frames in input order
    _, rows = read_trc(tmp_path / "r_P1.trc")
    np.testing.assert_array_equal(rows[:, 0], [1, 2, 3])


def test_refusals_leave_nothing_behind(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    kp, res, mats, sources = numbered_case()
    for fmt in ("trc", "c3d"):
        with pytest.raises(ConfigError, match="stdout"):
            write_result("-", kp, res, mats, sources, FPS, INPUT_INFO, fmt=fmt)
        with pytest.raises(ConfigError, match="marker axes"):
            write_result(tmp_path / f"r.{fmt}", kp, res, mats, sources, FPS, INPUT_INFO, marker_axes="sideways")
    assert capsys.readouterr().out == ""
    (tmp_path / "r_P2.trc").write_text("precious")  # the second track's file exists: nothing is written
    with pytest.raises(ConfigError, match="r_P2.trc"):
        write_result(tmp_path / "r.trc", kp, res, mats, sources, FPS, INPUT_INFO)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r_P2.trc"]
    assert output_format("a.TRC") == "trc" and output_format("a.c3d") == "c3d"
    with pytest.raises(ConfigError, match="says trc"):
        output_format("a.trc", "c3d")


def test_one_track_is_one_file_with_the_given_name(tmp_path: Path) -> None:
    kp, res, mats, sources = numbered_case()
    one = [0, 2, 3]
    kp1 = kp.subset(one)
    res1 = replace(res, poses_camera=res.poses_camera[one], poses_root_relative=res.poses_root_relative[one],
                   lifted=res.lifted[one])  # fmt: skip
    assert write_result(tmp_path / "one.trc", kp1, res1, mats[one], [sources[i] for i in one], FPS, INPUT_INFO) == [
        tmp_path / "one.trc"
    ]
    tracks = np.full((1, 12, 3), np.nan)
    write_trc(tmp_path / "nan.trc", MarkerTracks(tuple(POSE2SIM_COCO), np.array([0]), np.array([0.0]), 1.0, None,
                                                 "level", [tracks]))  # fmt: skip
    assert read_trc(tmp_path / "nan.trc")[1].shape == (1, 38)


def test_c3d_reads_back_in_ezc3d(tmp_path: Path) -> None:
    ezc3d = pytest.importorskip("ezc3d")
    kp, res, mats, sources = numbered_case()
    write_result(tmp_path / "clip.c3d", kp, res, mats, sources, FPS, INPUT_INFO)
    c3d = ezc3d.c3d(str(tmp_path / "clip_P1.c3d"))
    point = c3d["parameters"]["POINT"]
    assert point["RATE"]["value"][0] == 30.0 and point["UNITS"]["value"] == ["mm"]
    assert point["SCALE"]["value"][0] < 0  # float storage
    assert point["LABELS"]["value"] == [marker_name(j) for j in kp.skeleton.joints]
    xyz = c3d["data"]["points"][:3].transpose(2, 1, 0)  # (F, M, 3) mm
    expected = to_markers(res.poses_camera) * 1000.0
    assert xyz.shape == (4, 12, 3)
    np.testing.assert_allclose(xyz[0], expected[0], atol=0.1)
    np.testing.assert_allclose(xyz[1], expected[2], atol=0.1)
    assert np.isnan(xyz[2:]).all() and np.isfinite(xyz[:2]).all()
    assert c3d["header"]["points"]["first_frame"] == 0  # ezc3d counts from 0: the file's frame 1
