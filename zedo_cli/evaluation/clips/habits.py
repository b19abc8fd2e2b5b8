"""A 2D detector's habits, injected into exact syrip12 keypoints, with masks of where each went.

`apply_habits` works on any clip's 2D (`(T, 12, 2)` px at a frame rate), so it serves the eased
key-pose clips too. In the order applied:

- jitter: Gaussian noise of `jitter_px` on every coordinate;
- swaps: events where the detector takes the body's left for its right, every left joint
  exchanged with its twin for a few frames (`swapped (T,)`);
- hand jumps: events where one wrist is put on a nearby adult's hand, a point held still at
  `hand_offset` (a fraction of the 2D pose's size) from where the wrist was when it began
  (`hand_jump (T, J)`, on the wrist only);
- dropouts: single joints missed with probability `dropout` (`dropped (T, J)`);
- lost track: events of frames without any detection (`lost (T,)`).

Missing joints are as zedo's `Keypoints2D` has them: NaN coordinates and confidence 0. Seen
joints get a confidence drawn in `confidence`. Masks say what the output shows: a lost frame
carries no other habit, a dropped joint no swap or hand jump of its own.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...errors import ConfigError
from ...lifting.detections import pose_size
from .motion import SYRIP12

WRISTS = (SYRIP12.index("left_wrist"), SYRIP12.index("right_wrist"))


@dataclass(frozen=True)
class DetectorHabits:
    """Rates are events per minute of clip; durations are frame ranges (inclusive)."""

    jitter_px: float = 2.0
    dropout: float = 0.02
    swaps_per_min: float = 2.0
    swap_frames: tuple[int, int] = (2, 8)
    hand_jumps_per_min: float = 2.0
    hand_jump_frames: tuple[int, int] = (3, 15)
    hand_offset: tuple[float, float] = (0.3, 0.8)
    losses_per_min: float = 1.0
    lost_frames: tuple[int, int] = (5, 30)
    confidence: tuple[float, float] = (0.5, 1.0)

    def __post_init__(self) -> None:
        rates = (self.jitter_px, self.dropout, self.swaps_per_min, self.hand_jumps_per_min, self.losses_per_min)
        if min(rates) < 0 or self.dropout > 1:
            raise ConfigError("detector habits: rates and jitter must be >= 0, dropout at most 1")
        for name in ("swap_frames", "hand_jump_frames", "lost_frames"):
            lo, hi = getattr(self, name)
            if not 1 <= lo <= hi:
                raise ConfigError(f"detector habits: {name} must be 1 <= low <= high, got {(lo, hi)}")


@dataclass(frozen=True)
class HabitMasks:
    """Where each habit shows in a clip's 2D: per frame `swapped` and `lost`, per joint `dropped`
    and `hand_jump`."""

    swapped: np.ndarray  # (T,) bool
    hand_jump: np.ndarray  # (T, J) bool
    dropped: np.ndarray  # (T, J) bool
    lost: np.ndarray  # (T,) bool

    @classmethod
    def none(cls, frames: int, joints: int) -> HabitMasks:
        return cls(np.zeros(frames, bool), np.zeros((frames, joints), bool), np.zeros((frames, joints), bool),
                   np.zeros(frames, bool))  # fmt: skip


def event_mask(rng: np.random.Generator, frames: int, fps: float, per_min: float, span: tuple[int, int]) -> list[slice]:
    """Event spans: a Poisson number of events (`per_min` per minute), each at a uniform start
    with a uniform length in `span` frames, cut at the clip's end."""
    count = int(rng.poisson(per_min * frames / fps / 60.0))
    starts = rng.integers(0, max(frames, 1), count)
    lengths = rng.integers(span[0], span[1] + 1, count)
    return [slice(int(s), int(min(s + n, frames))) for s, n in zip(starts, lengths, strict=True)]


def apply_habits(
    xy: np.ndarray, fps: float, habits: DetectorHabits, rng: np.random.Generator
) -> tuple[np.ndarray, np.ndarray, HabitMasks]:
    """Detected 2D `(T, 12, 2)` (NaN: missing), confidences `(T, 12)` and the masks, from exact
    syrip12 pixels `xy (T, 12, 2)` of one clip at `fps`."""
    frames, joints = xy.shape[:2]
    out = xy + rng.normal(0.0, habits.jitter_px, xy.shape)
    swapped = np.zeros(frames, bool)
    for span in event_mask(rng, frames, fps, habits.swaps_per_min, habits.swap_frames):
        swapped[span] = True
    out[swapped] = out[swapped][:, SYRIP12.flip_permutation]
    hand = np.zeros((frames, joints), bool)
    size = pose_size(xy)
    for span in event_mask(rng, frames, fps, habits.hand_jumps_per_min, habits.hand_jump_frames):
        wrist = WRISTS[int(rng.integers(2))]
        angle = rng.uniform(0, 2 * np.pi)
        offset = rng.uniform(*habits.hand_offset) * size[span.start] * np.array([np.cos(angle), np.sin(angle)])
        target = out[span.start, wrist] + offset
        out[span, wrist] = target + rng.normal(0.0, habits.jitter_px, (span.stop - span.start, 2))
        hand[span, wrist] = True
    dropped = rng.random((frames, joints)) < habits.dropout
    lost = np.zeros(frames, bool)
    for span in event_mask(rng, frames, fps, habits.losses_per_min, habits.lost_frames):
        lost[span] = True
    missing = dropped | lost[:, None]
    conf = np.where(missing, 0.0, rng.uniform(*habits.confidence, (frames, joints)))
    out[missing] = np.nan
    masks = HabitMasks(swapped & ~lost, hand & ~missing, dropped & ~lost[:, None], lost)
    return out, conf, masks
