"""Calibration files for `zedo lift --intrinsics FILE`, read into typed models (pydantic) whose
errors name the file and the field. The format is told from the extension, else the content:

- zedo's JSON: `{"K": 3x3}` or `{"fx", "fy", "cx", "cy"}`, optional `dist` (OpenCV's order),
  `model` ("pinhole" | "fisheye") and `image_size` [w, h]; and/or per image
  `{"images": {image id or file name: entry}}`;
- OpenCV FileStorage, YAML (`%YAML:1.0` of OpenCV 4 and `%YAML 1.2` of OpenCV 5, which cv2
  reads alike), XML or JSON, read with cv2.FileStorage: `camera_matrix`,
  `distortion_coefficients`, `image_width`, `image_height` (and an optional `model` string);
- Pose2Sim `Calib.toml` and anipose `calibration.toml`: one table per camera with `name`,
  `size` [w, h], `matrix`, `distortions`, `fisheye`; tables that are not cameras (`metadata`,
  `capture_volume`, `charuco`, `checkerboard`) are skipped; `camera` picks one by name.

Every error is a `CameraInputError` (exit code 3): `FILE: field: what is wrong`.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, PositiveFloat, Strict, ValidationError, model_validator

from ..errors import CameraInputError, IntrinsicsError
from ..strict_json import loads
from .model import CameraModel

CAMERA_FILE_FORMATS = ("zedo", "opencv", "toml")
NOT_CAMERAS = frozenset({"metadata", "capture_volume", "charuco", "checkerboard"})  # tables of a calibration TOML
_OPENCV_SUFFIXES = (".yml", ".yaml", ".xml")


Number = Annotated[float, Strict()]  # an int or a float; never a boolean (true is not 1 px)


class _Model(BaseModel):
    model_config = ConfigDict(allow_inf_nan=False, extra="ignore", frozen=True)


class ZedoEntry(_Model):
    """One camera of zedo's JSON: K, or fx fy cx cy; the lens and image size optional."""

    K: list[list[Number]] | None = None
    fx: Number | None = None
    fy: Number | None = None
    cx: Number | None = None
    cy: Number | None = None
    dist: list[Number] = []
    model: Literal["pinhole", "fisheye"] = "pinhole"
    image_size: tuple[PositiveFloat, PositiveFloat] | None = None

    @model_validator(mode="after")
    def _has_intrinsics(self) -> ZedoEntry:
        if self.K is None:
            for key in ("fx", "fy", "cx", "cy"):
                if getattr(self, key) is None:
                    raise ValueError(f"missing field {key!r} (give 'K' or 'fx', 'fy', 'cx', 'cy')")
        return self

    def matrix(self) -> list[list[Number]]:
        if self.K is not None:
            return self.K
        return [[self.fx, 0.0, self.cx], [0.0, self.fy, self.cy], [0.0, 0.0, 1.0]]  # type: ignore[list-item]


class OpenCVCalibration(_Model):
    """The nodes of an OpenCV FileStorage calibration (OpenCV's calibration sample writes them)."""

    camera_matrix: list[list[Number]]
    distortion_coefficients: list[Number] = []
    image_width: PositiveFloat | None = None
    image_height: PositiveFloat | None = None
    model: Literal["pinhole", "fisheye"] = "pinhole"


class TomlCamera(_Model):
    """One camera table of a Pose2Sim or anipose calibration TOML."""

    name: str | None = None
    size: tuple[PositiveFloat, PositiveFloat] | None = None
    matrix: list[list[Number]]
    distortions: list[Number] = []
    fisheye: bool = False


@dataclass(frozen=True)
class CameraFile:
    """What a calibration file holds for a lift: one camera for every image and/or per image."""

    path: str
    format: str  # zedo | opencv | toml
    camera: CameraModel | None  # for every image (None: per image only)
    images: dict[str, CameraModel] = field(default_factory=dict)  # by image id or file name (zedo's JSON)
    name: str | None = None  # the camera picked in a file of several (TOML)


