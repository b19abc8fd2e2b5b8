"""A null joint in the ground truth names the joint, the pose and the file; a joint set
that lacks a protocol's joint says which; analysed poses are counted honestly."""

from __future__ import annotations

import numpy as np
import pytest

from zedo_cli.analysis.analyse import poses_counted
from zedo_cli.data.datasets import PoseSet
from zedo_cli.data.skeleton import get_skeleton
from zedo_cli.errors import ConfigError, InputFormatError
from zedo_cli.evaluation.result_scoring import PredictedPoses, align_to_truth


def _poses(n: int) -> np.ndarray:
    return np.random.default_rng(0).normal(size=(n, 12, 3)) * 0.1


def test_a_null_ground_truth_joint_is_named_with_its_pose_and_file() -> None:
    skel = get_skeleton("syrip12")
    truth = _poses(3)
    truth[1, 4] = np.nan
    gt = PoseSet(truth, skel, ["a.jpg", "b.jpg", "c.jpg"], "gt.npz")
    pred = PredictedPoses(_poses(3), skel, ["a.jpg", "b.jpg", "c.jpg"])
    with pytest.raises(InputFormatError) as info:
        align_to_truth(pred, gt, "syrip12")
    assert str(info.value) == (f"gt.npz: pose b.jpg: joint {skel.joints[4]} is null or missing (protocol syrip12 "
                               "needs every syrip12 joint; 1 of 3 poses lack one)")  # fmt: skip


def test_a_joint_set_without_the_protocols_joint_is_a_usage_error() -> None:
    gt = PoseSet(_poses(2), get_skeleton("syrip12"), ["a", "b"], "gt.npz")
    pred = PredictedPoses(_poses(2), get_skeleton("syrip12"), ["a", "b"])
    with pytest.raises(ConfigError, match="protocol h36m17 needs joint .*, which gt.npz's joint set \\(syrip12\\)"):
        align_to_truth(pred, gt, "h36m17")


def test_poses_are_counted_in_frames_and_people() -> None:
    assert poses_counted(np.arange(809), np.zeros(809, int)) == "809 poses (809 frames, 1 person)"
    assert poses_counted(np.array([0, 0, 1, 1]), np.array([0, 1, 0, 1])) == "4 poses (2 frames, 2 people)"
    assert poses_counted(np.array([0]), np.array([0])) == "1 pose"
