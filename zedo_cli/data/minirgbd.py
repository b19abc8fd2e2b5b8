"""MINI-RGBD (Hesse et al., 2018): the data set's own layout, its SMIL joints, the two
mappings to H36M-17, the two train / test splits and the 17 / 16-joint protocols (the
benchmark on it, with the depth camera's intrinsics: `evaluation.minirgbd_benchmark`).

Layout (ALGORITHM.md 1.1, 1.2, 1.5): `DIR/NN/joints_3D/syn_joints_3D_XXXXX.txt` and
`DIR/NN/joints_2Ddep/syn_joints_2Ddep_XXXXX.txt` for sequences NN = 01..12 of 1000 frames
each. Every file has one line per SMIL joint, 25 lines in the order of `SMIL25_JOINTS`; the
first three columns of a 3D line are x, y, z in metres in the depth camera's frame, the first
two of a 2D line are u, v in pixels of the 640x480 depth image. Further columns (depth, joint
id) are not used.

The joint names and both mappings live here rather than in skeleton.py: SMIL-25 is only ever
read from these files and converted at once to `h36m17`.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import ConfigError, DataError, InputFormatError
from .datasets import PoseSet
from .skeleton import Skeleton, center_on_root, get_skeleton

# The depth image the 2D is given in (the camera's intrinsics: evaluation.minirgbd_benchmark).
DEPTH_IMAGE_SIZE = (640, 480)
SEQUENCES = tuple(f"{i:02d}" for i in range(1, 13))
FRAMES_PER_SEQUENCE = 1000
DIR_3D, DIR_2D = "joints_3D", "joints_2Ddep"
PREFIX_3D, PREFIX_2D = "syn_joints_3D_", "syn_joints_2Ddep_"

# SMIL (SMPL-like) joint order of the files. SMPL naming: Thigh = hip, Calf = knee,
# Foot = ankle, Toes = foot, Shoulder = collar, UpperArm = shoulder, ForeArm = elbow,
# Hand = wrist.
SMIL25_JOINTS = (
    "global", "leftThigh", "rightThigh", "spine", "leftCalf", "rightCalf", "spine1", "leftFoot",
    "rightFoot", "spine2", "leftToes", "rightToes", "neck", "leftShoulder", "rightShoulder", "head",
    "leftUpperArm", "rightUpperArm", "leftForeArm", "rightForeArm", "leftHand", "rightHand",
    "leftFingers", "rightFingers", "noseVertex",
)  # fmt: skip

# h36m17 joint -> SMIL joint. "reference" is the authors' table (ALGORITHM.md 1.2): H36M
# ankles from the toe joints and shoulders from the collar joints, so its figures compare
# with the paper. "anatomical" takes the true ankle and shoulder joints.
_COMMON = {
    "pelvis": "global", "right_hip": "rightThigh", "right_knee": "rightCalf",
    "left_hip": "leftThigh", "left_knee": "leftCalf", "spine": "spine", "thorax": "spine2",
    "neck": "neck", "head": "head", "left_elbow": "leftForeArm", "left_wrist": "leftHand",
    "right_elbow": "rightForeArm", "right_wrist": "rightHand",
}  # fmt: skip
MAPPINGS: dict[str, dict[str, str]] = {
    "reference": {**_COMMON, "right_ankle": "rightToes", "left_ankle": "leftToes",
                  "left_shoulder": "leftShoulder", "right_shoulder": "rightShoulder"},
    "anatomical": {**_COMMON, "right_ankle": "rightFoot", "left_ankle": "leftFoot",
                   "left_shoulder": "leftUpperArm", "right_shoulder": "rightUpperArm"},
}  # fmt: skip

# Sequences per split side. "paper": 9 train / 3 test as the paper states; "reference": the
# authors' code, 10 / 2 (ALGORITHM.md 1.7).
SPLITS: dict[str, dict[str, tuple[str, ...]]] = {
    "paper": {"train": SEQUENCES[:9], "test": SEQUENCES[9:]},
    "reference": {"train": SEQUENCES[:10], "test": SEQUENCES[10:]},
}
SIDES = ("train", "test", "all")

MINIRGBD_LICENSE = (
    "Trained on MINI-RGBD (Hesse et al., ECCV workshops 2018) under the data set's own terms, "
    "which forbid redistributing the data. These weights are for research / non-commercial use only."
)

_FRAME_3D = re.compile(r"syn_joints_3D_(\d{5})\.txt")  # frames are listed from the 3D files


@dataclass
class MiniFrames:
    """Frames of MINI-RGBD in the `h36m17` joint set, in sequence then frame order."""

    names: list[str]  # "NN/XXXXX"
    poses_camera: np.ndarray  # (N, 17, 3) metres, depth camera frame (not root-relative)
    keypoints_2d: np.ndarray | None  # (N, 17, 2) depth-image pixels, None when not read
    skeleton: Skeleton
    mapping: str
    source: str


def joint_file_path(root: Path, sequence: str, frame: str, kind: str) -> Path:
    """Path of one joint file; `kind` is DIR_3D or DIR_2D."""
    prefix = PREFIX_3D if kind == DIR_3D else PREFIX_2D
    return root / sequence / kind / f"{prefix}{frame}.txt"


def read_joint_file(path: Path, columns: int) -> np.ndarray:
    """The first `columns` numbers of each of the 25 joint lines of one file: `(25, columns)`.

    Blank lines are skipped; the error names the file and the 1-based line number.
    """
    try:
        text = path.read_text()
    except FileNotFoundError:
        raise DataError(f"{path}: file not found") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputFormatError(f"{path}: cannot read the joint file ({exc})") from None
    rows: list[list[float]] = []
    what = "x y z in metres" if columns == 3 else "u v in pixels"
    for number, line in enumerate(text.splitlines(), start=1):
        fields = line.split()
        if not fields:
            continue
        if len(fields) < columns:
            raise InputFormatError(f"{path}: line {number}: expected at least {columns} numbers ({what}), got {line!r}")
        try:
            values = [float(v) for v in fields[:columns]]
        except ValueError:
            raise InputFormatError(f"{path}: line {number}: not a number in {line.strip()!r}") from None
        if not all(np.isfinite(values)):
            raise InputFormatError(f"{path}: line {number}: NaN or infinite value in {line.strip()!r}")
        rows.append(values)
    if len(rows) != len(SMIL25_JOINTS):
        raise InputFormatError(f"{path}: expected {len(SMIL25_JOINTS)} joint lines (SMIL order), found {len(rows)}")
    return np.asarray(rows, dtype=np.float64)


def get_mapping(name: str) -> dict[str, str]:
    try:
        return MAPPINGS[name]
    except KeyError:
        raise ConfigError(f"unknown MINI-RGBD mapping {name!r}; choose one of {', '.join(MAPPINGS)}") from None


def smil_to_h36m17(points: np.ndarray, mapping: str = "reference") -> np.ndarray:
    """SMIL-25 points `(..., 25, D)` -> `h36m17` points `(..., 17, D)` by the named mapping."""
    table = get_mapping(mapping)
    h36m = get_skeleton("h36m17")
    return points[..., [SMIL25_JOINTS.index(table[j]) for j in h36m.joints], :]


def split_sequences(split: str, side: str) -> tuple[str, ...]:
    """Sequence names of one side ("train", "test" or "all") of a split ("paper", "reference")."""
    if split not in SPLITS:
        raise ConfigError(f"unknown MINI-RGBD split {split!r}; choose one of {', '.join(SPLITS)}")
    if side not in SIDES:
        raise ConfigError(f"unknown split side {side!r}; choose one of {', '.join(SIDES)}")
    return SEQUENCES if side == "all" else SPLITS[split][side]


def sequence_frames(root: Path, sequence: str) -> list[str]:
    """Frame numbers ("XXXXX") of one sequence that have a 3D joint file, sorted."""
    folder = root / sequence / DIR_3D
    if not (root / sequence).is_dir():
        raise DataError(f"{root / sequence}: sequence {sequence} not found (is {root} the MINI-RGBD folder "
                        "holding 01..12?)")  # fmt: skip
    if not folder.is_dir():
        raise DataError(f"{folder}: folder not found (each sequence needs {DIR_3D}/ and {DIR_2D}/)")
    frames = sorted(m.group(1) for p in folder.iterdir() if (m := _FRAME_3D.fullmatch(p.name)))
    if not frames:
        raise DataError(f"{folder}: no {PREFIX_3D}XXXXX.txt files")
    return frames


def check_stride(stride: int) -> None:
    if stride < 1:
        raise ConfigError(f"--stride must be >= 1, got {stride}")


def load_minirgbd(
    root: str | Path,
    sequences: tuple[str, ...],
    *,
    mapping: str = "reference",
    stride: int = 1,
    with_2d: bool = True,
) -> MiniFrames:
    """Read every `stride`-th frame of each sequence, mapped to `h36m17`.

    With `with_2d`, each frame's 2D file must exist too (an error names the missing file).
    """
    root = Path(root)
    get_mapping(mapping)
    check_stride(stride)
    if not root.is_dir():
        raise DataError(f"{root}: MINI-RGBD folder not found")
    names, pts3d, pts2d = [], [], []
    for seq in sequences:
        for frame in sequence_frames(root, seq)[::stride]:
            names.append(f"{seq}/{frame}")
            pts3d.append(read_joint_file(joint_file_path(root, seq, frame, DIR_3D), 3))
            if with_2d:
                path_2d = joint_file_path(root, seq, frame, DIR_2D)
                if not path_2d.is_file():
                    raise DataError(f"{path_2d}: file not found (frame {seq}/{frame} has a 3D file but no 2D one)")
                pts2d.append(read_joint_file(path_2d, 2))
    skel = get_skeleton("h36m17")
    poses = smil_to_h36m17(np.stack(pts3d), mapping)
    kp = smil_to_h36m17(np.stack(pts2d), mapping) if with_2d else None
    return MiniFrames(names, poses, kp, skel, mapping, f"MINI-RGBD sequences {','.join(sequences)} ({root})")


def load_minirgbd_3d(
    root: str | Path, split: str = "paper", side: str = "train", *, mapping: str = "reference", stride: int = 1
) -> PoseSet:
    """Root-relative (pelvis-centred) `h36m17` training / test poses of one split side."""
    frames = load_minirgbd(root, split_sequences(split, side), mapping=mapping, stride=stride, with_2d=False)
    source = f"MINI-RGBD {split} split, {side} side, {mapping} mapping ({root})"
    return PoseSet(center_on_root(frames.poses_camera, frames.skeleton), frames.skeleton, frames.names, source)


# The 16-joint protocol of the paper's tables is not in the reference code and its dropped
# joint is unknown (ALGORITHM.md 6). Default: the pelvis, the root, whose error is zero by
# construction once both sides are root-centred, so the 16 scored joints are exactly those
# that carry information (one of the paper's rows fits 17/16 of a 17-joint figure).
PROTOCOLS = ("17", "16")
DEFAULT_DROPPED_JOINT = "pelvis"


def protocol_joints(protocol: str, dropped: str = DEFAULT_DROPPED_JOINT) -> tuple[str, ...]:
    """The `h36m17` joints scored by a protocol: all 17, or 16 without `dropped`."""
    joints = get_skeleton("h36m17").joints
    if protocol not in PROTOCOLS:
        raise ConfigError(f"unknown protocol {protocol!r}; choose 17 or 16 joints")
    if protocol == "17":
        return joints
    if dropped not in joints:
        raise ConfigError(f"--drop-joint {dropped!r} is not an h36m17 joint; joints: {', '.join(joints)}")
    return tuple(j for j in joints if j != dropped)
