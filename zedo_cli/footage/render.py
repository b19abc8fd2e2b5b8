"""`zedo render`: a result's lifted skeletons drawn over the footage they were lifted from.

Each person's `keypoints_3d` (camera frame, metres) is projected through its frame's camera
(the result's `CameraModel` of each person, lens distortion included) into the
original image, so the overlay shows how well the 3D pose explains the footage. Video frames
are matched to the result by `frame_index`; images of a folder by `file_name`, else by
`image_id` (the image's stem, as text or as a number). Frames the result does not mention pass
through unchanged; the output is never written partially (files.py).
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..camera.calibration import IMAGE_SUFFIXES
from ..camera.video import QUEUE_DEPTH, VideoWriter, frames_ahead, probe_video, require_frame_rate
from ..data.skeleton import center_on_root
from ..errors import ConfigError, InputFormatError, ZedoError, plural
from ..files import atomic_path, check_writable, make_output_folder
from ..formats.readers.result import ResultPoses
from .draw import SideView, Style, draw_flag, draw_skeleton, flag_names, label, stamp

VIDEO_SUFFIXES = (".mp4",)
CANVASES = QUEUE_DEPTH + 3  # frames with a side panel in flight: queued, being encoded, being drawn
OnFrame = Callable[[int, int], None]


@dataclass(frozen=True)
class RenderSettings:
    side_view: bool = False  # a panel beside the frame: the skeletons seen from the side
    overwrite: bool = False
    fps: float | None = None  # the video's frame rate where its file stores none (a bare stream)


@dataclass(frozen=True)
class Person:
    """One person of one frame, ready to draw."""

    index: int  # position in its frame
    px: np.ndarray | None  # (J, 2) pixels in the original image; None: not lifted
    observed: np.ndarray  # (J,) bool
    relative: np.ndarray | None  # (J, 3) root-relative camera-frame metres (side view)
    flags: list[str]


@dataclass(frozen=True)
class RenderSummary:
    output: str
    frames: int  # frames written
    drawn: int  # frames with at least one person of the result
    persons: int  # lifted persons drawn
    seconds: float


def camera_poses(result: ResultPoses) -> np.ndarray:
    """`(N, J, 3)` metres in the camera frame, whatever frame the file was written in."""
    if result.coordinate_frame == "camera":
        return result.poses
    if result.root_translation is None:
        raise InputFormatError(f"{result.source}: a {result.coordinate_frame}-frame result without root_translation")
    return result.poses + result.root_translation[:, None, :]


def people(result: ResultPoses) -> list[Person]:
    """Every row of the result projected through its frame's camera."""
    if result.cameras is None or result.flags is None:
        raise InputFormatError(f"{result.source}: a {result.format} result has no per-frame flags; render reads "
                               "the JSON or JSON Lines result (zedo lift --output-format json / jsonl)")  # fmt: skip
    poses = camera_poses(result)
    out = []
    for i, camera in enumerate(result.cameras):
        if camera is None:
            raise InputFormatError(f"{result.source}: frame {result.frame_index[i]}: camera: missing")
        lifted = bool(result.lifted[i]) and bool(np.isfinite(poses[i]).any())
        out.append(Person(
            int(result.person[i]),
            camera.project(poses[i]) if lifted else None,
            result.observed[i],
            center_on_root(poses[i], result.skeleton) if lifted else None,
            result.flags[i],
        ))  # fmt: skip
    return out


