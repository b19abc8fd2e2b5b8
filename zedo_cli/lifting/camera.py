"""Pinhole intrinsics, projection, pixel rays, projection onto rays, least-squares translation.

Camera frame: x right, y down, z forward (OpenCV), metres. Batched over leading dims:
points `(..., J, 3)`, pixels `(..., J, 2)`, matrices `(..., 3, 3)`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import torch

from ..camera.model import CameraModel, lens_groups
from ..errors import CameraInputError, ConfigError, IntrinsicsError

if TYPE_CHECKING:
    from ..camera.files import CameraFile

PSEUDO_FOCAL_PX = 2000.0  # the paper's pseudo focal length when the camera is unknown
# Pixel quantities (coordinates, image sizes, principal points, focal lengths) are bounded by
# PIXEL_LIMIT: no real image is a million pixels wide, and lifting runs in float32, whose
# 24-bit mantissa resolves 1/16 px at 1e6 px but only whole pixels at 1e7.
PIXEL_LIMIT = 1e6
MIN_FOCAL_PX = 1.0  # below 1 px any image of a pixel or more spans 90 degrees or more


@dataclass(frozen=True)
class Intrinsics:
    """fx, fy, cx, cy in pixels; `source` says where they came from (pseudo, cli, file)."""

    fx: float
    fy: float
    cx: float
    cy: float
    source: str = "cli"

    def __post_init__(self) -> None:
        values = (self.fx, self.fy, self.cx, self.cy)
        if not all(np.isfinite(v) for v in values):
            raise IntrinsicsError(f"intrinsics must be finite numbers, got {values}")
        if not (MIN_FOCAL_PX <= self.fx <= PIXEL_LIMIT and MIN_FOCAL_PX <= self.fy <= PIXEL_LIMIT):
            raise IntrinsicsError(
                f"focal length must be in [{MIN_FOCAL_PX:g}, {PIXEL_LIMIT:g}] px, got fx={self.fx:g}, fy={self.fy:g}"
            )
        if abs(self.cx) > PIXEL_LIMIT or abs(self.cy) > PIXEL_LIMIT:
            raise IntrinsicsError(
                f"principal point must be within {PIXEL_LIMIT:g} px of the image origin, got ({self.cx:g}, {self.cy:g})"
            )

    @classmethod
    def pseudo(cls, width: float, height: float, focal: float = PSEUDO_FOCAL_PX) -> Intrinsics:
        """The paper's pseudo intrinsics: f = 2000 px, principal point at the image centre."""
        return cls(focal, focal, width / 2.0, height / 2.0, "pseudo")

    @classmethod
    def from_matrix(cls, k: np.ndarray, source: str) -> Intrinsics:
        k = np.asarray(k, dtype=np.float64)
        if k.shape != (3, 3):
            raise IntrinsicsError(f"K must be a 3x3 matrix, got shape {k.shape}")
        if k[0, 1] != 0 or k[1, 0] != 0 or k[2, 0] != 0 or k[2, 1] != 0 or k[2, 2] != 1:
            raise IntrinsicsError("K must be [[fx, 0, cx], [0, fy, cy], [0, 0, 1]] (no skew)")
        return cls(float(k[0, 0]), float(k[1, 1]), float(k[0, 2]), float(k[1, 2]), source)

    def matrix(self) -> np.ndarray:
        return np.array([[self.fx, 0.0, self.cx], [0.0, self.fy, self.cy], [0.0, 0.0, 1.0]])


def pixel_rays(xy: torch.Tensor, k: torch.Tensor) -> torch.Tensor:
    """Rays `(..., J, 3)` = K^-1 [u, v, 1] through pixels `xy (..., J, 2)`; their z is 1."""
    fx, fy = k[..., 0, 0, None], k[..., 1, 1, None]
    cx, cy = k[..., 0, 2, None], k[..., 1, 2, None]
    x = (xy[..., 0] - cx) / fx
    y = (xy[..., 1] - cy) / fy
    return torch.stack([x, y, torch.ones_like(x)], dim=-1)


