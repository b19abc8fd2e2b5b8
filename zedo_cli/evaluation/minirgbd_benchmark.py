"""The paper's MINI-RGBD protocols (ALGORITHM.md 1.5, 6): lift the frames of one split side
from their depth-image 2D with the depth camera's intrinsics and score them on 17 or 16 joints.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ..data.minirgbd import DEFAULT_DROPPED_JOINT, MiniFrames, load_minirgbd, protocol_joints, split_sequences
from ..data.skeleton import center_on_root, get_skeleton
from ..errors import WeightsError
from ..lifting.camera import Intrinsics
from ..lifting.config import LiftConfig
from ..lifting.solver import LiftProgress, LiftResult, lift
from ..prior.weights import Prior
from .syrip_benchmark import score_poses

# The Kinect depth camera of MINI-RGBD (ALGORITHM.md 1.5); the 2D is in its 640x480 image.
DEPTH_INTRINSICS = Intrinsics(
    fx=588.67905803875317, fy=590.25690113005601, cx=322.22048191353628, cy=237.46785983766890,
    source="minirgbd-depth",
)  # fmt: skip


def score_minirgbd(
    pred: np.ndarray, truth: np.ndarray, joints: tuple[str, ...]
) -> tuple[float, float, dict[str, float]]:
    """MPJPE, PA-MPJPE (mm) and per-joint MPJPE over `joints` of `h36m17` poses `(N, 17, 3)`.

    Both sides are centred on the pelvis over all 17 joints first, then the protocol's joints
    are kept (ALGORITHM.md 6: the reference subtracts joint 0 from the GT).
    """
    skel = get_skeleton("h36m17")
    idx = [skel.index(j) for j in joints]
    p, t = center_on_root(pred, skel)[:, idx], center_on_root(truth, skel)[:, idx]
    return score_poses(p, t, joints)


# The reference's depth-scale clamp for MINI-RGBD (ALGORITHM.md 3.0): [0, 4] times the 1 m
# base distance, where SyRIP's presets use [0.5, 8].
MINI_SCALE_CLAMP = (0.0, 4.0)


def minirgbd_lift_config(config: LiftConfig) -> LiftConfig:
    """`config` with the reference's MINI-RGBD depth-scale clamp."""
    return replace(config, scale_min=MINI_SCALE_CLAMP[0], scale_max=MINI_SCALE_CLAMP[1])


@dataclass
class MiniScore:
    """Errors of one MINI-RGBD run (mm), overall, per joint and per sequence."""

    split: str
    side: str
    mapping: str
    protocol: str
    joints: tuple[str, ...]
    count: int
    mpjpe_mm: float
    pa_mpjpe_mm: float
    per_joint_mm: dict[str, float]
    per_sequence_mm: dict[str, float]
    mean_reprojection_error_px: float
    seconds: float  # lifting wall time
    poses_per_second: float


@dataclass
class MiniBenchmark:
    score: MiniScore
    frames: MiniFrames  # the ground truth and its 2D
    result: LiftResult  # the lifted poses, in the frames' order


def _per_sequence(pred: np.ndarray, truth: np.ndarray, names: list[str], joints: tuple[str, ...]) -> dict[str, float]:
    seqs = np.array([n.split("/")[0] for n in names])
    return {s: score_minirgbd(pred[seqs == s], truth[seqs == s], joints)[0] for s in dict.fromkeys(seqs.tolist())}


def run_minirgbd_benchmark(
    root: str | Path,
    prior: Prior,
    config: LiftConfig,
    *,
    split: str = "paper",
    side: str = "test",
    mapping: str = "reference",
    protocol: str = "17",
    dropped: str = DEFAULT_DROPPED_JOINT,
    stride: int = 1,
    device: str = "cpu",
    callback: Callable[[LiftProgress], None] | None = None,
) -> MiniBenchmark:
    """Lift the frames of one split side from their 2D with the depth camera's K and score
    them against the 3D joints (both centred on the pelvis).

    `prior` must be of the `h36m17` joint set; `config` gets the reference's MINI-RGBD
    depth-scale clamp. Every joint is observed (confidence 1).
    """
    if prior.skeleton.name != "h36m17":
        raise WeightsError(f"{prior.path}: the MINI-RGBD benchmark needs an h36m17 prior, not {prior.skeleton.name} "
                           "(train one with: zedo fit-prior --minirgbd-dir DIR)")  # fmt: skip
    joints = protocol_joints(protocol, dropped)
    frames = load_minirgbd(root, split_sequences(split, side), mapping=mapping, stride=stride)
    assert frames.keypoints_2d is not None
    n = len(frames.names)
    k = np.broadcast_to(DEPTH_INTRINSICS.matrix(), (n, 3, 3)).copy()
    start = time.perf_counter()
    res = lift(frames.keypoints_2d, np.ones((n, frames.skeleton.num_joints)), k, prior, minirgbd_lift_config(config),
               device=device, callback=callback)  # fmt: skip
    seconds = time.perf_counter() - start
    mpjpe, pa, per_joint = score_minirgbd(res.poses_camera, frames.poses_camera, joints)
    per_seq = _per_sequence(res.poses_camera, frames.poses_camera, frames.names, joints)
    reproj = float(np.nanmean(res.reprojection_error_px))
    score = MiniScore(split, side, mapping, protocol, joints, n, mpjpe, pa, per_joint, per_seq, reproj,
                      seconds, n / seconds if seconds > 0 else float("nan"))  # fmt: skip
    return MiniBenchmark(score, frames, res)
