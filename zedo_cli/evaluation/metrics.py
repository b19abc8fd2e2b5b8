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


def cohen_kappa(a: np.ndarray, b: np.ndarray) -> float:
    """Cohen's kappa of two raters' labels `a`, `b` `(N,)` (any hashable labels): (p_o - p_e) / (1 - p_e),
    p_o the observed agreement, p_e the agreement expected from each rater's label frequencies.
    NaN when p_e = 1 (both raters gave one and the same label to everything)."""
    a, b = np.asarray(a), np.asarray(b)
    if a.shape != b.shape or a.ndim != 1 or not len(a):
        raise ValueError("cohen_kappa needs two label arrays of the same length > 0")
    labels = np.union1d(a, b)
    p_o = float((a == b).mean())
    p_e = float(sum((a == k).mean() * (b == k).mean() for k in labels))
    return (p_o - p_e) / (1.0 - p_e) if p_e < 1.0 else float("nan")


def decisive_calls(low: np.ndarray, high: np.ndarray, truth: np.ndarray, threshold: float
                   ) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """Symmetry calls from intervals: a call is decisive where the interval lies on one side of the threshold
    (symmetric: `high <= threshold`; asymmetric: `low > threshold`), and agrees where it is the truth's call
    (symmetric: `truth <= threshold`). Returns the masks (decisive, decisive and agreeing)."""
    symmetric = high <= threshold
    decisive = symmetric | (low > threshold)
    return decisive, decisive & (symmetric == (truth <= threshold))
