"""`zedo render`: skeletons land where the camera (with its lens) projects the joints, frames the
result does not mention pass through unchanged, errors are one line with a documented code."""

from __future__ import annotations

import json
from pathlib import Path

import cv2
import numpy as np
import pytest
from analysis_results import kicking_poses, result_document
from typer.testing import CliRunner

from zedo_cli.camera.model import CameraModel
from zedo_cli.cli import app
from zedo_cli.footage.draw import LEFT, RIGHT
from zedo_cli.footage.render import RenderSettings, people, render_video
from zedo_cli.formats.readers.result import read_result

runner = CliRunner()
W, H, N = 640, 480, 12
DIST = [-0.3, 0.1, 0.0, 0.0, 0.0]
EMPTY = 5  # a frame without a person


def background(i: int) -> np.ndarray:
    """A smooth frame (mp4v keeps it nearly as it is), a little different per frame."""
    u, v = np.meshgrid(np.linspace(0, 1, W), np.linspace(0, 1, H))
    g = (60 + 80 * u + 40 * v + 2 * i).astype(np.uint8)
    return np.dstack([g, g // 2 + 40, 160 - g // 2])


def write_clip(path: Path, frames: int = N) -> Path:
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"mp4v"), 10.0, (W, H))
    for i in range(frames):
        writer.write(background(i))
    writer.release()
    return path


def read_clip(path: Path) -> list[np.ndarray]:
    cap = cv2.VideoCapture(str(path))
    frames = []
    while (got := cap.read())[0]:
        frames.append(got[1])
    cap.release()
    return frames


def write_result(path: Path, flagged: int = 3) -> Path:
    """A result over the clip: one person per frame but EMPTY, lifted through a lens with
    distortion; the left wrist filled by the prior; person of frame `flagged` flagged."""
    poses = kicking_poses(N) + np.array([0.12, 0.0, 0.0])
    doc = result_document(poses, fps=10.0)
    for frame in doc["frames"]:
        frame["camera"].update(model="pinhole", dist=DIST)
        person = frame["persons"][0]
        person["observed"][8] = False  # left_wrist
        person["flags"] = ["joints_filled_by_prior: left_wrist"] if frame["frame_index"] == flagged else []
    doc["frames"] = [f for f in doc["frames"] if f["frame_index"] != EMPTY]
    kept = len(doc["frames"])  # the summary counts what the file holds (the reader checks it)
    doc["summary"].update(frames_total=kept, instances_total=kept, instances_lifted=kept)
    path.write_text(json.dumps(doc))
    return path


def colour_near(pixel: np.ndarray, colour: tuple[int, int, int], tol: int = 70) -> bool:
    return bool(np.abs(pixel.astype(int) - np.array(colour)).max() < tol)


def test_projection_goes_through_the_lens(tmp_path: Path) -> None:
    res = read_result(write_result(tmp_path / "r.zedo.json"))
    persons = people(res)
    lens = res.cameras[0]
    assert lens.distorted
    np.testing.assert_allclose(persons[0].px, lens.project(res.poses[0]))
    pinhole = CameraModel(lens.fx, lens.fy, lens.cx, lens.cy).project(res.poses[0])
    assert np.abs(persons[0].px - pinhole).max() > 4  # the lens moves the outer joints by pixels


def test_root_frame_result_is_put_back_in_the_camera(tmp_path: Path) -> None:
    path = write_result(tmp_path / "r.zedo.json")
    doc = json.loads(path.read_text())
    doc["coordinate_frame"] = "root"
    for frame in doc["frames"]:
        person = frame["persons"][0]
        person["keypoints_3d"] = (np.array(person["keypoints_3d"]) - person["root_translation"]).tolist()
    (tmp_path / "root.zedo.json").write_text(json.dumps(doc))
    camera, root = people(read_result(path)), people(read_result(tmp_path / "root.zedo.json"))
    np.testing.assert_allclose(root[2].px, camera[2].px, atol=1e-6)


