"""Choosing whom to lift when a frame holds several people (`zedo lift --person`).

Infant recordings often hold more than the infant: a caregiver's hands, a parent in the
background. Instances are grouped into frames (by frame index where the input has one, else by
image id) and one of them is kept per frame, or all of them:

- `largest`: the largest box around the observed joints;
- `center`: the observed joints' box centre nearest the image centre (needs image sizes);
- `highest-score`: the highest detection score (mean joint confidence where there is none);
- `auto`: in the first frame, the instance with the most observed joints, ties broken by score
  then size; in every later frame, the instance nearest (box centre) to the one kept in the
  previous frame, as long as it lies within one box diagonal of it; otherwise the first rule
  again. This follows one infant through a video without jumping to a parent who scores higher;
- `all`: every instance, each keeping its place in its frame.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..data.keypoints import Keypoints2D
from ..errors import ConfigError

PERSON_MODES = ("auto", "largest", "center", "highest-score", "all")


@dataclass(frozen=True)
class Selection:
    """The kept instances (indices into the input, in input order) and each one's place in
    its frame (0 = the frame's first instance in the input)."""

    index: np.ndarray  # (M,) int
    person: np.ndarray  # (M,) int


def frame_keys(kp: Keypoints2D) -> list[object]:
    """The frame of each instance: its frame index where the input has one, else its image id."""
    frames = kp.frame_indices or [None] * len(kp)
    return [("frame", f) if f is not None else ("image", i) for f, i in zip(frames, kp.image_ids, strict=True)]


def group_by_frame(kp: Keypoints2D) -> list[list[int]]:
    """Instance indices per frame, frames in order of first appearance."""
    groups: dict[object, list[int]] = {}
    for i, key in enumerate(frame_keys(kp)):
        groups.setdefault(key, []).append(i)
    return list(groups.values())


def _boxes(kp: Keypoints2D) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per instance: box centre (N, 2), box area (N,) and box diagonal (N,) of the observed
    joints; NaN centre and zero size for an instance with no observed joint."""
    ok = (kp.confidence > 0) & np.isfinite(kp.xy).all(-1)
    pts = np.where(ok[..., None], kp.xy, np.nan)
    with warnings.catch_warnings():  # all-NaN rows (nothing observed) are expected
        warnings.simplefilter("ignore", RuntimeWarning)
        lo, hi = np.nanmin(pts, axis=1), np.nanmax(pts, axis=1)
    size = np.nan_to_num(hi - lo)
    return (lo + hi) / 2.0, size[:, 0] * size[:, 1], np.hypot(size[:, 0], size[:, 1])


def _scores(kp: Keypoints2D) -> np.ndarray:
    """Detection score, or the mean confidence of the observed joints where there is none."""
    conf = np.where(kp.confidence > 0, kp.confidence, np.nan)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        mean_conf = np.nan_to_num(np.nanmean(conf, axis=1))
    return np.array([mean_conf[i] if s is None else float(s) for i, s in enumerate(kp.scores)])


def _rank_first(candidates: list[int], observed: np.ndarray, scores: np.ndarray, area: np.ndarray) -> int:
    return max(candidates, key=lambda i: (observed[i], scores[i], area[i]))


def select_people(kp: Keypoints2D, mode: str) -> Selection:
    """Which instances to lift under `mode` (one of PERSON_MODES)."""
    if mode not in PERSON_MODES:
        raise ConfigError(f"--person must be one of {', '.join(PERSON_MODES)}, got {mode!r}")
    groups = group_by_frame(kp)
    if mode == "all":
        pairs = [(i, place) for group in groups for place, i in enumerate(group)]
    else:
        choose = _chooser(kp, mode)
        pairs = []
        for group in groups:
            kept = choose(group)
            pairs.append((kept, group.index(kept)))
    pairs.sort()
    return Selection(np.array([i for i, _ in pairs], dtype=int), np.array([p for _, p in pairs], dtype=int))


def _chooser(kp: Keypoints2D, mode: str) -> Callable[[list[int]], int]:
    centre, area, diagonal = _boxes(kp)
    scores = _scores(kp)
    observed = ((kp.confidence > 0) & np.isfinite(kp.xy).all(-1)).sum(1)
    if mode == "largest":
        return lambda group: max(group, key=lambda i: area[i])
    if mode == "highest-score":
        return lambda group: max(group, key=lambda i: scores[i])
    if mode == "center":
        if not np.isfinite(kp.image_sizes).all():
            raise ConfigError(f"{kp.path}: --person center needs image sizes; give --image-size W H or --images")
        image_centre = kp.image_sizes / 2.0
        dist = np.linalg.norm(centre - image_centre, axis=1)
        return lambda group: min(group, key=lambda i: np.inf if np.isnan(dist[i]) else dist[i])
    previous: list[int] = []

    def auto(group: list[int]) -> int:
        kept = _rank_first(group, observed, scores, area)
        if previous and len(group) > 1:
            last = previous[-1]
            dist = {i: float(np.linalg.norm(centre[i] - centre[last])) for i in group}
            nearest = min(group, key=lambda i: np.inf if np.isnan(dist[i]) else dist[i])
            if dist[nearest] <= max(diagonal[last], 1.0):
                kept = nearest
        previous.append(kept)
        return kept

    return auto
