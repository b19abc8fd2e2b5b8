"""Tests of the detector joint sets in zedo_cli.data.skeleton: BODY_25, COCO-18, Halpe-26."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from zedo_cli.data.skeleton import (
    SKELETONS,
    body25_variant,
    convert_points,
    skeleton_for_joint_count,
    skeleton_from_joint_names,
)


def test_joint_counts_and_orders() -> None:
    assert {k: getattr(skeleton_for_joint_count(k), "name", None) for k in (12, 17, 18, 25, 26)} == {
        12: None, 17: "coco17", 18: "coco18", 25: "body25", 26: "halpe26"}  # fmt: skip
    body25 = SKELETONS["body25"]
    # OpenPose doc/02_output.md: 1 Neck (= thorax), 8 MidHip (= pelvis), 11 RAnkle, 19 LBigToe, 24 RHeel
    assert [body25.joints[k] for k in (1, 8, 11, 19, 24)] == [
        "thorax", "pelvis", "right_ankle", "left_big_toe", "right_heel"]  # fmt: skip
    coco18 = SKELETONS["coco18"]
    expected = ["thorax", "right_hip", "left_ankle", "right_eye", "left_ear"]
    assert [coco18.joints[k] for k in (1, 8, 13, 14, 17)] == expected
    halpe = SKELETONS["halpe26"]
    assert halpe.joints[:17] == SKELETONS["coco17"].joints
    assert [halpe.joints[k] for k in (17, 18, 19, 20, 25)] == ["head", "thorax", "pelvis", "left_big_toe", "right_heel"]


def test_tool_joint_names() -> None:
    mmpose_halpe = [*SKELETONS["coco17"].joints, "head", "neck", "hip", "left_big_toe", "right_big_toe",
                    "left_small_toe", "right_small_toe", "left_heel", "right_heel"]  # fmt: skip
    assert skeleton_from_joint_names(mmpose_halpe) == SKELETONS["halpe26"]
    assert skeleton_from_joint_names(list(SKELETONS["body25"].joints)) == SKELETONS["body25"]
    assert skeleton_from_joint_names(["nose"] * 17) is None


def test_derived_joint_missing_when_a_source_is_missing_or_nan() -> None:
    body25, h36m = SKELETONS["body25"], SKELETONS["h36m17"]
    points = np.arange(3 * 25 * 2, dtype=np.float64).reshape(3, 25, 2)
    conf = np.full((3, 25), 0.9)
    conf[0, body25.index("left_eye")] = 0.4
    conf[1, body25.index("right_eye")] = 0.0
    points[2, body25.index("right_eye")] = np.nan  # NaN with a confidence: still missing, never a position
    out, out_conf = convert_points(points, conf, body25, h36m)
    head = h36m.index("head")
    assert out_conf[0, head] == 0.4 and np.isfinite(out[0, head]).all()
    for n in (1, 2):
        assert out_conf[n, head] == 0.0 and np.isnan(out[n, head]).all()
    assert (out_conf[:, h36m.index("pelvis")] == 0.9).all()


SYRIP_DIR = Path(__file__).resolve().parents[3] / "shared" / "data" / "syrip"


@pytest.mark.skipif(not (SYRIP_DIR / "keypoints2d_gt_real700.json").exists(), reason="SyRIP data not here")
def test_body25_and_body25b_told_apart_on_real_infant_poses() -> None:
    """SyRIP's 700 real infant images (2D ground truth), written as BODY_25 (its neck and mid-hip
    moved by 10 % of the shoulder / hip width, as a detector places them) and as BODY_25B."""
    from zedo_cli.formats import read_keypoints

    kp = read_keypoints(SYRIP_DIR / "keypoints2d_gt_real700.json")
    rng = np.random.default_rng(0)
    for name in ("body25", "body25b"):
        xy, conf = convert_points(kp.xy, kp.confidence, kp.skeleton, SKELETONS[name])
        if name == "body25":
            for joint, (a, b) in ((1, (2, 5)), (8, (9, 12))):
                width = np.linalg.norm(xy[:, a] - xy[:, b], axis=-1)[:, None]
                xy[:, joint] += rng.normal(0.0, 0.1, (len(xy), 2)) * width
        assert body25_variant(xy, conf)[0] == name
        single = [body25_variant(xy[i : i + 1], conf[i : i + 1])[0] for i in range(0, len(xy), 7)]
        assert all(d in (name, None) for d in single) and single.count(name) > 0.7 * len(single)
