"""`zedo calibrate`: a KNOWN lens rendered onto checkerboard views is recovered; untrustworthy
calibrations are refused with one line and exit code 6, and nothing is written; the file is
OpenCV FileStorage that OpenCV reads back."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
import pytest
from typer.testing import CliRunner

from camera.board_render import lens, render_views
from zedo_cli.camera.calibration import Board, CalibrationSettings, Detection, calibrate, find_corners
from zedo_cli.camera.calibration_writer import write_calibration
from zedo_cli.camera.model import CameraModel
from zedo_cli.cli import app
from zedo_cli.errors import CalibrationError, ConfigError

BOARD = Board(9, 6, 0.03)
SMALL = lens(640, 360)  # f 300 px, k1 -0.3, k2 0.1: the task's lens at half size
runner = CliRunner()


@pytest.fixture(scope="module")
def small_views() -> list[np.ndarray]:
    return [v.image for v in render_views(SMALL, BOARD, 15)]


def detections(images: list[np.ndarray]) -> list[Detection]:
    return [Detection(f"view{i}", (im.shape[1], im.shape[0]), find_corners(im, BOARD)) for i, im in enumerate(images)]


def write_views(folder: Path, images: list[np.ndarray]) -> list[str]:
    folder.mkdir(exist_ok=True)
    names = []
    for i, image in enumerate(images):
        names.append(str(folder / f"view{i:02d}.png"))
        cv2.imwrite(names[-1], image)
    return names


def test_recovers_the_known_lens(small_views: list[np.ndarray], tmp_path: Path) -> None:
    cal = calibrate(detections(small_views), CalibrationSettings(BOARD))
    cam = cal.camera
    assert abs(cam.fx / SMALL.fx - 1) < 0.01 and abs(cam.fy / SMALL.fy - 1) < 0.01
    assert abs(cam.dist[0] - SMALL.dist[0]) < 0.02 and abs(cam.dist[1] - SMALL.dist[1]) < 0.05
    assert abs(cam.cx - SMALL.cx) < 3 and abs(cam.cy - SMALL.cy) < 3
    assert cal.rms < 0.5 and len(cal.view_errors) >= 13 and max(e for _, e in cal.view_errors) < 1.0
    # the file OpenCV reads back, with the standard key names
    write_calibration(tmp_path / "cam.yml", cal)
    fs = cv2.FileStorage(str(tmp_path / "cam.yml"), cv2.FILE_STORAGE_READ)
    np.testing.assert_allclose(fs.getNode("camera_matrix").mat(), cam.matrix(), rtol=1e-12)
    np.testing.assert_allclose(fs.getNode("distortion_coefficients").mat().ravel(), cam.dist, rtol=1e-12)
    assert (fs.getNode("image_width").real(), fs.getNode("image_height").real()) == (640, 360)
    assert fs.getNode("model").string() == "pinhole" and fs.getNode("rms").real() == pytest.approx(cal.rms)
    fs.release()


@pytest.mark.slow
def test_recovers_the_known_lens_at_full_size() -> None:
    truth = lens()  # 1280x720, f 600 px (about 3 s to render)
    cam = calibrate(detections([v.image for v in render_views(truth, BOARD, 15)]), CalibrationSettings(BOARD)).camera
    assert abs(cam.fx / truth.fx - 1) < 0.01 and abs(cam.dist[0] - truth.dist[0]) < 0.02


def test_fisheye_lens() -> None:
    truth = CameraModel(260.0, 260.0, 320.0, 180.0, (0.05, -0.02, 0.01, 0.0), "fisheye", (640, 360))
    views = [v.image for v in render_views(truth, BOARD, 12, seed=3)]
    cal = calibrate(detections(views), CalibrationSettings(BOARD, fisheye=True))
    assert cal.camera.model == "fisheye" and len(cal.camera.dist) == 4
    assert abs(cal.camera.fx / truth.fx - 1) < 0.01 and cal.rms < 0.5
    # its projection matches the truth's across the image
    pts = np.c_[np.random.default_rng(0).uniform(-0.8, 0.8, (50, 2)), np.ones(50)]
    assert np.abs(cal.camera.project(pts) - truth.project(pts)).max() < 2.0


def test_refusals(small_views: list[np.ndarray]) -> None:
    found = detections(small_views)
    with pytest.raises(CalibrationError, match="found in only 3 of 3 views, at least 5"):
        calibrate(found[:3], CalibrationSettings(BOARD))
    with pytest.raises(CalibrationError, match=r"above --max-rms 0\.001 px \(worst views: view"):
        calibrate(found, CalibrationSettings(BOARD, max_rms=0.001))
    blank = [Detection(f"b{i}", (640, 360), None) for i in range(4)]
    with pytest.raises(CalibrationError, match="found in none of the 4 views"):
        calibrate(blank, CalibrationSettings(BOARD))
    assert find_corners(np.full((360, 640), 128, np.uint8), BOARD) is None
    assert CalibrationError("x").exit_code == 6
    with pytest.raises(ConfigError, match="COLSxROWS"):
        Board.parse("9 by 6", 0.03)
    with pytest.raises(ConfigError, match="square"):
        Board.parse("7x7", 0.03)


def test_cli_images_and_report(small_views: list[np.ndarray], tmp_path: Path) -> None:
    blank = np.full((360, 640), 128, np.uint8)
    names = write_views(tmp_path / "views", [*small_views, blank])
    out = tmp_path / "cam.yml"
    result = runner.invoke(app, ["calibrate", *names, "--board", "9x6", "--square", "0.03", "-o", str(out)])
    assert result.exit_code == 0, result.output
    assert "RMS reprojection error" in result.stderr and "view15.png" in result.stderr.split("board not found")[1]
    fs = cv2.FileStorage(str(out), cv2.FILE_STORAGE_READ)
    assert fs.getNode("camera_matrix").mat()[0, 0] == pytest.approx(SMALL.fx, rel=0.01)
    # not replaced without --overwrite; exit 2 and the file untouched
    before = out.read_bytes()
    again = runner.invoke(app, ["calibrate", *names, "--board", "9x6", "--square", "0.03", "-o", str(out)])
    assert again.exit_code == 2 and out.read_bytes() == before


def test_cli_refusals_write_nothing(small_views: list[np.ndarray], tmp_path: Path) -> None:
    names = write_views(tmp_path / "views", small_views[:6])
    out = tmp_path / "cam.yml"

    def args(*inputs: str, board: str = "9x6") -> list[str]:
        return ["calibrate", *inputs, "--board", board, "--square", "0.03", "-o", str(out), "-q"]

    strict = runner.invoke(app, [*args(*names), "--max-rms", "0.001"])
    assert strict.exit_code == 6 and strict.stderr.count("\n") == 1 and "--max-rms" in strict.stderr
    wrong_board = runner.invoke(app, args(*names[:2], board="8x5"))  # a failing search is slow
    assert wrong_board.exit_code == 6 and "found in none" in wrong_board.stderr
    (tmp_path / "broken.mp4").write_bytes(b"not a video")
    video = runner.invoke(app, args(str(tmp_path / "broken.mp4")))
    assert video.exit_code == 3 and "broken.mp4: cannot open as a video" in video.stderr
    assert not out.exists() and list(tmp_path.glob(".cam.yml*")) == []


def test_cli_video_frames_sampled(small_views: list[np.ndarray], tmp_path: Path) -> None:
    clip = tmp_path / "board.mp4"
    writer = cv2.VideoWriter(str(clip), cv2.VideoWriter_fourcc(*"mp4v"), 10, (640, 360))
    for image in small_views:  # each view held for 2 frames: 30 frames
        for _ in range(2):
            writer.write(cv2.cvtColor(image, cv2.COLOR_GRAY2BGR))
    writer.release()
    out = tmp_path / "cam.json"
    args = ["calibrate", str(clip), "--board", "9x6", "--square", "0.03", "--frames", "15", "-o", str(out)]
    result = runner.invoke(app, args)
    assert result.exit_code == 0, result.output
    assert result.stderr.count("board.mp4#") >= 13  # per-view errors name the frames used
    fs = cv2.FileStorage(str(out), cv2.FILE_STORAGE_READ)
    assert abs(fs.getNode("camera_matrix").mat()[0, 0] / SMALL.fx - 1) < 0.02
    assert abs(fs.getNode("distortion_coefficients").mat().ravel()[0] - SMALL.dist[0]) < 0.03
