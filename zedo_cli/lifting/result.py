"""`LiftResult`: what a lift gives, a plain record of numpy arrays (no torch), so that the writers,
the readers of stored results (`formats.export`) and the CLI's option handling can use it
without loading the network code."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .config import LiftConfig

LIFTED = "lifted"  # `LiftResult.status` of a lifted instance; else a reason (`solver.NOT_LIFTED`)
# A pose whose K hypotheses lie further apart than this (`hypothesis_spread_m`) may land in another
# solution (a limb or the whole pose at another depth): flagged `unstable_solution`. Chosen on held-out
# SyRIP folds (benchmarks/accuracy/hypothesis_spread.py; docs/lifting.md, "Same answer on every machine").
UNSTABLE_SPREAD_M = 0.08


def joint_spread(hypotheses: np.ndarray | None, reported: np.ndarray) -> np.ndarray:
    """RMS distance `(N, J)` of the hypotheses `(N, K, J, 3)` (NaN: unusable) from the reported
    root-relative poses `(N, J, 3)`; 0 without hypotheses."""
    if hypotheses is None:
        return np.zeros(reported.shape[:2])
    d2 = ((hypotheses - reported[:, None]) ** 2).sum(-1)  # (N, K, J)
    usable = np.isfinite(d2)
    count = usable.sum(axis=1)
    # NaN where no hypothesis is usable (an instance not lifted), without nanmean's empty-slice warning
    mean = np.where(usable, d2, 0.0).sum(axis=1) / np.maximum(count, 1)
    return np.where(count > 0, np.sqrt(mean), np.nan)


def hypothesis_spread(hypotheses: np.ndarray, reported: np.ndarray) -> np.ndarray:
    """Per pose `(N,)`, the largest over joints of `joint_spread`: how far (metres, RMS over the
    usable hypotheses) the hypotheses `(N, K, J, 3)` lie from the reported pose `(N, J, 3)` at
    their most different joint; NaN where fewer than two hypotheses are usable (nothing to compare)."""
    spread = joint_spread(hypotheses, reported)
    usable = np.isfinite(hypotheses).all(axis=(2, 3)).sum(1)
    measured = (usable >= 2) & np.isfinite(spread).all(1)
    return np.where(measured, np.nan_to_num(spread).max(1, initial=0.0), np.nan)


@dataclass
class LiftResult:
    """3D poses in metres, camera frame (x right, y down, z forward). NaN where not lifted."""

    poses_camera: np.ndarray  # (N, J, 3)
    poses_root_relative: np.ndarray  # (N, J, 3), root point at the origin
    root_translation: np.ndarray  # (N, 3), the root point in the camera frame
    reprojection_error_px: np.ndarray  # (N, J), NaN for joints that were not observed
    observed: np.ndarray  # (N, J) bool, joints used as ray constraints
    lifted: np.ndarray  # (N,) bool, False for instances that were not lifted (see `status`)
    config: LiftConfig
    seconds: float
    status: np.ndarray | None = None  # (N,) str (object array): "lifted" or a key of NOT_LIFTED; None: from `lifted`
    # (N, K, J, 3) root-relative poses of the K hypotheses (`config.hypotheses`), NaN for those not
    # lifted (and for all but hypothesis 0 of warm-started instances); None when K = 1.
    hypotheses: np.ndarray | None = None
    # (N, J) calibrated 90 % radii in metres around the root-relative joints (uncertainty.py), NaN
    # where not lifted; None when no calibration fits the prior and settings (`uncertainty_note` says why).
    uncertainty_m: np.ndarray | None = None
    uncertainty_note: str = "not computed"
    uncertainty_coverage: float | None = None  # the probability the radii hold (the calibration's)
    # (N,) `hypothesis_spread`, NaN where not lifted; None when K = 1 (nothing to compare).
    hypothesis_spread_m: np.ndarray | None = None
    # (N, J) joints whose depth side the 2D cannot tell (`--temporal clip`: the limb's stretch between two
    # passages near the image plane); None: not measured (the other modes).
    depth_ambiguous: np.ndarray | None = None
    # (N, J) at a depth-ambiguous ankle or wrist, the knee's or elbow's flexion (degrees, 0 = straight) had the limb
    # taken the other side; NaN elsewhere; None: not measured
    other_flexion_deg: np.ndarray | None = None
    # `--temporal clip`: each track's skeleton as the result's params record it (`clip.TrackSkeleton.to_dict`).
    track_skeletons: list[dict] | None = None
    # `--temporal clip`: instances `(N,)` whose 2D left and right were exchanged (corrected before lifting), and
    # joints `(N, J)` far off their own path in 2D (not used); None: not looked for (`detections.py`).
    detection_swapped: np.ndarray | None = None
    detection_outliers: np.ndarray | None = None

    def unstable(self) -> np.ndarray | None:
        """`(N,)` lifted poses whose hypotheses spread over UNSTABLE_SPREAD_M; None when K = 1."""
        if self.hypothesis_spread_m is None:
            return None
        with np.errstate(invalid="ignore"):
            return self.lifted & (self.hypothesis_spread_m > UNSTABLE_SPREAD_M)

    def __post_init__(self) -> None:
        if self.status is None:  # results built by hand know only "lifted" and "too few joints"
            self.status = np.where(self.lifted, LIFTED, "too_few_observed_joints").astype(object)
