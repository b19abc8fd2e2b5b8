"""Named joint sets and conversions between them, by joint name.

This is the only module where joint indices are written. Every other module asks a
`Skeleton` for names, bones, root rule and left/right pairs.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ConfigError


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
_SYRIP12_JOINTS = tuple(j for j in _H36M17_JOINTS if j not in ("pelvis", "spine", "thorax", "neck", "head"))
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

# OpenPose BODY_25 (openpose:doc/02_output.md). OpenPose's "Neck" is the midpoint of the
# shoulders, which H36M calls the thorax, and its "MidHip" is H36M's pelvis (FORMATS.md 3.4), so
# they carry those names here and convert to h36m17 by name.
_BODY25_JOINTS = (
    "nose", "thorax", "right_shoulder", "right_elbow", "right_wrist", "left_shoulder", "left_elbow",
    "left_wrist", "pelvis", "right_hip", "right_knee", "right_ankle", "left_hip", "left_knee",
    "left_ankle", "right_eye", "left_eye", "right_ear", "left_ear", "left_big_toe", "left_small_toe",
    "left_heel", "right_big_toe", "right_small_toe", "right_heel",
)  # fmt: skip
# OpenPose's 18-joint "COCO" model: BODY_25 without the mid-hip and the feet, eyes and ears last.
_COCO18_JOINTS = (
    "nose", "thorax", "right_shoulder", "right_elbow", "right_wrist", "left_shoulder", "left_elbow",
    "left_wrist", "right_hip", "right_knee", "right_ankle", "left_hip", "left_knee", "left_ankle",
    "right_eye", "left_eye", "right_ear", "left_ear",
)  # fmt: skip
# OpenPose's experimental BODY_25B (openpose_train experimental_models, Pose2Sim's default model):
# COCO-17 in COCO's order, then the upper neck, the head top and the feet. It has no mid-hip and
# no neck at the shoulder midpoint, so it must never be read as BODY_25 (same joint count).
# Its head top is called "head", like Halpe's, and converts to the H36M head by name.
_BODY25B_JOINTS = (
    *_COCO17_JOINTS, "upper_neck", "head", "left_big_toe", "left_small_toe", "left_heel",
    "right_big_toe", "right_small_toe", "right_heel",
)  # fmt: skip
# Halpe-26 (AlphaPose, RTMPose "body with feet"): COCO-17, then head top, neck (= thorax), hip
# (= pelvis) and the feet (Fang-Haoshu/Halpe-FullBody README).
_HALPE26_JOINTS = (
    *_COCO17_JOINTS, "head", "thorax", "pelvis", "left_big_toe", "right_big_toe", "left_small_toe",
    "right_small_toe", "left_heel", "right_heel",
)  # fmt: skip
_FACE = [("nose", "left_eye"), ("nose", "right_eye"), ("left_eye", "left_ear"), ("right_eye", "right_ear")]
_FEET = [
    ("left_ankle", "left_heel"), ("left_ankle", "left_big_toe"), ("left_big_toe", "left_small_toe"),
    ("right_ankle", "right_heel"), ("right_ankle", "right_big_toe"), ("right_big_toe", "right_small_toe"),
]  # fmt: skip
_TRUNK = [
    ("thorax", "left_shoulder"), ("thorax", "right_shoulder"), ("thorax", "pelvis"),
    ("pelvis", "left_hip"), ("pelvis", "right_hip"), ("thorax", "nose"),
]  # fmt: skip

SKELETONS: dict[str, Skeleton] = {
    "h36m17": Skeleton(
        "h36m17",
        _H36M17_JOINTS,
        _bones(
            _H36M17_JOINTS,
            [
                ("pelvis", "right_hip"),
                ("pelvis", "left_hip"),
                ("pelvis", "spine"),
                ("spine", "thorax"),
                ("thorax", "neck"),
                ("neck", "head"),
                ("thorax", "left_shoulder"),
                ("thorax", "right_shoulder"),
                *_LIMBS,
            ],
        ),  # fmt: skip
        ("pelvis",),
    ),
    "syrip12": Skeleton(
        "syrip12",
        _SYRIP12_JOINTS,
        _bones(
            _SYRIP12_JOINTS,
            [
                ("right_hip", "left_hip"),
                ("right_shoulder", "left_shoulder"),
                ("right_hip", "right_shoulder"),
                ("left_hip", "left_shoulder"),
                *_LIMBS,
            ],
        ),  # fmt: skip
        ("right_hip", "left_hip"),
    ),
    "coco17": Skeleton(
        "coco17",
        _COCO17_JOINTS,
        _bones(
            _COCO17_JOINTS,
            [
                ("left_hip", "right_hip"),
                ("left_shoulder", "right_shoulder"),
                ("left_hip", "left_shoulder"),
                ("right_hip", "right_shoulder"),
                ("nose", "left_eye"),
                ("nose", "right_eye"),
                ("left_eye", "left_ear"),
                ("right_eye", "right_ear"),
                *_LIMBS,
            ],
        ),  # fmt: skip
        ("right_hip", "left_hip"),
    ),
    "lsp14": Skeleton(
        "lsp14",
        _LSP14_JOINTS,
        _bones(_LSP14_JOINTS, [("neck", "head"), *_LIMBS]),
        ("right_hip", "left_hip"),
    ),
    "body25": Skeleton(
        "body25", _BODY25_JOINTS, _bones(_BODY25_JOINTS, [*_TRUNK, *_FACE, *_FEET, *_LIMBS]), ("pelvis",)
    ),
    "coco18": Skeleton(
        "coco18",
        _COCO18_JOINTS,
        _bones(
            _COCO18_JOINTS,
            [
                ("thorax", "left_shoulder"),
                ("thorax", "right_shoulder"),
                ("thorax", "left_hip"),
                ("thorax", "right_hip"),
                ("thorax", "nose"),
                *_FACE,
                *_LIMBS,
            ],
        ),  # fmt: skip
        ("right_hip", "left_hip"),
    ),
    "body25b": Skeleton(
        "body25b",
        _BODY25B_JOINTS,
        _bones(
            _BODY25B_JOINTS,
            [
                ("left_hip", "right_hip"),
                ("left_shoulder", "right_shoulder"),
                ("left_hip", "left_shoulder"),
                ("right_hip", "right_shoulder"),
                ("upper_neck", "head"),
                *_FACE,
                *_FEET,
                *_LIMBS,
            ],
        ),  # fmt: skip
        ("right_hip", "left_hip"),
    ),
    "halpe26": Skeleton(
        "halpe26",
        _HALPE26_JOINTS,
        _bones(_HALPE26_JOINTS, [*_TRUNK, ("nose", "head"), *_FACE, *_FEET, *_LIMBS]),
        ("pelvis",),
    ),
}

# Joints that a source skeleton lacks but can derive as the mean of others it has, as
# alternatives in order of preference. A derived joint is missing when any of its sources is,
# with the lowest source confidence (FORMATS.md 3.4; MMPose and MotionBERT average the scores).
DERIVED_JOINTS: dict[str, tuple[tuple[str, ...], ...]] = {
    "pelvis": (("left_hip", "right_hip"),),
    "thorax": (("left_shoulder", "right_shoulder"),),
    # (pelvis + thorax) / 2 as in MMPose's COCO -> H36M rule; with a detected pelvis and thorax
    # (BODY_25, Halpe-26: MotionBERT's (Neck + Hip) / 2) those are used, not the four corners.
    "spine": (("pelvis", "thorax"), ("left_hip", "right_hip", "left_shoulder", "right_shoulder")),
    "head": (("left_eye", "right_eye"),),
}
# Joints taken from a differently named joint when the source lacks the exact one
# (COCO has no neck base; MMPose and MotionBERT use the nose for H36M joint 9).
ALIASES: dict[str, str] = {"neck": "nose"}

# Joint counts of detector outputs that carry no joint names (FORMATS.md 3.7). K = 17 is also
# H36M-17, but detectors emit COCO-17; K = 25 is BODY_25 or BODY_25B (`body25_variant` tells
# them apart); readers prefer names or meta data where a file has them.
_BY_COUNT = {17: "coco17", 18: "coco18", 25: "body25", 26: "halpe26"}
# Other tools' names for joints, per skeleton (MMPose configs/_base_/datasets/{h36m,halpe26}.py;
# "root (pelvis)" is the name in MMPose's tests/data/h36m/h36m_coco.json), after `_normalise`.
_TOOL_JOINT_NAMES: dict[str, dict[str, str]] = {
    "h36m17": {"root": "pelvis", "root_(pelvis)": "pelvis", "right_foot": "right_ankle", "left_foot": "left_ankle",
               "neck_base": "neck"},
    "halpe26": {"neck": "thorax", "hip": "pelvis"},
    "body25": {"neck": "thorax", "mid_hip": "pelvis", "midhip": "pelvis"},
    "body25b": {"neck": "upper_neck", "head_top": "head", "headtop": "head"},
    "coco18": {"neck": "thorax"},
}  # fmt: skip


@dataclass(frozen=True)
class SkeletonSource:
    """Which joint set an input was read as, and why (recorded as the output's
    ``input.source_skeleton``), e.g. ("coco17", "categories[0].keypoints names")."""

    name: str
    reason: str

    def to_dict(self) -> dict[str, str]:
        return {"name": self.name, "reason": self.reason}


@dataclass(frozen=True)
class JointNameMatch:
    """A known skeleton whose joints are a file's joint names in some order.

    `order[j]` is the position in the file of the skeleton's joint j, so that
    ``file_values[order]`` puts per-joint values of the file into the skeleton's order.
    """

    skeleton: Skeleton
    order: tuple[int, ...]

    @property
    def is_identity(self) -> bool:
        return self.order == tuple(range(len(self.order)))


def _normalise(name: str) -> str:
    """A joint name compared case-blind, with spaces and hyphens as underscores."""
    return "_".join(name.strip().lower().replace("-", " ").split())


def skeleton_for_joint_count(count: int) -> Skeleton | None:
    """The skeleton a detector output with `count` unnamed joints uses (17 -> coco17,
    18 -> coco18, 25 -> body25, 26 -> halpe26), or None."""
    name = _BY_COUNT.get(count)
    return SKELETONS[name] if name is not None else None


def joint_count_names() -> str:
    """The supported unnamed joint counts, for messages: "17 (coco17), 18 (coco18), ..."."""
    return ", ".join(f"{count} ({name})" for count, name in sorted(_BY_COUNT.items()))


def skeleton_option_hint(count: int) -> str:
    """What to do about `count` unnamed joints that no count stands for, for messages: name the
    joint set with --skeleton ("--skeleton syrip12" when one skeleton has that many joints)."""
    names = [name for name, skel in SKELETONS.items() if skel.num_joints == count]
    if not names:
        return f"no zedo joint set has {count} joints (--skeleton names one: {', '.join(SKELETONS)})"
    return "name the joint set with --skeleton " + " or --skeleton ".join(names)


def match_joint_names(names: tuple[str, ...] | list[str]) -> JointNameMatch | None:
    """The skeleton whose joints are exactly `names`, in any order, in zedo's names or a tool's
    (MMPose's ``root (pelvis)``/``neck_base`` for H36M, ``neck``/``hip`` for Halpe-26, ...);
    None when no skeleton has these names (or a name repeats)."""
    normalised = [_normalise(name) for name in names]
    for skeleton in SKELETONS.values():
        if len(normalised) != skeleton.num_joints:
            continue
        aliases = _TOOL_JOINT_NAMES.get(skeleton.name, {})
        mapped = [aliases.get(name, name) for name in normalised]
        if len(set(mapped)) == len(mapped) and set(mapped) == set(skeleton.joints):
            position = {name: k for k, name in enumerate(mapped)}
            return JointNameMatch(skeleton, tuple(position[joint] for joint in skeleton.joints))
    return None


def skeleton_from_joint_names(names: tuple[str, ...] | list[str]) -> Skeleton | None:
    """The skeleton whose joints are exactly `names` in its own order (see `match_joint_names`
    for any order); else None."""
    match = match_joint_names(names)
    return match.skeleton if match is not None and match.is_identity else None


# Joint-geometry checks that hold in one 25-joint layout and not in the other, as (joint,
# (a, b)): joint lies near the midpoint of a and b. BODY_25: the neck (1) between the shoulders
# (2, 5) and the mid-hip (8) between the hips (9, 12), as OpenPose defines them. BODY_25B: the
# nose (0) between the eyes (1, 2), and the eyes' midpoint near the ears' (3, 4; written as the
# eyes' midpoint against the ears'). Read in the other layout, each check compares an arm, an
# eye or a shoulder with unrelated joints.
_MIDPOINTS_BODY25 = (((1,), (2, 5)), ((8,), (9, 12)))
_MIDPOINTS_BODY25B = (((0,), (1, 2)), ((1, 2), (3, 4)))


def _box_diagonal(xy: np.ndarray, present: np.ndarray) -> np.ndarray:
    """Per instance, the diagonal of the box around its present joints; NaN with fewer than 3."""
    pts = np.where(present[..., None], xy, np.nan)
    out = np.full(len(xy), np.nan)
    enough = present.sum(axis=1) >= 3
    if enough.any():
        lo, hi = np.nanmin(pts[enough], axis=1), np.nanmax(pts[enough], axis=1)
        with np.errstate(over="ignore", invalid="ignore"):
            out[enough] = np.hypot(*(hi - lo).T)
    return out


def _midpoint_error(xy: np.ndarray, present: np.ndarray, checks: tuple) -> np.ndarray:
    """Per instance, the mean distance of `checks` (see above) over those whose joints are all
    present, in units of the body's box diagonal; NaN where no check can be made."""
    pts = np.where(present[..., None], xy, np.nan)
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):  # absurd coordinates give inf, not noise
        terms = [
            np.linalg.norm(pts[:, list(near)].mean(axis=1) - pts[:, list(pair)].mean(axis=1), axis=-1)
            for near, pair in checks
        ]
        stacked = np.stack(terms)  # (checks, N)
        counts = np.isfinite(stacked).sum(axis=0)
        mean = np.where(counts > 0, np.nansum(stacked, axis=0) / np.maximum(counts, 1), np.nan)
        return mean / _box_diagonal(xy, present)