def test_render_video(tmp_path: Path) -> None:
    clip = write_clip(tmp_path / "clip.mp4")
    result = write_result(tmp_path / "clip.zedo.json")
    out = tmp_path / "out.mp4"
    cli = runner.invoke(app, ["render", str(result), "--video", str(clip), "-o", str(out)])
    assert cli.exit_code == 0, cli.output
    assert "rendered 12 frames (11 with people, 11 skeletons)" in " ".join(cli.stderr.split())
    rendered, source = read_clip(out), read_clip(clip)
    assert len(rendered) == N and rendered[0].shape == (H, W, 3)
    res = read_result(result)
    persons = people(res)
    for row in (0, 6):  # frames 0 and 7
        frame = rendered[int(res.frame_index[row])]
        px, joints = persons[row].px, res.skeleton.joints
        for j in np.flatnonzero(res.observed[row]):  # observed joints: a filled marker of their side's colour
            u, v = np.round(px[j]).astype(int)
            assert colour_near(frame[v, u], LEFT if joints[j].startswith("left_") else RIGHT), (row, joints[j])
    # the frame without a person: as it was, up to the codec's second pass (a few levels, no pixel far off)
    diff = [np.abs(r.astype(int) - s.astype(int)).max(-1) for r, s in zip(rendered, source, strict=True)]
    changed = [int((d > 40).sum()) for d in diff]
    assert changed[EMPTY] == 0 and min(changed[:EMPTY] + changed[EMPTY + 1 :]) > 500, changed
    # the flagged person (frame 3) is boxed in magenta, the others are not (the codec blurs its hue: red and
    # blue both well above green, which the background never has)
    magenta = [int(((f[..., 2] - f[..., 1].astype(int) > 60) & (f[..., 0] - f[..., 1].astype(int) > 60)).sum())
               for f in rendered]  # fmt: skip
    assert magenta[3] > 500 and max(magenta[:3] + magenta[4:]) < 20, magenta


def test_render_side_view_and_images(tmp_path: Path) -> None:
    folder = tmp_path / "images"
    folder.mkdir()
    for i in range(3):
        cv2.imwrite(str(folder / f"f{i}.png"), background(i))
    doc = json.loads(write_result(tmp_path / "r.zedo.json").read_text())
    doc["frames"] = doc["frames"][:2]  # f0.png and f1.png
    doc["summary"].update(frames_total=2, instances_total=2, instances_lifted=2)
    (tmp_path / "r.zedo.json").write_text(json.dumps(doc))
    out = tmp_path / "rendered"
    cli = runner.invoke(app, ["render", str(tmp_path / "r.zedo.json"), "--images", str(folder), "-o", str(out),
                              "--side-view"])  # fmt: skip
    assert cli.exit_code == 0, cli.output
    assert cli.stderr.strip().endswith(f"wrote 3 PNGs into {out}") and len(list(out.glob("*.png"))) == 3
    f0, f2 = cv2.imread(str(out / "f0.png")), cv2.imread(str(out / "f2.png"))
    assert f0.shape[0] == H and f0.shape[1] > W  # the panel beside the frame
    np.testing.assert_array_equal(f2[:, :W], background(2))  # no person: unchanged (PNG is lossless)
    assert (f0[:, :W] != background(0)).any(axis=-1).sum() > 500


def test_render_errors(tmp_path: Path) -> None:
    clip = write_clip(tmp_path / "short.mp4", frames=6)
    result = write_result(tmp_path / "clip.zedo.json")
    out = tmp_path / "out.mp4"
    beyond = runner.invoke(app, ["render", str(result), "--video", str(clip), "-o", str(out)])
    assert beyond.exit_code == 3 and "frame_index 6" in beyond.stderr and "after the end" in beyond.stderr
    assert not out.exists() and list(tmp_path.glob(".out.mp4*")) == []
    (tmp_path / "bad.mp4").write_bytes(b"nope")
    bad = runner.invoke(app, ["render", str(result), "--video", str(tmp_path / "bad.mp4"), "-o", str(out)])
    assert bad.exit_code == 3 and bad.stderr.count("\n") == 1 and "bad.mp4: cannot open as a video" in bad.stderr
    out.write_bytes(b"keep")
    full = write_clip(tmp_path / "full.mp4")
    exists = runner.invoke(app, ["render", str(result), "--video", str(full), "-o", str(out)])
    assert exists.exit_code == 2 and out.read_bytes() == b"keep"
    both = runner.invoke(app, ["render", str(result), "-o", str(out)])
    assert both.exit_code == 2 and "exactly one of" in both.stderr
    keypoints = tmp_path / "kp.json"  # 2D keypoints (COCO results), not a result: lift them first
    keypoints.write_text(json.dumps([{"image_id": 1, "keypoints": [1.0] * 51, "score": 1.0}]))
    two_d = runner.invoke(app, ["render", str(keypoints), "--video", str(full), "-o", str(tmp_path / "k.mp4")])
    assert two_d.exit_code == 3 and two_d.stderr.count("\n") == 1
    assert "2D keypoints (coco-results), not a zedo result (3D poses): lift them first (zedo lift" in two_d.stderr
    doc = json.loads(result.read_text())
    doc["frames"][0]["camera"]["image_size"] = [1280, 720]
    (tmp_path / "other.zedo.json").write_text(json.dumps(doc))
    with pytest.raises(Exception, match="lifted for a 1280x720 image"):
        render_video(read_result(tmp_path / "other.zedo.json"), full, tmp_path / "o.mp4", RenderSettings())
