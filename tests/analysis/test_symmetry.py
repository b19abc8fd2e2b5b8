"""The symmetry angle (Huang et al. 2022) on constructed poses with known answers."""

from __future__ import annotations

import numpy as np
import pytest
from analysis_poses import SKEL, UP, rotation, set_limb, standing, to_array

from zedo_cli.analysis.pose.geometry import require_joints
from zedo_cli.analysis.pose.symmetry import measure_name, symmetry_angles, symmetry_band, symmetry_call
from zedo_cli.data.skeleton import Skeleton
from zedo_cli.errors import InputFormatError

NAMES = [measure_name(p) for p in ("upper_arm", "forearm", "thigh", "shank")]


def angles(pts: dict[str, np.ndarray]) -> dict[str, float]:
    return {k: float(v) for k, v in symmetry_angles(to_array(pts), SKEL).items()}


def test_names_are_the_documented_ones() -> None:
    assert list(symmetry_angles(to_array(standing()), SKEL)) == [
        "symmetry_upper_arm_deg", "symmetry_forearm_deg", "symmetry_thigh_deg", "symmetry_shank_deg",
    ]  # fmt: skip


def test_a_mirror_symmetric_pose_gives_zero() -> None:
    pts = standing()
    for side in ("left", "right"):  # the same asymmetric-looking posture on both sides, mirrored
        set_limb(pts, side, "leg", 35.0, 20.0, bend=50.0)
        set_limb(pts, side, "arm", 120.0, 40.0, bend=70.0)
    assert all(v == pytest.approx(0.0, abs=1e-6) for v in angles(pts).values())


@pytest.mark.parametrize("deg", [10.0, 28.0, 45.0, 90.0, 150.0])
def test_known_angle_in_each_pair(deg: float) -> None:
    pts = standing()
    set_limb(pts, "left", "leg", deg, 0.0)  # the whole left leg swings forward: thigh and shank
    set_limb(pts, "right", "arm", 0.0, 0.0, bend=deg)  # the right forearm bends: forearm only
    got = angles(pts)
    assert got["symmetry_thigh_deg"] == pytest.approx(deg, abs=1e-6)
    assert got["symmetry_shank_deg"] == pytest.approx(deg, abs=1e-6)
    assert got["symmetry_forearm_deg"] == pytest.approx(deg, abs=1e-6)
    assert got["symmetry_upper_arm_deg"] == pytest.approx(0.0, abs=1e-6)


def test_both_arms_pointing_to_one_side_are_fully_asymmetric() -> None:
    # Both arms pointing to the infant's left: the right arm crosses the midline. Mirrored it
    # points right, so the angle is 180 - 2 * 0 = 180 for horizontal arms.
    pts = standing()
    set_limb(pts, "left", "arm", 0.0, 90.0)
    set_limb(pts, "right", "arm", 0.0, -90.0)
    assert angles(pts)["symmetry_upper_arm_deg"] == pytest.approx(180.0, abs=1e-6)


def test_invariant_to_rigid_motion_and_left_right_swap() -> None:
    rng = np.random.default_rng(0)
    pose = to_array(standing()) + rng.normal(0, 0.03, (12, 3))
    ref = symmetry_angles(pose, SKEL)
    r = rotation(rng.normal(size=3), 73.0)
    moved = symmetry_angles(pose @ r.T + np.array([0.3, -1.0, 2.0]), SKEL)
    # Swap the sides: relabel left as right and mirror the body (x -> -x), i.e. the same infant
    # seen in a mirror: each pair's angle is unchanged.
    swapped = (pose * np.array([-1.0, 1.0, 1.0]))[SKEL.flip_permutation]
    swapped_angles = symmetry_angles(swapped, SKEL)
    # Relabelling alone (no mirror) also keeps the angle: angle(L, H R) = angle(H L, R).
    relabelled = symmetry_angles(pose[SKEL.flip_permutation], SKEL)
    for n in NAMES:
        assert moved[n] == pytest.approx(ref[n], abs=1e-9)
        assert swapped_angles[n] == pytest.approx(ref[n], abs=1e-9)
        assert relabelled[n] == pytest.approx(ref[n], abs=1e-9)


def test_the_mirror_plane_normal_follows_the_shoulders_and_hips() -> None:
    # Turn the pelvis 30 degrees about the vertical axis, legs with it: still symmetric.
    pts = standing()
    r = rotation(UP, 30.0)
    for j in ("hip", "knee", "ankle"):
        for side in ("left", "right"):
            pts[f"{side}_{j}"] = r @ pts[f"{side}_{j}"]
    got = angles(pts)
    assert got["symmetry_thigh_deg"] == pytest.approx(0.0, abs=1e-6)
    assert got["symmetry_shank_deg"] == pytest.approx(0.0, abs=1e-6)


def test_batch_shapes_and_missing_joints() -> None:
    poses = np.stack([to_array(standing())] * 3)
    poses[1, SKEL.index("left_wrist")] = np.nan
    got = symmetry_angles(poses, SKEL)
    assert got["symmetry_forearm_deg"].shape == (3,)
    assert np.isnan(got["symmetry_forearm_deg"][1]) and np.isfinite(got["symmetry_upper_arm_deg"][1])


def test_the_shank_call_tests_the_shank_angle() -> None:
    # The published code calls the shank from the thigh angle. A symmetric thigh with an
    # asymmetric shank (one knee bent) must give an asymmetric shank call.
    pts = standing()
    set_limb(pts, "left", "leg", 0.0, 0.0, bend=60.0)
    got = angles(pts)
    assert got["symmetry_thigh_deg"] == pytest.approx(0.0, abs=1e-6)
    assert symmetry_call(got["symmetry_thigh_deg"], 28.0) == "symmetric"
    assert symmetry_call(got["symmetry_shank_deg"], 28.0) == "asymmetric"


def test_calls_and_bands() -> None:
    assert symmetry_call(28.0, 28.0) == "symmetric"  # "at most" the threshold
    assert symmetry_call(28.01, 28.0) == "asymmetric"
    assert symmetry_call(np.nan, 28.0) == ""
    assert symmetry_call(20.0, 28.0, 15.0, 27.0) == "symmetric"
    assert symmetry_call(20.0, 28.0, 15.0, 31.0) == "uncertain"
    assert symmetry_call(35.0, 28.0, 29.0, 40.0) == "asymmetric"
    assert [symmetry_band(v) for v in (0.0, 29.99, 30.0, 59.99, 60.0, 180.0)] == [1, 1, 2, 2, 3, 3]
    assert np.isnan(symmetry_band(np.nan))


def test_a_skeleton_without_the_joints_is_refused() -> None:
    legs = Skeleton("legs", ("left_hip", "right_hip", "left_knee", "right_knee"), (), ("left_hip", "right_hip"))
    with pytest.raises(InputFormatError, match=r"r\.json: skeleton legs lacks the joint\(s\) left_shoulder"):
        require_joints(legs, ("left_shoulder", "left_hip"), "r.json")
