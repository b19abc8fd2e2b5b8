"""Temporal mode: lifting video sequences (one person per frame per track, frames in order).

Frame-by-frame lifting treats every frame alone, so the 3D poses of a video jitter: the depth
of each joint, which one image constrains least, is re-guessed in every frame. The temporal
modes (`TEMPORAL_MODES`) use the neighbouring frames:

- `none`: frame-by-frame, the preset as is (batched over all frames).
- `smooth`: frame-by-frame, then the smoothing filter (`smooth_sequence`) over time, applied
  per track to the root-relative poses and to the root translations. Cheapest; the joints
  leave their rays by the amount the filter moves them.
- `two-pass`: `smooth`, then a short warm-started refinement (batched over all frames, see
  `lifting.lift(start_poses=...)`) from the smoothed poses, which puts the observed joints
  back on the rays of the smoothed detections while the prior keeps the pose plausible:
  closer to the 2D than `smooth`, a little more jitter and error, ~25 % slower.
- `clip`: `two-pass`, then each track lifted as one infant: one skeleton per track, every limb bone
  at its length in every frame, the depth side of a limb kept between its passages near the image
  plane, and the stretches whose side the 2D cannot tell flagged (`clip.py`).

Tried and dropped (benchmarks, notes): a sequential warm start (frame t from frame t-1's
result, a few prior steps): no batching across frames and the pose drifts, since a short loop
at low noise cannot follow large changes (worse than frame-by-frame).

Frames whose person is not lifted (too few observed joints) stay NaN, and the filter ignores
them (NaN-aware): a gap never spreads into its neighbours. Where the input numbers its frames
(`frames`), the filter runs on that time axis: a frame missing from the input (an OpenPose
frame without people) is a gap too, and a gap longer than the filter's radius (3 sigma) is
never blended across. Measured against frame-by-frame in
`benchmarks/accuracy/temporal.py`.

Only one sequence is smoothed: frames that are not one (several image sizes, frame numbers or
file names that do not count up, a pose that jumps from frame to frame) are refused before any
work (`sequence.py`). After smoothing, each pose is measured against its input 2D again: one
the filter pulled off its detection is `poor_fit` (not lifted), as frame by frame.
"""

from __future__ import annotations

import functools
import time
from collections.abc import Callable, Sequence
from dataclasses import replace

import numpy as np

from ..camera.model import CameraModel, undistort_instances
from ..data.skeleton import Skeleton
from ..errors import ConfigError
from ..prior.weights import Prior
from .chunks import lift_workers, plan_chunks
from .clip import ClipTrack, lift_clip_track, limb_parents, needs_joints, root_relative
from .config import DEFAULT_SIGMA_FRAMES, DEFAULT_TEMPORAL_MODE, TEMPORAL_MODES, LiftConfig
from .detections import fix_detections
from .reprojection import poor_fit, reprojection_error_px
from .sequence import check_sequence
from .solver import LIFTED, LiftProgress, LiftResult, lift, observed_mask

DEFAULT_CLIP_FPS = 30.0  # the frame rate clip mode's detection checks assume where the input states none


def gaussian_kernel(sigma: float, truncate: float = 3.0) -> np.ndarray:
    """Normalised Gaussian weights `(2r+1,)` of standard deviation `sigma` frames, r = ceil(truncate sigma)."""
    radius = max(1, int(np.ceil(truncate * sigma)))
    offsets = np.arange(-radius, radius + 1, dtype=np.float64)
    kernel = np.exp(-0.5 * (offsets / sigma) ** 2)
    return kernel / kernel.sum()


