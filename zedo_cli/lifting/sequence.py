"""Whether instances are one video sequence, before the temporal mode smooths them as one.

The temporal modes (`temporal.py`) blend each frame's pose with its neighbours'. On frames that
are not one recording (a set of photos of different infants, two clips run together, frames out
of order) that blending pulls every pose towards unrelated ones: on SyRIP's 700 photos `--temporal
smooth` raised the mean reprojection error from 9.7 px to 169 px (worst 885 px). So the frames
must show that they belong together, or the temporal mode refuses them (`check_sequence`,
a `ConfigError`: the option does not fit the input, exit code 2):

1. **One image size.** A video has one frame size; photos have many (SyRIP's 700: 103).
2. **Frame numbers that count up**, per track: the input's own frame numbers (OpenPose file
   names, MMPose `frame_id`, JSON Lines `frame`) where it has them, else the number in each
   image's file name (`frame_000123.jpg`), where it names its images.
3. **A pose that moves continuously**: between consecutive frames of a track, the median over
   the joints seen in both of how far a joint moves, divided by the person's 2D radius (RMS
   distance of its joints from their centre) and by the frame step; the median of that over
   every pair of consecutive frames must be at most `MAX_MEDIAN_JUMP`. Measured
   (`zedo_cli/evaluation/clips/eased.py`'s generator, SyRIP poses, 4 x 12 key poses, seeds 0 and 1): 0.05
   for 1 s transitions at 30 fps, 0.14 for 0.3 s transitions at 30 fps or 1 s at 10 fps, 0.64
   at 5 fps (a new pose every 2-3 frames, which a filter of 2 frames smears); SyRIP's 700
   photos in id order: 2.0 (5th percentile of the pairs 0.81).

Numbers and names are optional: an input with neither (COCO image ids) is judged by 1 and 3.
Pure numpy, vectorised over all pairs.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from pathlib import PurePath

import numpy as np

from ..errors import ConfigError

MAX_MEDIAN_JUMP = 0.5  # a frame's pose moves at most half its radius from the last (median over pairs)
_NUMBER = re.compile(r"\d+")


def _listed(values: Sequence[object], limit: int = 3) -> str:
    shown = ", ".join(str(v) for v in values[:limit])
    return shown + (", ..." if len(values) > limit else "")


def _by_track(n: int, tracks: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
    """The instances in track order (input order within a track) `(N,)`, and for each position
    whether the next one is the same track's next frame `(N - 1,)`."""
    labels = np.zeros(n, dtype=np.int64) if tracks is None else np.asarray(tracks)
    order = np.argsort(labels, kind="stable")
    return order, labels[order][1:] == labels[order][:-1]


def _image_size_problem(image_sizes: np.ndarray | None) -> str | None:
    if image_sizes is None:
        return None
    sizes = np.asarray(image_sizes, dtype=np.float64).reshape(-1, 2)
    sizes = sizes[np.isfinite(sizes).all(1)]
    distinct, counts = np.unique(sizes, axis=0, return_counts=True)
    if len(distinct) <= 1:
        return None
    common = distinct[np.argsort(-counts, kind="stable")]
    return f"{len(distinct)} image sizes ({_listed([f'{w:g}x{h:g}' for w, h in common])}), where a video has one"


def _order_problem(
    n: int, tracks: np.ndarray | None, frames: np.ndarray | None, file_names: Sequence[str | None] | None
) -> str | None:
    """Why the instances are not in time order: frame numbers, else file names, that do not count up."""
    order, same = _by_track(n, tracks)
    if frames is not None:
        numbers, what = np.asarray(frames, dtype=np.int64), "frame {a} after frame {b}"
        names = [str(f) for f in numbers]
        label = "frame numbers"
    elif file_names is not None and len(file_names) == n and all(f for f in file_names):
        stems = [PurePath(str(f)).stem for f in file_names]
        found = [_NUMBER.findall(stem) for stem in stems]
        missing = [str(file_names[i]) for i, nums in enumerate(found) if not nums]
        if missing:
            return f"file names without a frame number ({_listed(missing, 2)}), so no time order"
        numbers = np.array([int(nums[-1]) for nums in found], dtype=np.int64)
        names, what, label = [str(f) for f in file_names], "{a} after {b}", "file names"
    else:
        return None
    ordered = numbers[order]
    back = np.flatnonzero(same & (ordered[1:] <= ordered[:-1]))
    if not len(back):
        return None
    i, j = order[back[0] + 1], order[back[0]]
    return f"{label} do not count up ({what.format(a=names[i], b=names[j])})"