class Painter:
    """Draws the persons of a frame (and the side panel) for one result."""

    def __init__(self, result: ResultPoses, settings: RenderSettings) -> None:
        self.result = result
        self.persons = people(result)
        self.side_view = settings.side_view
        self._relative = np.array([p.relative for p in self.persons if p.relative is not None]).reshape(1, -1, 3)
        self._sides: dict[int, SideView] = {}
        self._canvases: list[np.ndarray] = []
        self._next = -1

    def side(self, height: int) -> SideView | None:
        """The side panel for frames `height` tall (one scale for the whole clip), or None."""
        if not self.side_view:
            return None
        if height not in self._sides:
            self._sides[height] = SideView.fit(self._relative, height)
        return self._sides[height]

    def paint(self, frame: np.ndarray, rows: list[int], frame_index: int, fps: float | None) -> np.ndarray:
        """`frame` with rows' persons drawn (in place), and the side panel when asked for. A frame
        with no rows is returned as it is (with an empty panel)."""
        skeleton, style = self.result.skeleton, Style.for_height(frame.shape[0])
        notes = []
        for r in rows:
            p = self.persons[r]
            if p.px is None:
                notes.append(f"person {p.index} not lifted: {flag_names(p.flags)}")
                continue
            draw_skeleton(frame, p.px, p.observed, skeleton, style)
            if p.flags:
                draw_flag(frame, p.px, p.flags, style)
        if rows:
            label(frame, stamp(frame_index, fps), (6, 6), (255, 255, 255), style)
            for k, note in enumerate(notes, 1):
                label(frame, note, (6, 6 + k * (int(30 * style.font_scale) + 10)), (220, 40, 220), style)
        side = self.side(frame.shape[0])
        if side is None:
            return frame
        canvas = self._canvas(frame.shape[0], frame.shape[1] + side.width)
        canvas[:, : frame.shape[1]] = frame
        drawn = [(self.persons[r].relative, self.persons[r].observed) for r in rows]
        side.draw(canvas[:, frame.shape[1] :], [(rel, obs) for rel, obs in drawn if rel is not None], skeleton, style)
        return canvas

    def _canvas(self, height: int, width: int) -> np.ndarray:
        """The next of CANVASES reused frame buffers: a fresh 3 MB array per frame costs more than
        the drawing (page faults); a buffer comes round again only after the frames queued
        before it are encoded (the video writer holds at most its queue's depth + 1)."""
        self._next = (self._next + 1) % CANVASES
        if len(self._canvases) <= self._next or self._canvases[self._next].shape[:2] != (height, width):
            buffer = np.empty((height, width, 3), np.uint8)
            self._canvases[self._next : self._next + 1] = [buffer]
        return self._canvases[self._next]


def _check_size(result: ResultPoses, width: int, height: int, rows: list[int], where: str) -> None:
    """The result was lifted for images of this size (else its projections land elsewhere)."""
    for r in rows:
        camera = result.cameras[r] if result.cameras is not None else None
        size = camera.image_size if camera is not None else None
        if size and (abs(size[0] - width) > 1 or abs(size[1] - height) > 1):
            raise InputFormatError(f"{result.source}: frame {result.frame_index[r]}: lifted for a "
                                   f"{size[0]:g}x{size[1]:g} image, but {where} is {width}x{height}")  # fmt: skip


def _rows_by_frame(result: ResultPoses) -> dict[int, list[int]]:
    out: dict[int, list[int]] = {}
    for i, f in enumerate(result.frame_index):
        out.setdefault(int(f), []).append(i)
    return out


def render_video(result: ResultPoses, video: str | Path, output: str | Path, settings: RenderSettings,
                 on_frame: OnFrame | None = None) -> RenderSummary:  # fmt: skip
    """Draw `result` over every frame of `video` (frame i <-> the result's frame_index i) into an
    MP4 (mp4v) at the video's frame rate."""
    start = time.perf_counter()
    if Path(output).suffix.lower() not in VIDEO_SUFFIXES:
        raise ConfigError(f"{output}: a video renders to an .mp4 file")
    check_writable(Path(output), settings.overwrite)
    info = probe_video(video)
    fps = require_frame_rate(info, settings.fps) or result.fps
    painter = Painter(result, settings)
    by_frame = _rows_by_frame(result)
    _check_size(result, info.width, info.height, [r for rows in by_frame.values() for r in rows], str(video))
    side = painter.side(info.height)
    width = info.width + (side.width if side else 0)
    done = drawn = persons = 0
    with atomic_path(output, overwrite=settings.overwrite) as tmp:
        encoded = tmp.with_name(tmp.name + ".mp4")  # OpenCV picks the container by the extension
        try:
            # decoding, drawing and encoding overlap on three threads (OpenCV releases the GIL)
            with VideoWriter(encoded, fps or 30.0, (width, info.height)) as writer:
                for done, frame in enumerate(frames_ahead(video), 1):
                    rows = by_frame.get(done - 1, [])
                    writer.write(painter.paint(frame, rows, done - 1, fps))
                    drawn += bool(rows)
                    persons += sum(painter.persons[r].px is not None for r in rows)
                    if on_frame is not None:
                        on_frame(done, info.frame_count)
            beyond = sorted(f for f in by_frame if f >= done)
            if beyond:
                raise InputFormatError(f"{result.source}: frame_index {beyond[0]}: the result has people in "
                                       f"{plural(len(beyond), 'frame')} after the end of {video} "
                                       f"({plural(done, 'frame')})")  # fmt: skip
            os.replace(encoded, tmp)
        finally:
            encoded.unlink(missing_ok=True)
    return RenderSummary(str(output), done, drawn, persons, time.perf_counter() - start)


