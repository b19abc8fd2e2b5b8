"""Camera calibration from views of a checkerboard, by OpenCV: `cv2.findChessboardCorners`
and `cv2.cornerSubPix` find the board's inner corners in each view, `cv2.calibrateCamera`
(pinhole with distortion) or `cv2.fisheye.calibrate` (`fisheye=True`) fits the camera.

Views are image files, or frames sampled evenly from video files. A calibration that cannot be
trusted is refused with a `CalibrationError` (exit code 6): the board found in no view or in
fewer than `min_views`, an RMS reprojection error above `max_rms`, views of different sizes.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import CalibrationError, ConfigError, InputFormatError
from .model import CameraModel
from .video import probe_video, sample_frames

IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff", ".webp", ".pgm", ".ppm")
MIN_VIEWS = 5  # the default floor: below it distortion and focal length trade off freely
MAX_RMS_PX = 1.0  # the default bound: a well-detected printed board gives a few tenths of a pixel
DEFAULT_VIDEO_FRAMES = 30
_CRITERIA = (3, 100, 1e-9)  # cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS


@dataclass(frozen=True)
class Board:
    """A checkerboard: `cols` x `rows` INNER corners (where four squares meet; a board of 10 x 7
    squares has 9 x 6), squares of `square` metres."""

    cols: int
    rows: int
    square: float

    def __post_init__(self) -> None:
        if self.cols < 2 or self.rows < 2:
            raise ConfigError(f"--board: at least 2x2 inner corners, got {self.cols}x{self.rows}")
        if self.cols == self.rows:  # a square board's corner order is ambiguous by 90 degrees
            raise ConfigError(f"--board: {self.cols}x{self.rows} is square; OpenCV needs different counts")
        if not (np.isfinite(self.square) and self.square > 0):
            raise ConfigError(f"--square: expected a positive length in metres, got {self.square}")

    @classmethod
    def parse(cls, text: str, square: float) -> Board:
        """`"9x6"` (inner corners, columns x rows) and the square's side in metres."""
        match = re.fullmatch(r"\s*(\d+)\s*[xX]\s*(\d+)\s*", text)
        if not match:
            raise ConfigError(f"--board: expected COLSxROWS inner corners such as 9x6, got {text!r}")
        return cls(int(match[1]), int(match[2]), square)

    @property
    def pattern(self) -> tuple[int, int]:
        return self.cols, self.rows

    def object_points(self) -> np.ndarray:
        """`(cols*rows, 3)` corner positions on the board plane (z = 0), metres, in OpenCV's order."""
        grid = np.mgrid[0 : self.cols, 0 : self.rows].T.reshape(-1, 2)
        return np.c_[grid * self.square, np.zeros(len(grid))].astype(np.float32)


@dataclass(frozen=True)
class CalibrationSettings:
    board: Board
    fisheye: bool = False
    min_views: int = MIN_VIEWS
    max_rms: float = MAX_RMS_PX
    video_frames: int = DEFAULT_VIDEO_FRAMES  # frames sampled evenly from each video
    k3: bool = False  # pinhole: fit k3 too (few views: it trades off against k1, k2)
    tangential: bool = False  # pinhole: fit p1, p2 too

    def __post_init__(self) -> None:
        if self.min_views < 3:
            raise ConfigError(f"--min-views: at least 3 (a board's view fixes 6 of the pose), got {self.min_views}")
        if not (np.isfinite(self.max_rms) and self.max_rms > 0):
            raise ConfigError(f"--max-rms: expected a positive number of pixels, got {self.max_rms}")
        if self.video_frames < 1:
            raise ConfigError(f"--frames: expected at least 1, got {self.video_frames}")


@dataclass(frozen=True)
class Detection:
    """One view: its name (file, or `file#frame`), image size, and the corners found (None: no board)."""

    name: str
    size: tuple[int, int]  # (width, height) px
    corners: np.ndarray | None  # (cols*rows, 2) float32 px


