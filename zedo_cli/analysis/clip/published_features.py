"""The clip features of Chambers et al. 2020 (IEEE TNSRE 28:2431), computed as their published code
computes them (github cchamber/Infant_movement_assessment: src/modules/util_data.py,
src/data/build_features.py, src/data/merge_data_sets.py), from one person's 2D keypoints. Written
anew in numpy from the steps of that code; docs/movement.md lists every step and the quirks kept.

    f = published_features(xy, fps, image_size)     # xy (T, J, 2) pixels by frame 0..T-1, skeleton order
    f.values["medianx_LAnkle"], f.values["Knee_lrCorr_angle"], f.reasons[name]

The steps, for 13 points (12 body joints and the neck, the shoulders' midpoint where both are seen):

1. x and y minus the image centre, divided by the image height;
2. each coordinate linearly interpolated over gaps (leading NaNs stay, trailing ones take the last value);
3. a centred rolling median, then a centred rolling mean, of w = int(0.5 fps) frames (NaN near the ends);
4. the body frame: upper-body points (neck, shoulders, elbows, wrists) rotated about the shoulders'
   midpoint by the shoulder line's angle, lower-body points (hips, knees, ankles) about the hips'
   midpoint by the hip line's angle, both divided by the trunk length (shoulder to hip midpoint), the
   lower body shifted by 1;
5. joint angles on step 3's coordinates (not the body frame): at the shoulder between the neck and the
   elbow, at the hip between the other hip and the knee (signed, 0-360, the left side mirrored), at the
   elbow between the shoulder and the wrist and at the knee between the hip and the ankle (0-180);
6. velocity (per second) and acceleration, each followed by a trailing mean of k = int(0.25 fps) frames;
   an angle changes the shortest way round;
7. per point / joint: medians, IQRs, the circular mean and variance, the entropy of rounded values, and
   per part the left-right Pearson correlation; per part the mean of the two sides (merge_data_sets.py).

Quirks of the published code kept on purpose (docs/movement.md): the hip line's angle is matched to
the shoulder line's frames by position, not by frame, when the two start at different frames;
`stdev_angle` is sqrt(degrees(circular variance)); the angle correlation pairs the left and right rows
by position after the frames without an angle are dropped; velocities over the last frames of a
position series repeat the last known one (pandas `interpolate` before the trailing mean). One
deviation: a series with no known value gets an empty entropy, with the reason (the published code gives 0).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ...data.skeleton import Skeleton
from ...stats import pearson
from .series import (
    circular_mean_deg,
    circular_variance,
    entropy_of_rounded,
    interpolate_gaps,
    iqr,
    nan_median,
    rolling_centered,
    rolling_trailing_mean,
    shortest_turn_deg,
    step_difference,
)

# The published point names (OpenPose's), those of the 12 body joints by zedo joint name.
JOINT_OF = {
    "RShoulder": "right_shoulder", "RElbow": "right_elbow", "RWrist": "right_wrist",
    "LShoulder": "left_shoulder", "LElbow": "left_elbow", "LWrist": "left_wrist",
    "RHip": "right_hip", "RKnee": "right_knee", "RAnkle": "right_ankle",
    "LHip": "left_hip", "LKnee": "left_knee", "LAnkle": "left_ankle",
}  # fmt: skip
POINTS = ("Neck", *JOINT_OF)  # (P,) = 13 points, the order of the arrays below
UPPER = ("Neck", "RShoulder", "RElbow", "RWrist", "LShoulder", "LElbow", "LWrist")
_AT = {name: i for i, name in enumerate(POINTS)}
# angle joint -> (its other two points): the angle at the joint from the first to the second
ANGLE_POINTS = {
    "RShoulder": ("Neck", "RElbow"), "RElbow": ("RShoulder", "RWrist"), "RHip": ("LHip", "RKnee"),
    "RKnee": ("RHip", "RAnkle"), "LShoulder": ("Neck", "LElbow"), "LElbow": ("LShoulder", "LWrist"),
    "LHip": ("RHip", "LKnee"), "LKnee": ("LHip", "LAnkle"),
}  # fmt: skip
XY_POINTS = ("LAnkle", "LWrist", "RAnkle", "RWrist")
ANGLE_STATS = {"mean_angle": "deg", "stdev_angle": "sqrt(deg)", "entropy_angle": "nats", "median_vel_angle": "deg/s",
               "IQR_vel_angle": "deg/s", "IQR_acc_angle": "deg/s^2"}  # fmt: skip
XY_STATS = {"medianx": "trunk", "mediany": "trunk", "IQRx": "trunk", "IQRy": "trunk", "medianvelx": "trunk/s",
            "medianvely": "trunk/s", "IQRvelx": "trunk/s", "IQRvely": "trunk/s", "IQRaccx": "trunk/s^2",
            "IQRaccy": "trunk/s^2", "meanent": "nats"}  # fmt: skip
LR_ANGLE_PARTS = ("Elbow", "Hip", "Knee", "Shoulder")
LR_X_PARTS = ("Ankle", "Elbow", "Hip", "Knee", "Shoulder", "Wrist")
# The 38 pre-registered part-level features (compute_surprise.py), left and right averaged.
PREREGISTERED = (
    "Ankle_medianx", "Wrist_medianx", "Ankle_mediany", "Wrist_mediany", "Knee_mean_angle", "Elbow_mean_angle",
    "Ankle_IQRx", "Wrist_IQRx", "Ankle_IQRy", "Wrist_IQRy", "Knee_stdev_angle", "Elbow_stdev_angle",
    "Ankle_medianvelx", "Wrist_medianvelx", "Ankle_medianvely", "Wrist_medianvely", "Knee_median_vel_angle",
    "Elbow_median_vel_angle", "Ankle_IQRvelx", "Wrist_IQRvelx", "Ankle_IQRvely", "Wrist_IQRvely",
    "Knee_IQR_vel_angle", "Elbow_IQR_vel_angle", "Ankle_IQRaccx", "Wrist_IQRaccx", "Ankle_IQRaccy", "Wrist_IQRaccy",
    "Knee_IQR_acc_angle", "Elbow_IQR_acc_angle", "Ankle_meanent", "Wrist_meanent", "Knee_entropy_angle",
    "Elbow_entropy_angle", "Ankle_lrCorr_x", "Wrist_lrCorr_x", "Knee_lrCorr_angle", "Elbow_lrCorr_angle",
)  # fmt: skip


@dataclass(frozen=True)
class Windows:
    """The published windows, in whole frames: int(seconds x fps), as the published code rounds."""

    fps: float
    smooth_s: float = 0.5  # rolling median, then rolling mean (centred)
    delta_s: float = 0.25  # trailing mean of velocities and accelerations

    @property
    def smooth(self) -> int:
        return int(self.smooth_s * self.fps)

    @property
    def delta(self) -> int:
        return int(self.delta_s * self.fps)

    @property
    def frames_needed(self) -> int:
        """Frames a clip needs for every statistic to have a value: both smoothing windows, then a
        velocity, its trailing mean, an acceleration and its trailing mean."""
        return 2 * (self.smooth - 1) + 2 * self.delta + 2

    @property
    def usable(self) -> bool:
        return self.smooth >= 1 and self.delta >= 1

    @property
    def too_slow(self) -> str:
        return f"{self.fps:g} fps is too low for the published windows (int(0.25 fps) = 0 frames; at least 4 fps)"

    def describe(self) -> str:
        return (f"int(0.5 fps) = {self.smooth} frames smoothed twice, int(0.25 fps) = {self.delta} frames per "
                f"dynamics mean: at least {self.frames_needed} frames")  # fmt: skip


@dataclass
class ClipFeatures:
    """Named clip features in order: value (NaN where empty), unit, and for each empty one the reason."""

    values: dict[str, float] = field(default_factory=dict)
    units: dict[str, str] = field(default_factory=dict)
    reasons: dict[str, str] = field(default_factory=dict)

    def add(self, name: str, value: float, unit: str, reason: str = "") -> None:
        self.values[name] = float(value)
        self.units[name] = unit
        if not np.isfinite(value):
            self.reasons[name] = reason or "undefined for this clip"


def all_empty(template: ClipFeatures, reason: str) -> ClipFeatures:
    """The features of `template`, every one empty for `reason`."""
    out = ClipFeatures()
    for name, unit in template.units.items():
        out.add(name, np.nan, unit, reason)
    return out


def smooth_positions(points: np.ndarray, windows: Windows) -> np.ndarray:
    """Steps 2 and 3 for `points (T, ...)`: interpolated over gaps, then the centred rolling median
    and mean of `windows.smooth` frames (none when that is 0, as published)."""
    out = interpolate_gaps(points)
    if windows.smooth > 0:
        out = rolling_centered(rolling_centered(out, windows.smooth, "median"), windows.smooth, "mean")
    return out


def signal_dynamics(values: np.ndarray, fps: float, window: int) -> tuple[np.ndarray, np.ndarray]:
    """Velocity and acceleration `(T, ...)` per second from the per-row steps of `values`: each step
    divided by 1/fps, then (pandas `interpolate`, then) a trailing mean of `window` rows."""
    dt = 1.0 / fps
    velocity = rolling_trailing_mean(interpolate_gaps(step_difference(values) / dt), window)
    acceleration = rolling_trailing_mean(interpolate_gaps(step_difference(velocity) / dt), window)
    return velocity, acceleration


def angle_statistics(angle: np.ndarray, fps: float, window: int) -> dict[str, float]:
    """The published per-joint angle features of the rows `angle (n,)` (degrees, consecutive rows,
    none unknown): the shortest-way steps from row to row (0 at the first), their velocity and
    acceleration, and the statistics of build_features.angle_features."""
    if not len(angle):
        return dict.fromkeys(ANGLE_STATS, np.nan)
    steps = np.concatenate([[0.0], shortest_turn_deg(angle[:-1], angle[1:])])
    dt = 1.0 / fps
    velocity = rolling_trailing_mean(interpolate_gaps(steps / dt), window)
    acceleration = rolling_trailing_mean(interpolate_gaps(step_difference(velocity) / dt), window)
    # the published slip kept: sqrt of the circular variance converted as if it were radians
    variance = circular_variance(angle)
    with np.errstate(invalid="ignore"):
        stdev = float(np.sqrt(np.degrees(variance)))
    return {
        "mean_angle": circular_mean_deg(angle),
        "stdev_angle": stdev,
        "entropy_angle": entropy_of_rounded(angle, 0),
        "median_vel_angle": nan_median(np.abs(velocity)),
        "IQR_vel_angle": iqr(velocity),
        "IQR_acc_angle": iqr(acceleration),
    }


def body_frame(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Step 4: smoothed normalised coordinates `x, y (T, P)` in the published body frame."""
    t = len(x)

    def line(left: str, right: str) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        lx, ly, rx, ry = x[:, _AT[left]], y[:, _AT[left]], x[:, _AT[right]], y[:, _AT[right]]
        angle = np.arctan2(ry - ly, rx - lx)
        seen = np.isfinite(np.stack([lx, ly, rx, ry])).any(0)  # the frames of the published pivot table
        return angle, (ry + ly) / 2, (rx + lx) / 2, seen

    s_angle, u_y, u_x, s_seen = line("LShoulder", "RShoulder")
    h_angle, l_y, l_x, h_seen = line("LHip", "RHip")
    # The published code puts the hip angle beside the shoulder angle by row position, not by frame.
    s_frames, h_frames = np.flatnonzero(s_seen), np.flatnonzero(h_seen)
    hip_by_row = np.full(t, np.nan)
    n = min(len(s_frames), len(h_frames))
    hip_by_row[s_frames[:n]] = h_angle[h_frames[:n]]
    keep = s_seen & h_seen  # then merged with both midpoints on the frame (inner)
    upper = np.isin(np.array(POINTS), UPPER)  # (P,)
    nan = np.full(t, np.nan)
    u_x, u_y, l_x, l_y = (np.where(keep, v, nan) for v in (u_x, u_y, l_x, l_y))
    s_angle, hip_by_row = np.where(keep, s_angle, nan), np.where(keep, hip_by_row, nan)
    ref_x = np.where(upper, u_x[:, None], l_x[:, None])  # (T, P)
    ref_y = np.where(upper, u_y[:, None], l_y[:, None])
    # the published sum u * upper + l * (1 - upper) is NaN when either reference is
    both = np.isfinite(u_x + l_x + u_y + l_y + s_angle + hip_by_row)[:, None]
    ref_x, ref_y = np.where(both, ref_x, np.nan), np.where(both, ref_y, np.nan)
    ref_dist = np.sqrt((u_y - l_y) ** 2 + (u_x - l_x) ** 2)[:, None]
    a = np.where(upper, s_angle[:, None], hip_by_row[:, None])
    a = np.where(both, a, np.nan)
    with np.errstate(invalid="ignore"):
        a = np.where(a < 0, 2 * np.pi + a, a)
        a = np.where(a < np.pi, np.pi - a, np.where((a > np.pi) & (a < 2 * np.pi), 3 * np.pi - a, a))
    xr = ref_x + np.cos(a) * (x - ref_x) - np.sin(a) * (y - ref_y)
    yr = ref_y + np.sin(a) * (x - ref_x) + np.cos(a) * (y - ref_y)
    with np.errstate(invalid="ignore", divide="ignore"):
        xb, yb = (xr - ref_x) / ref_dist, (yr - ref_y) / ref_dist
    return xb, np.where(upper, yb, yb + 1.0)