def smooth_sequence(values: np.ndarray, sigma: float, *, truncate: float = 3.0) -> np.ndarray:
    """NaN-aware Gaussian smoothing of `values (T, ...)` over time (axis 0), `sigma` in frames.

    y_t = sum_s w(s - t) m_s x_s / sum_s w(s - t) m_s, with w a Gaussian of `sigma` frames
    truncated at `truncate` sigma and m_s = 1 where x_s is finite, else 0 (per element).
    Properties: a constant is unchanged; the kernel is symmetric, so inside a sequence there
    is no lag (offline filter, zero phase) and a straight-line motion passes unchanged; motion
    faster than about 1 / (2 pi sigma) cycles per frame is damped (sigma = 2 at 30 fps: the
    gain is 1/2 at about 2.8 Hz). Near an edge or a gap the window is one-sided and renormalised,
    so a moving joint is pulled back towards the frames that exist (a lag of up to
    sigma * sqrt(2/pi) ~ 0.8 sigma frames for a constant velocity at the very first/last frame).
    NaN entries stay NaN and never reach their neighbours. `sigma = 0` returns a copy.
    """
    if sigma < 0 or not np.isfinite(sigma):
        raise ConfigError(f"sigma must be a finite number of frames >= 0, got {sigma}")
    values = np.asarray(values, dtype=np.float64)
    if sigma == 0 or len(values) < 2:
        return values.copy()
    kernel = gaussian_kernel(sigma, truncate)
    radius = len(kernel) // 2
    finite = np.isfinite(values)
    x = np.where(finite, values, 0.0)
    m = finite.astype(np.float64)
    pad = [(radius, radius)] + [(0, 0)] * (values.ndim - 1)
    xp, mp = np.pad(x, pad), np.pad(m, pad)
    num = np.zeros_like(x)
    den = np.zeros_like(x)
    n = len(values)
    for i, w in enumerate(kernel):  # a banded sum: O(T r), fine for long videos
        num += w * xp[i : i + n]
        den += w * mp[i : i + n]
    with np.errstate(invalid="ignore", divide="ignore"):
        out = num / den
    return np.where(finite, out, np.nan)


def _track_slices(tracks: np.ndarray | None, n: int) -> list[np.ndarray]:
    """Indices of each track's frames, in the given (time) order."""
    if tracks is None:
        return [np.arange(n)]
    tracks = np.asarray(tracks)
    if tracks.shape != (n,):
        raise ConfigError(f"tracks must have one label per instance ({n}), got shape {tracks.shape}")
    _, first = np.unique(tracks, return_index=True)
    return [np.flatnonzero(tracks == tracks[i]) for i in np.sort(first)]


def smooth_on_frames(values: np.ndarray, frames: np.ndarray | None, sigma: float) -> np.ndarray:
    """`smooth_sequence` of `values (T, ...)` placed at frame numbers `frames (T,)` (increasing):
    missing frames are NaN on the time axis, so the weights follow real time and nothing is
    blended across a gap longer than the filter's radius. Numbers whose median step exceeds 1
    (timestamps, every n-th frame) are counted in that step. `frames` None (or not increasing):
    the values are consecutive frames."""
    values = np.asarray(values, dtype=np.float64)
    if frames is None or len(values) < 2 or sigma == 0:
        return smooth_sequence(values, sigma)
    frames = np.asarray(frames, dtype=np.int64)
    if frames.shape != (len(values),) or not (np.diff(frames) > 0).all():
        return smooth_sequence(values, sigma)
    # Numbers that step by more than 1 as a rule (millisecond timestamps, every 10th frame kept)
    # are counted in their usual step, so sigma stays in the input's frames and gaps stay gaps.
    step = int(np.median(np.diff(frames)))
    if step > 1:
        frames = np.round((frames - frames[0]) / step).astype(np.int64)
        if not (np.diff(frames) > 0).all():
            return smooth_sequence(values, sigma)
    radius = len(gaussian_kernel(sigma)) // 2
    out = np.empty_like(values)
    # Segments split at gaps wider than the radius: no weight reaches across them, and the dense
    # time axis of a segment stays short (at most (radius + 1) x its frames).
    breaks = np.flatnonzero(np.diff(frames) > radius) + 1
    for seg in np.split(np.arange(len(frames)), breaks):
        offsets = frames[seg] - frames[seg[0]]
        dense = np.full((int(offsets[-1]) + 1, *values.shape[1:]), np.nan)
        dense[offsets] = values[seg]
        out[seg] = smooth_sequence(dense, sigma)[offsets]
    return out


