"""experiments/still_limb_lift.py: its clips hold the left arm rigid in the trunk's frame with bones of one length,
and its two side rules change only how clip mode picks a side."""

from __future__ import annotations

import numpy as np
from helpers import synthetic_poses

from experiments.still_limb_lift import JOINTS, held_arm_clip, sides_kept_in_trunk_frame, true_sides
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


def test_side_rules_are_put_back() -> None:
    solutions, choose = clip.ray_solutions, clip.choose_sides
    torso = np.repeat(synthetic_poses(1, seed=2)[:, [JOINTS.index(n) for n in clip.TORSO]], 5, axis=0)
    with sides_kept_in_trunk_frame(torso, 10.0):
        assert clip.choose_sides is not choose
    with true_sides(np.zeros((5, 12, 3))):
        assert clip.ray_solutions is not solutions
    assert (clip.ray_solutions, clip.choose_sides) == (solutions, choose)