def joint_angle_series(x: np.ndarray, y: np.ndarray) -> dict[str, np.ndarray]:
    """Step 5: per angle joint, its angle per frame `(T,)` in degrees (NaN where a point is unknown)."""
    out = {}
    for bp, (b, c) in ANGLE_POINTS.items():
        i0, i1, i2 = _AT[bp], _AT[b], _AT[c]
        dx1, dy1, dx2, dy2 = x[:, i1] - x[:, i0], y[:, i1] - y[:, i0], x[:, i2] - x[:, i0], y[:, i2] - y[:, i0]
        dot = dx1 * dx2 + dy1 * dy2
        det = dx1 * dy2 - dy1 * dx2
        angle = np.arctan2(det, dot) * 180 / np.pi
        part = bp[1:]
        if bp in ("LShoulder", "LHip"):
            angle = angle * -1
        if part in ("Elbow", "Knee"):
            angle = np.abs(angle)
        else:
            angle = np.where(angle < 0, angle + 360, angle)
        known = np.isfinite(x[:, [i0, i1, i2]]).all(1)  # the published rows: the three points' x known
        out[bp] = np.where(known, angle, np.nan)
    return out


def points_of(xy: np.ndarray, skeleton: Skeleton) -> np.ndarray:
    """`(T, P, 2)` pixels of POINTS from skeleton-ordered keypoints `xy (T, J, 2)`; the neck is the
    shoulders' midpoint where both are known."""
    body = np.stack([xy[:, skeleton.index(j)] for j in JOINT_OF.values()], axis=1)  # (T, 12, 2)
    neck = (body[:, list(JOINT_OF).index("LShoulder")] + body[:, list(JOINT_OF).index("RShoulder")]) / 2
    return np.concatenate([neck[:, None], body], axis=1)


