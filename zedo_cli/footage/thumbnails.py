"""Thumbnails of chosen frames of a result, cut from its video or images with the lifted skeleton drawn
over them (`zedo analyze --report` with `--video` / `--images`: the frames a person should review).

A video must fit the result: as many frames as the result's last frame needs, and the image size each
frame was lifted for; else one line refuses it (VideoMismatchError) before anything is cut.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..camera.video import VideoInfo, probe_video, read_frames
from ..errors import InputFormatError, plural
from ..formats.readers.result import ResultPoses
from .render import Painter, RenderSettings, _check_size, _rows_by_frame, list_images, match_images
from .video_check import VideoMismatchError

MARGIN = 0.25  # of the persons' extent, around them in a thumbnail
# How far the head reaches beyond the shoulders' midpoint, in trunk lengths (shoulders' to hips' midpoint):
# an infant's head is about as long as its trunk is to the neck, so 0.8 keeps the crown in the picture
# when the input has no face points (a body-only detector, or the skeleton alone).
HEAD_REACH = 0.8
THUMB_WIDTH = 360  # pixels: the report shows them at 270 px, sharp on a high-density screen


def check_video_fits(result: ResultPoses, video: str | Path, info: VideoInfo | None = None) -> tuple[int, int]:
    """The video's (width, height) when it can be the footage of `result`; else VideoMismatchError. `info`: the
    video already probed (`probe_video`), else it is probed here."""
    info = probe_video(video) if info is None else info
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

    frame = np.ascontiguousarray(frame)
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
        rows = by_frame.get(f, [])
        if painter is not None:
            frame = painter.paint(frame, rows, f, result.fps)
            frame = _around(frame, [_with_head(result, r, p) for r in rows if (p := painter.persons[r].px) is not None])
        out[f] = _png(frame)
    return out


def _with_head(result: ResultPoses, row: int, px: np.ndarray) -> np.ndarray:
    """The pixels a thumbnail keeps in view for one person: its drawn joints `px (J, 2)`, the input's
    other keypoints of the row (face, feet, ...) and the head's reach beyond the shoulders (HEAD_REACH)."""
    names = list(result.skeleton.joints)
    points = [px]
    if result.other_keypoints_2d is not None:
        points.append(result.other_keypoints_2d[row])
    if {"left_shoulder", "right_shoulder", "left_hip", "right_hip"} <= set(names):
        shoulders = (px[names.index("left_shoulder")] + px[names.index("right_shoulder")]) / 2
        hips = (px[names.index("left_hip")] + px[names.index("right_hip")]) / 2
        points.append((shoulders + HEAD_REACH * (shoulders - hips))[None])  # NaN when a joint is: dropped
    return np.concatenate(points)


def _around(frame: np.ndarray, pixels: list[np.ndarray]) -> np.ndarray:
    """The part of `frame` around the drawn persons (`(J, 2)` pixels each) with a margin of MARGIN of
    their extent, in the frame's aspect, at least a third of its width, moved inside the frame (persons
    partly outside it stay at its edge); the whole frame when none is drawn."""
    pts = np.concatenate(pixels) if pixels else np.empty((0, 2))
    pts = pts[np.isfinite(pts).all(-1)]
    if not len(pts):
        return frame
    h, w = frame.shape[:2]
    lo, hi = pts.min(0), pts.max(0)  # (2,) x, y
    half = (hi - lo) * (0.5 + MARGIN)
    half_w = min(max(half[0], half[1] * w / h, w / 6), w / 2)
    half_h = half_w * h / w
    cx = float(np.clip((lo[0] + hi[0]) / 2, half_w, w - half_w))
    cy = float(np.clip((lo[1] + hi[1]) / 2, half_h, h - half_h))
    x0, y0 = int(round(cx - half_w)), int(round(cy - half_h))
    return frame[y0 : y0 + int(round(2 * half_h)), x0 : x0 + int(round(2 * half_w))]