@dataclass(frozen=True)
class Calibration:
    """The fitted camera and how well it fits its views."""

    camera: CameraModel
    rms: float  # px, over every corner of every used view (OpenCV's figure)
    view_errors: list[tuple[str, float]]  # per used view: its RMS reprojection error, px
    views_without_board: list[str] = field(default_factory=list)
    board: Board | None = None


def find_corners(image: np.ndarray, board: Board) -> np.ndarray | None:
    """The board's inner corners `(cols*rows, 2)` px refined to sub-pixel, or None if not found."""
    import cv2

    gray = image if image.ndim == 2 else cv2.cvtColor(image, cv2.COLOR_BGR2GRAY)
    flags = cv2.CALIB_CB_ADAPTIVE_THRESH | cv2.CALIB_CB_NORMALIZE_IMAGE
    found, corners = cv2.findChessboardCorners(gray, board.pattern, flags=flags)
    if not found:
        return None
    # the refinement window stays inside one square: a third of the smallest corner spacing
    pts = corners.reshape(board.rows, board.cols, 2)
    spacing = min(
        np.linalg.norm(np.diff(pts, axis=0), axis=-1).min(), np.linalg.norm(np.diff(pts, axis=1), axis=-1).min()
    )
    half = int(np.clip(spacing / 3, 2, 11))
    refined = cv2.cornerSubPix(gray, corners, (half, half), (-1, -1), _CRITERIA)
    return refined.reshape(-1, 2)


def _read_image(path: Path) -> np.ndarray:
    import cv2

    image = cv2.imread(str(path), cv2.IMREAD_GRAYSCALE)
    if image is None:
        raise InputFormatError(f"{path}: cannot read as an image")
    return image


def expand_views(inputs: list[str]) -> list[Path]:
    """Image files, video files and folders (their images, sorted by name), in the order given."""
    paths: list[Path] = []
    for name in inputs:
        path = Path(name)
        if path.is_dir():
            found = sorted(p for p in path.iterdir() if p.suffix.lower() in IMAGE_SUFFIXES)
            if not found:
                raise InputFormatError(f"{path}: folder holds no images ({', '.join(IMAGE_SUFFIXES)})")
            paths += found
        elif not path.is_file():
            raise InputFormatError(f"{path}: file not found")
        else:
            paths.append(path)
    return paths


def is_image(path: Path) -> bool:
    return path.suffix.lower() in IMAGE_SUFFIXES


def count_views(paths: list[Path], video_frames: int) -> int:
    """How many views `detect_views` will look at (each video opened to count its frames)."""
    return sum(1 if is_image(p) else min(video_frames, probe_video(p).frame_count) for p in paths)


def detect_views(paths: list[Path], settings: CalibrationSettings) -> Iterator[Detection]:
    """The board's corners in each image and in frames sampled evenly from each video, one view
    at a time (a video's sampled frames are decoded before its first detection)."""
    for path in paths:
        if is_image(path):
            image = _read_image(path)
            yield Detection(str(path), (image.shape[1], image.shape[0]), find_corners(image, settings.board))
            continue
        for index, frame in sample_frames(path, settings.video_frames):
            size = (frame.shape[1], frame.shape[0])
            yield Detection(f"{path}#{index}", size, find_corners(frame, settings.board))