def published_features(xy: np.ndarray, skeleton: Skeleton, fps: float, image_size: np.ndarray) -> ClipFeatures:
    """The per-side and the 38 pre-registered part-level features of one person's clip.

    xy `(T, J, 2)`: pixels in `skeleton`'s order for frames 0..T-1 (NaN where missing or the frame
    absent); image_size `(T, 2)` or `(2,)`: width, height (only centres the coordinates: no feature
    depends on it, the body frame and the angles being free of translation and scale)."""
    windows = Windows(fps)
    if not windows.usable:  # int(0.25 fps) = 0: the published windows are empty
        return all_empty(published_features(xy, skeleton, 30.0, image_size), windows.too_slow)
    pts = points_of(xy, skeleton)  # (T, P, 2)
    size = np.broadcast_to(np.asarray(image_size, dtype=float), (len(pts), 2))
    w, h = size[:, :1], size[:, 1:]
    x = smooth_positions((pts[..., 0] - w / 2) / h, windows)  # (T, P)
    y = smooth_positions((pts[..., 1] - h / 2) / h, windows)
    xb, yb = body_frame(x, y)
    angles = joint_angle_series(x, y)
    reasons = _Reasons(pts, windows)
    out = ClipFeatures()

    for bp in sorted(ANGLE_POINTS):  # per-side angle features
        rows = angles[bp][np.isfinite(angles[bp])]
        stats = angle_statistics(rows, fps, windows.delta)
        for stat, unit in ANGLE_STATS.items():
            out.add(f"{stat}_{bp}", stats[stat], unit, reasons.of((bp, *ANGLE_POINTS[bp])))
    for part in LR_ANGLE_PARTS:  # by position after the frames without an angle are dropped (published)
        left, right = (angles[s + part][np.isfinite(angles[s + part])] for s in "LR")
        n = min(len(left), len(right))
        need = (f"L{part}", *ANGLE_POINTS[f"L{part}"], f"R{part}", *ANGLE_POINTS[f"R{part}"])
        out.add(f"lrCorr_angle_{part}", pearson(left[:n], right[:n]), "r", reasons.of(need))

    vx, ax = signal_dynamics(xb, fps, windows.delta)  # (T, P)
    vy, ay = signal_dynamics(yb, fps, windows.delta)
    for bp in XY_POINTS:
        i = _AT[bp]
        stats = {
            "medianx": nan_median(xb[:, i]), "mediany": nan_median(yb[:, i]),
            "IQRx": iqr(xb[:, i]), "IQRy": iqr(yb[:, i]),
            "medianvelx": nan_median(np.abs(vx[:, i])), "medianvely": nan_median(np.abs(vy[:, i])),
            "IQRvelx": iqr(vx[:, i]), "IQRvely": iqr(vy[:, i]), "IQRaccx": iqr(ax[:, i]), "IQRaccy": iqr(ay[:, i]),
            "meanent": (entropy_of_rounded(xb[:, i], 2) + entropy_of_rounded(yb[:, i], 2)) / 2,
        }  # fmt: skip
        for stat, unit in XY_STATS.items():
            out.add(f"{stat}_{bp}", stats[stat], unit, reasons.of((bp, *_FRAME_POINTS), body=True))
    dist = np.sqrt(xb**2 + yb**2)  # (T, P)
    for part in LR_X_PARTS:
        r = pearson(dist[:, _AT["L" + part]], dist[:, _AT["R" + part]])
        out.add(f"lrCorr_x_{part}", r, "r", reasons.of(("L" + part, "R" + part, *_FRAME_POINTS), body=True))

    for name in PREREGISTERED:  # merge_data_sets.py: the mean of the sides that have a value
        part, stat = name.split("_", 1)
        if stat.startswith("lrCorr"):
            source = [f"{stat}_{part}"]
        else:
            source = [f"{stat}_{s}{part}" for s in "LR"]
        values = np.array([out.values[s] for s in source])
        known = values[np.isfinite(values)]
        value = float(known.mean()) if len(known) else np.nan
        out.add(name, value, out.units[source[0]], _merged([out.reasons[s] for s in source if s in out.reasons]))
    return out


