"""Pose error metrics. Pure functions; units are in the names. Inputs in metres."""

from __future__ import annotations

import numpy as np

from ..rotation import procrustes_align


def per_joint_error_mm(pred: np.ndarray, target: np.ndarray) -> np.ndarray:
    """Euclidean error `(N, J)` in mm between `pred` and `target` `(N, J, 3)` in metres."""
    return 1000.0 * np.linalg.norm(pred - target, axis=-1)


def mpjpe_mm(pred: np.ndarray, target: np.ndarray) -> float:
    """Mean per-joint position error in mm (mean over joints, then over poses)."""
    return float(per_joint_error_mm(pred, target).mean())


def pa_per_joint_error_mm(pred: np.ndarray, target: np.ndarray) -> np.ndarray:
    """Per-joint error `(N, J)` in mm after similarity Procrustes alignment (no reflections)."""
    return per_joint_error_mm(procrustes_align(pred, target), target)


def pa_mpjpe_mm(pred: np.ndarray, target: np.ndarray) -> float:
    """MPJPE in mm after aligning each prediction to its target by scale, rotation, translation."""
    return float(pa_per_joint_error_mm(pred, target).mean())
