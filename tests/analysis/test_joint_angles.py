"""Joint-angle conventions (docs/clinical.md), pinned on constructed poses."""

from __future__ import annotations

import numpy as np
import pytest
from analysis_poses import FRONT, LEFT, SKEL, UP, random_rigid, rotation, set_limb, standing, to_array

from zedo_cli.analysis.pose.joint_angles import ANGLE_NAMES, joint_angles, trunk_frame


def angles(pts: dict[str, np.ndarray] | np.ndarray) -> dict[str, float]:
    pose = to_array(pts) if isinstance(pts, dict) else pts
    return {k: float(v) for k, v in joint_angles(pose, SKEL).items()}


def test_the_standing_pose_is_all_zero() -> None:
    got = angles(standing())
    assert list(got) == list(ANGLE_NAMES) and len(got) == 12
    assert all(v == pytest.approx(0.0, abs=1e-6) for v in got.values())


def test_trunk_frame_axes() -> None:
    up, left, front = trunk_frame(to_array(standing()), SKEL)
    np.testing.assert_allclose(up, UP, atol=1e-12)
    np.testing.assert_allclose(left, LEFT, atol=1e-12)
    np.testing.assert_allclose(front, FRONT, atol=1e-12)  # towards the camera for a pose facing it


@pytest.mark.parametrize("side", ["left", "right"])
@pytest.mark.parametrize(("flexion", "abduction", "bend"), [(90.0, 0.0, 0.0), (45.0, 30.0, 90.0), (-20.0, -10.0, 30.0),
                                                            (30.0, 70.0, 120.0), (180.0, 0.0, 10.0)])  # fmt: skip
def test_known_hip_and_shoulder_angles(side: str, flexion: float, abduction: float, bend: float) -> None:
    pts = standing()
    set_limb(pts, side, "leg", flexion, abduction, bend=bend)
    set_limb(pts, side, "arm", flexion, abduction, bend=bend)
    got = angles(pts)
    for joint in ("hip", "shoulder"):
        assert got[f"{side}_{joint}_flexion_deg"] == pytest.approx(flexion, abs=1e-6)
        assert got[f"{side}_{joint}_abduction_deg"] == pytest.approx(abduction, abs=1e-6)
    assert got[f"{side}_knee_flexion_deg"] == pytest.approx(abs(bend), abs=1e-6)
    assert got[f"{side}_elbow_flexion_deg"] == pytest.approx(abs(bend), abs=1e-6)
    other = "right" if side == "left" else "left"
    assert got[f"{other}_hip_flexion_deg"] == pytest.approx(0.0, abs=1e-6)


def test_arms_overhead_read_180_without_jumping() -> None:
    for flexion in (170.0, 180.0, 200.0):
        pts = standing()
        set_limb(pts, "left", "arm", flexion, 0.0)
        assert angles(pts)["left_shoulder_flexion_deg"] == pytest.approx(flexion, abs=1e-6)


def test_flexion_is_undefined_beyond_80_degrees_abduction() -> None:
    pts = standing()
    set_limb(pts, "left", "arm", 40.0, 85.0)
    got = angles(pts)
    assert np.isnan(got["left_shoulder_flexion_deg"])
    assert got["left_shoulder_abduction_deg"] == pytest.approx(85.0, abs=1e-6)


def test_angles_do_not_depend_on_the_body_orientation() -> None:
    pts = standing()
    set_limb(pts, "left", "leg", 60.0, 25.0, bend=70.0)
    set_limb(pts, "right", "arm", 100.0, 20.0, bend=45.0)
    ref = angles(pts)
    lying = to_array(pts) @ rotation(LEFT, 90.0).T  # supine: the front now points up the image
    for seed in range(3):
        moved = angles(random_rigid(lying, seed))
        for k, v in ref.items():
            assert moved[k] == pytest.approx(v, abs=1e-6), k


def test_left_right_swap_exchanges_the_sides() -> None:
    pts = standing()
    set_limb(pts, "left", "leg", 60.0, 25.0, bend=70.0)
    pose = to_array(pts)
    mirrored = (pose * np.array([-1.0, 1.0, 1.0]))[SKEL.flip_permutation]
    ref, got = angles(pose), angles(mirrored)
    for k, v in ref.items():
        twin = k.replace("left_", "@").replace("right_", "left_").replace("@", "right_")
        assert got[twin] == pytest.approx(v, abs=1e-6), k