def match_images(result: ResultPoses, images: list[Path]) -> dict[Path, list[int]]:
    """The result's rows of each image: by file name (its base name), else by image_id equal to
    the image's stem (`27` matches `27.png` and `000027.jpg`). A row matching no image is an error."""
    by_name = {p.name: p for p in images}
    by_stem = {p.stem: p for p in images}
    by_number = {int(p.stem): p for p in images if p.stem.isdigit()}
    out: dict[Path, list[int]] = {}
    unmatched = []
    for i, (name, image_id) in enumerate(zip(result.file_names, result.image_ids, strict=True)):
        path = by_name.get(Path(name).name) if name else None
        if path is None:
            path = by_stem.get(str(image_id))
        if path is None and isinstance(image_id, int):
            path = by_number.get(image_id)
        if path is None:
            unmatched.append(name or str(image_id))
        else:
            out.setdefault(path, []).append(i)
    if unmatched:
        raise InputFormatError(f"{result.source}: {plural(len(unmatched), 'person', 'people')} match no image of "
                               f"the folder (first: {unmatched[0]}; matched by file_name, else image_id = the "
                               "file's stem)")  # fmt: skip
    return out


def list_images(folder: Path) -> list[Path]:
    if not folder.is_dir():
        raise InputFormatError(f"{folder}: not a folder of images")
    found = sorted(p for p in folder.iterdir() if p.suffix.lower() in IMAGE_SUFFIXES)
    if not found:
        raise InputFormatError(f"{folder}: folder holds no images ({', '.join(IMAGE_SUFFIXES)})")
    return found


def render_images(result: ResultPoses, folder: str | Path, output: str | Path, settings: RenderSettings,
                  on_frame: OnFrame | None = None) -> RenderSummary:  # fmt: skip
    """Draw `result` over the images of `folder`, writing `<stem>.png` for every image into the
    folder `output` (created if missing; its parent must exist). Every output is checked before
    the first is written."""
    import cv2

    start = time.perf_counter()
    folder, output = Path(folder), Path(output)
    images = list_images(folder)
    if output.exists() and output.resolve() == folder.resolve():
        raise ConfigError(f"{output}: the output folder must not be the images' folder")
    matched = match_images(result, images)
    targets = [output / f"{p.stem}.png" for p in images]
    if len(set(targets)) < len(targets):
        raise InputFormatError(f"{folder}: two images share a stem: their PNGs would have one name")
    make_output_folder(output)
    for target in targets:
        check_writable(target, settings.overwrite)
    painter = Painter(result, settings)
    drawn = persons = 0
    for done, (path, target) in enumerate(zip(images, targets, strict=True), 1):
        frame = cv2.imread(str(path), cv2.IMREAD_COLOR)
        if frame is None:
            raise InputFormatError(f"{path}: cannot read as an image")
        rows = matched.get(path, [])
        _check_size(result, frame.shape[1], frame.shape[0], rows, str(path))
        index = int(result.frame_index[rows[0]]) if rows else done - 1
        ok, png = cv2.imencode(".png", painter.paint(frame, rows, index, result.fps))
        if not ok:
            raise ZedoError(f"{target}: OpenCV could not encode the PNG")
        with atomic_path(target, overwrite=settings.overwrite) as tmp:
            tmp.write_bytes(png.tobytes())
        drawn += bool(rows)
        persons += sum(painter.persons[r].px is not None for r in rows)
        if on_frame is not None:
            on_frame(done, len(images))
    return RenderSummary(str(output), len(images), drawn, persons, time.perf_counter() - start)
