"""The rejected depth-sign vote of experiments/depth_sign_vote.py does what its docs say: within a run of frames
where a segment points clearly along the depth axis, frames lifted on the losing side take the winning sign
with the segment's length kept, and the distal joints move with it; frames outside runs are left alone."""

from __future__ import annotations

import numpy as np
from helpers import synthetic_poses

from experiments.depth_sign_vote import JOINT, Vote, runs, vote


def test_runs_are_the_stretches_of_true() -> None:
    assert runs(np.array([0, 1, 1, 0, 1, 0, 0, 1], bool)) == [(1, 3), (4, 5), (7, 8)]
    assert runs(np.zeros(4, bool)) == []


def _clip_with_a_flipped_thigh() -> tuple[np.ndarray, np.ndarray]:
    """30 frames of one pose whose left thigh points away from the camera (unit z 0.8), then the same clip
    with the thigh lifted towards the camera in frames 10-12 (knee and ankle moved with it)."""
    pose = synthetic_poses(1, seed=5)[0]
    hip, knee, ankle = JOINT["left_hip"], JOINT["left_knee"], JOINT["left_ankle"]
    pose[knee] = pose[hip] + np.array([0.06, 0.0, 0.08])  # length 0.1, unit z 0.8
    pose[ankle] = pose[knee] + np.array([0.0, 0.1, 0.0])  # the shank in the image plane
    clip = np.repeat(pose[None], 30, axis=0)
    flipped = clip.copy()
    flipped[10:13, [knee, ankle], 2] -= 0.16
    return clip, flipped


def test_the_losing_frames_take_the_winning_sign_and_keep_their_lengths() -> None:
    clip, flipped = _clip_with_a_flipped_thigh()
    voted = vote(flipped, Vote())
    np.testing.assert_allclose(voted, clip, atol=1e-12)


def test_a_clip_that_never_points_along_the_depth_axis_is_left_alone() -> None:
    clip, flipped = _clip_with_a_flipped_thigh()
    assert np.array_equal(vote(flipped, Vote(tau=0.9)), flipped)  # |unit z| 0.8 never exceeds 0.9
