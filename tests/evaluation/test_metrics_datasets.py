"""Tests of the pose metrics (zedo_cli.evaluation.metrics) and the 3D pose loaders (zedo_cli.data.datasets).

The SyRIP tests read the shared data folder and skip when it is absent."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import torch

from zedo_cli.data.datasets import PoseSet, load_npz_poses, load_syrip_3d
from zedo_cli.data.skeleton import get_skeleton, root_point
from zedo_cli.errors import ConfigError, DataError
from zedo_cli.evaluation.metrics import mpjpe_mm, pa_mpjpe_mm, pa_per_joint_error_mm, per_joint_error_mm
from zedo_cli.rotation import random_rotations

SYRIP = Path(__file__).resolve().parents[3] / "shared/data/syrip"
H36M = get_skeleton("h36m17")
SYRIP12 = get_skeleton("syrip12")


def _poses(n: int, joints: int, seed: int) -> np.ndarray:
    return 0.2 * np.random.default_rng(seed).normal(size=(n, joints, 3))


def _with_nan() -> np.ndarray:
    poses = _poses(2, 17, 0)
    poses[1, 4, 2] = np.nan
    return poses


UNKNOWN_NAMES = np.array([f"j{i}" for i in range(17)])


# --- metrics -------------------------------------------------------------------------------


def test_mpjpe_of_identical_poses_is_zero_and_of_a_shift_is_the_shift() -> None:
    target = _poses(5, 12, 0)
    assert mpjpe_mm(target, target) == 0.0
    shift = np.array([0.006, 0.0, 0.008])  # 10 mm
    assert mpjpe_mm(target + shift, target) == pytest.approx(10.0, abs=1e-9)
    errors = per_joint_error_mm(target + shift, target)
    assert errors.shape == (5, 12)
    np.testing.assert_allclose(errors, 10.0, atol=1e-9)


def test_mpjpe_is_mean_over_joints_then_poses() -> None:
    target = np.zeros((2, 2, 3))
    pred = target.copy()
    pred[0, 0, 0] = 0.004  # 4 mm on one joint
    assert mpjpe_mm(pred, target) == pytest.approx(1.0)


def test_pa_mpjpe_is_invariant_to_a_similarity_transform_of_the_prediction() -> None:
    target = _poses(6, 12, 1)
    pred = target + 0.01 * np.random.default_rng(2).normal(size=target.shape)
    base = pa_mpjpe_mm(pred, target)
    assert 0.0 < base < mpjpe_mm(pred, target) + 1e-9
    rot = random_rotations(6, torch.Generator().manual_seed(3)).numpy()
    scale = np.array([0.3, 1.0, 2.0, 5.0, 0.8, 1.2])[:, None, None]
    moved = scale * (pred @ rot) + np.array([0.5, -1.0, 3.0])
    assert pa_mpjpe_mm(moved, target) == pytest.approx(base, rel=1e-8)
    np.testing.assert_allclose(pa_per_joint_error_mm(moved, target), pa_per_joint_error_mm(pred, target), atol=1e-8)


def test_pa_mpjpe_of_a_similarity_copy_is_zero() -> None:
    target = _poses(3, 17, 4)
    rot = random_rotations(3, torch.Generator().manual_seed(5)).numpy()
    assert pa_mpjpe_mm(2.0 * target @ rot + 1.0, target) < 1e-6


def test_benchmark_scores_leave_out_poses_that_were_not_lifted() -> None:
    from zedo_cli.evaluation.syrip_benchmark import lifted_rows, score_poses

    target = _poses(4, 12, 6)
    pred = target + 0.01 * np.random.default_rng(7).normal(size=target.shape)
    pred[2] = np.nan  # a person the lift refused: NaN, as LiftResult reports it
    assert lifted_rows(pred).tolist() == [True, True, False, True]
    keep = [0, 1, 3]
    mpjpe, pa, per_joint = score_poses(pred, target, SYRIP12.joints)
    assert mpjpe == pytest.approx(mpjpe_mm(pred[keep], target[keep]))
    assert pa == pytest.approx(pa_mpjpe_mm(pred[keep], target[keep]))  # no SVD of NaN
    assert set(per_joint) == set(SYRIP12.joints) and all(np.isfinite(v) for v in per_joint.values())
    none = score_poses(np.full_like(pred, np.nan), target, SYRIP12.joints)
    assert np.isnan(none[0]) and np.isnan(none[1]) and all(np.isnan(v) for v in none[2].values())


# --- npz loader ----------------------------------------------------------------------------


def _write_npz(path: Path, **arrays: np.ndarray) -> Path:
    np.savez(path, **arrays)
    return path


def test_load_npz_poses_detects_skeleton_and_centres_on_pelvis(tmp_path: Path) -> None:
    poses = _poses(4, 17, 6) + np.array([0.1, 0.2, 3.0])
    path = _write_npz(tmp_path / "poses.npz", poses=poses, joint_names=np.array(H36M.joints))
    data = load_npz_poses(path)
    assert isinstance(data, PoseSet)
    assert data.skeleton.name == "h36m17"
    assert data.poses.shape == (4, 17, 3) and data.poses.dtype == np.float64
    np.testing.assert_allclose(data.poses[:, H36M.index("pelvis")], 0.0, atol=1e-12)
    np.testing.assert_allclose(data.poses, poses - poses[:, :1], atol=1e-12)
    assert data.names == ["0", "1", "2", "3"]
    assert data.summary() == {"source": str(path), "count": 4, "skeleton": "h36m17"}


def test_load_npz_poses_with_explicit_skeleton_and_names(tmp_path: Path) -> None:
    poses = _poses(2, 12, 7)
    path = _write_npz(tmp_path / "p.npz", poses=poses, names=np.array(["a.jpg", "b.jpg"]))
    data = load_npz_poses(path, skeleton="syrip12")
    assert data.skeleton.name == "syrip12"
    assert data.names == ["a.jpg", "b.jpg"]
    np.testing.assert_allclose(root_point(data.poses, SYRIP12), 0.0, atol=1e-12)


def test_load_npz_poses_unknown_skeleton_name_is_config_error(tmp_path: Path) -> None:
    path = _write_npz(tmp_path / "p.npz", poses=_poses(2, 12, 8))
    with pytest.raises(ConfigError, match="nope"):
        load_npz_poses(path, skeleton="nope")


@pytest.mark.parametrize(
    ("arrays", "skeleton", "needle"),
    [
        ({"pose": _poses(2, 17, 0)}, "h36m17", "no 'poses'"),
        ({"poses": _poses(2, 17, 0)[..., :2]}, "h36m17", "shape"),
        ({"poses": _poses(2, 17, 0).reshape(2, 51)}, "h36m17", "shape"),
        ({"poses": np.zeros((0, 17, 3))}, "h36m17", "shape"),
        ({"poses": _with_nan()}, "h36m17", "NaN"),
        ({"poses": _poses(2, 17, 0), "joint_names": UNKNOWN_NAMES}, None, "skeleton"),
        ({"poses": _poses(2, 17, 0)}, None, "joint_names"),
        ({"poses": _poses(2, 17, 0)}, "syrip12", "17 joints"),
        ({"poses": _poses(2, 12, 0), "joint_names": np.array(H36M.joints)}, None, "12 joints"),
    ],
)
def test_load_npz_poses_errors_name_the_file(
    tmp_path: Path, arrays: dict[str, np.ndarray], skeleton: str | None, needle: str
) -> None:
    path = _write_npz(tmp_path / "bad_poses.npz", **arrays)
    with pytest.raises(DataError) as info:
        load_npz_poses(path, skeleton=skeleton)
    assert "bad_poses.npz" in str(info.value)
    assert needle in str(info.value)


def test_load_npz_poses_missing_or_unreadable_file(tmp_path: Path) -> None:
    with pytest.raises(DataError, match="absent.npz"):
        load_npz_poses(tmp_path / "absent.npz")
    garbage = tmp_path / "garbage.npz"
    garbage.write_bytes(b"this is not an npz file")
    with pytest.raises(DataError, match="garbage.npz"):
        load_npz_poses(garbage, skeleton="h36m17")


def test_load_npz_poses_rejects_a_plain_npy_file(tmp_path: Path) -> None:
    path = tmp_path / "poses.npy"
    np.save(path, _poses(2, 17, 9))
    with pytest.raises(DataError, match="poses.npy"):
        load_npz_poses(path, skeleton="h36m17")


def test_load_npz_poses_rejects_names_of_the_wrong_length(tmp_path: Path) -> None:
    path = _write_npz(tmp_path / "p.npz", poses=_poses(3, 17, 10), names=np.array(["only_one"]))
    with pytest.raises(DataError, match="names"):
        load_npz_poses(path, skeleton="h36m17")


# --- SyRIP ---------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def syrip_dir() -> Path:
    if not SYRIP.is_dir():
        pytest.skip(f"SyRIP data folder not found at {SYRIP}")
    return SYRIP


@pytest.fixture(scope="module")
def syrip_splits(syrip_dir: Path) -> dict[str, PoseSet]:
    return {split: load_syrip_3d(syrip_dir, split) for split in ("train", "test", "all")}


def test_syrip_split_sizes(syrip_splits: dict[str, PoseSet]) -> None:
    assert {k: len(v.names) for k, v in syrip_splits.items()} == {"train": 600, "test": 100, "all": 700}
    for data in syrip_splits.values():
        assert data.poses.shape == (len(data.names), 12, 3)
        assert data.skeleton.name == "syrip12"
        assert np.isfinite(data.poses).all()


def test_syrip_train_and_test_are_disjoint_and_cover_all(syrip_splits: dict[str, PoseSet]) -> None:
    train, test, every = (set(syrip_splits[s].names) for s in ("train", "test", "all"))
    assert len(train) == 600 and len(test) == 100 and len(every) == 700
    assert not train & test
    assert train | test == every


def test_syrip_poses_are_centred_on_the_hip_midpoint(syrip_splits: dict[str, PoseSet]) -> None:
    for data in syrip_splits.values():
        np.testing.assert_allclose(root_point(data.poses, SYRIP12), 0.0, atol=1e-9)


def test_syrip_poses_are_infant_sized_in_metres(syrip_splits: dict[str, PoseSet]) -> None:
    poses = syrip_splits["all"].poses
    thigh = np.linalg.norm(poses[:, SYRIP12.index("left_hip")] - poses[:, SYRIP12.index("left_knee")], axis=-1)
    assert 0.05 < float(np.median(thigh)) < 0.15  # ALGORITHM.md 1.1: median thigh 0.093 m


def test_syrip_test_order_follows_the_annotation_file(syrip_dir: Path, syrip_splits: dict[str, PoseSet]) -> None:
    doc = json.loads((syrip_dir / "keypoints2d_gt_test100.json").read_text())
    assert syrip_splits["test"].names == [str(img["file_name"]) for img in doc["images"]]


def test_syrip_all_poses_match_train_and_test_by_name(syrip_splits: dict[str, PoseSet]) -> None:
    every = dict(zip(syrip_splits["all"].names, syrip_splits["all"].poses, strict=True))
    for split in ("train", "test"):
        data = syrip_splits[split]
        for name, pose in zip(data.names, data.poses, strict=True):
            np.testing.assert_array_equal(pose, every[name])


def test_syrip_unknown_split_and_missing_folder(tmp_path: Path) -> None:
    with pytest.raises(DataError, match="absent"):
        load_syrip_3d(tmp_path / "absent", "train")
    with pytest.raises(DataError, match="valid"):
        load_syrip_3d(tmp_path, "valid")
    # A folder without the SyRIP files names the first missing file.
    with pytest.raises(DataError, match="poses3d_corrected.npy"):
        load_syrip_3d(tmp_path, "train")
