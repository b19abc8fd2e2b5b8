"""How well a lifted pose reproduces its 2D: the reprojection error of each joint (through the lens where there
is one), and the poor-fit test a lift applies after lifting and the temporal modes again after smoothing."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import torch

from ..camera.model import CameraModel, lens_groups
from .camera import project

# A lifted pose whose mean reprojection error exceeds this fraction of the RMS radius of its
# observed 2D joints does not reproduce its detection. SyRIP's 1400 real poses (GT and FiDIP 2D,
# `fast`) stay below 0.18 (with exact rays, ray_weight 1: 0.04); tiny noisy detections drawn to the
# camera reach 1 to 5.
MAX_REPROJECTION_RATIO = 0.5


def poor_fit(xy: np.ndarray, observed: np.ndarray, reproj: np.ndarray) -> np.ndarray:
    """Poses `(N,)` whose mean reprojection error `reproj (N, J)` px over their `observed (N, J)`
    joints exceeds MAX_REPROJECTION_RATIO times the RMS radius of those joints' pixels `xy (N, J, 2)`
    about their centre: the pose does not reproduce its detection (NaN errors count as poor).
    Checked after lifting (`status` poor_fit), and again after the temporal mode's smoothing."""
    with np.errstate(all="ignore"):
        count = np.maximum(observed.sum(1), 1)
        centre = np.where(observed[..., None], xy, 0.0).sum(1) / count[:, None]  # (N, 2)
        radius = np.sqrt(np.where(observed, ((xy - centre[:, None]) ** 2).sum(-1), 0.0).sum(1) / count)
        mean_error = np.where(observed, reproj, 0.0).sum(1) / count
        return ~(mean_error <= MAX_REPROJECTION_RATIO * radius)


def reprojection_error_px(
    cam: np.ndarray, xy: np.ndarray, k: np.ndarray, obs: np.ndarray, cameras: Sequence[CameraModel | None] | None = None
) -> np.ndarray:
    """Pixel distances `(N, J)` between the 2D `xy` and the points `cam (N, J, 3)` projected
    through K `(N, 3, 3)`, or through the lens of an instance's camera with distortion
    (`cameras`, as in `lift`); NaN where not observed."""
    uv = project(torch.as_tensor(cam), torch.as_tensor(k, dtype=torch.float64)).numpy()
    for camera, idx in lens_groups(cameras).items():
        uv[idx] = camera.project(cam[idx])
    err = np.linalg.norm(uv - xy, axis=-1)
    return np.where(obs, err, np.nan)
