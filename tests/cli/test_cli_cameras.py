"""zedo lift with calibration files and lenses (docs/cameras.md): the lens in the output and read
back, --camera, bad files (one line, exit 3, nothing written), and the camera sanity flags."""

from __future__ import annotations

import json
from pathlib import Path

import cv2
import numpy as np
import pytest
from typer.testing import CliRunner

from tests.helpers import write_coco
from zedo_cli.cli import app
from zedo_cli.formats.readers.result import read_result

runner = CliRunner()
LENS_DIST = (-0.3, 0.1, 0.0, 0.0, 0.0)


def lift_args(prior: Path, *extra: str) -> list[str]:
    return ["lift", "--prior", str(prior), "--steps", "30", "-q", *extra]


def write_yaml(path: Path, size: tuple[int, int] = (640, 480), dist: tuple[float, ...] = LENS_DIST) -> Path:
    storage = cv2.FileStorage(str(path), cv2.FILE_STORAGE_WRITE)
    storage.write("image_width", size[0])
    storage.write("image_height", size[1])
    storage.write("camera_matrix", np.array([[1000.0, 0, 320], [0, 1000, 240], [0, 0, 1]]))
    storage.write("distortion_coefficients", np.asarray(dist).reshape(1, -1))
    storage.release()
    return path


@pytest.mark.parametrize("fmt", ["json", "jsonl", "csv", "npz"])
def test_the_lens_is_stated_and_read_back(tiny_prior_path: Path, tmp_path: Path, fmt: str) -> None:
    src = write_coco(tmp_path / "kp.json", n=2)
    out = tmp_path / f"out.{fmt}"
    calib = write_yaml(tmp_path / "camera.yml")
    result = runner.invoke(app, lift_args(tiny_prior_path, str(src), "--intrinsics", str(calib), "-o", str(out)))
    assert result.exit_code == 0, result.output
    cameras = read_result(out).cameras
    assert cameras is not None and len(cameras) == 2
    assert cameras[0].dist == LENS_DIST and cameras[0].model == "pinhole" and cameras[0].fx == 1000.0
    if fmt == "json":
        block = json.loads(out.read_text())["frames"][0]["camera"]
        assert block == {"K": [[1000.0, 0.0, 320.0], [0.0, 1000.0, 240.0], [0.0, 0.0, 1.0]],
                         "image_size": [640.0, 480.0], "source": "file", "model": "pinhole",
                         "dist": list(LENS_DIST)}  # fmt: skip


def test_pose2sim_camera_by_name(tiny_prior_path: Path, tmp_path: Path) -> None:
    src = write_coco(tmp_path / "kp.json", n=1)
    calib = tmp_path / "Calib.toml"
    table = ('[{key}]\nname = "{key}"\nsize = [ 640.0, 480.0]\nmatrix = [ [ {f}, 0.0, 320.0], [ 0.0, {f}, 240.0], '
             "[ 0.0, 0.0, 1.0]]\ndistortions = [ -0.2, 0.05, 0.0, 0.0]\nfisheye = false\n\n")  # fmt: skip
    calib.write_text(table.format(key="cam01", f=900.0) + table.format(key="cam02", f=1100.0) + "[metadata]\n")
    out = tmp_path / "out.json"
    result = runner.invoke(app, lift_args(tiny_prior_path, str(src), "--intrinsics", str(calib), "-o", str(out)))
    assert result.exit_code == 3 and "choose one with --camera" in result.output and not out.exists()
    result = runner.invoke(app, lift_args(tiny_prior_path, str(src), "--intrinsics", str(calib), "--camera",
                                          "cam02", "-o", str(out)))  # fmt: skip
    assert result.exit_code == 0, result.output
    doc = json.loads(out.read_text())
    assert doc["frames"][0]["camera"]["K"][0][0] == 1100.0 and doc["frames"][0]["camera"]["dist"] == [-0.2, 0.05, 0, 0]
    assert doc["params"]["camera"] == "cam02"


@pytest.mark.parametrize(
    ("extra", "needle", "code"),
    [
        (["--camera", "front"], "--camera front", 3),
        ([], "image_width, image_height: the camera was calibrated for 1280 x 720 px images", 3),
    ],
)
def test_camera_errors_write_nothing(
    tiny_prior_path: Path, tmp_path: Path, extra: list[str], needle: str, code: int
) -> None:
    src = write_coco(tmp_path / "kp.json", n=1)
    calib = write_yaml(tmp_path / "camera.yml", size=(1280, 720))
    out = tmp_path / "out.json"
    result = runner.invoke(app, lift_args(tiny_prior_path, str(src), "--intrinsics", str(calib), *extra,
                                          "-o", str(out)))  # fmt: skip
    assert result.exit_code == code, result.output
    assert needle in result.output and str(calib) in result.output
    assert len(result.output.strip().splitlines()) == 1 and not out.exists()


def test_camera_needs_a_file(tiny_prior_path: Path, tmp_path: Path) -> None:
    src = write_coco(tmp_path / "kp.json", n=1)
    result = runner.invoke(app, lift_args(tiny_prior_path, str(src), "--camera", "cam01"))
    assert result.exit_code == 2 and "--intrinsics" in result.output


def test_a_far_focal_length_is_flagged(tiny_prior_path: Path, tmp_path: Path) -> None:
    """Before: --focal 100000 put the infant tens of metres away with exit 0 and no word."""
    src = write_coco(tmp_path / "kp.json", n=2)
    out = tmp_path / "out.json"
    result = runner.invoke(app, lift_args(tiny_prior_path, str(src), "--focal", "100000", "-o", str(out)))
    assert result.exit_code == 0, result.output
    assert "2 lifted instances flagged implausible_distance" in result.output
    flags = [f for frame in json.loads(out.read_text())["frames"] for p in frame["persons"] for f in p["flags"]]
    assert len([f for f in flags if f.startswith("implausible_distance: ")]) == 2
    assert all(float(f.split(": ")[1].split()[0]) > 10 for f in flags if f.startswith("implausible"))


def test_keypoints_outside_the_image_are_flagged(tiny_prior_path: Path, tmp_path: Path) -> None:
    """Before: --image-size 64 48 with keypoints at x = 350 lifted silently."""
    src = write_coco(tmp_path / "kp.json", n=1)
    doc = json.loads(src.read_text())
    for image in doc["images"]:
        del image["width"], image["height"]
    src.write_text(json.dumps(doc))
    out = tmp_path / "out.json"
    result = runner.invoke(app, lift_args(tiny_prior_path, str(src), "--image-size", "64", "48",
                                          "-o", str(out)))  # fmt: skip
    assert result.exit_code == 0, result.output
    assert "1 instance flagged keypoints_outside_image" in result.output
    person = json.loads(out.read_text())["frames"][0]["persons"][0]
    assert any(f.startswith("keypoints_outside_image: ") for f in person["flags"])


def test_a_plausible_lift_has_no_camera_flags(tiny_prior_path: Path, tmp_path: Path) -> None:
    src = write_coco(tmp_path / "kp.json", n=2)
    out = tmp_path / "out.json"
    result = runner.invoke(app, lift_args(tiny_prior_path, str(src), "--focal", "1000", "-o", str(out)))
    assert result.exit_code == 0 and "flagged" not in result.output, result.output
    flags = [f for frame in json.loads(out.read_text())["frames"] for p in frame["persons"] for f in p["flags"]]
    assert not [f for f in flags if "implausible" in f or "outside" in f]
