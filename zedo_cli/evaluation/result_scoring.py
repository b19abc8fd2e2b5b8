"""Scoring a zedo result file against 3D ground truth on a named protocol."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..data.datasets import SCORING_PROTOCOLS, PoseSet
from ..data.skeleton import Skeleton, center_on_root, convert_points, get_skeleton
from ..errors import ConfigError, InputFormatError
from ..formats.readers.result import read_result


@dataclass
class PredictedPoses:
    """First person of each lifted frame of a zedo result file."""

    poses: np.ndarray  # (N, J, 3) metres, camera frame
    skeleton: Skeleton
    keys: list[str]  # file name, else str(image_id), per pose
    source: str = "the result"  # the file, for messages


def read_result_file(path: str | Path) -> PredictedPoses:
    """The first person of each lifted frame of a zedo result (any format `zedo lift` writes)."""
    res = read_result(path)
    keep = np.flatnonzero((res.person == 0) & res.lifted)
    if not len(keep):
        raise InputFormatError(f"{path}: no lifted poses")
    keys = [res.file_names[i] or str(res.image_ids[i]) for i in keep]
    return PredictedPoses(res.poses[keep], res.skeleton, keys, str(path))


def _all_observed(poses: np.ndarray, src: Skeleton, dst: Skeleton) -> tuple[np.ndarray, np.ndarray]:
    return convert_points(poses, np.ones(poses.shape[:2]), src, dst)


def align_to_truth(pred: PredictedPoses, truth: PoseSet, protocol: str) -> tuple[np.ndarray, np.ndarray, Skeleton]:
    """Prediction and truth of the images both have, in the protocol's joint set, root-centred."""
    if protocol not in SCORING_PROTOCOLS:
        raise ConfigError(f"unknown protocol {protocol!r}; protocols: {', '.join(SCORING_PROTOCOLS)}")
    dst = get_skeleton(SCORING_PROTOCOLS[protocol])
    index = {k: i for i, k in enumerate(pred.keys)}
    common = [(index[n], t) for t, n in enumerate(truth.names) if n in index]
    if not common:
        raise InputFormatError("no prediction matches a ground-truth pose by file name or image id")
    p_idx, t_idx = zip(*common, strict=True)
    p, p_conf = _all_observed(pred.poses[list(p_idx)], pred.skeleton, dst)
    t, t_conf = _all_observed(truth.poses[list(t_idx)], truth.skeleton, dst)
    for conf, where, names in ((t_conf, truth.source, [truth.names[t] for t in t_idx]),
                               (p_conf, pred.source, [pred.keys[i] for i in p_idx])):  # fmt: skip
        absent = ~conf.astype(bool)
        if absent.all(0).any():  # in no pose: the joint set lacks it
            raise ConfigError(f"protocol {protocol} needs joint {dst.joints[int(np.argmax(absent.all(0)))]}, which "
                              f"{where}'s joint set ({(truth if where == truth.source else pred).skeleton.name}) "
                              "lacks")  # fmt: skip
        if absent.any():  # a null joint: say which, in which pose of which file
            row, joint = (int(k[0]) for k in np.nonzero(absent))
            raise InputFormatError(f"{where}: pose {names[row]}: joint {dst.joints[joint]} is null or missing "
                                   f"(protocol {protocol} needs every {dst.name} joint; "
                                   f"{int(absent.any(1).sum())} of {len(conf)} poses lack one)")  # fmt: skip
    return center_on_root(p, dst), center_on_root(t, dst), dst
