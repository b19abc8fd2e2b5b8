"""Adult motion-capture loading (generated files in the real layout) and the batch augmentation."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import torch

from zedo_cli.data.adult import ADULT_FILES, PoseAugmentation, load_adult_poses
from zedo_cli.data.skeleton import get_skeleton
from zedo_cli.errors import ConfigError, DataError
from zedo_cli.prior.recipes import load_recipe


def _write_adult_dir(root, n: int = 5):
    rng = np.random.default_rng(0)
    names = np.array(get_skeleton("h36m17").joints)
    for k, file in enumerate(ADULT_FILES):
        poses = rng.normal(size=(n, 17, 3)).astype(np.float32) + np.array([3.0, 1.0, -2.0], np.float32)
        np.savez(root / file, poses=poses, joint_names=names, clip=np.array([f"c{k}"] * n))
    return root


def test_adult_poses_are_mapped_and_centred_on_the_hip_midpoint(tmp_path) -> None:
    data = load_adult_poses(_write_adult_dir(tmp_path))
    skel = get_skeleton("syrip12")
    assert data.poses.shape == (15, 12, 3) and data.skeleton is skel
    np.testing.assert_allclose(data.poses[:, skel.root_indices].mean(axis=1), 0, atol=1e-6)
    assert data.names[0] == f"{ADULT_FILES[0]}:c0"


def test_missing_adult_file_is_named(tmp_path) -> None:
    _write_adult_dir(tmp_path)
    (tmp_path / ADULT_FILES[1]).unlink()
    with pytest.raises(DataError, match=ADULT_FILES[1]):
        load_adult_poses(tmp_path)


def test_augmentation_rotates_and_scales_within_range_reproducibly() -> None:
    poses = torch.randn(64, 12, 3, dtype=torch.float64)
    poses -= poses.mean(dim=1, keepdim=True)
    aug = PoseAugmentation(rotate=True, scale_min=0.2, scale_max=1.0)
    out = aug(poses, torch.Generator().manual_seed(5))
    again = aug(poses, torch.Generator().manual_seed(5))
    assert torch.equal(out, again)
    torch.testing.assert_close(out.mean(dim=1), torch.zeros(64, 3, dtype=torch.float64))
    ratio = out.norm(dim=(1, 2)) / poses.norm(dim=(1, 2))  # rotation keeps norms; scale changes them
    assert ratio.min() >= 0.2 - 1e-9 and ratio.max() <= 1.0 + 1e-9 and ratio.std() > 0.05
    assert not torch.allclose(out / ratio[:, None, None], poses)  # turned, not only scaled
    assert not PoseAugmentation().active


def test_augmentation_settings_are_checked() -> None:
    with pytest.raises(ConfigError, match="exceeds"):
        PoseAugmentation(scale_min=2.0, scale_max=1.0)
    with pytest.raises(ConfigError, match="> 0"):
        PoseAugmentation(scale_min=0.0)


def test_adult_recipe_asks_for_rotation_and_scale() -> None:
    recipe = load_recipe(Path(__file__).resolve().parents[2] / "weights_spec" / "adult12-rotscale.toml")
    assert recipe.augment == PoseAugmentation(rotate=True, scale_min=0.2, scale_max=1.0)
    assert recipe.training.batch_size == 1024
