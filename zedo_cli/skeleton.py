"""Named joint sets and conversions between them, by joint name.

This is the only module where joint indices are written. Every other module asks a
`Skeleton` for names, bones, root rule and left/right pairs.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .errors import ConfigError


@dataclass(frozen=True)
class Skeleton:
    """A joint set: ordered joint names, bones as index pairs, and the root rule.

    The root point of a pose is the mean of the `root` joints (e.g. the hip midpoint for
    `syrip12`, the pelvis joint for `h36m17`).
    """

    name: str
    joints: tuple[str, ...]
    bones: tuple[tuple[int, int], ...]
    root: tuple[str, ...]

    @property
    def num_joints(self) -> int:
        return len(self.joints)

    def index(self, joint: str) -> int:
        return self.joints.index(joint)

    @property
    def root_indices(self) -> list[int]:
        return [self.index(j) for j in self.root]

    @property
    def flip_permutation(self) -> list[int]:
        """Index permutation that swaps every left joint with its right twin."""
        perm = []
        for joint in self.joints:
            if joint.startswith("left_"):
                twin = "right_" + joint[len("left_") :]
            elif joint.startswith("right_"):
                twin = "left_" + joint[len("right_") :]
            else:
                twin = joint
            perm.append(self.index(twin))
        return perm


def _bones(joints: tuple[str, ...], pairs: list[tuple[str, str]]) -> tuple[tuple[int, int], ...]:
    return tuple((joints.index(a), joints.index(b)) for a, b in pairs)


_H36M17_JOINTS = (
    "pelvis", "right_hip", "right_knee", "right_ankle", "left_hip", "left_knee", "left_ankle",
    "spine", "thorax", "neck", "head", "left_shoulder", "left_elbow", "left_wrist",
    "right_shoulder", "right_elbow", "right_wrist",
)  # fmt: skip
_LIMBS = [
    ("right_hip", "right_knee"), ("right_knee", "right_ankle"),
    ("left_hip", "left_knee"), ("left_knee", "left_ankle"),
    ("left_shoulder", "left_elbow"), ("left_elbow", "left_wrist"),
    ("right_shoulder", "right_elbow"), ("right_elbow", "right_wrist"),
]  # fmt: skip

# H36M order without pelvis, spine, thorax, neck and head: the paper's SyRIP-12 order.
_SYRIP12_JOINTS = tuple(
    j for j in _H36M17_JOINTS if j not in ("pelvis", "spine", "thorax", "neck", "head")
)
_COCO17_JOINTS = (
    "nose", "left_eye", "right_eye", "left_ear", "right_ear", "left_shoulder", "right_shoulder",
    "left_elbow", "right_elbow", "left_wrist", "right_wrist", "left_hip", "right_hip",
    "left_knee", "right_knee", "left_ankle", "right_ankle",
)  # fmt: skip
# SyRIP's 3D order (LSP-14), as in Infant-Postural-Symmetry's correct_3D.npy.
_LSP14_JOINTS = (
    "right_ankle", "right_knee", "right_hip", "left_hip", "left_knee", "left_ankle",
    "right_wrist", "right_elbow", "right_shoulder", "left_shoulder", "left_elbow", "left_wrist",
    "neck", "head",
)  # fmt: skip

SKELETONS: dict[str, Skeleton] = {
    "h36m17": Skeleton(
        "h36m17",
        _H36M17_JOINTS,
        _bones(
            _H36M17_JOINTS,
            [("pelvis", "right_hip"), ("pelvis", "left_hip"), ("pelvis", "spine"),
             ("spine", "thorax"), ("thorax", "neck"), ("neck", "head"),
             ("thorax", "left_shoulder"), ("thorax", "right_shoulder"), *_LIMBS],
        ),  # fmt: skip
        ("pelvis",),
    ),
    "syrip12": Skeleton(
        "syrip12",
        _SYRIP12_JOINTS,
        _bones(
            _SYRIP12_JOINTS,
            [("right_hip", "left_hip"), ("right_shoulder", "left_shoulder"),
             ("right_hip", "right_shoulder"), ("left_hip", "left_shoulder"), *_LIMBS],
        ),  # fmt: skip
        ("right_hip", "left_hip"),
    ),
    "coco17": Skeleton(
        "coco17",
        _COCO17_JOINTS,
        _bones(
            _COCO17_JOINTS,
            [("left_hip", "right_hip"), ("left_shoulder", "right_shoulder"),
             ("left_hip", "left_shoulder"), ("right_hip", "right_shoulder"),
             ("nose", "left_eye"), ("nose", "right_eye"), ("left_eye", "left_ear"),
             ("right_eye", "right_ear"), *_LIMBS],
        ),  # fmt: skip
        ("right_hip", "left_hip"),
    ),
    "lsp14": Skeleton(
        "lsp14",
        _LSP14_JOINTS,
        _bones(_LSP14_JOINTS, [("neck", "head"), *_LIMBS]),
        ("right_hip", "left_hip"),
    ),
}

# Joints that a source skeleton lacks but can derive as the mean of others it has.
# A derived joint is missing when any of its sources is (FORMATS.md 3.4).
DERIVED_JOINTS: dict[str, tuple[str, ...]] = {
    "pelvis": ("left_hip", "right_hip"),
    "thorax": ("left_shoulder", "right_shoulder"),
    "spine": ("left_hip", "right_hip", "left_shoulder", "right_shoulder"),
    "head": ("left_eye", "right_eye"),
}
# Joints taken from a differently named joint when the source lacks the exact one
# (COCO has no neck base; MMPose and MotionBERT use the nose for H36M joint 9).
ALIASES: dict[str, str] = {"neck": "nose"}


def get_skeleton(name: str) -> Skeleton:
    try:
        return SKELETONS[name]
    except KeyError:
        known = ", ".join(sorted(SKELETONS))
        raise ConfigError(f"unknown skeleton {name!r}; known skeletons: {known}") from None


def conversion_sources(src: Skeleton, dst: Skeleton) -> list[list[int]]:
    """For each joint of `dst`, the indices of `src` whose mean gives it.

    An empty list means `dst` joint cannot be obtained from `src` at all.
    """
    sources: list[list[int]] = []
    for joint in dst.joints:
        if joint in src.joints:
            sources.append([src.index(joint)])
        elif joint in DERIVED_JOINTS and all(j in src.joints for j in DERIVED_JOINTS[joint]):
            sources.append([src.index(j) for j in DERIVED_JOINTS[joint]])
        elif joint in ALIASES and ALIASES[joint] in src.joints:
            sources.append([src.index(ALIASES[joint])])
        else:
            sources.append([])
    return sources


def convert_points(
    points: np.ndarray, confidence: np.ndarray, src: Skeleton, dst: Skeleton
) -> tuple[np.ndarray, np.ndarray]:
    """Convert points `(..., J_src, D)` with confidences `(..., J_src)` to the `dst` joint set.

    A derived joint is the mean of its sources, with the lowest source confidence; it is
    missing (NaN, confidence 0) when any source is missing (confidence 0) or unavailable.
    """
    if points.shape[-2] != src.num_joints:
        raise ConfigError(
            f"expected {src.num_joints} joints for skeleton {src.name}, got {points.shape[-2]}"
        )
    lead = points.shape[:-2]
    out = np.full((*lead, dst.num_joints, points.shape[-1]), np.nan, dtype=np.float64)
    out_conf = np.zeros((*lead, dst.num_joints), dtype=np.float64)
    for j, idx in enumerate(conversion_sources(src, dst)):
        if not idx:
            continue
        conf = confidence[..., idx].min(axis=-1)
        present = conf > 0
        mean = points[..., idx, :].mean(axis=-2)
        out[..., j, :] = np.where(present[..., None], mean, np.nan)
        out_conf[..., j] = np.where(present, conf, 0.0)
    return out, out_conf


def root_point(points: np.ndarray, skeleton: Skeleton) -> np.ndarray:
    """Root point `(..., D)` of points `(..., J, D)`: the mean of the skeleton's root joints."""
    return points[..., skeleton.root_indices, :].mean(axis=-2)


def center_on_root(points: np.ndarray, skeleton: Skeleton) -> np.ndarray:
    """Points `(..., J, D)` translated so that the skeleton's root point is the origin."""
    return points - root_point(points, skeleton)[..., None, :]
