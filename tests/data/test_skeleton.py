"""Tests of the joint sets and conversions by name (zedo_cli.data.skeleton)."""

from __future__ import annotations

import numpy as np
import pytest

from zedo_cli.data.skeleton import (
    SKELETONS,
    Skeleton,
    center_on_root,
    convert_points,
    get_skeleton,
    root_point,
)
from zedo_cli.errors import ConfigError

ALL_NAMES = sorted(SKELETONS)


def _random_points(skeleton: Skeleton, dim: int = 3, lead: tuple[int, ...] = (), seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return rng.normal(size=(*lead, skeleton.num_joints, dim))


def _bone_lengths(points: np.ndarray, skeleton: Skeleton) -> np.ndarray:
    a = np.array([i for i, _ in skeleton.bones])
    b = np.array([j for _, j in skeleton.bones])
    return np.linalg.norm(points[..., a, :] - points[..., b, :], axis=-1)


def _flip(points: np.ndarray, skeleton: Skeleton) -> np.ndarray:
    mirrored = points * np.array([-1.0, 1.0, 1.0])
    return mirrored[..., skeleton.flip_permutation, :]


# --- flips ---------------------------------------------------------------------------------


@pytest.mark.parametrize("name", ALL_NAMES)
def test_flip_permutation_is_an_involution(name: str) -> None:
    skel = get_skeleton(name)
    perm = skel.flip_permutation
    assert sorted(perm) == list(range(skel.num_joints))
    assert [perm[p] for p in perm] == list(range(skel.num_joints))


@pytest.mark.parametrize("name", ALL_NAMES)
def test_flip_permutation_swaps_left_and_right(name: str) -> None:
    skel = get_skeleton(name)
    perm = skel.flip_permutation
    for i, joint in enumerate(skel.joints):
        twin = skel.joints[perm[i]]
        if joint.startswith("left_"):
            assert twin == "right_" + joint[len("left_") :]
        elif joint.startswith("right_"):
            assert twin == "left_" + joint[len("right_") :]
        else:
            assert twin == joint


@pytest.mark.parametrize("name", ALL_NAMES)
def test_flipping_a_pose_keeps_bone_lengths(name: str) -> None:
    skel = get_skeleton(name)
    pose = _random_points(skel, lead=(5,), seed=1)
    flipped = _flip(pose, skel)
    perm = skel.flip_permutation
    # The bone set is closed under the flip, and each bone keeps the length of its mirror twin.
    bones = {frozenset(b) for b in skel.bones}
    twins = [(perm[a], perm[b]) for a, b in skel.bones]
    assert all(frozenset(t) in bones for t in twins)
    original = np.linalg.norm(pose[:, [a for a, _ in twins]] - pose[:, [b for _, b in twins]], axis=-1)
    np.testing.assert_allclose(_bone_lengths(flipped, skel), original, atol=1e-12)
    # As a multiset per pose, the bone lengths are unchanged.
    sorted_flipped = np.sort(_bone_lengths(flipped, skel), axis=-1)
    np.testing.assert_allclose(sorted_flipped, np.sort(_bone_lengths(pose, skel), axis=-1), atol=1e-12)
    # Flipping twice gives the pose back.
    np.testing.assert_allclose(_flip(flipped, skel), pose, atol=0)


def test_bones_are_valid_index_pairs() -> None:
    for skel in SKELETONS.values():
        for a, b in skel.bones:
            assert 0 <= a < skel.num_joints and 0 <= b < skel.num_joints and a != b
        assert len(set(skel.joints)) == skel.num_joints


# --- conversions ---------------------------------------------------------------------------


def test_convert_coco17_to_syrip12_picks_joints_by_name() -> None:
    coco, syrip = get_skeleton("coco17"), get_skeleton("syrip12")
    points = _random_points(coco, dim=2, seed=2)
    conf = np.linspace(0.1, 0.9, coco.num_joints)
    out, out_conf = convert_points(points, conf, coco, syrip)
    assert out.shape == (12, 2) and out_conf.shape == (12,)
    for joint in ("right_hip", "left_wrist", "right_ankle", "left_shoulder"):
        np.testing.assert_array_equal(out[syrip.index(joint)], points[coco.index(joint)])
        assert out_conf[syrip.index(joint)] == conf[coco.index(joint)]
    # Every syrip12 joint exists in coco17.
    assert np.isfinite(out).all() and (out_conf > 0).all()
    # Explicit value: syrip12 joint 0 is right_hip, COCO index 12.
    assert syrip.joints[0] == "right_hip"
    np.testing.assert_array_equal(out[0], points[12])


def test_convert_coco17_to_h36m17_derives_pelvis_as_hip_mean_with_lowest_confidence() -> None:
    coco, h36m = get_skeleton("coco17"), get_skeleton("h36m17")
    points = _random_points(coco, dim=2, seed=3)
    conf = np.full(coco.num_joints, 0.9)
    conf[coco.index("left_hip")] = 0.4
    conf[coco.index("right_hip")] = 0.7
    out, out_conf = convert_points(points, conf, coco, h36m)
    pelvis = h36m.index("pelvis")
    expected = (points[coco.index("left_hip")] + points[coco.index("right_hip")]) / 2
    np.testing.assert_allclose(out[pelvis], expected, atol=1e-12)
    assert out_conf[pelvis] == pytest.approx(0.4)
    # Thorax is the shoulder mean; neck is aliased to the nose.
    thorax = (points[coco.index("left_shoulder")] + points[coco.index("right_shoulder")]) / 2
    np.testing.assert_allclose(out[h36m.index("thorax")], thorax, atol=1e-12)
    np.testing.assert_array_equal(out[h36m.index("neck")], points[coco.index("nose")])


def test_derived_joint_is_missing_when_one_source_is_missing() -> None:
    coco, h36m = get_skeleton("coco17"), get_skeleton("h36m17")
    points = _random_points(coco, dim=2, lead=(2,), seed=4)
    conf = np.ones((2, coco.num_joints))
    conf[1, coco.index("right_hip")] = 0.0
    out, out_conf = convert_points(points, conf, coco, h36m)
    pelvis, spine = h36m.index("pelvis"), h36m.index("spine")
    # Instance 0 is complete; instance 1 lacks its right hip.
    assert np.isfinite(out[0]).all() and (out_conf[0] > 0).all()
    for j in (pelvis, spine, h36m.index("right_hip")):
        assert np.isnan(out[1, j]).all()
        assert out_conf[1, j] == 0.0
    # Joints not depending on the right hip stay present.
    assert np.isfinite(out[1, h36m.index("left_hip")]).all()
    assert np.isfinite(out[1, h36m.index("thorax")]).all()


def test_convert_points_rejects_wrong_joint_count() -> None:
    coco, syrip = get_skeleton("coco17"), get_skeleton("syrip12")
    with pytest.raises(ConfigError, match="17"):
        convert_points(np.zeros((16, 2)), np.ones(16), coco, syrip)


def test_convert_to_same_skeleton_is_identity() -> None:
    skel = get_skeleton("h36m17")
    points = _random_points(skel, seed=5)
    conf = np.full(skel.num_joints, 0.5)
    out, out_conf = convert_points(points, conf, skel, skel)
    np.testing.assert_array_equal(out, points)
    np.testing.assert_array_equal(out_conf, conf)


# --- root ----------------------------------------------------------------------------------


def test_root_point_and_center_on_root_use_hip_midpoint_for_syrip12() -> None:
    syrip = get_skeleton("syrip12")
    pose = _random_points(syrip, lead=(3,), seed=6)
    hip_mid = (pose[:, syrip.index("left_hip")] + pose[:, syrip.index("right_hip")]) / 2
    np.testing.assert_allclose(root_point(pose, syrip), hip_mid, atol=1e-12)
    centred = center_on_root(pose, syrip)
    np.testing.assert_allclose(root_point(centred, syrip), 0.0, atol=1e-12)
    np.testing.assert_allclose(centred, pose - hip_mid[:, None, :], atol=1e-12)


def test_root_point_for_h36m17_is_the_pelvis() -> None:
    h36m = get_skeleton("h36m17")
    pose = _random_points(h36m, seed=7)
    np.testing.assert_array_equal(root_point(pose, h36m), pose[h36m.index("pelvis")])


def test_get_skeleton_unknown_names_the_known_skeletons() -> None:
    with pytest.raises(ConfigError) as info:
        get_skeleton("nope")
    message = str(info.value)
    assert "nope" in message
    for name in SKELETONS:
        assert name in message
