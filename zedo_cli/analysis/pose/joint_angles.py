"""Joint angles in degrees, with the conventions of docs/clinical.md.

- Knee and elbow flexion: the angle between the proximal segment (hip -> knee, shoulder ->
  elbow) and the distal one (knee -> ankle, elbow -> wrist): 0 = straight, 90 = right angle.
- Hip and shoulder flexion and abduction, relative to a trunk frame built from the hips and
  shoulders (origin irrelevant):
    up        u = unit(shoulder midpoint - hip midpoint)                (cranial)
    left      l = unit(w - (w.u) u), w = unit(L hip - R hip) + unit(L shoulder - R shoulder)
    anterior  a = l x u                                                 (ventral, the front)
  For the thigh (hip -> knee) or the upper arm (shoulder -> elbow), unit direction d:
    flexion   = atan2(d.a, -d.u): the angle of d's projection on the sagittal plane (u, a) from
                straight down the trunk (-u), positive towards the front; 0 = segment along the
                trunk, 90 = pointing forward, 180 = overhead; negative = extension (behind the
                trunk). Range [-90, 270) so that arms overhead do not jump between +-180.
                Undefined (NaN) when d is within 10 degrees of the left-right axis (abduction
                beyond 80 degrees), where the sagittal projection has no direction.
    abduction = asin(s d.l), s = +1 for the left limb and -1 for the right: the angle out of the
                sagittal plane, positive away from the midline, negative = adduction (across it).
  The frame is the infant's own, so the measures do not change when the whole body turns
  (lying supine or prone, or seen from any camera).
"""

from __future__ import annotations

import numpy as np

from ...data.skeleton import Skeleton
from .geometry import angle_between_deg, joint, unit

SIDES = ("left", "right")
# measure base name -> (proximal joint, middle joint, distal joint)
_FLEXION = {"knee_flexion": ("hip", "knee", "ankle"), "elbow_flexion": ("shoulder", "elbow", "wrist")}
# measure base name prefix -> (proximal joint, distal joint)
_TRUNK_LIMBS = {"hip": ("hip", "knee"), "shoulder": ("shoulder", "elbow")}
ANGLE_BASES = (
    "hip_flexion",
    "hip_abduction",
    "knee_flexion",
    "shoulder_flexion",
    "shoulder_abduction",
    "elbow_flexion",
)
FLEXION_UNDEFINED_DEG = 80.0  # beyond this abduction, flexion is NaN
FLEXION_RANGE_DEG = (-90.0, 270.0)  # hip and shoulder flexion: [-90, 270), wrapping at 90 degrees of extension


def angle_name(side: str, base: str) -> str:
    """`left_knee_flexion_deg` etc.: the measure's name in every output."""
    return f"{side}_{base}_deg"


ANGLE_NAMES = tuple(angle_name(side, base) for base in ANGLE_BASES for side in SIDES)
# Angles on a circle (their differences wrap at 360 degrees): the hip and shoulder flexions.
CIRCULAR_ANGLES = tuple(angle_name(side, f"{b}_flexion") for b in _TRUNK_LIMBS for side in SIDES)


def trunk_frame(poses: np.ndarray, skeleton: Skeleton) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Unit axes (up, left, anterior), each `(..., 3)`, of the trunk frame of poses `(..., J, 3)`."""
    mid_hip = (joint(poses, skeleton, "left_hip") + joint(poses, skeleton, "right_hip")) / 2
    mid_sh = (joint(poses, skeleton, "left_shoulder") + joint(poses, skeleton, "right_shoulder")) / 2
    up = unit(mid_sh - mid_hip)
    w = unit(joint(poses, skeleton, "left_hip") - joint(poses, skeleton, "right_hip")) + unit(
        joint(poses, skeleton, "left_shoulder") - joint(poses, skeleton, "right_shoulder")
    )
    left = unit(w - (w * up).sum(-1, keepdims=True) * up)
    return up, left, np.cross(left, up)


def joint_angles(poses: np.ndarray, skeleton: Skeleton) -> dict[str, np.ndarray]:
    """Every angle of ANGLE_NAMES: poses `(..., J, 3)` -> `{name: (...)}` degrees."""
    out: dict[str, np.ndarray] = {}
    up, left_axis, anterior = trunk_frame(poses, skeleton)
    for side in SIDES:
        s = 1.0 if side == "left" else -1.0
        for base, (a, b) in _TRUNK_LIMBS.items():
            d = unit(joint(poses, skeleton, f"{side}_{b}") - joint(poses, skeleton, f"{side}_{a}"))
            lateral = s * (d * left_axis).sum(-1)
            abduction = np.degrees(np.arcsin(np.clip(lateral, -1.0, 1.0)))
            flexion = np.degrees(np.arctan2((d * anterior).sum(-1), -(d * up).sum(-1)))
            flexion = np.where(flexion < -90.0, flexion + 360.0, flexion)  # [-90, 270)
            with np.errstate(invalid="ignore"):
                flexion = np.where(np.abs(abduction) > FLEXION_UNDEFINED_DEG, np.nan, flexion)
            out[angle_name(side, f"{base}_flexion")] = flexion
            out[angle_name(side, f"{base}_abduction")] = abduction
        for base, (a, m, b) in _FLEXION.items():
            pa, pm, pb = (joint(poses, skeleton, f"{side}_{x}") for x in (a, m, b))
            out[angle_name(side, base)] = angle_between_deg(pm - pa, pb - pm)
    return {name: out[name] for name in ANGLE_NAMES}
