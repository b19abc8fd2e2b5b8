"""The published clip statistics (Chambers et al. 2020) on angles that only 3D gives, and the mean 3D
dispersion of the hands and feet: the `3d_` features of `zedo analyze` (docs/movement.md).

    f = features_3d(poses, skeleton, fps)     # poses (T, J, 3) by frame 0..T-1, NaN where not lifted
    f.values["3d_mean_angle_LKnee"], f.values["3d_median_vel_angle_RHipFlexion"], f.reasons[name]

Steps, as the 2D features take them (`published_features`): every coordinate of every joint
interpolated over gaps, then a centred rolling median and mean of int(0.5 fps) frames; per frame:

- `LElbow`, `RElbow`, `LKnee`, `RKnee`: the interior angle at the joint between the directions to the
  proximal and the distal joint (shoulder and wrist, hip and ankle), 0-180 degrees, 180 = straight: the
  convention of the published 2D elbow and knee angle, so the 2D and 3D features compare directly;
- `LHipFlexion`, `LHipAbduction`, `LShoulderFlexion`, `LShoulderAbduction` (and R): the thigh's and the
  upper arm's flexion and abduction in zedo's trunk frame (`joint_angles`: flexion from straight down
  the trunk, positive forward, in [-90, 270), undefined beyond 80 degrees of abduction; abduction
  positive away from the midline);

then per angle the rows (frames) where it is known and the published statistics of them
(`published_features.angle_statistics`: mean_angle, stdev_angle, entropy_angle, median_vel_angle,
IQR_vel_angle, IQR_acc_angle); `3d_lrCorr_angle_<part>`: Pearson's r of the left and right angle over the
frames where both are known (paired by frame, not by position as the published 2D code pairs them);

- `3d_mean_dispersion_<LWrist|RWrist|LAnkle|RAnkle>`: the mean Euclidean distance of the joint's
  trunk-normalised position from its clip centroid. The position is taken from the shoulders' midpoint
  (wrists) or the hips' midpoint (ankles), expressed in the trunk frame (up, left, anterior) and divided
  by the trunk length (hip midpoint to shoulder midpoint), so it is free of where the infant lies, how it
  turns and how large it is (units: trunk lengths). After Soualmi et al. (EMBC 2023), whose exact
  definition could not be looked up here: this is the definition zedo computes.
"""

from __future__ import annotations

import numpy as np

from ...data.skeleton import Skeleton
from ...stats import pearson
from ..pose.geometry import angle_between_deg, joint
from ..pose.joint_angles import angle_name, joint_angles, trunk_frame
from .published_features import ANGLE_STATS, ClipFeatures, Windows, all_empty, angle_statistics, smooth_positions

PREFIX = "3d_"
_SIDE = {"L": "left", "R": "right"}
_INTERIOR = {"Elbow": ("shoulder", "elbow", "wrist"), "Knee": ("hip", "knee", "ankle")}
_TRUNK = {"HipFlexion": "hip_flexion", "HipAbduction": "hip_abduction", "ShoulderFlexion": "shoulder_flexion",
          "ShoulderAbduction": "shoulder_abduction"}  # fmt: skip
PARTS = (*_INTERIOR, *_TRUNK)  # Elbow, Knee, HipFlexion, HipAbduction, ShoulderFlexion, ShoulderAbduction
DISTAL = {"Wrist": ("wrist", "shoulder"), "Ankle": ("ankle", "hip")}  # joint, the girdle it is measured from


def angle_series_3d(poses: np.ndarray, skeleton: Skeleton) -> dict[str, np.ndarray]:
    """Per `<side><part>` (e.g. `LKnee`, `RHipFlexion`), the angle `(T,)` degrees of poses `(T, J, 3)`."""
    trunk = joint_angles(poses, skeleton)
    out = {}
    for s, side in _SIDE.items():
        for part, (a, m, b) in _INTERIOR.items():
            pa, pm, pb = (joint(poses, skeleton, f"{side}_{x}") for x in (a, m, b))
            out[s + part] = angle_between_deg(pa - pm, pb - pm)
        for part, base in _TRUNK.items():
            out[s + part] = trunk[angle_name(side, base)]
    return out


def dispersion(poses: np.ndarray, skeleton: Skeleton, side: str, part: str) -> float:
    """The mean 3D dispersion of one distal joint of poses `(T, J, 3)` (trunk lengths; NaN if never known)."""
    up, left, anterior = trunk_frame(poses, skeleton)  # (T, 3) each
    mid = {
        g: (joint(poses, skeleton, f"left_{g}") + joint(poses, skeleton, f"right_{g}")) / 2 for g in ("hip", "shoulder")
    }
    trunk = np.linalg.norm(mid["shoulder"] - mid["hip"], axis=-1)  # (T,)
    name, girdle = DISTAL[part]
    v = joint(poses, skeleton, f"{_SIDE[side]}_{name}") - mid[girdle]  # (T, 3)
    with np.errstate(invalid="ignore", divide="ignore"):
        c = np.stack([(v * ax).sum(-1) for ax in (up, left, anterior)], -1) / trunk[:, None]  # (T, 3)
    c = c[np.isfinite(c).all(-1)]
    if not len(c):
        return np.nan
    return float(np.linalg.norm(c - c.mean(0), axis=-1).mean())


def features_3d(poses: np.ndarray, skeleton: Skeleton, fps: float) -> ClipFeatures:
    """The `3d_` features of one person's clip: poses `(T, J, 3)` (any frame and unit; NaN where not lifted)."""
    windows = Windows(fps)
    if not windows.usable:
        return all_empty(features_3d(poses, skeleton, 30.0), windows.too_slow)
    smooth = smooth_positions(poses, windows)  # (T, J, 3)
    angles = angle_series_3d(smooth, skeleton)
    out = ClipFeatures()
    short = len(poses) < windows.frames_needed
    why = (f"the clip ({len(poses)} frames at {fps:g} fps) is too short for the published windows "
           f"({windows.describe()})" if short else "undefined for this clip (e.g. a constant series)")  # fmt: skip
    for bp in sorted(angles):
        rows = angles[bp][np.isfinite(angles[bp])]
        stats = angle_statistics(rows, fps, windows.delta)
        reason = why
        if not len(rows) and bp[1:] in ("HipFlexion", "ShoulderFlexion") and not short:
            reason = "flexion undefined in every frame (abduction beyond 80 degrees)"
        for stat, unit in ANGLE_STATS.items():
            out.add(f"{PREFIX}{stat}_{bp}", stats[stat], unit, reason)
    for part in PARTS:
        out.add(f"{PREFIX}lrCorr_angle_{part}", pearson(angles["L" + part], angles["R" + part]), "r", why)
    for part in DISTAL:
        for s in _SIDE:
            out.add(f"{PREFIX}mean_dispersion_{s}{part}", dispersion(smooth, skeleton, s, part), "trunk", why)
    return out
