"""A hand-built lifting result for the writer and plot tests: four instances in three images,
one with a missing joint (filled by the prior), one not lifted (too few observed joints)."""

from __future__ import annotations

import numpy as np
from helpers import K_TEST, SKELETON, synthetic_poses

from zedo_cli.data.keypoints import Keypoints2D
from zedo_cli.data.skeleton import root_point
from zedo_cli.lifting.config import LiftConfig
from zedo_cli.lifting.solver import LiftResult

MISSING = (1, 2)  # instance 1, joint 2 (right_ankle): not observed, filled by the prior
UNLIFTED = 3
PARAMS = {"preset": "test", "steps": 5, "seed": 0}
INPUT_INFO = {"path": "kp.json", "format": "coco-annotations", "skeleton": "syrip12"}


def make_case() -> tuple[Keypoints2D, LiftResult, np.ndarray, list[str]]:
    """`(kp, res, intrinsics, sources)`; instances 0 and 1 share image 10."""
    n, j = 4, SKELETON.num_joints
    trans = np.array([[0.0, 0.0, 1.0], [0.1, 0.0, 1.2], [-0.1, 0.05, 0.9], [0.0, 0.0, 1.0]])
    cam = synthetic_poses(n, seed=1) + trans[:, None]  # (N, J, 3), root points at `trans`
    uv = cam @ K_TEST.T
    xy = uv[..., :2] / uv[..., 2:]
    conf = np.full((n, j), 0.9)
    observed = np.ones((n, j), dtype=bool)
    xy[MISSING], conf[MISSING], observed[MISSING] = np.nan, 0.0, False
    xy[UNLIFTED, 2:], conf[UNLIFTED, 2:], observed[UNLIFTED, 2:] = np.nan, 0.0, False
    lifted = np.array([True, True, True, False])
    cam[UNLIFTED] = np.nan
    root = root_point(cam, SKELETON)  # (N, 3)
    # Distinct mean errors per instance: 1.0 < 2.0 < 3.0 px (instance 2 is the worst).
    reproj = np.where(observed, np.array([1.0, 2.0, 3.0, np.nan])[:, None], np.nan)
    kp = Keypoints2D(
        xy, conf, SKELETON, [10, 10, 11, 12], ["a.jpg", "a.jpg", "b.jpg", None],
        np.array([[640.0, 480.0]] * 3 + [[np.nan, np.nan]]), [0.9, 0.8, None, 0.5], "kp.json", "coco-annotations",
    )  # fmt: skip
    res = LiftResult(cam, cam - root[:, None], root, reproj, observed, lifted, LiftConfig(), 1.25)
    intrinsics = np.stack([K_TEST] * n)
    intrinsics[2, 0, 0] = intrinsics[2, 1, 1] = 1500.0  # one frame with its own K
    return kp, res, intrinsics, ["cli", "cli", "file", "pseudo"]
