"""Video files through OpenCV: what a clip is (size, frame rate, frame count), its frames, and
frames sampled evenly from it. Frames are BGR `uint8 (H, W, 3)` arrays, as OpenCV gives them.

A file OpenCV cannot open, or one without a single decodable frame, raises `VideoError`
(an input error, exit code 3) naming the file.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputFormatError


class VideoError(InputFormatError):
    """A video file cannot be opened or decoded."""


@dataclass(frozen=True)
class VideoInfo:
    """What the container says about a clip. `fps` is None when it states none (or nonsense);
    `frame_count` is the container's count (OpenCV's estimate for some containers)."""

    path: str
    width: int
    height: int
    fps: float | None
    frame_count: int

    @property
    def size(self) -> tuple[int, int]:
        return self.width, self.height


def _open(path: str | Path):  # noqa: ANN202 (cv2.VideoCapture has no stub type)
    import cv2

    name = str(path)
    if not Path(name).is_file():
        raise VideoError(f"{name}: video file not found")
    cap = cv2.VideoCapture(name)
    if not cap.isOpened():
        cap.release()
        raise VideoError(f"{name}: cannot open as a video (no decoder for it in OpenCV, or not a video)")
    return cap


def probe_video(path: str | Path) -> VideoInfo:
    """Size, frame rate and frame count of a video file; the first frame is decoded to be sure
    the file is a video OpenCV can read."""
    import cv2

    cap = _open(path)
    try:
        ok, frame = cap.read()
        if not ok or frame is None:
            raise VideoError(f"{path}: no decodable frame in the video")
        fps = float(cap.get(cv2.CAP_PROP_FPS))
        count = int(cap.get(cv2.CAP_PROP_FRAME_COUNT))
    finally:
        cap.release()
    height, width = frame.shape[:2]
    return VideoInfo(str(path), int(width), int(height), fps if np.isfinite(fps) and 0 < fps < 1e4 else None,
                     max(count, 1))  # fmt: skip


def iter_frames(path: str | Path) -> Iterator[np.ndarray]:
    """Every frame of the video, in order, decoded one at a time."""
    cap = _open(path)
    try:
        while True:
            ok, frame = cap.read()
            if not ok:
                return
            yield frame
    finally:
        cap.release()


def evenly_spaced(total: int, count: int) -> list[int]:
    """`count` frame indices spread evenly over `total` frames (all of them when fewer)."""
    if total <= count:
        return list(range(total))
    return sorted({int(round(i)) for i in np.linspace(0, total - 1, count)})


def sample_frames(path: str | Path, count: int) -> list[tuple[int, np.ndarray]]:
    """About `count` frames `(index, frame)` evenly spaced over the video. Frames are decoded in
    order (seeking is unreliable in several codecs); only the chosen ones are kept."""
    info = probe_video(path)
    wanted = set(evenly_spaced(info.frame_count, count))
    return [(i, frame) for i, frame in enumerate(iter_frames(path)) if i in wanted]
