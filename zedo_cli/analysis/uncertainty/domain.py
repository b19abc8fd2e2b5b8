"""Whether a clip is like the clips the calibrations were fitted on: where it is not, no calibrated interval is
stated for it, and every measure says why (`outside calibration: ...`).

The check: the infant's trunk in the image. The calibration clips show the trunk (hips' midpoint to shoulders'
midpoint, in the input's 2D) within 69 degrees of the image's up in every clip (the median over its frames); an
infant filmed upside down or lying across the image beyond `MAX_TRUNK_TILT_DEG` is outside them (docs/clinical.md,
"Outside calibration").
"""

from __future__ import annotations

import warnings

import numpy as np

from ...formats.readers.result_record import ResultPoses
from .calibration import Assignment

MAX_TRUNK_TILT_DEG = 90.0
OUTSIDE = "outside calibration"


def trunk_tilt_deg(xy: np.ndarray, joints: tuple[str, ...]) -> np.ndarray:
    """`(M,)` the angle in degrees between the image's up and the trunk (hips' midpoint to shoulders' midpoint) of
    pixels `xy (M, J, 2)`; NaN where a hip or shoulder is missing."""
    at = {n: joints.index(n) for n in ("left_hip", "right_hip", "left_shoulder", "right_shoulder")}
    up = (xy[:, at["left_shoulder"]] + xy[:, at["right_shoulder"]] - xy[:, at["left_hip"]] - xy[:, at["right_hip"]]) / 2
    return np.abs(np.degrees(np.arctan2(up[:, 0], -up[:, 1])))


def outside_calibration(result: ResultPoses, index: np.ndarray) -> np.ndarray:
    """`(M,)` per analysed pose `index` why its track lies outside the calibration clips ("" where it does not, or
    where the result has no 2D to tell)."""
    why = np.full(len(index), "", dtype=object)
    joints = result.skeleton.joints
    if result.keypoints_2d is None or not {"left_hip", "right_shoulder"} <= set(joints):
        return why
    tilt = trunk_tilt_deg(result.keypoints_2d[index], joints)
    for p in np.unique(result.person[index]):
        mine = result.person[index] == p
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # a track without a hip or shoulder seen: no check
            median = float(np.nanmedian(tilt[mine]))
        if median > MAX_TRUNK_TILT_DEG:
            why[mine] = (f"{OUTSIDE}: the infant's trunk points {median:.0f} deg from the image's up (median over the "
                         f"track), the calibration clips' within {MAX_TRUNK_TILT_DEG:g} deg: turn the video so that "
                         "the head is up")  # fmt: skip
    return why


def without_outside(assignment: Assignment, outside: np.ndarray) -> Assignment:
    """`assignment` with the poses whose `outside (M,)` reason is set given no calibration, and that reason."""
    moved = (outside != "") & (assignment.index >= 0)
    if not moved.any():
        return assignment
    return Assignment(assignment.calibrations, np.where(moved, -1, assignment.index),
                      np.where(moved, outside, assignment.why_not))  # fmt: skip
