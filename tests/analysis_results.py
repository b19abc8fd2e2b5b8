"""zedo result files built from constructed poses, for the tests of `zedo analyze`: written by
zedo's own writers, with `uncertainty_m` added where a test needs it (no lift writes it yet)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
from analysis_poses import SKEL, set_limb, standing, to_array
from helpers import K_TEST

from zedo_cli.data.keypoints import Keypoints2D
from zedo_cli.data.skeleton import root_point
from zedo_cli.formats.writers.result_json import build_result_document
from zedo_cli.lifting.config import LiftConfig
from zedo_cli.lifting.solver import LiftResult


def kicking_poses(frames: int, fps: float = 30.0) -> np.ndarray:
    """`(frames, 12, 3)` camera-frame poses 1 m from the camera: the left knee bends
    sinusoidally (1 Hz, 0 to 60 degrees), the right one stays straight."""
    out = []
    for t in range(frames):
        pts = standing()
        set_limb(pts, "left", "leg", 0.0, 0.0, bend=30.0 - 30.0 * np.cos(2 * np.pi * t / fps))
        out.append(to_array(pts) + np.array([0.0, 0.0, 1.0]))
    return np.array(out)


def result_document(poses: np.ndarray, *, fps: float | None = None, radius: float | None = None,
                    units: str = "m") -> dict[str, Any]:  # fmt: skip
    """The zedo.pose3d/1 document of camera-frame `poses (N, 12, 3)`, one person per frame;
    with `radius`, every person carries `uncertainty_m` (that radius for every joint)."""
    n = len(poses)
    uv = poses @ K_TEST.T
    xy = uv[..., :2] / uv[..., 2:]
    conf = np.ones((n, 12))
    kp = Keypoints2D(xy, conf, SKEL, list(range(n)), [f"f{i}.png" for i in range(n)],
                     np.array([[640.0, 480.0]] * n), [None] * n, "kp.json", "zedo-2d")  # fmt: skip
    root = root_point(poses, SKEL)
    res = LiftResult(poses, poses - root[:, None], root, np.zeros((n, 12)), np.ones((n, 12), bool),
                     np.ones(n, bool), LiftConfig(), 0.1)  # fmt: skip
    doc = build_result_document(kp, res, np.stack([K_TEST] * n), ["cli"] * n,
                                params={"preset": "test", "fps": fps}, input_info={"path": "kp.json"},
                                units=units)  # fmt: skip
    if radius is not None:
        for frame in doc["frames"]:
            for person in frame["persons"]:
                person["uncertainty_m"] = [radius] * 12
    return doc


def write_document(path: Path, doc: dict[str, Any]) -> Path:
    path.write_text(json.dumps(doc))
    return path
