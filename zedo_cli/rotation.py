"""Rotations and Procrustes alignment. Pure functions."""

from __future__ import annotations

import numpy as np
import torch


def quaternion_to_matrix(q: torch.Tensor) -> torch.Tensor:
    """Rotation matrices `(..., 3, 3)` of quaternions `q (..., 4)` = (w, x, y, z).

    Uses the 2/|q|^2 scaling, so `q` need not be unit length (ZeDO's initial fit optimises an
    unnormalised quaternion).
    """
    w, x, y, z = q.unbind(-1)
    s = 2.0 / (q * q).sum(-1)
    rows = [
        1 - s * (y * y + z * z), s * (x * y - z * w), s * (x * z + y * w),
        s * (x * y + z * w), 1 - s * (x * x + z * z), s * (y * z - x * w),
        s * (x * z - y * w), s * (y * z + x * w), 1 - s * (x * x + y * y),
    ]  # fmt: skip
    return torch.stack(rows, dim=-1).reshape(*q.shape[:-1], 3, 3)


def random_rotations(n: int, generator: torch.Generator) -> torch.Tensor:
    """`n` rotation matrices `(n, 3, 3)` drawn uniformly from SO(3) (normalised Gaussian quaternions)."""
    q = torch.randn(n, 4, generator=generator, dtype=torch.float64)
    return quaternion_to_matrix(q / q.norm(dim=-1, keepdim=True))


def _kabsch(p0: np.ndarray, t0: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The rotation `(..., 3, 3)` (row vectors: p0 @ rot) that best maps centred `p0` onto centred
    `t0`, reflections excluded, and the singular values with the reflection fix applied."""
    cov = np.swapaxes(p0, -1, -2) @ t0  # (..., 3, 3)
    u, sing, vt = np.linalg.svd(cov)
    d = np.sign(np.linalg.det(u @ vt))  # -1 where the best orthogonal map is a reflection
    fix = np.ones(sing.shape)
    fix[..., -1] = d
    return (u * fix[..., None, :]) @ vt, sing * fix


def best_rotation(src: np.ndarray, dst: np.ndarray) -> np.ndarray:
    """The rotation about the origin (row vectors: src @ rot) that best fits `src (..., K, 3)` to
    `dst (..., K, 3)` in least squares, with no scaling or translation."""
    return _kabsch(src, dst)[0]


def procrustes_align(pred: np.ndarray, target: np.ndarray) -> np.ndarray:
    """`pred (..., J, 3)` after the similarity transform (scale, rotation, translation) that best
    fits it to `target` in least squares. Reflections are excluded (det R = +1)."""
    mu_p = pred.mean(axis=-2, keepdims=True)
    mu_t = target.mean(axis=-2, keepdims=True)
    p0 = pred - mu_p
    rot, sing = _kabsch(p0, target - mu_t)
    scale = sing.sum(-1) / (p0**2).sum(axis=(-1, -2))
    return scale[..., None, None] * (p0 @ rot) + mu_t
