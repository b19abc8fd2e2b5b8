"""Calibration files: OpenCV FileStorage written by OpenCV itself (YAML with either header, XML,
JSON), Pose2Sim and anipose TOML in their real layouts (INTEROP.md), zedo's JSON; bad files fail
with one line naming the file and the field."""

from __future__ import annotations

import json
from pathlib import Path

import cv2
import numpy as np
import pytest

from zedo_cli.camera.files import read_camera_file
from zedo_cli.camera.model import CameraModel
from zedo_cli.errors import CameraInputError

K = np.array([[600.0, 0.0, 640.0], [0.0, 610.0, 360.0], [0.0, 0.0, 1.0]])
DIST = (-0.3, 0.1, 0.001, -0.002, 0.0)


def write_opencv(path: Path, k: np.ndarray = K, dist: tuple[float, ...] = DIST, size: tuple[int, int] = (1280, 720)):
    """A calibration as OpenCV's calibration sample writes it, by cv2.FileStorage (format by extension)."""
    storage = cv2.FileStorage(str(path), cv2.FILE_STORAGE_WRITE)
    storage.write("image_width", size[0])
    storage.write("image_height", size[1])
    storage.write("camera_matrix", k)
    storage.write("distortion_coefficients", np.asarray(dist, dtype=np.float64).reshape(-1, 1))
    storage.write("avg_reprojection_error", 0.21)
    storage.release()
    return path


@pytest.mark.parametrize("name", ["calib.yml", "calib.yaml", "calib.xml", "calib.json", "calib.txt"])
def test_opencv_files_written_by_opencv(tmp_path: Path, name: str) -> None:
    path = tmp_path / name
    if name.endswith(".txt"):  # no telling extension: the content says FileStorage YAML
        path.write_text(write_opencv(tmp_path / "c.yml").read_text())
    else:
        write_opencv(path)
    calib = read_camera_file(path)
    assert calib.format == "opencv" and calib.images == {}
    assert calib.camera == CameraModel(600.0, 610.0, 640.0, 360.0, DIST, "pinhole", (1280, 720))


@pytest.mark.parametrize("header", ["%YAML:1.0", "%YAML 1.2"])
def test_both_yaml_headers_read(tmp_path: Path, header: str) -> None:
    """OpenCV 4 writes `%YAML:1.0`, OpenCV 5 `%YAML 1.2`; cv2 reads both."""
    text = write_opencv(tmp_path / "w.yml").read_text().splitlines()
    assert text[0].startswith("%YAML")
    path = tmp_path / "c.yml"
    path.write_text("\n".join([header, *text[1:]]) + "\n")
    assert read_camera_file(path).camera.dist == DIST


def test_opencv_fisheye_and_no_size(tmp_path: Path) -> None:
    path = tmp_path / "fish.yml"
    storage = cv2.FileStorage(str(path), cv2.FILE_STORAGE_WRITE)
    storage.write("camera_matrix", K)
    storage.write("distortion_coefficients", np.array([[0.05, -0.01, 0.002, 0.0]]))
    storage.write("model", "fisheye")
    storage.release()
    camera = read_camera_file(path).camera
    assert camera.model == "fisheye" and camera.image_size is None and camera.dist == (0.05, -0.01, 0.002, 0.0)


POSE2SIM = """\
[cam_01]
name = "cam_01"
size = [ 1920.0, 1080.0]
matrix = [ [ 1400.5, 0.0, 960.2], [ 0.0, 1401.0, 540.7], [ 0.0, 0.0, 1.0]]
distortions = [ -0.05, 0.02, 0.0003, -0.0001]
rotation = [ 1.2, -0.1, 0.3]
translation = [ 0.5, 0.2, 2.1]
fisheye = false

[cam_02]
name = "cam_02"
size = [ 1280.0, 720.0]
matrix = [ [ 600.0, 0.0, 640.0], [ 0.0, 610.0, 360.0], [ 0.0, 0.0, 1.0]]
distortions = [ -0.3, 0.1, 0.001, -0.002]
rotation = [ 0.0, 0.0, 0.0]
translation = [ 0.0, 0.0, 0.0]
fisheye = false

[metadata]
adjusted = false
error = 0.0
"""

ANIPOSE = """\
[cam_0]
name = "A"
size = [ 1280, 720,]
matrix = [ [ 500.0, 0.0, 640.0,], [ 0.0, 500.0, 360.0,], [ 0.0, 0.0, 1.0,],]
distortions = [ 0.05, -0.01, 0.002, 0.0,]
rotation = [ 0.0, 0.0, 0.0,]
translation = [ 0.0, 0.0, 0.0,]
fisheye = true

[cam_1]
name = "B"
size = [ 1280, 720,]
matrix = [ [ 900.0, 0.0, 640.0,], [ 0.0, 900.0, 360.0,], [ 0.0, 0.0, 1.0,],]
distortions = [ -0.2, 0.05, 0.0, 0.0, 0.01,]
rotation = [ 0.1, 0.2, 0.3,]
translation = [ 1.0, 0.0, 0.0,]

[metadata]
adjusted = true
error = 0.4

[charuco]
squares_x = 7
"""


def test_pose2sim_toml_picks_by_name(tmp_path: Path) -> None:
    path = tmp_path / "Calib.toml"
    path.write_text(POSE2SIM)
    calib = read_camera_file(path, "cam_02")
    assert calib.format == "toml" and calib.name == "cam_02"
    assert calib.camera == CameraModel(600.0, 610.0, 640.0, 360.0, (-0.3, 0.1, 0.001, -0.002), "pinhole", (1280, 720))


