"""Thumbnails of chosen frames of a result, cut from its video or images with the lifted skeleton drawn
over them (`zedo analyze --report` with `--video` / `--images`: the frames a person should review).

A video must fit the result: as many frames as the result's last frame needs, and the image size each
frame was lifted for; else one line refuses it (VideoMismatchError) before anything is cut.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..camera.video import probe_video, read_frames
from ..errors import InputFormatError, plural
from ..formats.result_reader import ResultPoses
from .render import Painter, RenderSettings, _check_size, _rows_by_frame, list_images, match_images
from .video_check import VideoMismatchError

THUMB_WIDTH = 360  # pixels: the report shows them at 270 px, sharp on a high-density screen


def check_video_fits(result: ResultPoses, video: str | Path) -> tuple[int, int]:
    """The video's (width, height) when it can be the footage of `result`; else VideoMismatchError."""
    info = probe_video(video)
    last = int(result.frame_index.max()) if len(result.frame_index) else -1
    if last >= info.frame_count:
        raise VideoMismatchError(f"{video}: {plural(info.frame_count, 'frame')}, but the result "
                                 f"{result.source} has people in frame {last}: not this result's footage")  # fmt: skip
    try:
        _check_size(result, info.width, info.height, list(range(len(result.frame_index))), str(video))
    except InputFormatError as err:
        raise VideoMismatchError(str(err)) from None
    return info.width, info.height


def _painter(result: ResultPoses) -> Painter | None:
    """A painter of the result's skeletons, or None for a result without cameras (a CSV: frames only)."""
    try:
        return Painter(result, RenderSettings())
    except InputFormatError:
        return None


def _png(frame: np.ndarray) -> bytes:
    import cv2

    h, w = frame.shape[:2]
    small = cv2.resize(frame, (THUMB_WIDTH, max(1, round(h * THUMB_WIDTH / w))), interpolation=cv2.INTER_AREA)
    ok, data = cv2.imencode(".png", small)
    if not ok:
        raise InputFormatError("a thumbnail could not be encoded as PNG")
    return data.tobytes()


def cut_thumbnails(result: ResultPoses, frames: list[int], *, video: str | Path | None = None,
                   images: str | Path | None = None) -> dict[int, bytes]:  # fmt: skip
    """PNG bytes by frame number of each of `frames`, from `video` or the folder `images`, the frame's
    lifted persons drawn over it."""
    import cv2

    by_frame = _rows_by_frame(result)
    painter = _painter(result)
    decoded: dict[int, np.ndarray] = {}
    if video is not None:
        check_video_fits(result, video)
        decoded = read_frames(video, set(frames))
    elif images is not None:
        paths = {r: path for path, rows in match_images(result, list_images(Path(images))).items() for r in rows}
        for f in frames:
            rows = by_frame.get(f, [])
            if rows and rows[0] in paths and (img := cv2.imread(str(paths[rows[0]]))) is not None:
                _check_size(result, img.shape[1], img.shape[0], rows, str(paths[rows[0]]))
                decoded[f] = img
    out = {}
    for f, frame in decoded.items():
        if painter is not None:
            frame = painter.paint(frame, by_frame.get(f, []), f, result.fps)
        out[f] = _png(frame)
    return out
