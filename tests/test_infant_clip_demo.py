"""examples/infant_clip_demo.py: the clip stays inside its frame, the footage
is a readable video with the infant drawn where its keypoints say, and the keypoints file is one a
detector would write (COCO-17, read by zedo without options). The whole demo, zedo commands
included, runs with `-m slow`."""

from __future__ import annotations

import importlib.util
import json
import subprocess
import sys
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest
from helpers import synthetic_poses

from zedo_cli.data.skeleton import center_on_root, get_skeleton
from zedo_cli.formats import read_keypoints

SCRIPT = Path(__file__).resolve().parents[1] / "examples" / "infant_clip_demo.py"
SKEL = get_skeleton("syrip12")


@pytest.fixture(scope="module")
def demo() -> ModuleType:
    spec = importlib.util.spec_from_file_location("infant_clip_demo", SCRIPT)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def clip(demo: ModuleType) -> np.ndarray:
    keys = center_on_root(synthetic_poses(demo.KEY_POSES, seed=5), SKEL)  # stands in for the prior's samples
    return demo.place(demo.clip_motion(keys), SKEL.joints)


def test_the_clip_stays_inside_the_frame_with_its_head(demo: ModuleType, clip: np.ndarray) -> None:
    assert clip.shape == (int(round((demo.KEY_POSES - 1) * demo.SECONDS_PER_POSE * demo.FPS)) + 1, 12, 3)
    head = demo.head_centres(clip, SKEL.joints)
    r = demo.FOCAL * demo.HEAD_RADIUS_M / head[:, 2]
    for px, pad in ((demo.project(clip).reshape(-1, 2), 0.0), (demo.project(head), r[:, None])):
        assert (px - pad >= demo.MARGIN_PX).all() and (px + pad <= [demo.WIDTH - demo.MARGIN_PX,
                                                                     demo.HEIGHT - demo.MARGIN_PX]).all()  # fmt: skip
    step = np.linalg.norm(np.diff(clip, axis=0), axis=-1).max()
    assert step < 0.02  # m per frame: a smooth motion, as the temporal mode expects


def test_the_footage_shows_the_body_where_its_keypoints_are(demo: ModuleType, clip: np.ndarray, tmp_path: Path) -> None:
    import cv2

    demo.write_footage(tmp_path / "clip.mp4", clip, SKEL.joints)
    demo.write_keypoints(tmp_path / "kp.jsonl", clip, SKEL.joints, np.random.default_rng(0))
    cap = cv2.VideoCapture(str(tmp_path / "clip.mp4"))
    assert (cap.get(cv2.CAP_PROP_FRAME_WIDTH), cap.get(cv2.CAP_PROP_FRAME_HEIGHT)) == (demo.WIDTH, demo.HEIGHT)
    assert int(cap.get(cv2.CAP_PROP_FRAME_COUNT)) == len(clip) and cap.get(cv2.CAP_PROP_FPS) == demo.FPS
    ok, first = cap.read()
    assert ok
    kp = read_keypoints(tmp_path / "kp.jsonl")
    assert kp.skeleton.name == "coco17" and len(kp) == len(clip)
    body = kp.to_skeleton(SKEL)
    assert np.isnan(kp.xy[:, :5]).all() and (body.confidence > 0.7).all()  # no face; every body joint seen
    u, v = np.round(body.xy[0]).astype(int).T
    pixels = first[v, u].astype(float)  # BGR under each joint of frame 0
    blanket = demo.blanket()[v, u].astype(float)
    assert (np.abs(pixels - blanket).sum(-1) > 40).mean() > 0.9  # the body is drawn there, not the blanket


@pytest.mark.slow
def test_the_whole_demo_runs_and_writes_every_file(tmp_path: Path) -> None:
    done = subprocess.run([sys.executable, str(SCRIPT), "--out", str(tmp_path)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    for name in ("clip.mp4", "clip.keypoints.jsonl", "clip.zedo.json", "clip.render.mp4", "analysis/clip.report.html"):
        assert (tmp_path / name).is_file(), name
    assert "zedo: warning" not in done.stderr  # inside the frame: nothing for zedo lift to flag
    doc = json.loads((tmp_path / "clip.zedo.json").read_text())
    assert doc["summary"]["instances_lifted"] == doc["summary"]["instances_total"] == 121
    report = (tmp_path / "analysis" / "clip.report.html").read_text()
    assert "<img alt='frame " in report  # the frames to review come with thumbnails cut from the footage
