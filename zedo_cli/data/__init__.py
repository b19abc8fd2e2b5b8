"""Data: joint sets (skeletons) and their conversions, the in-memory 2D keypoint record, and the
loaders of the 3D pose sets (SyRIP, npz files, adult motion capture, MINI-RGBD).

Depends on nothing in zedo_cli but `errors` and `rotation`; numpy only, no torch.
"""

from __future__ import annotations

from ..lazy import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(
    __name__,
    globals(),
    {
        ".adult": ["ADULT_LICENSE", "PoseAugmentation", "load_adult_poses"],
        ".datasets": ["PoseSet", "load_npz_poses", "load_syrip_3d", "npz_license"],
        ".keypoints": ["Keypoints2D", "OtherKeypoints"],
        ".minirgbd": ["MINIRGBD_LICENSE", "load_minirgbd", "load_minirgbd_3d"],
        ".skeleton": [
            "SKELETONS",
            "Skeleton",
            "bone_lengths",
            "center_on_root",
            "convert_points",
            "get_skeleton",
            "root_point",
        ],
    },
)