def project(points: torch.Tensor, k: torch.Tensor, min_depth: float = 1e-6) -> torch.Tensor:
    """Pixels `(..., J, 2)` of camera-frame points `(..., J, 3)`; depth clamped to `min_depth`."""
    z = points[..., 2].clamp_min(min_depth)
    u = k[..., 0, 0, None] * points[..., 0] / z + k[..., 0, 2, None]
    v = k[..., 1, 1, None] * points[..., 1] / z + k[..., 1, 2, None]
    return torch.stack([u, v], dim=-1)


def project_onto_rays(points: torch.Tensor, unit_rays: torch.Tensor) -> torch.Tensor:
    """Orthogonal projection of camera-frame points `(..., J, 3)` onto their unit rays."""
    return (points * unit_rays).sum(-1, keepdim=True) * unit_rays


@dataclass(frozen=True)
class TranslationSolve:
    """The root translation of `solve_root_translation_ex`, with what went wrong per pose."""

    translation: torch.Tensor  # (..., 3); where `singular`, the `fallback` given (or NaN)
    singular: torch.Tensor  # (...,) bool: the rays do not determine T (they all coincide)
    flipped: torch.Tensor  # (...,) bool: the least-squares T was behind the camera and was negated


def solve_root_translation_ex(
    pose: torch.Tensor, rays: torch.Tensor, weights: torch.Tensor, fallback: torch.Tensor | None = None
) -> TranslationSolve:
    """Translation T `(..., 3)` that best puts each joint of `pose + T` on its ray.

    `pose (..., J, 3)` root-relative, `rays (..., J, 3)` with z = 1, `weights (..., J)` (0 for
    missing joints). Per joint, X + T on ray r gives two linear equations:
    -T_x + r_x T_z = X_x - r_x X_z and -T_y + r_y T_z = X_y - r_y X_z, solved in weighted least
    squares via the 3x3 normal equations. A solution behind the camera (T_z < 0) is negated,
    as in the reference, and reported in `flipped`: the negated T does not keep the joints on
    their rays (it is not a least-squares solution), so the caller must not trust the pose.
    A singular system (all weighted rays the same, e.g. every joint at one pixel) is reported
    in `singular` instead of raising; its rows get `fallback` (default NaN).
    """
    rx, ry = rays[..., 0], rays[..., 1]
    zeros, ones = torch.zeros_like(rx), torch.ones_like(rx)
    a = torch.cat([torch.stack([-ones, zeros, rx], -1), torch.stack([zeros, -ones, ry], -1)], dim=-2)  # (..., 2J, 3)
    b = torch.cat([pose[..., 0] - rx * pose[..., 2], pose[..., 1] - ry * pose[..., 2]], dim=-1)
    w = torch.cat([weights, weights], dim=-1)  # (..., 2J)
    aw = a * w[..., None]
    normal = aw.transpose(-1, -2) @ a  # (..., 3, 3)
    rhs = (aw * b[..., None]).sum(-2)  # (..., 3)
    t, info = torch.linalg.solve_ex(normal, rhs)  # the same LU as linalg.solve, without raising
    singular = (info != 0) | ~torch.isfinite(t).all(-1)
    flipped = ~singular & (t[..., 2] < 0)
    t = torch.where(flipped[..., None], -t, t)
    fill = torch.full_like(t, float("nan")) if fallback is None else fallback.to(t)
    return TranslationSolve(torch.where(singular[..., None], fill, t), singular, flipped)


def solve_root_translation(pose: torch.Tensor, rays: torch.Tensor, weights: torch.Tensor) -> torch.Tensor:
    """`solve_root_translation_ex`'s translation alone: NaN where the system is singular."""
    return solve_root_translation_ex(pose, rays, weights).translation


def check_focal(focal: float | None) -> None:
    """A focal length given on the command line: a number of pixels in [MIN_FOCAL_PX, PIXEL_LIMIT]."""
    if focal is not None and not (np.isfinite(focal) and MIN_FOCAL_PX <= focal <= PIXEL_LIMIT):
        raise IntrinsicsError(
            f"--focal must be a number of pixels in [{MIN_FOCAL_PX:g}, {PIXEL_LIMIT:g}], got {focal:g}"
        )


