"""Tests of rotations and Procrustes alignment (zedo_cli.rotation)."""

from __future__ import annotations

import numpy as np
import torch

from zedo_cli.evaluation.metrics import mpjpe_mm
from zedo_cli.rotation import procrustes_align, quaternion_to_matrix, random_rotations


def _assert_rotations(r: torch.Tensor | np.ndarray) -> None:
    r = np.asarray(r, dtype=np.float64)
    eye = np.broadcast_to(np.eye(3), r.shape)
    np.testing.assert_allclose(np.swapaxes(r, -1, -2) @ r, eye, atol=1e-10)
    np.testing.assert_allclose(np.linalg.det(r), 1.0, atol=1e-10)


def _random_pose(seed: int, n: int = 6, joints: int = 12) -> np.ndarray:
    return 0.2 * np.random.default_rng(seed).normal(size=(n, joints, 3))


def test_quaternion_to_matrix_is_orthonormal_for_unnormalised_quaternions() -> None:
    g = torch.Generator().manual_seed(0)
    q = 3.0 * torch.randn(50, 4, generator=g, dtype=torch.float64)
    r = quaternion_to_matrix(q)
    assert r.shape == (50, 3, 3)
    _assert_rotations(r)


def test_quaternion_to_matrix_is_scale_invariant() -> None:
    g = torch.Generator().manual_seed(1)
    q = torch.randn(20, 4, generator=g, dtype=torch.float64)
    scale = 0.1 + 5.0 * torch.rand(20, 1, generator=g, dtype=torch.float64)
    np.testing.assert_allclose(quaternion_to_matrix(q * scale), quaternion_to_matrix(q), atol=1e-12)
    # q and -q are the same rotation.
    np.testing.assert_allclose(quaternion_to_matrix(-q), quaternion_to_matrix(q), atol=1e-12)


def test_quaternion_to_matrix_known_values() -> None:
    identity = quaternion_to_matrix(torch.tensor([2.0, 0.0, 0.0, 0.0], dtype=torch.float64))
    np.testing.assert_allclose(identity, np.eye(3), atol=1e-15)
    # 90 degrees about z, (w, x, y, z) = (cos 45, 0, 0, sin 45): x axis -> y axis.
    half = np.sqrt(0.5)
    rz = quaternion_to_matrix(torch.tensor([half, 0.0, 0.0, half], dtype=torch.float64)).numpy()
    np.testing.assert_allclose(rz @ np.array([1.0, 0.0, 0.0]), [0.0, 1.0, 0.0], atol=1e-12)


def test_quaternion_to_matrix_batches_over_leading_dims() -> None:
    q = torch.randn(2, 3, 4, generator=torch.Generator().manual_seed(2), dtype=torch.float64)
    r = quaternion_to_matrix(q)
    assert r.shape == (2, 3, 3, 3)
    np.testing.assert_allclose(r[1, 2], quaternion_to_matrix(q[1, 2]), atol=0)


def test_random_rotations_are_rotations_and_seeded() -> None:
    r = random_rotations(40, torch.Generator().manual_seed(3))
    assert r.shape == (40, 3, 3) and r.dtype == torch.float64
    _assert_rotations(r)
    again = random_rotations(40, torch.Generator().manual_seed(3))
    assert torch.equal(r, again)
    other = random_rotations(40, torch.Generator().manual_seed(4))
    assert not torch.allclose(r, other)


def test_procrustes_recovers_a_similarity_transformed_pose() -> None:
    target = _random_pose(5)
    rot = random_rotations(target.shape[0], torch.Generator().manual_seed(5)).numpy()
    scale = np.array([0.5, 1.0, 1.7, 2.5, 0.9, 3.0])[:, None, None]
    shift = np.random.default_rng(6).normal(size=(target.shape[0], 1, 3))
    pred = scale * (target @ rot) + shift
    aligned = procrustes_align(pred, target)
    np.testing.assert_allclose(aligned, target, atol=1e-10)
    assert mpjpe_mm(aligned, target) < 1e-6


def test_procrustes_does_not_reflect() -> None:
    target = _random_pose(7)
    mirrored = target * np.array([-1.0, 1.0, 1.0])
    aligned = procrustes_align(mirrored, target)
    # A reflection would map the mirror image back exactly; a proper rotation cannot.
    assert mpjpe_mm(aligned, target) > 10.0
    # The rotation that was used is proper: the aligned pose is a rotated and scaled mirror.
    c_aligned = aligned - aligned.mean(axis=-2, keepdims=True)
    c_mirror = mirrored - mirrored.mean(axis=-2, keepdims=True)
    for a, m in zip(c_aligned, c_mirror, strict=True):
        r, *_ = np.linalg.lstsq(m, a, rcond=None)
        s = np.cbrt(np.linalg.det(r))
        assert s > 0
        _assert_rotations(r / s)


def test_procrustes_single_pose_without_batch() -> None:
    target = _random_pose(8)[0]
    rot = random_rotations(1, torch.Generator().manual_seed(8)).numpy()[0]
    pred = 1.3 * target @ rot + np.array([0.1, -0.2, 2.0])
    np.testing.assert_allclose(procrustes_align(pred, target), target, atol=1e-10)
