"""Pinhole intrinsics, projection, pixel rays, projection onto rays, least-squares translation.

Camera frame: x right, y down, z forward (OpenCV), metres. Batched over leading dims:
points `(..., J, 3)`, pixels `(..., J, 2)`, matrices `(..., 3, 3)`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import torch

from ..errors import CameraInputError, IntrinsicsError

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


def _intrinsics_entry(entry: object, where: str) -> Intrinsics:
    """One intrinsics entry of a K.json file: {"K": 3x3} or {"fx", "fy", "cx", "cy"}."""
    if not isinstance(entry, dict):
        raise CameraInputError(f"{where}: expected an object with 'K' or 'fx', 'fy', 'cx', 'cy'")
    try:
        if "K" in entry:
            rows = entry["K"]
            if not isinstance(rows, list) or any(_holds_boolean(row) for row in rows):
                raise ValueError("K: expected a 3x3 list of numbers")
            return Intrinsics.from_matrix(np.asarray(rows, dtype=np.float64), "file")
        values = [entry[key] for key in ("fx", "fy", "cx", "cy")]
        for key, value in zip(("fx", "fy", "cx", "cy"), values, strict=True):
            if isinstance(value, bool) or not isinstance(value, int | float):  # true is not 1 px
                got = "a boolean" if isinstance(value, bool) else type(value).__name__
                raise ValueError(f"{key}: expected a number, got {got}")
        return Intrinsics(*(float(v) for v in values), source="file")
    except KeyError as exc:
        raise CameraInputError(f"{where}: missing field {exc.args[0]!r}") from None
    except OverflowError:  # an integer of hundreds of digits
        raise CameraInputError(f"{where}: number too large") from None
    except (TypeError, ValueError) as exc:
        raise CameraInputError(f"{where}: {exc}") from None
    except IntrinsicsError as exc:
        raise CameraInputError(f"{where}: {exc}") from None


def _holds_boolean(row: object) -> bool:
    return isinstance(row, bool) or (isinstance(row, list) and any(isinstance(v, bool) for v in row))


def read_intrinsics_file(path: str) -> tuple[Intrinsics | None, dict[str, Intrinsics]]:
    """A K.json file: a global entry (`{"K": ...}` or `{"fx": ...}`), and/or per-image entries
    `{"images": {"<image_id or file_name>": entry}}`. Returns (global or None, per image)."""
    import json

    try:
        with open(path, encoding="utf-8") as fh:
            doc = json.load(fh)
    except FileNotFoundError:
        raise CameraInputError(f"{path}: intrinsics file not found") from None
    except (OSError, UnicodeDecodeError, ValueError, RecursionError) as exc:  # ValueError: JSON, digit limit
        raise CameraInputError(f"{path}: not a readable JSON file ({exc})") from None
    if not isinstance(doc, dict):
        raise CameraInputError(f"{path}: expected a JSON object")
    per_image: dict[str, Intrinsics] = {}
    images = doc.get("images", {})
    if not isinstance(images, dict):
        raise CameraInputError(f"{path}: 'images' must map image ids or file names to intrinsics")
    for key, entry in images.items():
        per_image[str(key)] = _intrinsics_entry(entry, f"{path}: images[{key!r}]")
    has_global = "K" in doc or "fx" in doc
    glob = _intrinsics_entry(doc, path) if has_global else None
    if glob is None and not per_image:
        raise CameraInputError(f"{path}: no intrinsics found (expected 'K', 'fx'... or 'images')")
    return glob, per_image


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


def resolve_intrinsics(
    image_sizes: np.ndarray,
    image_ids: list[int | str],
    file_names: list[str | None],
    *,
    focal: float | None = None,
    principal_point: tuple[float, float] | None = None,
    intrinsics_file: str | None = None,
) -> tuple[np.ndarray, list[str]]:
    """Intrinsics `(N, 3, 3)` and their source per instance.

    Precedence: a K.json entry for the image (by image id, then file name), the file's global
    entry, then `focal` / `principal_point` from the command line, else the pseudo intrinsics
    (f = 2000 px at the image centre). A centre needs the image size: an instance without
    one and without a principal point is an error.
    """
    check_focal(focal)
    check_principal_point(principal_point)
    glob, per_image = read_intrinsics_file(intrinsics_file) if intrinsics_file else (None, {})
    pairs = list(zip(image_ids, file_names, strict=True))
    if per_image and pairs and not any(str(i) in per_image or (n and n in per_image) for i, n in pairs):
        raise CameraInputError(f"{intrinsics_file}: images: no key matches an input image's id or file name "
                               f"(keys {', '.join(list(per_image)[:3])}; first image id {pairs[0][0]!r}, "
                               f"file name {pairs[0][1]!r})")  # fmt: skip
    mats, sources = [], []
    for i, (size, image_id, name) in enumerate(zip(image_sizes, image_ids, file_names, strict=True)):
        entry = per_image.get(str(image_id)) or (per_image.get(name) if name else None) or glob
        if entry is None:
            if principal_point is not None:
                cx, cy = principal_point
            elif np.isfinite(size).all() and (size > 0).all():
                if (size > PIXEL_LIMIT).any():
                    raise CameraInputError(f"instance {i} (image_id {image_id!r}): image size {size[0]:g} x "
                                           f"{size[1]:g} px is out of range (0, {PIXEL_LIMIT:g}]")  # fmt: skip
                cx, cy = size[0] / 2.0, size[1] / 2.0
            else:
                raise CameraInputError(
                    f"instance {i} (image_id {image_id!r}) has no image size: pass --image-size W H, "
                    "--principal-point CX CY or --intrinsics K.json"
                )
            f = PSEUDO_FOCAL_PX if focal is None else focal
            source = "pseudo" if focal is None and principal_point is None else "cli"
            entry = Intrinsics(f, f, float(cx), float(cy), source)
        mats.append(entry.matrix())
        sources.append(entry.source)
    return np.array(mats).reshape(-1, 3, 3), sources
