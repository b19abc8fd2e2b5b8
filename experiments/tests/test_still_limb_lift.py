"""experiments/still_limb_lift.py: its clips hold the left arm rigid in the trunk's frame with bones of one length,
and its two side rules change only how clip mode picks a side."""

from __future__ import annotations

import numpy as np
from helpers import synthetic_poses

from experiments.still_limb_lift import JOINTS, held_arm_clip, side_rule, true_sides
from zedo_cli.evaluation.clips.cameras import turned_supine
from zedo_cli.evaluation.clips.stillness import trunk_axes
from zedo_cli.lifting import clip


def test_the_held_arm_keeps_its_place_in_the_trunk_frame() -> None:
    cam, xy, conf = held_arm_clip(turned_supine(synthetic_poses(40, seed=1), JOINTS), seed=0, supine=True)
    axes, _ = trunk_axes(cam, JOINTS)
    at = JOINTS.index
    for side, still in (("left", True), ("right", False)):
        for parent, child in ((f"{side}_shoulder", f"{side}_elbow"), (f"{side}_elbow", f"{side}_wrist")):
            local = np.einsum("tij,tj->ti", axes, cam[:, at(child)] - cam[:, at(parent)])
            assert np.ptp(np.linalg.norm(local, axis=-1)) < 1e-9  # one bone length
            assert (np.ptp(local, axis=0).max() < 1e-9) == still  # a held bone's direction never changes
    assert xy.shape == (300, 12, 2) and conf.shape == (300, 12)


def test_a_side_rule_sees_each_bone_in_turn_and_is_put_back() -> None:
    solutions, choose = clip.ray_solutions, clip.choose_sides
    seen = []

    def rule(unary, separation, near, far, parent, bone):  # noqa: ANN001, ANN202
        seen.append(bone)
        return np.zeros(len(unary), np.int8)

    with side_rule(rule):
        assert (clip.ray_solutions, clip.choose_sides) != (solutions, choose)
        for _ in clip.LIMB_BONES:
            clip.ray_solutions(np.zeros((3, 3)), np.tile([0.0, 0.0, 1.0], (3, 1)), 0.1)
            clip.choose_sides(np.zeros((3, 2)), np.zeros(3))
    assert seen == list(clip.LIMB_BONES)
    assert (clip.ray_solutions, clip.choose_sides) == (solutions, choose)


def test_true_sides_picks_the_solution_nearer_the_truth() -> None:
    truth = np.zeros((2, 12, 3))
    truth[:, JOINTS.index("left_knee")] = [[0.0, 0.0, 1.0], [0.0, 0.0, 2.0]]
    near, far = np.tile([0.0, 0.0, 1.1], (2, 1)), np.tile([0.0, 0.0, 1.9], (2, 1))
    sides = true_sides(truth)(np.zeros((2, 2)), np.zeros(2), near, far, np.zeros((2, 3)), ("left_hip", "left_knee"))
    assert sides.tolist() == [0, 1]
