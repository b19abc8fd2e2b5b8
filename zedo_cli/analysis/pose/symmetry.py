"""Postural symmetry of four segment pairs (Huang, Wan, Luan, Tunik, Ostadabbas, "Computer Vision
to the Rescue: Infant Postural Symmetry Estimation from Incongruent Annotations", 2022).

For each pair (upper arm: shoulder -> elbow, forearm: elbow -> wrist, thigh: hip -> knee, shank:
knee -> ankle) the right segment is mirrored through the plane that passes through the midpoint
of the two shoulders (arms) or hips (legs), with its normal along the right-to-left shoulder
(hip) vector; the symmetry angle is the angle, in degrees, between the left segment and the
mirrored right one. A mirror image of a pose gives 0. Swapping left and right gives the same
angle (the reflection is its own inverse and orthogonal, and the normal only changes sign).

The plane's position does not matter for a segment's direction (the offset cancels in the
difference of two mirrored points), so only the normal is computed.

The call: symmetric when the angle is at most the threshold (default 28 degrees, the paper's 3D
threshold, chosen there by agreement with 10 human raters), else asymmetric; with a 90 %
interval, "uncertain" when the interval straddles the threshold. The paper's bands: 1 (< 30),
2 (30 to < 60), 3 (>= 60 degrees).

Deviation from the published code (measure_3d_*.py of Infant-Postural-Symmetry): its shank
flag tests the thigh angle (`if leg1_ang <= thres` where `leg2_ang` is meant); here every
pair's call tests its own angle.
"""

from __future__ import annotations

import numpy as np

from ...data.skeleton import Skeleton
from .geometry import angle_between_deg, joint, reflect, unit

DEFAULT_THRESHOLD_DEG = 28.0
BAND_EDGES_DEG = (30.0, 60.0)
# pair -> (proximal joint, distal joint, joint whose left/right pair sets the mirror plane)
PAIRS: dict[str, tuple[str, str, str]] = {
    "upper_arm": ("shoulder", "elbow", "shoulder"),
    "forearm": ("elbow", "wrist", "shoulder"),
    "thigh": ("hip", "knee", "hip"),
    "shank": ("knee", "ankle", "hip"),
}
SYMMETRY_JOINTS = tuple(
    f"{side}_{j}" for side in ("left", "right") for j in ("shoulder", "elbow", "wrist", "hip", "knee", "ankle")
)
CALLS = ("symmetric", "asymmetric", "uncertain")


def measure_name(pair: str) -> str:
    """`symmetry_upper_arm_deg` etc.: the measure's name in every output."""
    return f"symmetry_{pair}_deg"


def symmetry_angles(poses: np.ndarray, skeleton: Skeleton) -> dict[str, np.ndarray]:
    """Symmetry angle per pair: poses `(..., J, 3)` -> `{measure_name(pair): (...)}` degrees in [0, 180]."""
    out: dict[str, np.ndarray] = {}
    for pair, (a, b, base) in PAIRS.items():
        normal = unit(joint(poses, skeleton, f"left_{base}") - joint(poses, skeleton, f"right_{base}"))
        left = joint(poses, skeleton, f"left_{b}") - joint(poses, skeleton, f"left_{a}")
        right = joint(poses, skeleton, f"right_{b}") - joint(poses, skeleton, f"right_{a}")
        out[measure_name(pair)] = angle_between_deg(left, reflect(right, normal))
    return out


def symmetry_call(value: float, threshold: float, low: float = np.nan, high: float = np.nan) -> str:
    """symmetric / asymmetric, or uncertain when a known 90 % interval straddles `threshold`;
    "" for an unknown value."""
    if not np.isfinite(value):
        return ""
    if np.isfinite(low) and np.isfinite(high):
        if high <= threshold:
            return "symmetric"
        if low > threshold:
            return "asymmetric"
        return "uncertain"
    return "symmetric" if value <= threshold else "asymmetric"


def symmetry_calls(values: np.ndarray, threshold: float, low: np.ndarray, high: np.ndarray) -> np.ndarray:
    """`symmetry_call` of each value `(M,)` that has a known `low` end, "uncertain" where it has none, "" where
    the value is unknown: the frame rows' calls (object array)."""
    values, low, high = (np.asarray(x, dtype=float) for x in (values, low, high))
    known, bounded = np.isfinite(values), np.isfinite(low)
    both = bounded & np.isfinite(high)
    out = np.full(values.shape, "", dtype=object)
    out[known] = "uncertain"
    with np.errstate(invalid="ignore"):
        by_value = known & bounded & ~both
        out[by_value] = np.where(values[by_value] <= threshold, "symmetric", "asymmetric")
        out[known & both & (low > threshold)] = "asymmetric"
        out[known & both & (high <= threshold)] = "symmetric"  # as symmetry_call: the high end decides first
    return out


def symmetry_bands(values: np.ndarray) -> np.ndarray:
    """`symmetry_band` of each value: 1, 2, 3 (floats), NaN where unknown."""
    values = np.asarray(values, dtype=float)
    with np.errstate(invalid="ignore"):
        bands = 1.0 + sum((values >= edge).astype(float) for edge in BAND_EDGES_DEG)
    return np.where(np.isfinite(values), bands, np.nan)


def symmetry_band(value: float) -> float:
    """The paper's band: 1 below 30 degrees, 2 from 30 to below 60, 3 from 60; NaN if unknown."""
    if not np.isfinite(value):
        return np.nan
    return float(1 + sum(value >= edge for edge in BAND_EDGES_DEG))
