"""Adult motion as bone directions: loading the adult files per clip, resampling onto a uniform
grid, removing the heading, and rebuilding poses with other bone lengths.

The syrip12 joints form no tree (hips and shoulders close a loop), so the motion is carried by 13
segments of a tree rooted at the hip midpoint (`SEGMENTS`): the two halves of the hip line, the
trunk (hip midpoint to shoulder midpoint), the two halves of the shoulder line and the eight limb
bones. A pose is its root point, one unit direction per segment and the segments' lengths; the two
trunk sides (hip to shoulder of one side) follow from the trunk, the two lines and their twist.
"""

from __future__ import annotations

import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...data.skeleton import convert_points, get_skeleton
from ...errors import DataError

SYRIP12 = get_skeleton("syrip12")
# (parent, child): "root" is the hips' midpoint, "neck" the shoulders' midpoint; parents come first.
SEGMENTS: tuple[tuple[str, str], ...] = (
    ("root", "left_hip"), ("root", "right_hip"), ("root", "neck"), ("neck", "left_shoulder"),
    ("neck", "right_shoulder"), ("left_hip", "left_knee"), ("left_knee", "left_ankle"),
    ("right_hip", "right_knee"), ("right_knee", "right_ankle"), ("left_shoulder", "left_elbow"),
    ("left_elbow", "left_wrist"), ("right_shoulder", "right_elbow"), ("right_elbow", "right_wrist"),
)  # fmt: skip
SEGMENT_NAMES: tuple[str, ...] = tuple(f"{p}->{c}" for p, c in SEGMENTS)
# Segment indices of left/right twins, for a symmetric infant (the girdle halves are equal already).
TWIN_SEGMENTS: tuple[tuple[int, int], ...] = ((5, 7), (6, 8), (9, 11), (10, 12))
TRUNK = 2  # root -> neck


@dataclass(frozen=True)
class AdultClip:
    """One clip of an adult file in syrip12 joints: its kept frames' times (s, increasing) and
    unit segment directions `(n, 13, 3)` in the file's world frame (+Y up)."""

    file: str
    name: str
    time: np.ndarray
    directions: np.ndarray
    source_step_s: float  # the file's sampling step (1 / its fps): 0.1 s

    @property
    def duration_s(self) -> float:
        return float(self.time[-1] - self.time[0])


def joints_with_root(poses: np.ndarray) -> dict[str, np.ndarray]:
    """syrip12 poses `(..., 12, 3)` by joint name, with "root" and "neck" (the girdles' midpoints)."""
    at = {name: poses[..., i, :] for i, name in enumerate(SYRIP12.joints)}
    at["root"] = (at["left_hip"] + at["right_hip"]) / 2
    at["neck"] = (at["left_shoulder"] + at["right_shoulder"]) / 2
    return at


def segment_vectors(poses: np.ndarray) -> np.ndarray:
    """Parent-to-child vectors `(..., 13, 3)` of `SEGMENTS` of syrip12 poses `(..., 12, 3)`."""
    at = joints_with_root(poses)
    return np.stack([at[c] - at[p] for p, c in SEGMENTS], axis=-2)


def unit(v: np.ndarray) -> np.ndarray:
    return v / np.maximum(np.linalg.norm(v, axis=-1, keepdims=True), 1e-12)


def build_poses(root: np.ndarray, directions: np.ndarray, lengths: np.ndarray) -> np.ndarray:
    """syrip12 poses `(T, 12, 3)` from root points `(T, 3)`, unit segment directions `(T, 13, 3)`
    and segment lengths `(13,)`, walking the tree from the root outwards."""
    seg = directions * np.asarray(lengths)[None, :, None]
    out = {"root": np.asarray(root, dtype=np.float64)}
    for s, (parent, child) in enumerate(SEGMENTS):
        out[child] = out[parent] + seg[:, s]
    return np.stack([out[n] for n in SYRIP12.joints], axis=1)


