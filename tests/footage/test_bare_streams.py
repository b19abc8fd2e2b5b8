"""A video whose file stores no frame rate (a bare MJPEG / H.264 / H.265 stream, no container): OpenCV
reports 25 fps for it, so without --fps `zedo lift --video`, `zedo analyze --video` and `zedo render`
refuse it in one line (exit 2); the container is recognised by its first bytes, so a real 25 fps MP4
is still read."""

from __future__ import annotations

import json
from pathlib import Path

import cv2
import numpy as np
import pytest
from test_lift_video import lift_args, write_keypoints
from test_render import H, W, background
from typer.testing import CliRunner

from zedo_cli.camera.video import bare_stream_kind, probe_video
from zedo_cli.cli import app

runner = CliRunner()
FRAMES = 5


def write_mjpeg(path: Path, frames: int = FRAMES) -> Path:
    """Concatenated JPEG frames: what an MJPEG camera or `ffmpeg -f mjpeg` writes."""
    with path.open("wb") as fh:
        for i in range(frames):
            fh.write(cv2.imencode(".jpg", background(i))[1].tobytes())
    return path


def write_mp4(path: Path, fps: float, frames: int = FRAMES) -> Path:
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"mp4v"), fps, (W, H))
    for i in range(frames):
        writer.write(background(i))
    writer.release()
    return path


@pytest.mark.parametrize(
    ("head", "kind"),
    [
        (b"\xff\xd8\xff\xe0\x00\x10JFIF", "a raw MJPEG stream"),
        (b"\x00\x00\x00\x01\x09\xf0\x00\x00", "a raw H.264 stream"),  # access unit delimiter
        (b"\x00\x00\x01\x67\x64\x00\x1f\xac", "a raw H.264 stream"),  # sequence parameter set, 3-byte start code
        (b"\x00\x00\x00\x01\x40\x01\x0c\x01", "a raw H.265 stream"),  # video parameter set
        (b"\x00\x00\x00\x1cftypisom", None),  # MP4
        (b"RIFF\xca\x1f\x00\x00AVI ", None),
        (b"\x1aE\xdf\xa3\xa3B\x86\x81", None),  # Matroska / WebM
        (b"\x00\x00\x01\xba\x21\x00\x01\x00", None),  # MPEG program stream: timed
        (b"\x00\x00\x01\xb3\x14\x00\xf0\x13", None),  # MPEG-1/2 video: its sequence header holds the rate
        (b"", None),
    ],
)
def test_bare_streams_are_told_from_containers_by_their_first_bytes(head: bytes, kind: str | None) -> None:
    assert bare_stream_kind(head) == kind


def test_a_bare_stream_has_no_rate_and_its_frames_counted(tmp_path: Path) -> None:
    raw = probe_video(write_mjpeg(tmp_path / "clip.mjpeg"))
    assert raw.fps is None and raw.bare_stream == "a raw MJPEG stream" and raw.frame_count == FRAMES
    assert cv2.VideoCapture(str(tmp_path / "clip.mjpeg")).get(cv2.CAP_PROP_FPS) == 25.0  # OpenCV's made-up rate
    real = probe_video(write_mp4(tmp_path / "clip.mp4", 25.0))
    assert real.fps == 25.0 and real.bare_stream is None


def test_lift_refuses_a_bare_stream_without_fps_and_reads_a_real_25_fps_mp4(tiny_prior_path: Path,
                                                                            tmp_path: Path) -> None:  # fmt: skip
    src = write_keypoints(tmp_path / "kp.json", 3)
    raw = write_mjpeg(tmp_path / "clip.mjpeg")
    refused = runner.invoke(app, lift_args(tiny_prior_path, str(src), "--video", str(raw)))
    assert refused.exit_code == 2 and refused.stderr.count("\n") == 1, refused.output
    assert "clip.mjpeg: a raw MJPEG stream stores no frame rate (no container): give --fps" in refused.stderr
    assert not (tmp_path / "kp.zedo.json").exists()
    stated = runner.invoke(app, lift_args(tiny_prior_path, str(src), "--video", str(raw), "--fps", "30"))
    assert stated.exit_code == 0, stated.output
    doc = json.loads((tmp_path / "kp.zedo.json").read_text())
    assert doc["params"]["fps"] == 30.0 and doc["params"]["video"]["frame_count"] == FRAMES
    mp4 = write_mp4(tmp_path / "clip25.mp4", 25.0)
    real = runner.invoke(app, lift_args(tiny_prior_path, str(src), "--video", str(mp4), "-o",
                                        str(tmp_path / "kp25.zedo.json")))  # fmt: skip
    assert real.exit_code == 0, real.output
    assert json.loads((tmp_path / "kp25.zedo.json").read_text())["params"]["fps"] == 25.0


def test_analyze_and_render_refuse_a_bare_stream_without_fps(tiny_prior_path: Path, tmp_path: Path) -> None:
    src = write_keypoints(tmp_path / "kp.json", 3)
    raw = write_mjpeg(tmp_path / "clip.mjpeg")
    assert runner.invoke(app, lift_args(tiny_prior_path, str(src), "--video", str(raw), "--fps", "30")).exit_code == 0
    result = str(tmp_path / "kp.zedo.json")
    analyzed = runner.invoke(app, ["analyze", result, "--video", str(raw), "--report", str(tmp_path / "rep")])
    assert analyzed.exit_code == 2 and analyzed.stderr.count("\n") == 1, analyzed.output
    assert "stores no frame rate" in analyzed.stderr and not list(tmp_path.glob("rep/*"))
    out = tmp_path / "kp.render.mp4"
    rendered = runner.invoke(app, ["render", result, "--video", str(raw), "-o", str(out)])
    assert rendered.exit_code == 2 and "give --fps" in rendered.stderr and not out.exists()
    rendered = runner.invoke(app, ["render", result, "--video", str(raw), "--fps", "30", "-o", str(out)])
    assert rendered.exit_code == 0, rendered.output
    cap = cv2.VideoCapture(str(out))
    assert cap.get(cv2.CAP_PROP_FPS) == pytest.approx(30.0) and int(cap.get(cv2.CAP_PROP_FRAME_COUNT)) == FRAMES
    assert np.isfinite(cap.get(cv2.CAP_PROP_FPS))
