"""`zedo lift --video`: the video's size, frame rate and frame count, checked against the keypoints.

- More keypoint frames than the video has (distinct frame numbers, or image ids when the input
  has no frame numbers), or a frame number past the video's end: `VideoMismatchError` (exit 3).
- Image sizes stated by the keypoint file that differ from the video's: the same error.
- Observed keypoints (confidence > 0) more than `OUTSIDE_MARGIN` of the frame's width or height
  beyond its edges are reported: the result's `params.video.keypoints_outside_frame` lists each
  such instance and joint, and the CLI prints a warning. Detectors place joints a little outside
  the image (a hand leaving the frame); far outside is a wrong size or a wrong video.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..camera.video import VideoInfo, count_frames, probe_video, require_frame_rate
from ..data.keypoints import Keypoints2D
from ..errors import ConfigError, InputFormatError, plural

OUTSIDE_MARGIN = 0.25  # of the width (x) or height (y), beyond the frame's edges


class VideoMismatchError(InputFormatError):
    """The keypoints cannot come from this video: more frames than it has, or another image size."""


@dataclass(frozen=True)
class VideoCheck:
    info: VideoInfo
    frames: int  # distinct frames of the keypoints
    outside: list[tuple[int, list[str]]]  # (instance index, joints far outside the frame)

    def params(self) -> dict[str, Any]:
        """The result's `params.video`."""
        return {
            "path": self.info.path, "width": self.info.width, "height": self.info.height, "fps": self.info.fps,
            "frame_count": self.info.frame_count, "keypoint_frames": self.frames,
            "outside_margin": OUTSIDE_MARGIN,
            "keypoints_outside_frame": [{"instance_index": i, "joints": joints} for i, joints in self.outside],
        }  # fmt: skip

    def warning(self) -> str | None:
        if not self.outside:
            return None
        first, joints = self.outside[0]
        return (f"{plural(len(self.outside), 'instance')} with keypoints more than {OUTSIDE_MARGIN:.0%} of the "
                f"frame outside {self.info.path}'s {self.info.width}x{self.info.height} frame (first: instance "
                f"{first}, {', '.join(joints)}); listed in params.video.keypoints_outside_frame")  # fmt: skip


def video_options(
    video: str | Path, image_size: tuple[float, float] | None, fps: float | None
) -> tuple[VideoInfo, tuple[float, float], float | None]:
    """The video's info, and the image size and fps lift uses: the options where given (an
    --image-size other than the video's is a usage error), else the video's."""
    info = probe_video(video)
    if image_size is not None and (abs(image_size[0] - info.width) > 1 or abs(image_size[1] - info.height) > 1):
        raise ConfigError(f"--image-size {image_size[0]:g} {image_size[1]:g} differs from {video}'s "
                          f"{info.width}x{info.height}")  # fmt: skip
    return info, (float(info.width), float(info.height)), require_frame_rate(info, fps)


def keypoint_frames(kp: Keypoints2D) -> tuple[int, int | None]:
    """Distinct frames of the keypoints, and the largest frame number when every instance has one."""
    numbers = kp.frame_indices
    if numbers is not None and all(n is not None for n in numbers):
        return len(set(numbers)), max(numbers)  # type: ignore[type-var]
    return len({str(i) for i in kp.image_ids}), None


def check_against_video(kp: Keypoints2D, info: VideoInfo, source: str) -> VideoCheck:
    """Raise `VideoMismatchError` when `kp` cannot come from the video; list keypoints far outside."""
    frames, last = keypoint_frames(kp)
    if frames > info.frame_count or (last is not None and last >= info.frame_count):
        exact = count_frames(info.path)  # the container's count can be an estimate: count before refusing
        if frames > exact or (last is not None and last >= exact):
            what = f"frame number {last}" if last is not None and last >= exact else plural(frames, "frame")
            raise VideoMismatchError(f"{source}: {what} but {info.path} has {plural(exact, 'frame')}")
    sizes = kp.image_sizes
    known = np.isfinite(sizes).all(axis=1)
    wrong = known & (np.abs(sizes - [info.width, info.height]) > 1).any(axis=1)
    if wrong.any():
        w, h = sizes[np.flatnonzero(wrong)[0]]
        raise VideoMismatchError(f"{source}: image size {w:g}x{h:g} but {info.path} is {info.width}x{info.height}")
    size = np.array([info.width, info.height], dtype=np.float64)
    with np.errstate(invalid="ignore"):
        far = ((kp.xy < -OUTSIDE_MARGIN * size) | (kp.xy > (1 + OUTSIDE_MARGIN) * size)).any(-1) & (kp.confidence > 0)
    outside = [(int(i), [kp.skeleton.joints[j] for j in np.flatnonzero(far[i])]) for i in np.flatnonzero(far.any(1))]
    return VideoCheck(info, frames, outside)