_FRAME_POINTS = ("LShoulder", "RShoulder", "LHip", "RHip")  # the body frame needs all four
_NEVER = "never detected: "


def _merged(reasons: list[str]) -> str:
    """One reason for a part-level feature from its sides' reasons (the joints never detected pooled)."""
    if reasons and all(r.startswith(_NEVER) for r in reasons):
        joints = [j for r in reasons for j in r.removeprefix(_NEVER).split(", ")]
        return _NEVER + ", ".join(dict.fromkeys(joints))
    return "; ".join(dict.fromkeys(reasons))


class _Reasons:
    """Why a feature is empty: a point never detected, a clip too short for the windows, or else undefined."""

    def __init__(self, pts: np.ndarray, windows: Windows) -> None:
        self.seen = {name: bool(np.isfinite(pts[:, i]).all(-1).any()) for name, i in _AT.items()}
        self.frames = len(pts)
        self.windows = windows

    def of(self, points: tuple[str, ...], body: bool = False) -> str:
        lacking = []
        for p in dict.fromkeys(points):
            if not self.seen[p]:
                lacking.append("both shoulders in one frame (the neck)" if p == "Neck" else JOINT_OF[p])
        if lacking:
            return _NEVER + ", ".join(lacking)
        if self.frames < self.windows.frames_needed:
            return f"the clip ({self.frames} frames) is too short for the published windows ({self.windows.describe()})"
        if body:
            return "undefined for this clip (no frame with both shoulders and both hips, or a constant series)"
        return "undefined for this clip (e.g. a constant series)"
