"""Scoring a zedo result file against 3D ground truth on a named protocol."""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..data.datasets import PoseSet
from ..data.skeleton import Skeleton, center_on_root, convert_points, get_skeleton
from ..errors import ConfigError, InputFormatError

# protocol -> joint set scored; both sides are converted to it and centred on its root
PROTOCOLS: dict[str, str] = {"syrip12": "syrip12", "h36m17": "h36m17"}


@dataclass
class PredictedPoses:
    """First person of each lifted frame of a zedo result file."""

    poses: np.ndarray  # (N, J, 3) metres, camera frame
    skeleton: Skeleton
    keys: list[str]  # file name, else str(image_id), per pose


def read_result_file(path: str | Path) -> PredictedPoses:
    path = Path(path)
    try:
        doc: Any = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise InputFormatError(f"{path}: file not found") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise InputFormatError(f"{path}: not a readable JSON file ({exc})") from None
    if not isinstance(doc, dict) or doc.get("schema") != "zedo.pose3d/1":
        raise InputFormatError(f"{path}: schema: expected a zedo result file (schema zedo.pose3d/1)")
    try:
        skel = get_skeleton(doc["skeleton"]["name"])
        poses, keys = [], []
        for f, frame in enumerate(doc["frames"]):
            person = frame["persons"][0]
            if person["keypoints_3d"] is None:
                continue
            pts = np.array([[np.nan] * 3 if p is None else p for p in person["keypoints_3d"]], dtype=float)
            if pts.shape != (skel.num_joints, 3):
                raise InputFormatError(f"{path}: frames[{f}].persons[0].keypoints_3d: expected {skel.num_joints}x3")
            poses.append(pts)
            keys.append(str(frame["file_name"]) if frame.get("file_name") else str(frame["image_id"]))
    except (KeyError, IndexError, TypeError, ValueError) as exc:
        raise InputFormatError(f"{path}: malformed result file ({type(exc).__name__}: {exc})") from None
    if not poses:
        raise InputFormatError(f"{path}: no lifted poses")
    return PredictedPoses(np.array(poses), skel, keys)


def _all_observed(poses: np.ndarray, src: Skeleton, dst: Skeleton) -> tuple[np.ndarray, np.ndarray]:
    return convert_points(poses, np.ones(poses.shape[:2]), src, dst)


def align_to_truth(pred: PredictedPoses, truth: PoseSet, protocol: str) -> tuple[np.ndarray, np.ndarray, Skeleton]:
    """Prediction and truth of the images both have, in the protocol's joint set, root-centred."""
    if protocol not in PROTOCOLS:
        raise ConfigError(f"unknown protocol {protocol!r}; protocols: {', '.join(PROTOCOLS)}")
    dst = get_skeleton(PROTOCOLS[protocol])
    index = {k: i for i, k in enumerate(pred.keys)}
    common = [(index[n], t) for t, n in enumerate(truth.names) if n in index]
    if not common:
        raise InputFormatError("no prediction matches a ground-truth pose by file name or image id")
    p_idx, t_idx = zip(*common, strict=True)
    p, p_conf = _all_observed(pred.poses[list(p_idx)], pred.skeleton, dst)
    t, t_conf = _all_observed(truth.poses[list(t_idx)], truth.skeleton, dst)
    if not (p_conf.all() and t_conf.all()):
        raise ConfigError(f"protocol {protocol} needs joints that {pred.skeleton.name} or {truth.skeleton.name} lack")
    return center_on_root(p, dst), center_on_root(t, dst), dst