def read_camera_file(path: str | Path, camera: str | None = None) -> CameraFile:
    """Read a calibration file (format by extension, else content); `camera` picks one camera
    by name in a file of several (Pose2Sim / anipose TOML), and must be None for the others."""
    name = str(path)
    try:
        text = Path(path).read_text(encoding="utf-8")
    except FileNotFoundError:
        raise CameraInputError(f"{name}: intrinsics file not found") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise CameraInputError(f"{name}: not a readable text file ({exc})") from None
    kind, doc = _detect(name, text)
    if kind != "toml" and camera is not None:
        kind_name = "an OpenCV FileStorage" if kind == "opencv" else "a zedo JSON"
        raise CameraInputError(f"{name}: --camera {camera}: {kind_name} calibration file holds one camera; "
                               "--camera picks one of the cameras of a Pose2Sim or anipose TOML file")  # fmt: skip
    if kind == "toml":
        return _read_toml(name, text, camera)
    if kind == "opencv":
        return _read_opencv(name, text)
    return _read_zedo(name, doc)


def _detect(name: str, text: str) -> tuple[str, Any]:
    """The file's format, and its JSON document when it is JSON."""
    suffix = Path(name).suffix.lower()
    head = text.lstrip()
    if suffix == ".toml":
        return "toml", None
    if suffix in _OPENCV_SUFFIXES or head.startswith(("%YAML", "<?xml", "<opencv_storage")):
        return "opencv", None
    if suffix == ".json" or head.startswith(("{", "[")):
        try:
            doc = loads(text)
        except (ValueError, RecursionError) as exc:  # bad JSON, a repeated key, an integer of thousands of digits
            raise CameraInputError(f"{name}: not a readable JSON file ({exc})") from None
        return ("opencv" if isinstance(doc, dict) and "camera_matrix" in doc else "zedo"), doc
    return "toml", None  # neither JSON nor FileStorage: a calibration TOML, or an error naming it


def _validate(name: str, prefix: str, model: type[_Model], data: Any) -> Any:
    """`data` as `model`; the first error as `FILE: field: message`, the field after `prefix`
    (pydantic's location ('K', 0, 1) reads K[0][1])."""
    try:
        return model.model_validate(data)
    except ValidationError as exc:
        first = exc.errors()[0]
        where = (prefix + "".join(f"[{p}]" if isinstance(p, int) else f".{p}" for p in first["loc"])).lstrip(".")
        message = str(first["msg"]).removeprefix("Value error, ")
        raise CameraInputError(f"{name}: {where}: {message}" if where else f"{name}: {message}") from None


def _camera(
    name: str, where: str, k: list[list[float]], dist: list[float], model: str,
    size: tuple[float, float] | None, k_field: str, dist_field: str,
) -> CameraModel:  # fmt: skip
    """A CameraModel from a file's values; an error names the matrix or the coefficients."""
    image_size = None if size is None else (int(round(size[0])), int(round(size[1])))
    try:
        base = CameraModel.from_matrix(k, (), "pinhole", image_size)
    except IntrinsicsError as exc:
        raise CameraInputError(f"{name}: {where}{k_field}: {exc}") from None
    try:
        return replace(base, dist=tuple(dist), model=model)  # type: ignore[arg-type]
    except IntrinsicsError as exc:
        raise CameraInputError(f"{name}: {where}{dist_field}: {exc}") from None


# --- zedo's JSON ---------------------------------------------------------------------------------


def _zedo_camera(name: str, where: str, entry: ZedoEntry) -> CameraModel:
    k_field = "K" if entry.K is not None else "fx, fy, cx, cy"
    return _camera(name, where, entry.matrix(), entry.dist, entry.model, entry.image_size, k_field, "dist")


def _read_zedo(name: str, doc: Any) -> CameraFile:
    if not isinstance(doc, dict):
        raise CameraInputError(f"{name}: expected a JSON object")
    images_doc = doc.get("images", {})
    if not isinstance(images_doc, dict):
        raise CameraInputError(f"{name}: images: 'images' must map image ids or file names to intrinsics")
    images: dict[str, CameraModel] = {}
    for key, value in images_doc.items():
        if not isinstance(value, dict):
            raise CameraInputError(f"{name}: images[{key!r}]: expected an object with 'K' or 'fx', 'fy', 'cx', 'cy'")
        entry = _validate(name, f"images[{key!r}]", ZedoEntry, value)
        images[str(key)] = _zedo_camera(name, f"images[{key!r}].", entry)
    glob = None
    if "K" in doc or "fx" in doc:
        glob = _zedo_camera(name, "", _validate(name, "", ZedoEntry, {k: v for k, v in doc.items() if k != "images"}))
    if glob is None and not images:
        raise CameraInputError(f"{name}: no intrinsics found (expected 'K', 'fx'... or 'images')")
    return CameraFile(name, "zedo", glob, images)


