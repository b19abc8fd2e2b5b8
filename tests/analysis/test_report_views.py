"""The skeleton views of the `zedo analyze` report: the mirrored right limbs and the view's size."""

from __future__ import annotations

import numpy as np
import pytest
from analysis_poses import SKEL, set_limb, standing, to_array

from zedo_cli.analysis.report.report import _mirrored_segments, _view_half_width


def test_the_mirrored_right_limbs_of_a_symmetric_pose_are_the_left_limbs() -> None:
    pts = standing()
    for side in ("left", "right"):
        set_limb(pts, side, "leg", 35.0, 20.0, bend=50.0)
        set_limb(pts, side, "arm", 120.0, 40.0, bend=70.0)
    segments = _mirrored_segments(to_array(pts), SKEL)
    left = [("shoulder", "elbow"), ("elbow", "wrist"), ("hip", "knee"), ("knee", "ankle")]
    expected = np.array([[pts[f"left_{a}"], pts[f"left_{b}"]] for a, b in left])
    assert segments == pytest.approx(expected, abs=1e-9)


def test_the_view_holds_mirrored_limbs_that_reach_beyond_the_pose() -> None:
    # a jumbled pose (seed 13) whose mirrored limbs reach 25 % further out than any joint: a limb
    # mirrored through a tilted mid-plane can swing from the depth axis into the image plane
    pose = to_array(standing()) + np.random.default_rng(13).normal(0.0, 0.1, (12, 3))
    mirrored = _mirrored_segments(pose, SKEL)
    assert np.abs(mirrored).max() > 1.2 * np.abs(pose).max()
    assert _view_half_width(pose, SKEL) == pytest.approx(1.1 * np.abs(mirrored).max())