def read_adult_file(path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """`poses (N, 17, 3)`, `clip (N,)`, `time (N,)` and `fps` of an adult file, checked."""
    try:
        with np.load(path, allow_pickle=False) as data:
            poses = np.asarray(data["poses"], dtype=np.float64)
            clips = np.asarray(data["clip"]).astype(str)
            time = np.asarray(data["time"], dtype=np.float64)
            fps = float(data["fps"])
    except (OSError, ValueError, KeyError, zipfile.BadZipFile) as exc:
        raise DataError(f"{path}: not an adult pose file with poses, clip, time and fps ({exc})") from None
    if poses.ndim != 3 or poses.shape[1:] != (17, 3) or not (len(clips) == len(time) == len(poses)):
        raise DataError(f"{path}: 'poses' must have shape (N, 17, 3) with one clip name and time per pose")
    if not (np.isfinite(poses).all() and np.isfinite(time).all() and fps > 0):
        raise DataError(f"{path}: poses, times and fps must be finite (fps > 0)")
    return poses, clips, time, fps


def load_adult_clips(path: str | Path) -> tuple[AdultClip, ...]:
    """Every clip of one adult file (the shared data's `*_h36m17.npz` layout), in the file's order
    of first appearance, its frames sorted by time; a clip needs two frames at distinct times."""
    path = Path(path)
    if not path.is_file():
        raise DataError(f"{path}: adult file not found")
    poses, clips, time, fps = read_adult_file(path)
    syrip, _ = convert_points(poses, np.ones(poses.shape[:2]), get_skeleton("h36m17"), SYRIP12)
    dirs = unit(segment_vectors(syrip))
    names, first, code = np.unique(clips, return_index=True, return_inverse=True)
    rank = np.argsort(np.argsort(first))  # each name's place in the file's order of first appearance
    order = np.lexsort((time, rank[code]))
    bounds = np.flatnonzero(np.diff(rank[code][order])) + 1
    out = []
    for rows in np.split(order, bounds):
        t = time[rows]
        keep = np.concatenate([[True], np.diff(t) > 1e-9])  # a repeated time: its first frame
        if keep.sum() >= 2:
            out.append(AdultClip(path.name, str(clips[rows[0]]), t[keep], dirs[rows[keep]], 1.0 / fps))
    return tuple(out)


def slerp(a: np.ndarray, b: np.ndarray, u: np.ndarray) -> np.ndarray:
    """Unit directions turned from unit `a (..., S, 3)` towards unit `b` along great circles by the
    fraction `u (...,)`; (nearly) equal or opposite directions are mixed straight and normalised."""
    cos = np.clip((a * b).sum(-1), -1.0, 1.0)
    theta = np.arccos(cos)
    sin = np.sin(theta)
    turns = sin > 1e-6
    safe = np.where(turns, sin, 1.0)
    uu = np.broadcast_to(np.asarray(u, dtype=np.float64)[..., None], theta.shape)
    wa = np.where(turns, np.sin((1 - uu) * theta) / safe, 1 - uu)
    wb = np.where(turns, np.sin(uu * theta) / safe, uu)
    out = wa[..., None] * a + wb[..., None] * b
    norm = np.linalg.norm(out, axis=-1, keepdims=True)
    return np.where(norm > 1e-9, out / np.maximum(norm, 1e-12), a)


def resample(clip: AdultClip, fps: float, max_gap_s: float) -> tuple[np.ndarray, np.ndarray]:
    """The clip on a uniform grid at `fps` from its first kept frame to its last: the source times
    `(T,)` of the grid and the directions `(T, 13, 3)` there.

    Between two kept frames at most `max_gap_s` apart every segment turns along a great circle at
    an even rate. A longer gap means the dropped frames moved less than the files' threshold
    (2 cm) from the earlier kept frame: the pose is held, then turns to the later kept frame over
    the last source step (0.1 s) of the gap. Grid frames that fall on a kept frame's time carry its
    directions exactly (up to the float error of the times).
    """
    t0, steps = clip.time[0], int(np.floor(clip.duration_s * fps + 1e-6))
    grid = t0 + np.arange(steps + 1) / fps
    k = np.clip(np.searchsorted(clip.time, grid, side="right") - 1, 0, len(clip.time) - 2)
    start, end = clip.time[k], clip.time[k + 1]
    gap = end - start
    step = np.minimum(clip.source_step_s, gap)
    move_from = np.where(gap <= max_gap_s + 1e-6, start, end - step)
    u = np.clip((grid - move_from) / (end - move_from), 0.0, 1.0)
    return grid, slerp(clip.directions[k], clip.directions[k + 1], u)


def trunk_frames(directions: np.ndarray) -> np.ndarray:
    """Per frame the trunk's axes as the columns of a rotation `(T, 3, 3)`: the body's left (hip and
    shoulder lines, made square to the trunk), up (hip midpoint to shoulder midpoint) and forward
    (left x up, so that left = up x forward)."""
    up = unit(directions[:, TRUNK])
    across = directions[:, 0] - directions[:, 1] + directions[:, 3] - directions[:, 4]
    left = unit(across - (across * up).sum(-1, keepdims=True) * up)
    return np.stack([left, up, np.cross(left, up)], axis=-1)


def yaw_matrices(angle: np.ndarray) -> np.ndarray:
    """Rotations `(T, 3, 3)` about the world's vertical (+Y) by `angle (T,)` (x turned towards -z)."""
    c, s = np.cos(angle), np.sin(angle)
    out = np.zeros((len(angle), 3, 3))
    out[:, 0, 0], out[:, 0, 2], out[:, 1, 1], out[:, 2, 0], out[:, 2, 2] = c, s, 1.0, -s, c
    return out


def gaussian_smooth(values: np.ndarray, sigma: float) -> np.ndarray:
    """`values (T,)` smoothed by a Gaussian of `sigma` samples, the ends reflected."""
    if sigma <= 0 or len(values) < 2:
        return values.astype(np.float64)
    half = int(np.ceil(3 * sigma))
    kernel = np.exp(-0.5 * (np.arange(-half, half + 1) / sigma) ** 2)
    padded = np.pad(values, half, mode="reflect" if len(values) > half else "edge")
    return np.convolve(padded, kernel / kernel.sum(), mode="valid")


def heading(directions: np.ndarray, fps: float, smooth_s: float) -> np.ndarray:
    """The body's smoothed heading `(T,)` (rad about +Y): the angle of its left axis in the
    horizontal plane, unwrapped and smoothed over `smooth_s` seconds. Undoing it
    (`yaw_matrices(-heading)`) turns the left axis towards +X: walking turns are removed, the
    sway of the trunk about its smoothed course is kept."""
    left = trunk_frames(directions)[:, :, 0]
    angle = np.unwrap(np.arctan2(-left[:, 2], left[:, 0]))
    return gaussian_smooth(angle, smooth_s * fps)


def mean_rotation(frames: np.ndarray) -> np.ndarray:
    """The rotation nearest the mean of rotations `(T, 3, 3)` (SVD projection)."""
    u, _, vt = np.linalg.svd(frames.mean(axis=0))
    d = np.sign(np.linalg.det(u @ vt))
    return u @ np.diag([1.0, 1.0, d]) @ vt
