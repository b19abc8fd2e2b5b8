"""Anatomical plausibility and symmetry-angle agreement of lifted poses .

- Twin-limb ratio (`data.skeleton.twin_limb_ratio`): per pose, the largest longer/shorter ratio
  of a left/right upper arm, forearm, thigh or shank; reported as the fractions of poses above
  1.3 and 1.6 (SyRIP's weak ground truth, Test100: 11 % and 1 %).
- Symmetry-angle error: the mean absolute difference, over poses and the four pairs, between
  the symmetry angles (`analysis.pose.symmetry`, Huang et al. 2022) of the lifted poses and of the
  ground truth.
"""

from __future__ import annotations

import numpy as np

from ..analysis.pose.symmetry import symmetry_angles
from ..data.skeleton import Skeleton, twin_limb_ratio

TWIN_RATIO_THRESHOLDS = (1.3, 1.6)


def twin_ratio_fractions(poses: np.ndarray, skeleton: Skeleton) -> dict[float, float]:
    """Fraction of the (finite) poses `(N, J, 3)` whose twin-limb ratio exceeds each threshold."""
    ratio = twin_limb_ratio(poses, skeleton)
    ratio = ratio[np.isfinite(ratio)]
    return {t: float((ratio > t).mean()) if len(ratio) else float("nan") for t in TWIN_RATIO_THRESHOLDS}


def symmetry_angle_error_deg(pred: np.ndarray, truth: np.ndarray, skeleton: Skeleton) -> float:
    """Mean absolute symmetry-angle difference (degrees) of `pred` and `truth` `(N, J, 3)`."""
    a, b = symmetry_angles(pred, skeleton), symmetry_angles(truth, skeleton)
    diffs = np.stack([np.abs(a[k] - b[k]) for k in a], axis=-1)
    return float(np.nanmean(diffs))