# --- OpenCV FileStorage --------------------------------------------------------------------------


def _node_value(node: Any) -> Any:
    """A FileStorage node as plain Python: a matrix as nested lists, a sequence as a list."""
    if node.empty() or node.isNone():
        return None
    if node.isMap():
        mat = node.mat()
        return None if mat is None else mat.tolist()
    if node.isSeq():
        return [_node_value(node.at(i)) for i in range(node.size())]
    if node.isString():
        return node.string()
    return node.real()


def _read_opencv(name: str, text: str) -> CameraFile:
    import cv2

    try:
        storage = cv2.FileStorage(text, cv2.FILE_STORAGE_READ | cv2.FILE_STORAGE_MEMORY)
    except (cv2.error, SystemError) as exc:  # cv2's Python binding wraps its parse error in a SystemError
        cause = exc if isinstance(exc, cv2.error) else (exc.__cause__ or exc.__context__ or exc)
        reason = str(cause).strip().split("error: ", 1)[-1]
        raise CameraInputError(f"{name}: not a readable OpenCV FileStorage file ({reason})") from None
    try:
        if not storage.isOpened():
            raise CameraInputError(f"{name}: not a readable OpenCV FileStorage file")
        nodes = {key: _node_value(storage.getNode(key)) for key in OpenCVCalibration.model_fields}
    finally:
        storage.release()
    values = {key: value for key, value in nodes.items() if value is not None}
    if "camera_matrix" not in values:
        raise CameraInputError(f"{name}: camera_matrix: missing (an OpenCV calibration file has camera_matrix, "
                               "distortion_coefficients, image_width and image_height)")  # fmt: skip
    dist = values.get("distortion_coefficients")
    if isinstance(dist, list) and dist and isinstance(dist[0], list):  # a 1xN or Nx1 matrix
        values["distortion_coefficients"] = [v for row in dist for v in row]
    calib = _validate(name, "", OpenCVCalibration, values)
    width, height = calib.image_width, calib.image_height
    if (width is None) != (height is None):
        raise CameraInputError(f"{name}: {'image_height' if height is None else 'image_width'}: missing "
                               "(give both image_width and image_height, or neither)")  # fmt: skip
    size = None if width is None or height is None else (width, height)
    camera = _camera(name, "", calib.camera_matrix, calib.distortion_coefficients, calib.model, size,
                     "camera_matrix", "distortion_coefficients")  # fmt: skip
    return CameraFile(name, "opencv", camera)


# --- Pose2Sim and anipose TOML -------------------------------------------------------------------


def _read_toml(name: str, text: str, pick: str | None) -> CameraFile:
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise CameraInputError(f"{name}: not a readable calibration file (zedo JSON, OpenCV YAML / XML / JSON, "
                               f"or Pose2Sim / anipose TOML: {exc})") from None  # fmt: skip
    tables = {key: value for key, value in doc.items() if isinstance(value, dict) and key not in NOT_CAMERAS}
    if not tables:
        raise CameraInputError(f"{name}: no camera tables (expected [cam_1]... with name, size, matrix, distortions)")
    # aniposelib orders cameras by their table names as strings; so do the names listed here
    cameras = {key: _validate(name, f"[{key}]", TomlCamera, tables[key]) for key in sorted(tables)}
    names = {key: cam.name or key for key, cam in cameras.items()}
    if pick is None:
        if len(cameras) > 1:
            raise CameraInputError(f"{name}: holds {len(cameras)} cameras ({', '.join(names.values())}): "
                                   "choose one with --camera NAME")  # fmt: skip
        key = next(iter(cameras))
    else:
        found = [key for key in cameras if pick in (names[key], key)]
        if not found:
            raise CameraInputError(f"{name}: --camera {pick}: no such camera (the file holds: "
                                   f"{', '.join(names.values())})")  # fmt: skip
        key = found[0]
    cam = cameras[key]
    model = "fisheye" if cam.fisheye else "pinhole"
    camera = _camera(name, f"[{key}].", cam.matrix, cam.distortions, model, cam.size, "matrix", "distortions")
    return CameraFile(name, "toml", camera, name=names[key])