def median_jump(
    xy: np.ndarray, observed: np.ndarray, tracks: np.ndarray | None = None, frames: np.ndarray | None = None
) -> tuple[float, int]:
    """The median, over pairs of consecutive frames of a track, of how far the pose moves `xy
    (N, J, 2)` (median over the joints `observed (N, J)` in both) per frame step, relative to
    the pose's 2D radius; and the number of pairs (NaN, 0 without any)."""
    n = len(xy)
    order, same = _by_track(n, tracks)
    a, b = order[:-1][same], order[1:][same]  # (P,) consecutive instances of one track
    if not len(a):
        return float("nan"), 0
    obs = np.asarray(observed, dtype=bool) & np.isfinite(xy).all(-1)
    both = obs[a] & obs[b]  # (P, J)
    with np.errstate(all="ignore"):
        dist = np.where(both, np.linalg.norm(xy[b] - xy[a], axis=-1), np.nan)  # (P, J) px
        count = obs[a].sum(1)
        centre = np.where(obs[a][..., None], xy[a], 0.0).sum(1) / np.maximum(count, 1)[:, None]  # (P, 2)
        radius = np.sqrt(np.where(obs[a], ((xy[a] - centre[:, None]) ** 2).sum(-1), 0.0).sum(1) / np.maximum(count, 1))
        steps = np.ones(len(a))
        if frames is not None:  # a gap of k frames may move k times as far
            numbers = np.asarray(frames, dtype=np.float64)
            gaps = numbers[b] - numbers[a]
            usual = np.median(gaps[gaps > 0]) if (gaps > 0).any() else 1.0
            steps = np.maximum(gaps / usual, 1.0)
        usable = both.any(1) & (count >= 2) & (radius > 0)
    if not usable.any():
        return float("nan"), 0
    joint_median = np.nanmedian(dist[usable], axis=1)  # (P',)
    return float(np.median(joint_median / radius[usable] / steps[usable])), int(usable.sum())


def sequence_problem(
    xy: np.ndarray,
    observed: np.ndarray,
    *,
    tracks: np.ndarray | None = None,
    frames: np.ndarray | None = None,
    image_sizes: np.ndarray | None = None,
    file_names: Sequence[str | None] | None = None,
) -> str | None:
    """Why the instances `xy (N, J, 2)` (joints `observed (N, J)`; `tracks`, `frames`,
    `image_sizes (N, 2)`, `file_names` as the temporal mode and the readers give them) are not
    one video sequence, or None when they are (the module's three checks)."""
    problem = _image_size_problem(image_sizes) or _order_problem(len(xy), tracks, frames, file_names)
    if problem:
        return problem
    jump, pairs = median_jump(xy, observed, tracks, frames)
    if pairs and jump > MAX_MEDIAN_JUMP:
        return (f"the pose jumps from frame to frame by {jump:.2f} times its own 2D radius (median over {pairs} "
                f"pairs of consecutive frames), where a video's moves by at most {MAX_MEDIAN_JUMP:g}")  # fmt: skip
    return None


def check_sequence(
    xy: np.ndarray,
    observed: np.ndarray,
    mode: str,
    *,
    tracks: np.ndarray | None = None,
    frames: np.ndarray | None = None,
    image_sizes: np.ndarray | None = None,
    file_names: Sequence[str | None] | None = None,
    source: str | None = None,
) -> None:
    """Refuse (ConfigError, one line naming why) instances that are not one video sequence for
    the temporal `mode`; `source` names the input in the message."""
    problem = sequence_problem(xy, observed, tracks=tracks, frames=frames, image_sizes=image_sizes,
                               file_names=file_names)  # fmt: skip
    if problem is None:
        return
    where = f"{source}: " if source else ""
    raise ConfigError(f"{where}--temporal {mode} smooths one video's frames, and these {len(xy)} are not one: "
                      f"{problem}; lift them frame by frame (without --temporal)")  # fmt: skip
