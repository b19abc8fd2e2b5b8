"""`CameraModel`: intrinsics, lens model and distortion coefficients, with OpenCV doing the work.

Camera frame: x right, y down, z forward (OpenCV), metres; pixels `(..., 2)`.
Coefficients are in OpenCV's order: pinhole (k1, k2, p1, p2[, k3[, k4, k5, k6[, s1..s4[, tx, ty]]]]),
fisheye (k1, k2, k3, k4).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from ..errors import IntrinsicsError

LensModel = Literal["pinhole", "fisheye"]
PINHOLE_COEFFICIENT_COUNTS = (0, 4, 5, 8, 12, 14)  # what cv2.undistortPoints / projectPoints accept
FISHEYE_COEFFICIENT_COUNT = 4

# OpenCV's default of 5 iterations leaves ~18 px at the corner of a 1280x720 image at f = 600 px
# with k1 = -0.3 (INTEROP.md); 200 iterations to 1e-14 invert projectPoints to ~1e-12 px.
UNDISTORT_CRITERIA = (3, 200, 1e-14)  # cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, max count, epsilon


@dataclass(frozen=True)
class CameraModel:
    """A camera: focal lengths and principal point (px), lens model, distortion coefficients."""

    fx: float
    fy: float
    cx: float
    cy: float
    dist: tuple[float, ...] = ()
    model: LensModel = "pinhole"
    image_size: tuple[int, int] | None = None  # (width, height) px, when known

    def __post_init__(self) -> None:
        if self.model not in ("pinhole", "fisheye"):
            raise IntrinsicsError(f"camera model must be 'pinhole' or 'fisheye', got {self.model!r}")
        if not all(np.isfinite(v) for v in (self.fx, self.fy, self.cx, self.cy, *self.dist)):
            raise IntrinsicsError("camera intrinsics and distortion coefficients must be finite numbers")
        if self.fx <= 0 or self.fy <= 0:
            raise IntrinsicsError(f"focal lengths must be positive, got fx={self.fx:g}, fy={self.fy:g}")
        counts = (FISHEYE_COEFFICIENT_COUNT,) if self.model == "fisheye" else PINHOLE_COEFFICIENT_COUNTS
        if len(self.dist) not in counts:
            allowed = " or ".join(map(str, counts))
            raise IntrinsicsError(f"a {self.model} camera takes {allowed} distortion values, not {len(self.dist)}")

    @property
    def distorted(self) -> bool:
        return any(c != 0 for c in self.dist)

    def matrix(self) -> np.ndarray:
        return np.array([[self.fx, 0.0, self.cx], [0.0, self.fy, self.cy], [0.0, 0.0, 1.0]])

    def _coefficients(self) -> np.ndarray:
        n = FISHEYE_COEFFICIENT_COUNT if self.model == "fisheye" else max(len(self.dist), 4)
        out = np.zeros(n)
        out[: len(self.dist)] = self.dist
        return out

    def undistort_pixels(self, xy: np.ndarray) -> np.ndarray:
        """Pixels `(..., 2)` of the distorted image -> where an ideal pinhole camera with the same
        matrix would see them. NaN stays NaN. Without distortion the pixels come back unchanged."""
        xy = np.asarray(xy, dtype=np.float64)
        if not self.distorted:
            return xy.copy()
        import cv2

        flat = xy.reshape(-1, 1, 2)
        ok = np.isfinite(flat).all(-1)[:, 0]
        out = np.full_like(flat, np.nan)
        if ok.any():
            pts, k, d = np.ascontiguousarray(flat[ok]), self.matrix(), self._coefficients()
            if self.model == "fisheye":
                out[ok] = cv2.fisheye.undistortPoints(pts, k, d, P=k, criteria=UNDISTORT_CRITERIA)
            else:
                out[ok] = cv2.undistortPoints(pts, k, d, R=None, P=k, criteria=UNDISTORT_CRITERIA)
        return out.reshape(xy.shape)

    def project(self, points: np.ndarray) -> np.ndarray:
        """Pixels `(..., 2)` in the original (distorted) image of camera-frame points `(..., 3)` in
        metres. Points at or behind the camera plane, and NaN points, give NaN."""
        import cv2

        points = np.asarray(points, dtype=np.float64)
        flat = points.reshape(-1, 3)
        ok = np.isfinite(flat).all(-1) & (flat[:, 2] > 1e-9)
        out = np.full((len(flat), 2), np.nan)
        if ok.any():
            pts = np.ascontiguousarray(flat[ok]).reshape(-1, 1, 3)
            zero = np.zeros(3)
            if self.model == "fisheye":
                px, _ = cv2.fisheye.projectPoints(pts, zero, zero, self.matrix(), self._coefficients())
            else:
                px, _ = cv2.projectPoints(pts, zero, zero, self.matrix(), self._coefficients())
            out[ok] = px.reshape(-1, 2)
        return out.reshape(*points.shape[:-1], 2)

    def to_json(self) -> dict:
        """The camera as the result file states it (next to its `source`)."""
        block: dict = {"model": self.model, "K": self.matrix().tolist(), "dist": [float(c) for c in self.dist]}
        if self.image_size is not None:
            block["image_size"] = [int(self.image_size[0]), int(self.image_size[1])]
        return block

    @classmethod
    def from_matrix(
        cls, k: np.ndarray, dist: tuple[float, ...] = (), model: LensModel = "pinhole",
        image_size: tuple[int, int] | None = None,
    ) -> CameraModel:  # fmt: skip
        """A camera from its 3x3 matrix `[[fx, 0, cx], [0, fy, cy], [0, 0, 1]]` (no skew)."""
        k = _matrix3(k, "K")
        if not np.isfinite(k).all():
            raise IntrinsicsError("K must hold finite numbers")
        if k[0, 1] != 0 or k[1, 0] != 0 or k[2, 0] != 0 or k[2, 1] != 0 or k[2, 2] != 1:
            raise IntrinsicsError("K must be [[fx, 0, cx], [0, fy, cy], [0, 0, 1]] (no skew)")
        if k[0, 0] == 0 or k[1, 1] == 0:  # not their product, which overflows or underflows at extremes
            raise IntrinsicsError(f"K is singular (fx={k[0, 0]:g}, fy={k[1, 1]:g})")
        return cls(float(k[0, 0]), float(k[1, 1]), float(k[0, 2]), float(k[1, 2]), tuple(map(float, dist)), model,
                   image_size)  # fmt: skip

    @classmethod
    def from_json(cls, block: dict) -> CameraModel:
        """A result file's camera block: `K`, and `model` / `dist` when the lift had a lens model
        (results without them were lifted through a pinhole camera without distortion)."""
        k = _matrix3(block["K"], "camera K")
        size = block.get("image_size")
        return cls(
            float(k[0, 0]),
            float(k[1, 1]),
            float(k[0, 2]),
            float(k[1, 2]),
            tuple(float(c) for c in block.get("dist") or ()),
            block.get("model", "pinhole"),
            None if size is None else (int(round(size[0])), int(round(size[1]))),
        )


def lens_groups(cameras: Sequence[CameraModel | None] | None) -> dict[CameraModel, list[int]]:
    """Instance indices per distinct camera with distortion, from one camera (or None: no lens)
    per instance; empty when no camera has distortion. A clip has one or a few cameras."""
    groups: dict[CameraModel, list[int]] = {}
    for i, camera in enumerate(cameras or ()):
        if camera is not None and camera.distorted:
            groups.setdefault(camera, []).append(i)
    return groups


def undistort_instances(xy: np.ndarray, cameras: Sequence[CameraModel | None] | None) -> np.ndarray:
    """Pixels `xy (N, J, 2)` of each instance's distorted image, undistorted through its camera
    (`cameras`, one per instance, None for none); instances without distortion are left as they
    are (the same array when no camera has distortion, so that the usual lift pays nothing)."""
    groups = lens_groups(cameras)
    if not groups:
        return xy
    out = np.array(xy, dtype=np.float64)
    for camera, idx in groups.items():
        out[idx] = camera.undistort_pixels(out[idx])
    return out


def _matrix3(k: Any, what: str) -> np.ndarray:
    """`k` as a 3x3 float array; an IntrinsicsError naming `what` for anything else, a ragged
    list of rows (`[[2000, 0, 640], [0, 2000], [0, 0, 1]]`) included."""
    try:
        matrix = np.asarray(k, dtype=np.float64)
    except (TypeError, ValueError, OverflowError):
        rows = [str(len(r)) if isinstance(r, list | tuple) else "?" for r in k] if isinstance(k, list | tuple) else []
        got = f", got rows of {', '.join(rows)} values" if rows else ""
        raise IntrinsicsError(f"{what} must be a 3x3 matrix of numbers{got}") from None
    if matrix.shape != (3, 3):
        raise IntrinsicsError(f"{what} must be a 3x3 matrix, got shape {matrix.shape}")
    return matrix
