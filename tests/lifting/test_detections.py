"""A detector's habits found before a track is lifted as one infant: left and right exchanged for a few
frames, and a joint jumping away; a clean track has neither."""

from __future__ import annotations

import numpy as np
from helpers import project_poses, synthetic_poses

from zedo_cli.data.skeleton import get_skeleton
from zedo_cli.lifting.clip import limb_parents
from zedo_cli.lifting.detections import find_outliers, find_swaps, fix_detections

FLIP = get_skeleton("syrip12").flip_permutation
WRIST = get_skeleton("syrip12").index("left_wrist")
PARENTS = limb_parents(get_skeleton("syrip12"))


def _track(n: int = 90, seed: int = 0) -> np.ndarray:
    """Pixels `(n, 12, 2)` of a pose turning slowly, 1 px noise."""
    base = synthetic_poses(1, seed=3)[0]
    ang = np.linspace(-0.4, 0.4, n)
    c, s = np.cos(ang), np.sin(ang)
    rot = np.zeros((n, 3, 3))
    rot[:, 0, 0], rot[:, 0, 2], rot[:, 1, 1], rot[:, 2, 0], rot[:, 2, 2] = c, s, 1.0, -s, c
    return project_poses(base @ rot.transpose(0, 2, 1)) + np.random.default_rng(seed).normal(0, 1.0, (n, 12, 2))


def test_frames_with_left_and_right_exchanged_are_found_and_corrected() -> None:
    clean = _track()
    assert not find_swaps(clean, FLIP).any()
    swapped = clean.copy()
    swapped[30:36] = swapped[30:36][:, FLIP]
    swapped[70:72] = swapped[70:72][:, FLIP]
    swapped[50, 3] = np.nan  # a missing joint does not confuse it
    found = find_swaps(swapped, FLIP)
    assert found[30:36].all() and found[70:72].all() and found.sum() == 8
    fixed, conf, fixes = fix_detections(swapped, np.ones((90, 12)), FLIP, 30.0, [np.arange(90)], PARENTS)
    assert (fixes.swapped == found).all()
    np.testing.assert_allclose(fixed[30:36], clean[30:36])


def test_a_joint_that_jumps_away_is_dropped_and_a_clean_track_keeps_every_joint() -> None:
    clean = _track()
    assert not find_outliers(clean, 30.0, PARENTS).any()
    jumped = clean.copy()
    jumped[40:52, WRIST] = clean[40, WRIST] + np.array([90.0, -60.0])  # held at an adult's hand for 12 frames
    found = find_outliers(jumped, 30.0, PARENTS)
    assert found[40:52, WRIST].all() and found.sum() == 12
    fixed, conf, fixes = fix_detections(jumped, np.ones((90, 12)), FLIP, 30.0, [np.arange(90)], PARENTS)
    assert np.isnan(fixed[40:52, WRIST]).all() and (conf[40:52, WRIST] == 0).all() and fixes.outliers.sum() == 12


def test_a_lost_stretch_is_a_gap_not_a_habit() -> None:
    lost = _track()
    lost[20:40] = np.nan
    assert not find_swaps(lost, FLIP).any() and not find_outliers(lost, 30.0, PARENTS).any()