def calibrate(detections: list[Detection], settings: CalibrationSettings) -> Calibration:
    """Fit the camera to the views where the board was found; refuse (CalibrationError) what
    cannot be trusted. The bounds are `settings.min_views` and `settings.max_rms`."""
    board = settings.board
    used = [d for d in detections if d.corners is not None]
    missing = [d.name for d in detections if d.corners is None]
    if not detections:
        raise CalibrationError("no views to calibrate from")
    if not used:
        raise CalibrationError(f"board {board.cols}x{board.rows} (inner corners) found in none of the "
                               f"{len(detections)} views (first: {detections[0].name}); check --board counts "
                               "corners, not squares")  # fmt: skip
    sizes = {d.size for d in used}
    if len(sizes) > 1:
        listed = ", ".join(f"{w}x{h}" for w, h in sorted(sizes))
        raise CalibrationError(f"views of different sizes ({listed}): one camera, one resolution per calibration")
    if len(used) < settings.min_views:
        raise CalibrationError(f"board found in only {len(used)} of {len(detections)} views, at least "
                               f"{settings.min_views} needed (--min-views)")  # fmt: skip
    size = sizes.pop()
    camera, rms, errors = _fit(used, size, settings)
    view_errors = [(d.name, e) for d, e in zip(used, errors, strict=True)]
    if not rms <= settings.max_rms:
        worst = sorted(view_errors, key=lambda v: -v[1])[:3]
        listed = ", ".join(f"{name} {err:.2f} px" for name, err in worst)
        raise CalibrationError(f"RMS reprojection error {rms:.3f} px is above --max-rms {settings.max_rms:g} px "
                               f"(worst views: {listed})")  # fmt: skip
    return Calibration(camera, float(rms), view_errors, missing, board)


def _fit(
    used: list[Detection], size: tuple[int, int], st: CalibrationSettings
) -> tuple[CameraModel, float, list[float]]:
    import cv2

    obj = st.board.object_points()
    try:
        if st.fisheye:
            # (1, N, 3) / (1, N, 2) float64: the shapes OpenCV 5's fisheye.calibrate accepts
            objs = [obj.reshape(1, -1, 3).astype(np.float64) for _ in used]
            imgs = [d.corners.reshape(1, -1, 2).astype(np.float64) for d in used]
            flags = cv2.CALIB_RECOMPUTE_EXTRINSIC | cv2.CALIB_FIX_SKEW  # cv2.fisheye.* before OpenCV 5
            rms, k, dist, rvecs, tvecs = cv2.fisheye.calibrate(
                objs, imgs, size, np.zeros((3, 3)), np.zeros(4), flags=flags, criteria=_CRITERIA
            )
        else:
            objs = [obj for _ in used]
            imgs = [d.corners.reshape(-1, 1, 2) for d in used]
            flags = (0 if st.k3 else cv2.CALIB_FIX_K3) | (0 if st.tangential else cv2.CALIB_ZERO_TANGENT_DIST)
            rms, k, dist, rvecs, tvecs = cv2.calibrateCamera(objs, imgs, size, None, None, flags=flags)
    except cv2.error as exc:
        raise CalibrationError(f"OpenCV could not fit a camera to the {len(used)} views ({exc.err.strip()})") from None
    coefficients = tuple(float(c) for c in np.ravel(dist))
    camera = CameraModel(float(k[0, 0]), float(k[1, 1]), float(k[0, 2]), float(k[1, 2]), coefficients,
                         "fisheye" if st.fisheye else "pinhole", size)  # fmt: skip
    errors = []
    for d, rvec, tvec in zip(used, rvecs, tvecs, strict=True):
        if st.fisheye:
            px, _ = cv2.fisheye.projectPoints(obj.reshape(-1, 1, 3).astype(np.float64), rvec, tvec, k, dist)
        else:
            px, _ = cv2.projectPoints(obj, rvec, tvec, k, dist)
        errors.append(float(np.sqrt(np.mean(np.sum((px.reshape(-1, 2) - d.corners) ** 2, axis=1)))))
    return camera, float(rms), errors


def calibrate_files(
    inputs: list[str], settings: CalibrationSettings, on_view: Callable[[int, int], None] | None = None
) -> Calibration:
    """`calibrate` on image / video / folder inputs; `on_view(done, total)` after each view."""
    paths = expand_views(inputs)
    total = count_views(paths, settings.video_frames)
    detections: list[Detection] = []
    for detection in detect_views(paths, settings):
        detections.append(detection)
        if on_view is not None:
            on_view(len(detections), total)
    return calibrate(detections, settings)
