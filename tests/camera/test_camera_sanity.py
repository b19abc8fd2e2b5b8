"""Camera sanity: implausible distances and keypoints outside the image are flagged, nothing else."""

from __future__ import annotations

import numpy as np

from zedo_cli.camera.sanity import MAX_DEPTH_M, MIN_DEPTH_M, OUTSIDE_MARGIN, check_camera_sanity


def test_distance_bounds_and_outside_margin() -> None:
    xy = np.full((5, 3, 2), 100.0)
    xy[3, 1] = [640 * (1 + OUTSIDE_MARGIN) + 1, 100]  # beyond the margin
    xy[4, 1] = [-0.5 * OUTSIDE_MARGIN * 640, 100]  # outside the image, within the margin
    observed = np.ones((5, 3), dtype=bool)
    sizes = np.tile([640.0, 480.0], (5, 1))
    depth = [1.0, MAX_DEPTH_M + 65, MIN_DEPTH_M / 2, 2.0, 2.0]
    roots = np.c_[np.zeros(5), np.zeros(5), depth]
    lifted = np.ones(5, dtype=bool)
    sanity = check_camera_sanity(xy, observed, sizes, roots, lifted)
    assert [sanity.flags(i) for i in range(5)] == [
        [], ["implausible_distance: 75.0 m"], ["implausible_distance: 0.1 m"],
        ["keypoints_outside_image: 1 joint(s)"], [],
    ]  # fmt: skip
    assert len(sanity.warnings()) == 2 and "2 lifted instances flagged implausible_distance" in sanity.warnings()[0]


def test_unknown_size_unobserved_joints_and_unlifted_are_not_flagged() -> None:
    xy = np.full((2, 2, 2), 5000.0)
    observed = np.array([[False, False], [True, True]])
    sizes = np.array([[640.0, 480.0], [np.nan, np.nan]])
    roots = np.array([[0, 0, 50.0], [np.nan, np.nan, np.nan]])
    sanity = check_camera_sanity(xy, observed, sizes, roots, np.array([False, False]))
    assert sanity.flags(0) == [] and sanity.flags(1) == [] and sanity.warnings() == []
