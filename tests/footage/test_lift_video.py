"""`zedo lift --video`: size and fps from the video, keypoints checked against it, one-line errors
with documented exit codes; and the whole chain lift -> render over the same clip."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from helpers import project_poses, synthetic_poses
from test_render import read_clip, write_clip
from typer.testing import CliRunner

from zedo_cli.camera.model import CameraModel
from zedo_cli.cli import app
from zedo_cli.footage.draw import LEFT, RIGHT

runner = CliRunner()


def lift_args(prior: Path, *extra: str) -> list[str]:
    return ["lift", "--prior", str(prior), "--steps", "30", "-q", *extra]


def write_keypoints(path: Path, n: int, *, far_joint: int | None = None) -> Path:
    """zedo-2d keypoints of `n` frames (image ids 0..n-1), no image size: the video gives it."""
    xy = project_poses(synthetic_poses(n, seed=3))
    if far_joint is not None:
        xy[1, far_joint] = [5000.0, 200.0]
    instances = [{"image_id": i, "keypoints": xy[i].tolist()} for i in range(n)]
    path.write_text(json.dumps({"skeleton": "syrip12", "instances": instances}))
    return path


def test_lift_takes_size_and_fps_from_the_video(tiny_prior_path: Path, tmp_path: Path) -> None:
    clip = write_clip(tmp_path / "clip.mp4", frames=5)  # 640x480 at 10 fps
    src = write_keypoints(tmp_path / "kp.json", 3)
    result = runner.invoke(app, lift_args(tiny_prior_path, str(src), "--video", str(clip)))
    assert result.exit_code == 0, result.output
    doc = json.loads((tmp_path / "kp.zedo.json").read_text())
    assert doc["params"]["fps"] == 10.0
    assert doc["frames"][0]["camera"]["image_size"] == [640.0, 480.0]
    assert doc["frames"][0]["camera"]["K"][0][2] == 320.0  # the pseudo camera at the video's centre
    video = doc["params"]["video"]
    assert (video["width"], video["height"], video["frame_count"], video["keypoint_frames"]) == (640, 480, 5, 3)
    assert video["keypoints_outside_frame"] == []
    # --fps wins over the video's
    again = runner.invoke(app, lift_args(tiny_prior_path, str(src), "--video", str(clip), "--fps", "25",
                                         "--overwrite"))  # fmt: skip
    assert again.exit_code == 0 and json.loads((tmp_path / "kp.zedo.json").read_text())["params"]["fps"] == 25.0


def test_lift_video_errors_and_flags(tiny_prior_path: Path, tmp_path: Path) -> None:
    clip = write_clip(tmp_path / "clip.mp4", frames=5)
    more = runner.invoke(app, lift_args(tiny_prior_path, str(write_keypoints(tmp_path / "long.json", 8)),
                                        "--video", str(clip)))  # fmt: skip
    assert more.exit_code == 3 and more.stderr.count("\n") == 1
    assert "long.json: 8 frames but" in more.stderr and "clip.mp4 has 5 frames" in more.stderr
    assert not (tmp_path / "long.zedo.json").exists()
    missing = runner.invoke(app, lift_args(tiny_prior_path, str(tmp_path / "long.json"), "--video", "nope.mp4"))
    assert missing.exit_code == 3 and "nope.mp4: video file not found" in missing.stderr
    (tmp_path / "bad.mp4").write_bytes(b"not a video")
    bad = runner.invoke(
        app, lift_args(tiny_prior_path, str(tmp_path / "long.json"), "--video", str(tmp_path / "bad.mp4"))
    )
    assert bad.exit_code == 3 and "bad.mp4: cannot open as a video" in bad.stderr
    size = runner.invoke(app, lift_args(tiny_prior_path, str(tmp_path / "long.json"), "--video", str(clip),
                                        "--image-size", "1280", "720"))  # fmt: skip
    assert size.exit_code == 2 and "differs from" in size.stderr
    far = write_keypoints(tmp_path / "far.json", 3, far_joint=4)  # left_knee of frame 1 at x = 5000
    flagged = runner.invoke(app, lift_args(tiny_prior_path, str(far), "--video", str(clip)))
    assert flagged.exit_code == 0, flagged.output
    assert "warning" in flagged.stderr and "instance 1, left_knee" in flagged.stderr
    video = json.loads((tmp_path / "far.zedo.json").read_text())["params"]["video"]
    assert video["keypoints_outside_frame"] == [{"instance_index": 1, "joints": ["left_knee"]}]


def test_lift_then_render_over_the_same_clip(tiny_prior_path: Path, tmp_path: Path) -> None:
    clip = write_clip(tmp_path / "clip.mp4", frames=4)
    src = write_keypoints(tmp_path / "kp.json", 3)
    assert runner.invoke(app, lift_args(tiny_prior_path, str(src), "--video", str(clip))).exit_code == 0
    out = tmp_path / "kp.render.mp4"
    rendered = runner.invoke(app, ["render", str(tmp_path / "kp.zedo.json"), "--video", str(clip), "-o", str(out)])
    assert rendered.exit_code == 0, rendered.output
    frames = read_clip(out)
    assert len(frames) == 4
    doc = json.loads((tmp_path / "kp.zedo.json").read_text())
    frame = doc["frames"][1]
    person = frame["persons"][0]
    # render projects as lift measured its reprojection error: the same camera, the same convention
    px = CameraModel.from_json(frame["camera"]).project(np.array(person["keypoints_3d"]))
    error = np.linalg.norm(px - np.array(person["keypoints_2d"]), axis=-1)
    np.testing.assert_allclose(error, person["reprojection_error_px"], atol=0.01)
    hits = 0
    for name, (u, v) in zip(doc["skeleton"]["joints"], np.round(px).astype(int), strict=True):
        if 0 <= u < 640 and 0 <= v < 480:
            expected = np.array(LEFT if name.startswith("left_") else RIGHT)
            hits += int(np.abs(frames[1][v, u].astype(int) - expected).max() < 70)
    assert hits >= 10
