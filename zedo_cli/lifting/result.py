"""`LiftResult`: what a lift gives, a plain record of numpy arrays (no torch), so that the writers,
the readers of stored results (`formats.export`) and the CLI's option handling can use it
without loading the network code."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .config import LiftConfig

LIFTED = "lifted"  # `LiftResult.status` of a lifted instance; else a reason (`solver.NOT_LIFTED`)


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

    def __post_init__(self) -> None:
        if self.status is None:  # results built by hand know only "lifted" and "too few joints"
            self.status = np.where(self.lifted, LIFTED, "too_few_observed_joints").astype(object)
