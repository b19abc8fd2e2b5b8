"""experiments/leg_depth_prior.py's mirrored legs (a rejected remedy, docs/movement.md) are the other solution of the
depth ambiguity: the same 2D (orthographic), bone lengths and knee angle, at least one leg moved per pose."""

from __future__ import annotations

import numpy as np
from helpers import synthetic_poses

from experiments.leg_depth_prior import interior_angle, mirror_legs
from zedo_cli.data.skeleton import get_skeleton

JOINTS = list(get_skeleton("syrip12").joints)


def test_mirrored_legs_keep_2d_bones_and_knee_angles_and_move_at_least_one_leg() -> None:
    poses = synthetic_poses(40, seed=2)
    mirrored = mirror_legs(poses, JOINTS, np.random.default_rng(0))
    np.testing.assert_array_equal(mirrored[..., :2], poses[..., :2])
    for side in ("left", "right"):
        hip, knee, ankle = (JOINTS.index(f"{side}_{j}") for j in ("hip", "knee", "ankle"))
        for a, b in ((hip, knee), (knee, ankle)):
            np.testing.assert_allclose(np.linalg.norm(mirrored[:, a] - mirrored[:, b], axis=-1),
                                       np.linalg.norm(poses[:, a] - poses[:, b], axis=-1), rtol=1e-12)  # fmt: skip
        np.testing.assert_allclose(interior_angle(mirrored, JOINTS, side, "knee"),
                                   interior_angle(poses, JOINTS, side, "knee"), atol=1e-9)  # fmt: skip
    legs = [JOINTS.index(f"{s}_{j}") for s in ("left", "right") for j in ("knee", "ankle")]
    others = [j for j in range(len(JOINTS)) if j not in legs]
    np.testing.assert_array_equal(mirrored[:, others], poses[:, others])
    moved = (mirrored[:, legs, 2] != poses[:, legs, 2]).any(axis=1)
    assert moved.all()