def test_anipose_toml_fisheye_and_table_names(tmp_path: Path) -> None:
    path = tmp_path / "calibration.toml"
    path.write_text(ANIPOSE)
    a = read_camera_file(path, "A").camera
    assert a.model == "fisheye" and a.dist == (0.05, -0.01, 0.002, 0.0)
    b = read_camera_file(path, "cam_1")  # the table's name picks it too
    assert b.name == "B" and b.camera.dist == (-0.2, 0.05, 0.0, 0.0, 0.01) and b.camera.model == "pinhole"


def test_one_camera_toml_needs_no_name(tmp_path: Path) -> None:
    path = tmp_path / "one.toml"
    path.write_text(POSE2SIM.split("[cam_02]")[0] + "[metadata]\nadjusted = false\n")
    assert read_camera_file(path).camera.fx == 1400.5


def test_zedo_json_with_lens_and_per_image(tmp_path: Path) -> None:
    path = tmp_path / "K.json"
    path.write_text(json.dumps({"K": K.tolist(), "dist": list(DIST), "image_size": [1280, 720],
                                "images": {"7": {"fx": 500, "fy": 500, "cx": 1, "cy": 2, "model": "fisheye",
                                                 "dist": [0.1, 0, 0, 0]}}}))  # fmt: skip
    calib = read_camera_file(path)
    assert calib.format == "zedo" and calib.camera == CameraModel(600, 610, 640, 360, DIST, "pinhole", (1280, 720))
    assert calib.images["7"] == CameraModel(500, 500, 1, 2, (0.1, 0, 0, 0), "fisheye")


def _message(path: Path, camera: str | None = None) -> str:
    with pytest.raises(CameraInputError) as info:
        read_camera_file(path, camera)
    message = str(info.value)
    assert str(path) in message and "\n" not in message
    return message


def test_toml_camera_choice_errors_list_the_names(tmp_path: Path) -> None:
    path = tmp_path / "Calib.toml"
    path.write_text(POSE2SIM)
    assert "2 cameras (cam_01, cam_02): choose one with --camera" in _message(path)
    assert "--camera front: no such camera (the file holds: cam_01, cam_02)" in _message(path, "front")
    yml = write_opencv(tmp_path / "c.yml")
    assert "--camera" in _message(yml, "cam_01")


def test_bad_opencv_files_name_the_field(tmp_path: Path) -> None:
    singular = write_opencv(tmp_path / "singular.yml", k=np.array([[0.0, 0, 640], [0, 600, 360], [0, 0, 1]]))
    assert "camera_matrix: K is singular" in _message(singular)
    nan = write_opencv(tmp_path / "nan.yml", dist=(-0.3, float("nan"), 0.0, 0.0, 0.0))
    assert "distortion_coefficients[1]: Input should be a finite number" in _message(nan)
    count = write_opencv(tmp_path / "count.xml", dist=(-0.3, 0.1, 0.0))
    assert "distortion_coefficients: a pinhole camera takes 0 or 4 or 5 or 8 or 12 or 14" in _message(count)
    skew = write_opencv(tmp_path / "skew.json", k=np.array([[600.0, 2, 640], [0, 600, 360], [0, 0, 1]]))
    assert "camera_matrix: K must be [[fx, 0, cx]" in _message(skew)
    broken = tmp_path / "broken.yml"
    broken.write_text("%YAML:1.0\n---\ncamera_matrix: [1, 2\n")
    assert "not a readable OpenCV FileStorage file" in _message(broken)
    lacking = tmp_path / "lacking.yml"
    lacking.write_text("%YAML:1.0\n---\nimage_width: 640\n")
    assert "camera_matrix: missing" in _message(lacking)


def test_bad_toml_files_name_the_table_and_field(tmp_path: Path) -> None:
    path = tmp_path / "Calib.toml"
    path.write_text(POSE2SIM.replace("distortions = [ -0.3, 0.1,", "distortions = [ nan, 0.1,"))
    assert "[cam_02].distortions[0]: Input should be a finite number" in _message(path, "cam_02")
    path.write_text(
        POSE2SIM.replace("matrix = [ [ 600.0, 0.0, 640.0], [ 0.0, 610.0", "matrix = [ [ 600.0, 0.0, 640.0], [ 0.0, 0.0")
    )
    assert "[cam_02].matrix: K is singular" in _message(path, "cam_02")
    path.write_text("[cam_1\nname = 1\n")
    assert "not a readable calibration file" in _message(path)
    path.write_text("[metadata]\nadjusted = false\n")
    assert "no camera tables" in _message(path)
    path.write_text('[cam_1]\nname = "x"\nsize = [ 640, 480]\n')
    assert "[cam_1].matrix: Field required" in _message(path)


def test_bad_zedo_json_names_the_field(tmp_path: Path) -> None:
    path = tmp_path / "K.json"
    path.write_text(json.dumps({"K": K.tolist(), "dist": [0.1, "x", 0, 0]}))
    assert "dist[1]: Input should be a valid number" in _message(path)
    path.write_text(json.dumps({"K": K.tolist(), "model": "fish"}))
    assert "model: Input should be 'pinhole' or 'fisheye'" in _message(path)
    path.write_text(json.dumps({"images": {"a.jpg": {"K": K.tolist(), "image_size": [0, 720]}}}))
    assert "images['a.jpg'].image_size[0]: Input should be greater than 0" in _message(path)
