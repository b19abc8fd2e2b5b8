"""Clips made atypical by construction: some joints held still in the trunk's frame while the rest moves (a limb
that does not move, the kind of one-sided difference the comparison with typical infants must catch)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np


def trunk_axes(poses: np.ndarray, joints: Sequence[str]) -> tuple[np.ndarray, np.ndarray]:
    """Per frame an orthonormal trunk frame `(T, 3, 3)` (rows: left, up, front) and its origin `(T, 3)`, the
    shoulders' midpoint, of poses `(T, J, 3)`."""
    at = {n: i for i, n in enumerate(joints)}
    ls, rs, lh, rh = (poses[:, at[n]] for n in ("left_shoulder", "right_shoulder", "left_hip", "right_hip"))
    origin = (ls + rs) / 2
    up = origin - (lh + rh) / 2
    up /= np.linalg.norm(up, axis=-1, keepdims=True)
    left = (ls - rs) + (lh - rh)
    left -= (left * up).sum(-1, keepdims=True) * up
    left /= np.linalg.norm(left, axis=-1, keepdims=True)
    front = np.cross(left, up)
    return np.stack([left, up, front], 1), origin


def hold_still(poses: np.ndarray, joints: Sequence[str], held: Sequence[str]) -> np.ndarray:
    """`poses (T, J, 3)` with the `held` joints kept at their first frame's coordinates in the trunk's frame."""
    axes, origin = trunk_axes(poses, joints)
    out = poses.copy()
    for name in held:
        i = list(joints).index(name)
        local = axes[0] @ (poses[0, i] - origin[0])  # (3,) in the first frame's trunk axes
        out[:, i] = origin + np.einsum("tij,i->tj", axes, local)
    return out