def body25_variant(xy: np.ndarray, confidence: np.ndarray) -> tuple[str | None, str]:
    """Whether 25-joint detections `xy (N, 25, 2)` are OpenPose BODY_25 or BODY_25B, from their
    joint geometry: ("body25" | "body25b" | None, an explanation for messages).

    Each layout has joints that lie near the midpoint of two others (BODY_25: neck and mid-hip;
    BODY_25B: nose and eyes, see `_MIDPOINTS_*`). The median error of each layout's checks over
    the instances, in body-box diagonals, must be at most half the other layout's. Measured on
    SyRIP's 700 real infant images (ground truth and FiDIP detections written in both layouts,
    the BODY_25 neck and mid-hip moved by 10 % of the shoulder / hip width): medians 0.02-0.06
    for the true layout against 0.19-0.21 for the other (the file is told right); image by
    image, never the wrong layout, but 18-20 % of the BODY_25B images alone are undecided.
    None when the instances cannot tell.
    """
    present = (confidence > 0) & np.isfinite(xy).all(axis=-1)
    e25 = _midpoint_error(xy, present, _MIDPOINTS_BODY25)
    e25b = _midpoint_error(xy, present, _MIDPOINTS_BODY25B)
    usable = np.isfinite(e25) & np.isfinite(e25b)
    if not usable.any():
        return None, "no person shows the neck, hips, shoulders, nose and eyes these checks need, at finite positions"
    m25, m25b = float(np.median(e25[usable])), float(np.median(e25b[usable]))
    detail = (f"midpoint errors in body-box diagonals: {m25:.3f} as BODY_25 (neck, mid-hip), "
              f"{m25b:.3f} as BODY_25B (nose, eyes), median of {int(usable.sum())} persons")  # fmt: skip
    if m25 <= 0.5 * m25b:
        return "body25", detail
    if m25b <= 0.5 * m25:
        return "body25b", detail
    return None, detail


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
            continue
        usable = [names for names in DERIVED_JOINTS.get(joint, ()) if all(j in src.joints for j in names)]
        if usable:
            sources.append([src.index(j) for j in usable[0]])
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
    missing (NaN, confidence 0) when any source is missing (confidence 0 or NaN coordinates) or
    unavailable.
    """
    if points.shape[-2] != src.num_joints:
        raise ConfigError(f"expected {src.num_joints} joints for skeleton {src.name}, got {points.shape[-2]}")
    lead = points.shape[:-2]
    out = np.full((*lead, dst.num_joints, points.shape[-1]), np.nan, dtype=np.float64)
    out_conf = np.zeros((*lead, dst.num_joints), dtype=np.float64)
    for j, idx in enumerate(conversion_sources(src, dst)):
        if not idx:
            continue
        conf = confidence[..., idx].min(axis=-1)
        mean = points[..., idx, :].mean(axis=-2)
        # A NaN source with a confidence (never from the readers) is missing too, not a NaN "position".
        present = (conf > 0) & np.isfinite(mean).all(axis=-1)
        out[..., j, :] = np.where(present[..., None], mean, np.nan)
        out_conf[..., j] = np.where(present, conf, 0.0)
    return out, out_conf


def root_point(points: np.ndarray, skeleton: Skeleton) -> np.ndarray:
    """Root point `(..., D)` of points `(..., J, D)`: the mean of the skeleton's root joints."""
    return points[..., skeleton.root_indices, :].mean(axis=-2)