def check_principal_point(point: tuple[float, float] | None) -> None:
    """A principal point given on the command line: finite, within PIXEL_LIMIT of the origin."""
    if point is not None and not all(np.isfinite(v) and abs(v) <= PIXEL_LIMIT for v in point):
        raise IntrinsicsError(
            f"--principal-point must be two numbers of pixels within {PIXEL_LIMIT:g} of the image origin, "
            f"got {point[0]:g} {point[1]:g}"
        )


def check_image_size(size: tuple[float, float] | None) -> None:
    """An image size given on the command line: W H pixels in (0, PIXEL_LIMIT]."""
    if size is not None and not all(np.isfinite(v) and 0 < v <= PIXEL_LIMIT for v in size):
        raise IntrinsicsError(f"--image-size must be W H in (0, {PIXEL_LIMIT:g}] px, got {size[0]:g} {size[1]:g}")


@dataclass(frozen=True)
class ResolvedCameras:
    """The camera of each of N instances, as `resolve_cameras` settles it."""

    matrices: np.ndarray  # (N, 3, 3) K, pixels
    sources: list[str]  # (N,) pseudo | cli | file
    lenses: list[CameraModel | None]  # (N,) the file's camera (model, coefficients); None: pinhole, no distortion
    image_sizes: np.ndarray  # (N, 2) the input's image sizes, the file's where the input has none (NaN: unknown)

    @property
    def distorted(self) -> bool:
        """Whether any instance's camera has lens distortion (then its 2D is undistorted to lift)."""
        return bool(lens_groups(self.lenses))


# The file's field that states the image size, per calibration file format (camera.files).
_SIZE_FIELDS = {"zedo": "image_size", "opencv": "image_width, image_height", "toml": "size"}


def _file_intrinsics(camera: CameraModel, path: str) -> Intrinsics:
    """The bounds every K is held to, for a file's camera; the error names the file."""
    try:
        return Intrinsics(camera.fx, camera.fy, camera.cx, camera.cy, "file")
    except IntrinsicsError as exc:
        raise CameraInputError(f"{path}: {exc}") from None


def _check_size(camera: CameraModel, size: np.ndarray, calib: CameraFile, i: int, image_id: int | str) -> None:
    """A file's camera stated for one image size cannot lift an image of another."""
    if camera.image_size is None or not np.isfinite(size).all():
        return
    if np.abs(np.asarray(camera.image_size, dtype=np.float64) - size).max() > 0.5:
        w, h = camera.image_size
        raise CameraInputError(
            f"{calib.path}: {_SIZE_FIELDS[calib.format]}: the camera was calibrated for {w} x {h} px images, but "
            f"instance {i} (image_id {image_id!r}) is {size[0]:g} x {size[1]:g} px (rescale the calibration, "
            "or check --image-size)"
        )


