"""Data: joint sets (skeletons) and their conversions, the in-memory 2D keypoint record, and the
loaders of the 3D pose sets (SyRIP, npz files, adult motion capture, MINI-RGBD).

Depends on nothing in zedo_cli but `errors` and `rotation`; numpy only, no torch.
"""

from __future__ import annotations

from .adult import ADULT_LICENSE, PoseAugmentation, load_adult_poses
from .datasets import PoseSet, load_npz_poses, load_syrip_3d, npz_license
from .keypoints import Keypoints2D
from .minirgbd import MINIRGBD_LICENSE, load_minirgbd, load_minirgbd_3d
from .skeleton import (
    SKELETONS,
    Skeleton,
    bone_lengths,
    center_on_root,
    convert_points,
    get_skeleton,
    root_point,
)

__all__ = [
    "ADULT_LICENSE", "MINIRGBD_LICENSE", "SKELETONS", "Keypoints2D", "PoseAugmentation", "PoseSet", "Skeleton",
    "bone_lengths", "center_on_root", "convert_points", "get_skeleton", "load_adult_poses", "load_minirgbd",
    "load_minirgbd_3d", "load_npz_poses", "load_syrip_3d", "npz_license", "root_point",
]  # fmt: skip