def smooth_tracks(
    poses_root_relative: np.ndarray,
    root_translation: np.ndarray,
    sigma: float,
    tracks: np.ndarray | None = None,
    frames: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """`smooth_sequence` per track over root-relative poses `(N, J, 3)` and translations `(N, 3)`,
    on the frame numbers `frames (N,)` where given (`smooth_on_frames`).

    Root-relative poses and translations are smoothed apart: the body's motion in the camera
    and its articulation are different signals, and the root stays at the origin (the filter
    is linear).
    """
    rel, trans = poses_root_relative.copy(), root_translation.copy()
    for idx in _track_slices(tracks, len(rel)):
        at = None if frames is None else np.asarray(frames)[idx]
        rel[idx] = smooth_on_frames(poses_root_relative[idx], at, sigma)
        trans[idx] = smooth_on_frames(root_translation[idx], at, sigma)
    return rel, trans


class _Progress:
    """Progress over several `lift` calls: their steps add up to one known total."""

    def __init__(self, total: int, callback: Callable[[LiftProgress], None] | None) -> None:
        self.total, self.offset, self.callback = total, 0, callback

    def part(self) -> Callable[[LiftProgress], None] | None:
        if self.callback is None:
            return None
        offset, callback = self.offset, self.callback
        return lambda p: callback(LiftProgress(offset + p.done, self.total))

    def advance(self, steps: int) -> None:
        self.offset += steps


def _progress_of(lifted: int, mode: str, config: LiftConfig, device: str,
                 callback: Callable[[LiftProgress], None] | None) -> tuple[_Progress, int]:  # fmt: skip
    """The progress over a sequence's lifts of `lifted` instances, and the steps of its first (cold) lift."""
    workers = lift_workers(device)
    cold = len(plan_chunks(lifted, config.hypotheses, config.chunk_size, workers)) * (config.init_steps + config.steps)
    warm = len(plan_chunks(lifted, 1, config.chunk_size, workers)) * config.warm_steps
    return _Progress(cold + (warm if mode in ("two-pass", "clip") else 0), callback), cold


def lift_sequence(
    xy: np.ndarray,
    confidence: np.ndarray,
    intrinsics: np.ndarray,
    prior: Prior,
    config: LiftConfig,
    *,
    mode: str = DEFAULT_TEMPORAL_MODE,
    sigma: float = DEFAULT_SIGMA_FRAMES,
    tracks: np.ndarray | None = None,
    frames: np.ndarray | None = None,
    min_confidence: float = 0.0,
    device: str = "cpu",
    callback: Callable[[LiftProgress], None] | None = None,
    seed: int = 0,
    cameras: Sequence[CameraModel | None] | None = None,
    image_sizes: np.ndarray | None = None,
    file_names: Sequence[str | None] | None = None,
    fps: float | None = None,
) -> LiftResult:
    """Lift a video: `xy (N, J, 2)`, `confidence (N, J)`, `intrinsics (N, 3, 3)` and `cameras`
    (lenses) as for `lift`, the instances being frames in time order (per track: `tracks (N,)`
    labels one person across frames; None is one track; `frames (N,)`: the input's frame
    numbers, so that missing frames are gaps, see `smooth_on_frames`; None: consecutive). `mode`
    in `TEMPORAL_MODES`; `sigma` is the smoothing filter's width in frames (modes `smooth` and
    `two-pass`). `config` is the preset; its `warm_*` fields set the warm-started loops. Unlifted
    frames are NaN, as with `lift`. With several hypotheses (`config.hypotheses`, seeded by
    `seed`) each frame's pose is their aggregate; the smoothed results keep no hypotheses (they
    were lifted before the smoothing).

    Before smoothing, the frames must be one sequence (`sequence.check_sequence`, with
    `image_sizes (N, 2)` and `file_names (N,)` where known): else a ConfigError, before any
    work. After smoothing, a pose the filter pulled away from its input 2D `xy` (through its
    lens) is not lifted, status `poor_fit`, by the test `lift` applies (`reprojection.poor_fit`).
    """
    if mode not in TEMPORAL_MODES:
        raise ConfigError(f"unknown temporal mode {mode!r}; modes: {', '.join(TEMPORAL_MODES)}")
    if sigma < 0 or not np.isfinite(sigma):
        raise ConfigError(f"sigma must be a finite number of frames >= 0, got {sigma}")
    start = time.perf_counter()
    n = len(xy)
    _track_slices(tracks, n)  # validates the labels early
    fixes = None
    if mode == "clip":  # a detector's habits found and corrected before the track is lifted as one infant
        xy, confidence, fixes = fix_detections(xy, confidence, prior.skeleton.flip_permutation, fps or DEFAULT_CLIP_FPS,
                                               _track_slices(tracks, n), limb_parents(prior.skeleton))  # fmt: skip
    observed = observed_mask(xy, confidence, min_confidence)
    if mode != "none":
        check_sequence(xy, observed, mode, tracks=tracks, frames=frames, image_sizes=image_sizes,
                       file_names=file_names)  # fmt: skip
    progress, cold_cost = _progress_of(int((observed.sum(1) >= config.min_observed).sum()), mode, config, device,
                                       callback)  # fmt: skip
    first = lift(xy, confidence, intrinsics, prior, config, callback=progress.part(),
                 min_confidence=min_confidence, device=device, seed=seed, cameras=cameras)  # fmt: skip
    progress.advance(cold_cost)
    if mode == "none":
        return replace(first, seconds=time.perf_counter() - start)
    rel, trans = smooth_tracks(first.poses_root_relative, first.root_translation, sigma, tracks, frames)
    if mode == "smooth":
        smoothed = replace(first, poses_camera=rel + trans[:, None], poses_root_relative=rel, root_translation=trans,
                           hypotheses=None, hypothesis_spread_m=None)  # fmt: skip
        return replace(_refit(smoothed, xy, intrinsics, cameras), seconds=time.perf_counter() - start)
    # two-pass: a short warm-started loop from the smoothed poses puts the joints back on rays. The rays
    # go through the detections smoothed by the same filter: rays through the raw pixels would bring
    # back their noise, one pixel being ~0.5 mm at 1 m with f = 2000 px (measured: jitter x3).
    # Only the joints the lift uses are smoothed: a joint below the confidence threshold (or at a detector's
    # placeholder 0, 0) would pull its neighbours' smoothed pixels towards it.
    xy_used = np.where(observed[..., None], xy, np.nan)
    xy_smooth = smooth_tracks_2d(undistort_instances(xy_used, cameras), sigma, tracks, frames)
    second = lift(xy_smooth, confidence, intrinsics, prior, config, callback=progress.part(), start_poses=rel,
                  start_translation=trans, min_confidence=min_confidence, device=device)  # fmt: skip
    # An instance the first pass could not lift (its start is NaN) stays not lifted, for the same reason,
    # rather than being lifted cold from the smoothed pixels.
    status = np.where(first.lifted, second.status, first.status)
    refined = replace(second, status=status, hypotheses=None, hypothesis_spread_m=None)
    if mode == "clip":
        refined = lift_tracks_as_infants(refined, xy_smooth, intrinsics, prior.skeleton, tracks, frames, sigma, fps)
        refined = replace(refined, detection_swapped=fixes.swapped,
                          detection_outliers=fixes.outliers | refined.detection_outliers)  # fmt: skip
    return replace(_refit(refined, xy, intrinsics, cameras), seconds=time.perf_counter() - start)


def lift_tracks_as_infants(res: LiftResult, xy_smooth: np.ndarray, intrinsics: np.ndarray, skeleton: Skeleton,
                           tracks: np.ndarray | None, frames: np.ndarray | None, sigma: float,
                           fps: float | None) -> LiftResult:  # fmt: skip
    """`res` (a two-pass lift) with each track lifted as one infant (`clip.lift_clip_track`)."""
    missing = needs_joints(skeleton)
    if missing:
        raise ConfigError(f"--temporal clip needs the limbs' joints; the prior's {skeleton.name} has no "
                          f"{', '.join(missing)}")  # fmt: skip
    poses = np.full_like(res.poses_camera, np.nan)
    ambiguous = np.zeros(res.observed.shape, bool)
    unreachable = np.zeros(res.observed.shape, bool)
    other = np.full(res.observed.shape, np.nan)
    skeletons = []
    labels = np.zeros(len(xy_smooth), np.int64) if tracks is None else np.asarray(tracks)
    for idx in _track_slices(tracks, len(xy_smooth)):
        cam = np.where(res.lifted[idx, None, None], res.poses_camera[idx], np.nan)
        track = ClipTrack(cam, res.observed[idx], xy_smooth[idx], intrinsics[idx], fps or DEFAULT_CLIP_FPS)
        label = labels[idx[0]].item() if hasattr(labels[idx[0]], "item") else labels[idx[0]]
        at = None if frames is None else np.asarray(frames)[idx]
        smooth = functools.partial(smooth_on_frames, frames=at, sigma=sigma)
        lifted = lift_clip_track(track, skeleton, label, smooth)
        poses[idx], ambiguous[idx], unreachable[idx] = lifted.poses, lifted.ambiguous, lifted.unreachable
        other[idx] = lifted.other_flexion_deg
        skeletons.append(lifted.skeleton.to_dict())
    rel, root = root_relative(poses, skeleton)
    return replace(res, poses_camera=poses, poses_root_relative=rel, root_translation=root,
                   observed=res.observed & ~unreachable, depth_ambiguous=ambiguous, other_flexion_deg=other,
                   track_skeletons=skeletons,
                   detection_outliers=unreachable)  # fmt: skip


def _refit(
    res: LiftResult, xy: np.ndarray, intrinsics: np.ndarray, cameras: Sequence[CameraModel | None] | None
) -> LiftResult:
    """`res` after smoothing, measured against the input's 2D `xy (N, J, 2)` (through the lens
    of `cameras`, as `lift` measures): reprojection errors, and status `poor_fit` (not lifted,
    NaN) for a pose that no longer reproduces its detection."""
    lifted = res.status == LIFTED
    cam = np.where(lifted[:, None, None], res.poses_camera, np.nan)
    reproj = reprojection_error_px(cam, xy, intrinsics, res.observed, cameras)
    status = np.where(lifted & poor_fit(xy, res.observed, reproj), "poor_fit", res.status).astype(object)
    lifted = status == LIFTED
    keep = lifted[:, None, None]
    return replace(res, poses_camera=np.where(keep, cam, np.nan),
                   poses_root_relative=np.where(keep, res.poses_root_relative, np.nan),
                   root_translation=np.where(lifted[:, None], res.root_translation, np.nan),
                   reprojection_error_px=np.where(lifted[:, None], reproj, np.nan), lifted=lifted,
                   status=status)  # fmt: skip


def smooth_tracks_2d(
    xy: np.ndarray, sigma: float, tracks: np.ndarray | None = None, frames: np.ndarray | None = None
) -> np.ndarray:
    """`smooth_sequence` per track over pixels `(N, J, 2)` (on `frames` where given); missing
    (NaN) joints stay NaN."""
    out = xy.astype(np.float64, copy=True)
    for idx in _track_slices(tracks, len(xy)):
        out[idx] = smooth_on_frames(xy[idx], None if frames is None else np.asarray(frames)[idx], sigma)
    return out
