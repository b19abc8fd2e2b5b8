"""Vector helpers shared by the measures: joints by name, angles between segments.

Every function takes poses `(..., J, 3)` in any unit (angles do not depend on it) and returns
degrees; a missing joint (NaN) or a zero-length segment gives NaN, never 0.
"""

from __future__ import annotations

import numpy as np

from ...data.skeleton import Skeleton
from ...errors import InputFormatError


def joint(poses: np.ndarray, skeleton: Skeleton, name: str) -> np.ndarray:
    """The points `(..., 3)` of joint `name`."""
    return poses[..., skeleton.index(name), :]


def require_joints(skeleton: Skeleton, names: tuple[str, ...], source: str) -> None:
    """Raise InputFormatError naming `source` when `skeleton` lacks any of `names`."""
    lacking = [n for n in names if n not in skeleton.joints]
    if lacking:
        raise InputFormatError(f"{source}: skeleton {skeleton.name} lacks the joint(s) {', '.join(lacking)} "
                               "that the measures need")  # fmt: skip


def unit(v: np.ndarray) -> np.ndarray:
    """`v / |v|` along the last axis; NaN where `|v|` is 0 or unknown."""
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(n > 1e-12, v / np.where(n > 0, n, 1.0), np.nan)


def angle_between_deg(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Angle in [0, 180] degrees between vectors `a` and `b` `(..., 3)`; atan2 of the cross and
    dot products, accurate near 0 and 180 where arccos is not."""
    ua, ub = unit(a), unit(b)
    return np.degrees(np.arctan2(np.linalg.norm(np.cross(ua, ub), axis=-1), (ua * ub).sum(-1)))


def reflect(v: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """Vectors `v (..., 3)` mirrored through a plane with unit `normal (..., 3)`: v - 2 (v.n) n."""
    return v - 2.0 * (v * normal).sum(-1, keepdims=True) * normal
