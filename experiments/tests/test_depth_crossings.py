"""experiments/depth_crossings.py measures what its docs say: a crossing of the image plane at speed dips
sharply (a V), a turn-back slowly (a U); the ROC AUC is the share of positive-negative pairs ranked right;
the sign-free depth estimate recovers |unit z| from the image-plane length and the clip's median length."""

from __future__ import annotations

import numpy as np
from helpers import synthetic_poses

from benchmarks.accuracy.limb_depth_flips import JOINT
from experiments.depth_crossings import roc_auc, unit_depths, v_depth


def test_a_crossing_dips_sharper_than_a_turn_back() -> None:
    t = np.linspace(-1.0, 1.0, 31)
    crossing = np.abs(np.sin(t))  # the segment's depth passes through zero at speed
    turn_back = 1.0 - np.cos(t)  # it slows to a stop at the image plane and returns
    assert v_depth(crossing, 10, 21) > 3 * v_depth(turn_back, 10, 21) > 0


def test_the_dip_is_read_at_the_lowest_frame_and_clipped_at_the_ends() -> None:
    series = np.array([0.0, 0.5, 1.0, 1.0])
    assert v_depth(series, 0, 4, half_width=2) == 1.0  # the lowest frame is the first: before = itself


def test_roc_auc_counts_ranked_pairs_and_half_ties() -> None:
    score = np.array([0.9, 0.4, 0.4, 0.1])
    positive = np.array([True, True, False, False])
    assert roc_auc(score, positive) == (1 + 1 + 0.5 + 1) / 4
    assert roc_auc(-score, positive) == 1 - roc_auc(score, positive)


def test_the_sign_free_estimate_recovers_the_depth_of_a_segment() -> None:
    pose = synthetic_poses(1, seed=3)[0]
    hip, knee = JOINT["left_hip"], JOINT["left_knee"]
    clip = np.repeat(pose[None], 20, axis=0)
    unit_z = np.linspace(-0.9, 0.9, 20)
    clip[:, knee] = clip[:, hip] + 0.1 * np.stack([np.sqrt(1 - unit_z**2), np.zeros(20), unit_z], axis=-1)
    lifted = clip.copy()
    lifted[:, knee, 2] = 2 * clip[:, hip, 2] - clip[:, knee, 2]  # every frame on the other side: same |z|
    lifted[5] = np.nan  # a frame not lifted is interpolated
    true_z, true_abs, lifted_abs, estimate = unit_depths(clip, lifted, "left", "thigh")
    np.testing.assert_allclose(true_z, unit_z, atol=1e-12)
    np.testing.assert_allclose(true_abs, np.abs(unit_z), atol=1e-12)
    np.testing.assert_allclose(lifted_abs, np.abs(unit_z), atol=1e-6)
    np.testing.assert_allclose(estimate, np.abs(unit_z), atol=1e-6)