def center_on_root(points: np.ndarray, skeleton: Skeleton) -> np.ndarray:
    """Points `(..., J, D)` translated so that the skeleton's root point is the origin."""
    return points - root_point(points, skeleton)[..., None, :]


def bone_lengths(poses: np.ndarray, skeleton: Skeleton) -> np.ndarray:
    """Length of every bone of `skeleton.bones` per pose: `(N, J, 3)` -> `(N, B)`, input units."""
    a, b = np.asarray(skeleton.bones, dtype=np.int64).reshape(-1, 2).T
    return np.linalg.norm(poses[:, a] - poses[:, b], axis=-1)


# The four limb segments whose left and right lengths a body shares (the symmetry pairs of
# Huang et al. 2022): (proximal, distal) joint names without the side.
TWIN_LIMBS = (("shoulder", "elbow"), ("elbow", "wrist"), ("hip", "knee"), ("knee", "ankle"))


def twin_limbs(skeleton: Skeleton) -> list[tuple[tuple[int, int], tuple[int, int]]]:
    """((left proximal, left distal), (right proximal, right distal)) joint indices of every
    twin limb (TWIN_LIMBS) that `skeleton` has; empty for a joint set without sides."""
    names = set(skeleton.joints)
    out = []
    for a, b in TWIN_LIMBS:
        ends = [f"{side}_{j}" for side in ("left", "right") for j in (a, b)]
        if names.issuperset(ends):
            out.append(((skeleton.index(ends[0]), skeleton.index(ends[1])),
                        (skeleton.index(ends[2]), skeleton.index(ends[3]))))  # fmt: skip
    return out


def twin_limb_ratio(poses: np.ndarray, skeleton: Skeleton) -> np.ndarray:
    """Per pose `(N, J, 3) -> (N,)`: the largest ratio, over the twin limbs, of the longer of a
    left/right limb to the shorter (1 = every twin pair equally long; NaN without twin limbs)."""
    pairs = twin_limbs(skeleton)
    if not pairs:
        return np.full(len(poses), np.nan)
    ratios = []
    for (lp, lc), (rp, rc) in pairs:
        left = np.linalg.norm(poses[:, lc] - poses[:, lp], axis=-1)
        right = np.linalg.norm(poses[:, rc] - poses[:, rp], axis=-1)
        with np.errstate(divide="ignore", invalid="ignore"):
            ratios.append(np.maximum(left, right) / np.minimum(left, right))
    return np.max(np.stack(ratios, axis=1), axis=1)
