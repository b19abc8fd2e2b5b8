"""Adult motion-capture poses (../shared/data/adult) and the augmentation that makes an adult
prior cover infants' orientations and sizes.

The adult files hold world-frame poses (+Y up, standing people) in the Human3.6M 17-joint
order, in metres, with the source's own root joint. Infant poses are camera-oriented and
infants lie, sit and roll, so an adult prior is trained with every batch turned by a uniformly
random rotation (SO(3)) and scaled by a log-uniform factor, both drawn from the training seed.
"""

from __future__ import annotations

import zipfile
from collections.abc import Callable
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
import torch

from ..errors import ConfigError, DataError
from ..rotation import quaternion_to_matrix
from .datasets import PoseSet
from .skeleton import center_on_root, convert_points, get_skeleton

ADULT_FILES = ("bandai_namco_h36m17.npz", "cmu_dmgnn_h36m17.npz", "deepmimic_pybullet_h36m17.npz")
ADULT_LICENSE = (
    "Trained on adult motion capture: Bandai-Namco-Research-Motiondataset, (c) 2022 Bandai Namco "
    "Research Inc., CC BY-NC 4.0 (https://creativecommons.org/licenses/by-nc/4.0/), modified: "
    "converted to joint positions, subsampled, rotated and scaled; CMU Graphics Lab Motion Capture "
    "Database (mocap.cs.cmu.edu, created with funding from NSF EIA-0196217); DeepMimic clips from "
    "pybullet / Bullet Physics (zlib). Because of the Bandai Namco data these weights are for "
    "non-commercial use only."
)


def load_adult_poses(adult_dir: str | Path, skeleton: str = "syrip12", files: tuple[str, ...] = ADULT_FILES) -> PoseSet:
    """Adult poses from `adult_dir`, in `skeleton`'s joints, centred on its root, in metres.

    Joint 0 of the files is the source's root joint, not always the hip midpoint; it is replaced
    by the mean of the two hips (the files' README) so every source has a Human3.6M-like pelvis.
    Axes stay the world's (+Y up); training turns them at random (see `PoseAugmentation`).
    """
    adult_dir = Path(adult_dir)
    if not adult_dir.is_dir():
        raise DataError(f"{adult_dir}: adult data folder not found")
    h36m = get_skeleton("h36m17")
    dst = get_skeleton(skeleton)
    chunks, names = [], []
    for file in files:
        path = adult_dir / file
        if not path.is_file():
            raise DataError(f"{path}: file not found (is --adult-dir the adult data folder?)")
        try:
            with np.load(path, allow_pickle=False) as data:
                poses = np.asarray(data["poses"], dtype=np.float64)
                joint_names = tuple(str(j) for j in data["joint_names"])
                clips = [str(c) for c in data["clip"]]
        except (OSError, ValueError, KeyError, zipfile.BadZipFile) as exc:
            raise DataError(f"{path}: not an adult pose file with poses, joint_names and clip ({exc})") from None
        if poses.ndim != 3 or poses.shape[1:] != (17, 3) or len(clips) != len(poses):
            raise DataError(f"{path}: 'poses' must have shape (N, 17, 3) with one clip name per pose")
        if len(joint_names) != 17 or not np.isfinite(poses).all():
            raise DataError(f"{path}: expected 17 joint names and finite poses")
        poses[:, 0] = poses[:, [1, 4]].mean(axis=1)  # pelvis := hip midpoint
        converted, _ = convert_points(poses, np.ones(poses.shape[:2]), h36m, dst)
        chunks.append(center_on_root(converted, dst))
        names += [f"{file}:{clip}" for clip in clips]
    poses = np.concatenate(chunks)
    return PoseSet(poses, dst, names, f"adult motion capture ({adult_dir}: {', '.join(files)})")


@dataclass(frozen=True)
class PoseAugmentation:
    """Per-pose random rotation (uniform over SO(3)) and log-uniform scale in [scale_min, scale_max].

    Applied to root-relative poses, so the root stays at the origin.
    """

    rotate: bool = False
    scale_min: float = 1.0
    scale_max: float = 1.0

    def __post_init__(self) -> None:
        if not isinstance(self.rotate, bool):
            raise ConfigError(f"augment rotate must be true or false, got {self.rotate!r}")
        for name in ("scale_min", "scale_max"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not value > 0:
                raise ConfigError(f"augment {name} must be a number > 0, got {value!r}")
        if self.scale_min > self.scale_max:
            raise ConfigError(f"augment scale_min ({self.scale_min}) exceeds scale_max ({self.scale_max})")

    @property
    def active(self) -> bool:
        return self.rotate or self.scale_min != 1.0 or self.scale_max != 1.0

    def to_dict(self) -> dict[str, object]:
        return asdict(self)

    def __call__(self, poses: torch.Tensor, generator: torch.Generator) -> torch.Tensor:
        """`poses (B, J, 3)` turned and scaled, one draw per pose."""
        batch = poses.shape[0]
        out = poses
        if self.rotate:
            q = torch.randn(batch, 4, generator=generator, device=poses.device, dtype=poses.dtype)
            rot = quaternion_to_matrix(q / q.norm(dim=-1, keepdim=True))
            out = out @ rot.transpose(-1, -2)
        if self.scale_min != 1.0 or self.scale_max != 1.0:
            lo, hi = np.log(self.scale_min), np.log(self.scale_max)
            u = torch.rand(batch, generator=generator, device=poses.device, dtype=poses.dtype)
            out = out * torch.exp(lo + (hi - lo) * u)[:, None, None]
        return out


BatchTransform = Callable[[torch.Tensor, torch.Generator], torch.Tensor]
