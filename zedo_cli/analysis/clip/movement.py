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
frames; otherwise the features are NaN. `movement_values` gathers them for the joint angles of one
person's rows (a whole clip, or an epoch of it), by the names of the analysis rows.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ...stats import pearson
from ..pose.joint_angles import ANGLE_BASES, ANGLE_NAMES, SIDES, angle_name
from ..pose.symmetry import PAIRS, measure_name

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


def movement_values(frames: np.ndarray, sel: np.ndarray, fps: float, *, estimates: Mapping[str, np.ndarray],
                    own: Mapping[str, np.ndarray], too_fast: Mapping[str, np.ndarray]) -> dict[str, float]:  # fmt: skip
    """The measured clip features of the rows `sel` of per-row series `(M,)` at `frames (M,)`, by their analysis
    row names: each joint angle's median |velocity|, its IQR and range (its `too_fast` rows left out), each angle's
    left-right correlation, and each symmetry pair's median of the frames' `own` angles where an estimate exists."""
    out: dict[str, float] = {}
    for name in ANGLE_NAMES:
        keep = sel & ~too_fast.get(name, np.zeros(len(sel), bool))
        feats = series_features(frames[keep], estimates[name][keep], fps)
        stem = name.removesuffix("_deg")
        out[f"{stem}_median_abs_velocity_deg_s"] = feats["median_abs_velocity"]
        out[f"{stem}_abs_velocity_iqr_deg_s"] = feats["abs_velocity_iqr"]
        out[f"{stem}_range_deg"] = feats["range"]
    for base in ANGLE_BASES:
        left, right = (estimates[angle_name(side, base)][sel] for side in SIDES)
        out[f"{base}_left_right_correlation"] = left_right_correlation(left, right)
    for name in (measure_name(pair) for pair in PAIRS):
        values = own[name][sel & np.isfinite(estimates[name])]
        median = float(np.nanmedian(values)) if np.isfinite(values).any() else np.nan
        out[name.removesuffix("_deg") + "_median_deg"] = median
    return out
