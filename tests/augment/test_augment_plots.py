"""Augmentation plots: bone lengths, fractions and angles, valid PNGs, no clobbering, bad inputs."""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np
import pytest

from zedo_cli.augment.plots import (
    bone_fractions,
    bone_lengths,
    evenly_spaced_rows,
    joint_angles,
    write_augmentation_plots,
)
from zedo_cli.data.skeleton import get_skeleton
from zedo_cli.errors import ConfigError

SKELETON = get_skeleton("syrip12")
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def png_size(path: Path) -> tuple[int, int]:
    data = path.read_bytes()
    assert data[:8] == PNG_SIGNATURE and data[12:16] == b"IHDR"
    return struct.unpack(">II", data[16:24])


def random_poses(n: int, scale: float, seed: int) -> np.ndarray:
    return np.random.default_rng(seed).normal(scale=scale, size=(n, SKELETON.num_joints, 3))


def test_bone_lengths_and_fractions() -> None:
    poses = random_poses(5, 0.3, seed=0)
    lengths = bone_lengths(poses, SKELETON)
    assert lengths.shape == (5, len(SKELETON.bones))
    a, b = SKELETON.bones[3]
    np.testing.assert_allclose(lengths[2, 3], np.linalg.norm(poses[2, a] - poses[2, b]))
    fractions = bone_fractions(poses, SKELETON)
    np.testing.assert_allclose(fractions.sum(axis=1), 1.0)
    # proportions do not depend on size
    np.testing.assert_allclose(bone_fractions(3.0 * poses, SKELETON), fractions)
    np.testing.assert_allclose(bone_lengths(3.0 * poses, SKELETON), 3.0 * lengths)


def test_joint_angles_right_angle_elbow_and_straight_knee() -> None:
    pose = random_poses(1, 0.3, seed=1)
    j = SKELETON.index
    pose[0, j("left_elbow")] = [0.0, 0.0, 0.0]
    pose[0, j("left_shoulder")] = [0.0, -0.3, 0.0]
    pose[0, j("left_wrist")] = [0.25, 0.0, 0.0]
    pose[0, j("right_hip")] = [0.1, 0.0, 0.0]
    pose[0, j("right_knee")] = [0.1, 0.4, 0.1]
    pose[0, j("right_ankle")] = [0.1, 0.8, 0.2]
    names, angles = joint_angles(pose, SKELETON)
    assert angles.shape == (1, len(names))
    # every hip and shoulder meets 3 bones (3 angles), every knee and elbow 2 (1 angle)
    assert len(names) == 4 * 3 + 4 * 1
    np.testing.assert_allclose(angles[0, names.index("left_elbow (left_shoulder, left_wrist)")], 90.0)
    np.testing.assert_allclose(angles[0, names.index("right_knee (right_hip, right_ankle)")], 180.0)
    assert np.all((angles >= 0) & (angles <= 180))


def test_evenly_spaced_rows() -> None:
    assert evenly_spaced_rows(10, 4).tolist() == [0, 3, 6, 9]
    assert evenly_spaced_rows(3, 4).tolist() == [0, 1, 2]
    assert evenly_spaced_rows(5, 1).tolist() == [0]
    for n in range(1, 30):
        for k in range(1, n + 1):
            assert len(set(evenly_spaced_rows(n, k).tolist())) == k


def make_sets() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    return random_poses(40, 0.12, seed=2), random_poses(30, 0.12, seed=3), random_poses(30, 0.4, seed=4)


def test_writes_three_valid_pngs(tmp_path: Path) -> None:
    infant, augmented, sources = make_sets()
    out = tmp_path / "plots" / "sub"  # created
    paths = write_augmentation_plots(out, SKELETON, infant, augmented, sources, pairs=2, dpi=50)
    assert [p.name for p in paths] == ["bone_lengths.png", "bone_angles.png", "pairs.png"]
    for path in paths:
        width, height = png_size(path)
        assert 300 <= width <= 1000 and 150 <= height <= 1000
        assert path.stat().st_size > 10_000  # drawn panels, not a blank canvas
    assert sorted(p.name for p in out.iterdir()) == sorted(p.name for p in paths)  # no temp files


def test_no_overwrite_without_flag(tmp_path: Path) -> None:
    infant, augmented, sources = make_sets()
    (tmp_path / "pairs.png").write_bytes(b"old")
    with pytest.raises(ConfigError, match="already exists"):
        write_augmentation_plots(tmp_path, SKELETON, infant, augmented, sources, pairs=1, dpi=40)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pairs.png"]  # checked before drawing
    assert (tmp_path / "pairs.png").read_bytes() == b"old"
    paths = write_augmentation_plots(tmp_path, SKELETON, infant, augmented, sources, pairs=1, dpi=40,
                                     overwrite=True)  # fmt: skip
    assert png_size(paths[2])[0] > 0


@pytest.mark.parametrize(
    ("change", "match"),
    [
        (lambda i, a, s: (i[:, :5], a, s), r"infant: expected poses of shape \(N, 12, 3\)"),
        (lambda i, a, s: (i, a[..., :2], s), "augmented: expected poses"),
        (lambda i, a, s: (i, a, s[:-1]), "sources: shape"),
        (lambda i, a, s: (i[:0], a, s), "infant: no poses"),
        (lambda i, a, s: (i, a, np.where(np.arange(12)[None, :, None] == 3, np.nan, s)), "sources: 30 poses"),
        (lambda i, a, s: (i, a[0], s[0]), "augmented: expected poses"),
    ],
)
def test_bad_inputs_raise_config_error(tmp_path: Path, change, match: str) -> None:
    infant, augmented, sources = change(*make_sets())
    with pytest.raises(ConfigError, match=match):
        write_augmentation_plots(tmp_path, SKELETON, infant, augmented, sources)
    with pytest.raises(ConfigError, match="pairs"):
        write_augmentation_plots(tmp_path, SKELETON, *make_sets(), pairs=0)
    assert list(tmp_path.iterdir()) == []
