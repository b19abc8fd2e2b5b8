"""Constructed syrip12 poses with known angles, for the tests of `zedo analyze`.

The standing pose faces the camera (OpenCV camera axes: x right, y down, z forward): the
infant's left is +x, up is -y, the front (anterior) is -z. Arms hang along the trunk, legs
are straight: every joint angle is 0 and the pose is mirror-symmetric about x = 0.
"""

from __future__ import annotations

import numpy as np

from zedo_cli.data.skeleton import get_skeleton

SKEL = get_skeleton("syrip12")
UP, LEFT, FRONT = np.array([0.0, -1.0, 0.0]), np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, -1.0])
THIGH, SHANK, UPPER_ARM, FOREARM = 0.1, 0.1, 0.08, 0.07
HIP_HALF, SHOULDER_HALF, TRUNK = 0.05, 0.06, 0.2


def standing() -> dict[str, np.ndarray]:
    pts: dict[str, np.ndarray] = {}
    for side, s in (("left", 1.0), ("right", -1.0)):
        hip = s * HIP_HALF * LEFT
        pts[f"{side}_hip"] = hip
        pts[f"{side}_knee"] = hip - THIGH * UP
        pts[f"{side}_ankle"] = hip - (THIGH + SHANK) * UP
        sh = s * SHOULDER_HALF * LEFT + TRUNK * UP
        pts[f"{side}_shoulder"] = sh
        pts[f"{side}_elbow"] = sh - UPPER_ARM * UP
        pts[f"{side}_wrist"] = sh - (UPPER_ARM + FOREARM) * UP
    return pts


def to_array(pts: dict[str, np.ndarray]) -> np.ndarray:
    """`(12, 3)` in the syrip12 order."""
    return np.array([pts[j] for j in SKEL.joints], dtype=float)


def direction(flexion_deg: float, abduction_deg: float, side: str) -> np.ndarray:
    """Unit vector of a segment with this flexion (from straight down, towards the front) and
    abduction (away from the midline) in the standing pose's trunk frame."""
    f, a = np.radians(flexion_deg), np.radians(abduction_deg)
    s = 1.0 if side == "left" else -1.0
    return np.cos(a) * (-np.cos(f) * UP + np.sin(f) * FRONT) + np.sin(a) * s * LEFT


def set_limb(pts: dict[str, np.ndarray], side: str, limb: str, flexion: float, abduction: float,
             bend: float = 0.0) -> None:  # fmt: skip
    """Place the `limb` ("leg" or "arm") of `side` with the proximal segment at (flexion,
    abduction) and the distal one turned `bend` degrees from it, towards increasing flexion
    (so the knee / elbow flexion is `bend`)."""
    root, mid, end = ("hip", "knee", "ankle") if limb == "leg" else ("shoulder", "elbow", "wrist")
    a, b = (THIGH, SHANK) if limb == "leg" else (UPPER_ARM, FOREARM)
    start = pts[f"{side}_{root}"]
    pts[f"{side}_{mid}"] = start + a * direction(flexion, abduction, side)
    f = np.radians(flexion)
    along = np.sin(f) * UP + np.cos(f) * FRONT  # unit, perpendicular to the proximal direction
    d = direction(flexion, abduction, side)
    pts[f"{side}_{end}"] = pts[f"{side}_{mid}"] + b * (np.cos(np.radians(bend)) * d + np.sin(np.radians(bend)) * along)


def rotation(axis: np.ndarray, angle_deg: float) -> np.ndarray:
    """Rodrigues: the rotation matrix about `axis` by `angle_deg`."""
    k = np.asarray(axis, float) / np.linalg.norm(axis)
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    t = np.radians(angle_deg)
    return np.eye(3) + np.sin(t) * kx + (1 - np.cos(t)) * kx @ kx


def random_rigid(pose: np.ndarray, seed: int) -> np.ndarray:
    """`pose (J, 3)` turned by a random rotation and moved by a random translation."""
    rng = np.random.default_rng(seed)
    r = rotation(rng.normal(size=3), rng.uniform(0, 360))
    return pose @ r.T + rng.normal(size=3)
