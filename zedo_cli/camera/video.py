"""Video files through OpenCV: what a clip is (size, frame rate, frame count), its frames, and
frames sampled evenly from it. Frames are BGR `uint8 (H, W, 3)` arrays, as OpenCV gives them.

A file OpenCV cannot open, or one without a single decodable frame, raises `VideoError`
(an input error, exit code 3) naming the file.

The frame rate comes from the container (MP4, MOV, AVI, MKV, ...). A bare stream of coded frames (raw
MJPEG, H.264 or H.265 "Annex B") has no container and stores no rate: OpenCV reports 25 fps for it, so
such a file is recognised by its first bytes, never by the value, and its rate must be given (`--fps`).
"""

from __future__ import annotations

import queue
import threading
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import ConfigError, InputFormatError, ZedoError

QUEUE_DEPTH = 8  # frames decoded ahead / waiting to be encoded: 8 x 2.8 MB at 1280x720


class VideoError(InputFormatError):
    """A video file cannot be opened or decoded."""


# The first bytes of bare streams, after a start code 00 00 01 for H.264 / H.265: the NAL unit types a stream
# begins with (access unit delimiter, SEI, parameter sets). MPEG-1/2 streams (00 00 01 B3) store their rate.
_JPEG_START = b"\xff\xd8\xff"
_START_CODE = b"\x00\x00\x01"
_H264_FIRST_NAL = {0x09, 0x06, 0x07, 0x27, 0x47, 0x67, 0x08, 0x28, 0x48, 0x68, 0x05, 0x25, 0x45, 0x65}
_H265_FIRST_NAL = {0x40, 0x42, 0x44, 0x46, 0x4E, 0x50}


def bare_stream_kind(head: bytes) -> str | None:
    """What kind of bare (container-less) video stream a file starting with `head` is, or None for a
    container (or anything else). Such a stream stores no frame rate."""
    if head.startswith(_JPEG_START):
        return "a raw MJPEG stream"
    rest = head[1:] if head.startswith(b"\x00" + _START_CODE) else head
    if rest.startswith(_START_CODE) and len(rest) > 3:
        if rest[3] in _H264_FIRST_NAL:
            return "a raw H.264 stream"
        if rest[3] in _H265_FIRST_NAL:
            return "a raw H.265 stream"
    return None


def _bare_stream(path: str | Path) -> str | None:
    with open(path, "rb") as fh:
        return bare_stream_kind(fh.read(8))


@dataclass(frozen=True)
class VideoInfo:
    """What the container says about a clip. `fps` is None when it states none (or nonsense), and for a
    bare stream (`bare_stream`: its kind), which has no container to state one; `frame_count` is the
    container's count (OpenCV's estimate for some containers; counted frame by frame for a bare stream)."""

    path: str
    width: int
    height: int
    fps: float | None
    frame_count: int
    bare_stream: str | None = None

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
    bare = _bare_stream(path)
    if bare is not None:  # OpenCV's 25 fps and frame count are made up for a stream without a container
        return VideoInfo(str(path), int(width), int(height), None, max(count_frames(path), 1), bare)
    return VideoInfo(str(path), int(width), int(height), fps if np.isfinite(fps) and 0 < fps < 1e4 else None,
                     max(count, 1))  # fmt: skip


def require_frame_rate(info: VideoInfo, fps: float | None) -> float | None:
    """The frame rate to use for `info`'s video: `fps` (the option) where given, else the container's;
    a bare stream, which stores none, without `fps` is a usage error (its rate would be a guess)."""
    if fps is not None:
        return fps
    if info.bare_stream is not None:
        raise ConfigError(f"{info.path}: {info.bare_stream} stores no frame rate (no container): give --fps, the "
                          "rate it was recorded at")  # fmt: skip
    return info.fps


def count_frames(path: str | Path) -> int:
    """The frames of the video counted one by one (without decoding them), for when the
    container's count is not to be trusted."""
    cap = _open(path)
    try:
        count = 0
        while cap.grab():
            count += 1
    finally:
        cap.release()
    return count


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


def read_frames(path: str | Path, wanted: set[int]) -> dict[int, np.ndarray]:
    """The frames numbered `wanted` (0-based), decoded in order: every frame is grabbed (seeking is
    unreliable in several codecs), only the wanted ones are decoded, and reading stops after the last."""
    cap = _open(path)
    out: dict[int, np.ndarray] = {}
    last = max(wanted, default=-1)
    try:
        for i in range(last + 1):
            if not cap.grab():
                break
            if i in wanted:
                ok, frame = cap.retrieve()
                if ok and frame is not None:
                    out[i] = frame
    finally:
        cap.release()
    return out


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


class _Failed:
    def __init__(self, exc: BaseException) -> None:
        self.exc = exc


_END = object()


def _put(q: queue.Queue, item: object, stop: threading.Event) -> bool:
    """Put unless told to stop; False when stopped."""
    while not stop.is_set():
        try:
            q.put(item, timeout=0.1)
            return True
        except queue.Full:
            continue
    return False


def frames_ahead(path: str | Path, depth: int = QUEUE_DEPTH) -> Iterator[np.ndarray]:
    """`iter_frames(path)`, decoded on a background thread up to `depth` frames ahead, so that
    decoding overlaps the caller's work (OpenCV releases the GIL while it decodes). Errors are
    raised in the caller; leaving the loop early stops the thread."""
    frames = iter_frames(path)
    first = next(frames, None)  # open errors are raised here, in the caller's thread
    q: queue.Queue = queue.Queue(maxsize=depth)
    stop = threading.Event()

    def work() -> None:
        try:
            if first is not None and _put(q, first, stop):
                for frame in frames:
                    if not _put(q, frame, stop):
                        break
            _put(q, _END, stop)
        except BaseException as exc:  # handed to the caller
            _put(q, _Failed(exc), stop)
        finally:
            frames.close()

    thread = threading.Thread(target=work, name="zedo-decode", daemon=True)
    thread.start()
    try:
        while (item := q.get()) is not _END:
            if isinstance(item, _Failed):
                raise item.exc
            yield item
    finally:
        stop.set()
        thread.join()


class VideoWriter:
    """An mp4v video written on a background thread (encoding overlaps the caller's drawing).

        with VideoWriter(path, fps, (width, height)) as out:
            out.write(frame)

    `path` must end in .mp4 (OpenCV picks the container by the extension). Errors of the
    encoder are raised by the next `write` or at the end of the block.
    """

    def __init__(self, path: str | Path, fps: float, size: tuple[int, int], depth: int = QUEUE_DEPTH) -> None:
        import cv2

        self._writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"mp4v"), float(fps), size)
        if not self._writer.isOpened():
            self._writer.release()
            raise ZedoError(f"{path}: OpenCV cannot write an mp4v video here")
        self._queue: queue.Queue[Any] = queue.Queue(maxsize=depth)
        self._error: BaseException | None = None
        self._thread = threading.Thread(target=self._work, name="zedo-encode", daemon=True)
        self._thread.start()

    def _work(self) -> None:
        while (frame := self._queue.get()) is not _END:
            if self._error is None:
                try:
                    self._writer.write(frame)
                except BaseException as exc:  # handed to the caller
                    self._error = exc

    def write(self, frame: np.ndarray) -> None:
        if self._error is not None:
            raise self._error
        self._queue.put(frame)

    def close(self) -> None:
        if self._thread.is_alive():
            self._queue.put(_END)
            self._thread.join()
        self._writer.release()
        if self._error is not None:
            raise self._error

    def __enter__(self) -> VideoWriter:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
