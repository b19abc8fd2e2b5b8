"""Per-clip movement features of joint-angle time series, in the style of General Movements
Assessment research (e.g. Chambers et al. 2020, "Computer vision to automatically assess infant
neuromotor risk"): how fast the joints move, how variable that is, how much they move, and how
alike the two sides move.

For one person's series `theta_t` (degrees, one value per frame, NaN where unknown) at `fps`:

- angular velocity v_t = (theta_{t+k} - theta_t) / (k / fps) between consecutive known frames
  k frames apart (a gap is bridged, not filled), the difference wrapped into [-180, 180);
- `median_abs_velocity`: the median of |v| (deg/s); `abs_velocity_iqr`: its interquartile
  range (75th - 25th percentile);
- `range`: max - min of theta over the clip (degrees), the range of motion;
- `left_right_correlation`: Pearson's r between the left and the right series of an angle over
  the frames where both are known (NaN when either is constant or fewer than 3 frames).

Frames are taken as evenly spaced at `fps` by their frame index. A clip needs at least 3 known
frames; otherwise the features are NaN.
"""

from __future__ import annotations

import numpy as np

from ...stats import pearson

MIN_FRAMES = 3


def angular_velocity(frames: np.ndarray, theta: np.ndarray, fps: float) -> np.ndarray:
    """Velocities (deg/s) between consecutive known frames of `theta (T,)` at `frames (T,)`."""
    ok = np.isfinite(theta)
    f, t = frames[ok].astype(float), theta[ok]
    if len(t) < 2:
        return np.zeros(0)
    d = (np.diff(t) + 180.0) % 360.0 - 180.0
    return d * fps / np.diff(f)


def series_features(frames: np.ndarray, theta: np.ndarray, fps: float) -> dict[str, float]:
    """median_abs_velocity (deg/s), abs_velocity_iqr (deg/s), range (deg) of one series."""
    known = theta[np.isfinite(theta)]
    if len(known) < MIN_FRAMES:
        return {"median_abs_velocity": np.nan, "abs_velocity_iqr": np.nan, "range": np.nan}
    speed = np.abs(angular_velocity(frames, theta, fps))
    q25, q50, q75 = np.percentile(speed, [25.0, 50.0, 75.0])
    return {"median_abs_velocity": float(q50), "abs_velocity_iqr": float(q75 - q25),
            "range": float(known.max() - known.min())}  # fmt: skip


def left_right_correlation(left: np.ndarray, right: np.ndarray) -> float:
    """Pearson's r of two series over the frames where both are known."""
    return pearson(left, right, min_count=MIN_FRAMES)