def resolve_cameras(
    image_sizes: np.ndarray,
    image_ids: list[int | str],
    file_names: list[str | None],
    *,
    focal: float | None = None,
    principal_point: tuple[float, float] | None = None,
    intrinsics_file: str | None = None,
    camera: str | None = None,
) -> ResolvedCameras:
    """The camera of each instance: K, its source and the lens of a calibration file.

    Precedence: a calibration file's entry for the image (zedo JSON `images`, by image id, then
    file name), the file's camera, then `focal` / `principal_point` from the command line, else
    the pseudo intrinsics (f = 2000 px at the image centre). A centre needs the image size: an
    instance without one and without a principal point is an error. `intrinsics_file` is any
    format of `camera.files` (zedo JSON, OpenCV FileStorage, Pose2Sim / anipose TOML); `camera`
    picks one camera of a file of several. A file's image size must match the input's.
    """
    check_focal(focal)
    check_principal_point(principal_point)
    if camera is not None and intrinsics_file is None:
        raise ConfigError("--camera picks a camera of an --intrinsics file: give the file too")
    calib = None
    if intrinsics_file:  # its pydantic models load only for a calibration file (start-up)
        from ..camera.files import read_camera_file

        calib = read_camera_file(intrinsics_file, camera)
    pairs = list(zip(image_ids, file_names, strict=True))
    if (
        calib is not None
        and calib.images
        and pairs
        and calib.camera is None
        and not any(str(i) in calib.images or (n and n in calib.images) for i, n in pairs)
    ):  # a per-image file meant for other images: never fall back to the pseudo camera silently
        raise CameraInputError(f"{calib.path}: images: no key matches an input image's id or file name "
                               f"(keys {', '.join(list(calib.images)[:3])}; first image id {pairs[0][0]!r}, "
                               f"file name {pairs[0][1]!r})")  # fmt: skip
    known: dict[CameraModel, Intrinsics] = {}  # each distinct camera checked once
    mats, sources, lenses = np.empty((len(image_ids), 3, 3)), [], []
    sizes = np.array(image_sizes, dtype=np.float64).reshape(-1, 2)
    for i, (size, image_id, name) in enumerate(zip(image_sizes, image_ids, file_names, strict=True)):
        lens = None
        if calib is not None:
            lens = calib.images.get(str(image_id)) or (calib.images.get(name) if name else None) or calib.camera
        if lens is not None:
            assert calib is not None
            _check_size(lens, sizes[i], calib, i, image_id)
            if lens.image_size is not None and not np.isfinite(sizes[i]).all():
                sizes[i] = lens.image_size
            entry = known.get(lens) or known.setdefault(lens, _file_intrinsics(lens, calib.path))
        else:
            entry = _command_line_intrinsics(i, size, image_id, focal, principal_point)
        mats[i] = entry.matrix()
        sources.append(entry.source)
        lenses.append(lens)
    return ResolvedCameras(mats, sources, lenses, sizes)


def _command_line_intrinsics(
    i: int, size: np.ndarray, image_id: int | str, focal: float | None, principal_point: tuple[float, float] | None
) -> Intrinsics:
    """--focal / --principal-point, else the pseudo intrinsics, for instance `i` of image size `size`."""
    if principal_point is not None:
        cx, cy = principal_point
    elif np.isfinite(size).all() and (size > 0).all():
        if (size > PIXEL_LIMIT).any():
            raise CameraInputError(f"instance {i} (image_id {image_id!r}): image size {size[0]:g} x "
                                   f"{size[1]:g} px is out of range (0, {PIXEL_LIMIT:g}]")  # fmt: skip
        cx, cy = size[0] / 2.0, size[1] / 2.0
    else:
        raise CameraInputError(
            f"instance {i} (image_id {image_id!r}) has no image size: pass --image-size W H, --video FILE (its "
            "size), --images COCO.json (a COCO results file's annotations), --principal-point CX CY or "
            "--intrinsics K.json"
        )
    f = PSEUDO_FOCAL_PX if focal is None else focal
    source = "pseudo" if focal is None and principal_point is None else "cli"
    return Intrinsics(f, f, float(cx), float(cy), source)


def resolve_intrinsics(
    image_sizes: np.ndarray,
    image_ids: list[int | str],
    file_names: list[str | None],
    *,
    focal: float | None = None,
    principal_point: tuple[float, float] | None = None,
    intrinsics_file: str | None = None,
) -> tuple[np.ndarray, list[str]]:
    """Intrinsics `(N, 3, 3)` and their source per instance, as `resolve_cameras` settles them,
    for a pinhole camera without distortion: a calibration file with lens distortion is refused
    here (use `resolve_cameras` and pass its `lenses` to `lift(..., cameras=...)`)."""
    cams = resolve_cameras(image_sizes, image_ids, file_names, focal=focal, principal_point=principal_point,
                           intrinsics_file=intrinsics_file)  # fmt: skip
    if cams.distorted:
        raise IntrinsicsError(f"{intrinsics_file}: the camera has lens distortion, which resolve_intrinsics would "
                              "ignore: use resolve_cameras and lift(..., cameras=resolved.lenses)")  # fmt: skip
    return cams.matrices, cams.sources
