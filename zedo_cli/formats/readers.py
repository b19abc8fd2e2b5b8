"""Readers of 2D keypoint JSON files into `Keypoints2D` (FORMATS.md 3.1, 3.2, 3.4, 3.7).

Three layouts are read:

- ``coco-annotations``: a COCO keypoint annotation file (``images``, ``annotations``,
  ``categories``), e.g. SyRIP ground truth. Visibility v = 0 is a missing joint, v = 1 (labelled
  but occluded) gets confidence 0.5, v = 2 gets 1.0; a float v in (0, 1) is taken as a confidence.
- ``coco-results``: a COCO keypoint results list ``[{image_id, keypoints: [x, y, c] * 17, score}]``
  from a detector (FiDIP, HRNet, AlphaPose). c is a confidence, clipped to [0, 1] (AlphaPose
  exceeds 1); c == 0 is a missing joint. Sizes come from ``--image-size`` or a companion
  annotation file (``images=``).
- ``zedo-2d``: zedo's own simple layout::

      {"schema": "zedo.keypoints2d/1",        # optional; when present exactly this string
       "skeleton": "h36m17",                  # h36m17 | coco17 | syrip12 | lsp14
       "image_size": [W, H],                  # optional default for every instance, pixels
       "instances": [
         {"image_id": 0,                      # int or str
          "file_name": "frame0000.png",       # optional
          "image_size": [W, H],               # optional, overrides the default
          "score": 0.93,                      # optional detection score
          "keypoints": [[x, y], [x, y, c], null, ...]}]}   # one entry per skeleton joint

  ``[x, y]`` has confidence 1, ``[x, y, c]`` a confidence c in [0, 1]; ``null`` or c == 0 is a
  missing joint. With ``"skeleton": "h36m17"`` this is the "H36M-style 2D JSON".

Coordinates are 0-indexed pixels from the image's top-left. Missing joints come out as NaN with
confidence 0, never as positions. Every malformed input raises `InputFormatError` whose message
starts with the file path and names the field as a JSON path, e.g.
``kp.json: annotations[3].keypoints: expected 51 numbers (17 joints x 3), got 50``.
"""

from __future__ import annotations

import dataclasses
import json
import math
import sys
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import ConfigError, InputFormatError
from ..skeleton import SKELETONS, Skeleton
from .keypoints import Keypoints2D

ImageId = int | str

INPUT_FORMATS = ("auto", "coco-annotations", "coco-results", "zedo-2d")
ZEDO_2D_SCHEMA = "zedo.keypoints2d/1"
OCCLUDED_CONFIDENCE = 0.5  # confidence of a COCO v = 1 joint (labelled but not visible)
_EXPECTED = (
    "expected COCO annotations (images, annotations, categories), a COCO results list, or zedo 2D (instances)"
)
# MMPose's H36M joint names (configs/_base_/datasets/h36m.py) that zedo names differently.
_JOINT_NAME_ALIASES = {
    "root": "pelvis", "right_foot": "right_ankle", "left_foot": "left_ankle", "neck_base": "neck",
}  # fmt: skip
_NAN_SIZE = (math.nan, math.nan)


@dataclass(frozen=True)
class _Image:
    """One entry of a COCO ``images`` list."""

    position: int
    size: tuple[float, float]  # width, height in pixels; NaN = unknown
    file_name: str | None


@dataclass(frozen=True)
class _Row:
    """One instance, ready to be stacked into a `Keypoints2D`."""

    image_id: ImageId
    xy: np.ndarray  # (J, 2) pixels, NaN = missing
    confidence: np.ndarray  # (J,) in [0, 1], 0 = missing
    file_name: str | None
    size: tuple[float, float]
    score: float | None


# --- checks shared by all readers ---------------------------------------------------------


def _error(path: str, where: str, message: str) -> InputFormatError:
    """`InputFormatError` "<path>: <where>: <message>" (where = a JSON path, "" for the top level)."""
    return InputFormatError(f"{path}: {where}: {message}" if where else f"{path}: {message}")


def _field(where: str, key: str) -> str:
    return f"{where}.{key}" if where else key


def _kind(value: Any) -> str:
    """JSON type of `value` with an article, for messages."""
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "a boolean"
    if isinstance(value, int | float):
        return "a number"
    if isinstance(value, str):
        return "a string"
    if isinstance(value, list):
        return "a list"
    if isinstance(value, dict):
        return "an object"
    return type(value).__name__


def _as_dict(value: Any, path: str, where: str) -> dict[str, Any]:
    if not isinstance(value, dict):
        raise _error(path, where, f"expected an object, got {_kind(value)}")
    return value


def _as_list(value: Any, path: str, where: str) -> list[Any]:
    if not isinstance(value, list):
        raise _error(path, where, f"expected a list, got {_kind(value)}")
    return value


def _required(obj: dict[str, Any], key: str, path: str, where: str) -> Any:
    if key not in obj:
        raise _error(path, _field(where, key), "missing required key")
    return obj[key]


def _number(value: Any, path: str, where: str) -> float:
    """A JSON number as a float (may be NaN or inf: JSON files from Python can hold those)."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise _error(path, where, f"expected a number, got {_kind(value)}")
    try:
        return float(value)
    except OverflowError:
        raise _error(path, where, "number too large") from None


def _pixels(value: Any, path: str, where: str) -> float:
    """An image width or height: a positive finite number of pixels."""
    number = _number(value, path, where)
    if not (math.isfinite(number) and number > 0):
        raise _error(path, where, f"expected a positive number of pixels, got {number:g}")
    return number


def _size_pair(value: Any, path: str, where: str) -> tuple[float, float]:
    """A ``[W, H]`` list in pixels."""
    items = _as_list(value, path, where)
    if len(items) != 2:
        raise _error(path, where, f"expected [width, height], got {len(items)} values")
    return _pixels(items[0], path, f"{where}[0]"), _pixels(items[1], path, f"{where}[1]")


def _image_id(value: Any, path: str, where: str) -> ImageId:
    if isinstance(value, str) or (isinstance(value, int) and not isinstance(value, bool)):
        return value
    raise _error(path, where, f"expected an integer or string image id, got {_kind(value)}")


def _optional_str(obj: dict[str, Any], key: str, path: str, where: str) -> str | None:
    value = obj.get(key)
    if value is not None and not isinstance(value, str):
        raise _error(path, _field(where, key), f"expected a string, got {_kind(value)}")
    return value


def _optional_score(obj: dict[str, Any], path: str, where: str) -> float | None:
    """The instance's detection ``score`` when present (null = absent)."""
    if obj.get("score") is None:
        return None
    score = _number(obj["score"], path, _field(where, "score"))
    if not math.isfinite(score):
        raise _error(path, _field(where, "score"), f"expected a finite number, got {score:g}")
    return score


def _confidence(value: Any, path: str, where: str) -> float:
    """A confidence that must already lie in [0, 1]."""
    conf = _number(value, path, where)
    if not 0.0 <= conf <= 1.0:
        raise _error(path, where, f"expected a confidence in [0, 1], got {conf:g}")
    return conf


def _flat_triplets(value: Any, num_joints: int, path: str, where: str) -> list[tuple[float, float, float]]:
    """``[x1, y1, c1, ...]`` of exactly `num_joints` joints as (x, y, third value) triplets."""
    values = _as_list(value, path, where)
    if len(values) != 3 * num_joints:
        raise _error(
            path, where, f"expected {3 * num_joints} numbers ({num_joints} joints x 3), got {len(values)}"
        )
    numbers = [_number(v, path, f"{where}[{k}]") for k, v in enumerate(values)]
    return [(numbers[k], numbers[k + 1], numbers[k + 2]) for k in range(0, len(numbers), 3)]


def _joints(
    points: list[tuple[float, float, float]], skeleton: Skeleton, path: str, where: str
) -> tuple[np.ndarray, np.ndarray]:
    """(x, y, confidence) per joint -> xy (J, 2) with NaN for missing, confidence (J,).

    A joint with confidence 0 is missing whatever its coordinates (COCO stores placeholders such
    as (-45, -45)); any other joint must have finite coordinates.
    """
    xy = np.full((skeleton.num_joints, 2), np.nan, dtype=np.float64)
    confidence = np.zeros(skeleton.num_joints, dtype=np.float64)
    for j, (x, y, conf) in enumerate(points):
        if conf <= 0.0:
            continue
        if not (math.isfinite(x) and math.isfinite(y)):
            raise _error(
                path, where,
                f"joint {j} ({skeleton.joints[j]}) is not marked missing but has coordinates ({x:g}, {y:g})",
            )  # fmt: skip
        xy[j] = (x, y)
        confidence[j] = conf
    return xy, confidence


def _build(rows: list[_Row], skeleton: Skeleton, path: str, fmt: str) -> Keypoints2D:
    """Stack instance rows into a `Keypoints2D`; zero rows is an error."""
    if not rows:
        raise _error(path, "", "no instances found")
    return Keypoints2D(
        xy=np.stack([r.xy for r in rows]).astype(np.float64),
        confidence=np.stack([r.confidence for r in rows]).astype(np.float64),
        skeleton=skeleton,
        image_ids=[r.image_id for r in rows],
        file_names=[r.file_name for r in rows],
        image_sizes=np.array([r.size for r in rows], dtype=np.float64).reshape(len(rows), 2),
        scores=[r.score for r in rows],
        path=path,
        format=fmt,
    )


def _parse_images(doc: dict[str, Any], path: str) -> dict[ImageId, _Image]:
    """COCO ``images[]`` by id. Width/height are optional (unknown = NaN) but must be valid if given."""
    images = _as_list(_required(doc, "images", path, ""), path, "images")
    index: dict[ImageId, _Image] = {}
    for i, entry in enumerate(images):
        where = f"images[{i}]"
        entry = _as_dict(entry, path, where)
        image_id = _image_id(_required(entry, "id", path, where), path, f"{where}.id")
        if image_id in index:
            other = index[image_id].position
            raise _error(path, f"{where}.id", f"duplicate image id {image_id!r} (also images[{other}])")
        width, height = (
            math.nan if entry.get(key) is None else _pixels(entry[key], path, f"{where}.{key}")
            for key in ("width", "height")
        )
        size = _NAN_SIZE if math.isnan(width) or math.isnan(height) else (width, height)
        index[image_id] = _Image(i, size, _optional_str(entry, "file_name", path, where))
    return index


def _skeleton_from_names(value: Any, path: str, where: str) -> Skeleton:
    """The skeleton whose joint names are exactly `value`; 17 unknown names mean COCO-17."""
    names = _as_list(value, path, where)
    for k, name in enumerate(names):
        if not isinstance(name, str):
            raise _error(path, f"{where}[{k}]", f"expected a joint name, got {_kind(name)}")
    joints = tuple(_JOINT_NAME_ALIASES.get(name, name) for name in names)
    for skeleton in SKELETONS.values():
        if skeleton.joints == joints:
            return skeleton
    if len(joints) == 17:
        return SKELETONS["coco17"]
    known = ", ".join(sorted(SKELETONS))
    raise _error(
        path, where,
        f"unsupported joint count {len(joints)} with unknown joint names "
        f"(expected 17 COCO joints or the joint names of a known skeleton: {known})",
    )  # fmt: skip


# --- COCO annotations ----------------------------------------------------------------------


def _categories_skeleton(doc: dict[str, Any], path: str) -> Skeleton:
    """Skeleton from ``categories[0].keypoints``; COCO-17 when the names are not given."""
    categories = _as_list(_required(doc, "categories", path, ""), path, "categories")
    if not categories:
        return SKELETONS["coco17"]
    first = _as_dict(categories[0], path, "categories[0]")
    if "keypoints" not in first:
        return SKELETONS["coco17"]
    return _skeleton_from_names(first["keypoints"], path, "categories[0].keypoints")


def _visibility_confidence(v: float, path: str, where: str) -> float:
    """COCO visibility -> confidence: 0 -> 0 (missing), 1 -> 0.5, 2 -> 1, a float in (0, 1) -> itself."""
    if v == 0:
        return 0.0
    if v == 1:
        return OCCLUDED_CONFIDENCE
    if v == 2:
        return 1.0
    if 0.0 < v < 1.0:
        return v
    raise _error(path, where, f"visibility {v:g} is neither 0, 1, 2 nor a confidence in (0, 1]")


def _parse_annotation(
    entry: Any, i: int, images: Mapping[ImageId, _Image], skeleton: Skeleton, path: str
) -> tuple[tuple[int, int], _Row]:
    """One annotation -> (sort key by image position then annotation position, row)."""
    where = f"annotations[{i}]"
    entry = _as_dict(entry, path, where)
    image_id = _image_id(_required(entry, "image_id", path, where), path, f"{where}.image_id")
    image = images.get(image_id)
    if image is None:
        raise _error(path, f"{where}.image_id", f"image id {image_id!r} is not in images")
    where_kp = f"{where}.keypoints"
    triplets = _flat_triplets(_required(entry, "keypoints", path, where), skeleton.num_joints, path, where_kp)
    points = [
        (x, y, _visibility_confidence(v, path, f"{where_kp}[{3 * j + 2}]"))
        for j, (x, y, v) in enumerate(triplets)
    ]
    xy, confidence = _joints(points, skeleton, path, where_kp)
    score = _optional_score(entry, path, where)
    return (image.position, i), _Row(image_id, xy, confidence, image.file_name, image.size, score)


def read_coco_annotations(data: Any, path: str) -> Keypoints2D:
    """Read a parsed COCO keypoint annotation file (FORMATS.md 3.1).

    Instances are ordered by their image's position in ``images``, then by annotation position.
    Sizes (pixels) and file names come from ``images[]``; the skeleton from ``categories[0]``.
    """
    doc = _as_dict(data, path, "")
    images = _parse_images(doc, path)
    skeleton = _categories_skeleton(doc, path)
    annotations = _as_list(_required(doc, "annotations", path, ""), path, "annotations")
    keyed = [_parse_annotation(entry, i, images, skeleton, path) for i, entry in enumerate(annotations)]
    keyed.sort(key=lambda item: item[0])
    return _build([row for _, row in keyed], skeleton, path, "coco-annotations")


# --- COCO results --------------------------------------------------------------------------


def _results_skeleton(values: Any, path: str, where: str) -> Skeleton:
    """Skeleton of a results instance, inferred from its flat keypoint list length (17 -> coco17)."""
    values = _as_list(values, path, where)
    if len(values) % 3:
        raise _error(path, where, f"expected x, y, c triplets (a multiple of 3 numbers), got {len(values)}")
    if len(values) // 3 != 17:
        raise _error(path, where, f"unsupported joint count {len(values) // 3} (COCO results need 17 joints)")
    return SKELETONS["coco17"]


def _result_confidence(c: float, path: str, where: str) -> float:
    """A detector confidence clipped to [0, 1] (AlphaPose exceeds 1); 0 means missing."""
    if math.isnan(c):
        raise _error(path, where, "expected a confidence, got NaN")
    return min(max(c, 0.0), 1.0)


def _parse_result(entry: Any, i: int, sizes: Mapping[ImageId, tuple[float, float]], path: str) -> _Row:
    where = f"[{i}]"
    entry = _as_dict(entry, path, where)
    image_id = _image_id(_required(entry, "image_id", path, where), path, f"{where}.image_id")
    where_kp = f"{where}.keypoints"
    values = _required(entry, "keypoints", path, where)
    skeleton = _results_skeleton(values, path, where_kp)
    triplets = _flat_triplets(values, skeleton.num_joints, path, where_kp)
    points = [
        (x, y, _result_confidence(c, path, f"{where_kp}[{3 * j + 2}]"))
        for j, (x, y, c) in enumerate(triplets)
    ]
    xy, confidence = _joints(points, skeleton, path, where_kp)
    size = tuple(float(s) for s in sizes.get(image_id, _NAN_SIZE))
    return _Row(image_id, xy, confidence, None, (size[0], size[1]), _optional_score(entry, path, where))


def read_coco_results(
    data: Any, path: str, image_sizes: Mapping[ImageId, tuple[float, float]] | None = None
) -> Keypoints2D:
    """Read a parsed COCO keypoint results list (FORMATS.md 3.2), every instance in file order.

    `image_sizes` maps image_id -> (width, height) in pixels; instances without one get NaN.
    """
    entries = _as_list(data, path, "")
    rows = [_parse_result(entry, i, image_sizes or {}, path) for i, entry in enumerate(entries)]
    return _build(rows, SKELETONS["coco17"], path, "coco-results")


# --- zedo 2D -------------------------------------------------------------------------------


def _zedo_skeleton(value: Any, path: str) -> Skeleton:
    if not isinstance(value, str):
        raise _error(path, "skeleton", f"expected a skeleton name, got {_kind(value)}")
    if value not in SKELETONS:
        known = ", ".join(sorted(SKELETONS))
        raise _error(path, "skeleton", f"unknown skeleton {value[:40]!r}; expected one of {known}")
    return SKELETONS[value]


def _zedo_point(value: Any, path: str, where: str) -> tuple[float, float, float]:
    """``null`` | ``[x, y]`` | ``[x, y, c]`` -> (x, y, confidence); null is missing."""
    if value is None:
        return math.nan, math.nan, 0.0
    items = _as_list(value, path, where)
    if len(items) not in (2, 3):
        raise _error(path, where, f"expected [x, y] or [x, y, c], got {len(items)} values")
    x, y = _number(items[0], path, f"{where}[0]"), _number(items[1], path, f"{where}[1]")
    conf = _confidence(items[2], path, f"{where}[2]") if len(items) == 3 else 1.0
    return x, y, conf


def _parse_zedo_instance(
    entry: Any, i: int, skeleton: Skeleton, default_size: tuple[float, float], path: str
) -> _Row:
    where = f"instances[{i}]"
    entry = _as_dict(entry, path, where)
    image_id = _image_id(_required(entry, "image_id", path, where), path, f"{where}.image_id")
    where_kp = f"{where}.keypoints"
    joints = _as_list(_required(entry, "keypoints", path, where), path, where_kp)
    if len(joints) != skeleton.num_joints:
        expected = f"expected {skeleton.num_joints} joints for skeleton {skeleton.name}"
        raise _error(path, where_kp, f"{expected}, got {len(joints)}")
    points = [_zedo_point(p, path, f"{where_kp}[{j}]") for j, p in enumerate(joints)]
    xy, confidence = _joints(points, skeleton, path, where_kp)
    size = default_size
    if "image_size" in entry:
        size = _size_pair(entry["image_size"], path, f"{where}.image_size")
    file_name = _optional_str(entry, "file_name", path, where)
    return _Row(image_id, xy, confidence, file_name, size, _optional_score(entry, path, where))


def read_zedo_2d(data: Any, path: str) -> Keypoints2D:
    """Read a parsed zedo 2D document (layout in the module docstring), instances in file order."""
    doc = _as_dict(data, path, "")
    if "schema" in doc and doc["schema"] != ZEDO_2D_SCHEMA:
        found = repr(doc["schema"][:40]) if isinstance(doc["schema"], str) else _kind(doc["schema"])
        raise _error(path, "schema", f"expected {ZEDO_2D_SCHEMA!r}, got {found}")
    skeleton = _zedo_skeleton(_required(doc, "skeleton", path, ""), path)
    default_size = _size_pair(doc["image_size"], path, "image_size") if "image_size" in doc else _NAN_SIZE
    instances = _as_list(_required(doc, "instances", path, ""), path, "instances")
    rows = [_parse_zedo_instance(entry, i, skeleton, default_size, path) for i, entry in enumerate(instances)]
    return _build(rows, skeleton, path, "zedo-2d")


# --- detection and the file-level entry point ----------------------------------------------


def _keys(obj: dict[str, Any]) -> str:
    keys = [k if k.isprintable() else repr(k) for k in map(str, obj)]
    shown = ", ".join(keys[:12])
    return shown + (f", ... ({len(keys)} keys)" if len(keys) > 12 else "")


def _is_results_entry(entry: Any) -> bool:
    """A dict with ``image_id`` and a flat ``keypoints`` list (not MMPose's nested [[x, y], ...])."""
    if not isinstance(entry, dict) or "image_id" not in entry:
        return False
    keypoints = entry.get("keypoints")
    return isinstance(keypoints, list) and not (keypoints and isinstance(keypoints[0], list))


def detect_format(data: Any, path: str = "<input>") -> str:
    """The format of a parsed JSON document: "coco-annotations", "coco-results" or "zedo-2d".

    FORMATS.md 3.7: a dict with images, annotations and categories is COCO annotations; a list of
    dicts with image_id and flat keypoints is COCO results (an empty list too: a detector that
    found nobody); a dict with instances is zedo 2D.
    """
    if isinstance(data, dict):
        if all(key in data for key in ("images", "annotations", "categories")):
            return "coco-annotations"
        if "instances" in data:
            return "zedo-2d"
        found = f"top-level JSON object has keys {_keys(data)}" if data else "top-level JSON object is empty"
    elif isinstance(data, list):
        if not data or _is_results_entry(data[0]):
            return "coco-results"
        if isinstance(data[0], dict):
            found = f"top-level JSON list of objects whose first has keys {_keys(data[0]) or '(none)'}"
            if isinstance(data[0].get("keypoints"), list):
                found += " and nested keypoints"
        else:
            found = f"top-level JSON list whose first element is {_kind(data[0])}"
    else:
        found = f"top-level JSON value is {_kind(data)}"
    raise _error(path, "", f"{found}; {_EXPECTED}")


_READERS: dict[str, Callable[[Any, str], Keypoints2D]] = {
    "coco-annotations": read_coco_annotations,
    "coco-results": read_coco_results,
    "zedo-2d": read_zedo_2d,
}


def _read_text(name: str) -> str:
    """The UTF-8 text of file `name` ("-" = stdin)."""
    try:
        if name == "-":
            raw = sys.stdin.buffer.read()
        elif Path(name).is_dir():
            raise _error(name, "", "is a directory, expected a JSON file")
        else:
            raw = Path(name).read_bytes()
    except FileNotFoundError:
        raise _error(name, "", "file not found") from None
    except OSError as exc:
        raise _error(name, "", f"cannot read file: {exc.strerror or exc}") from None
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise _error(name, "", f"not UTF-8 text (invalid byte at offset {exc.start})") from None


def _load_json(name: str) -> Any:
    text = _read_text(name)
    if not text.strip():
        raise _error(name, "", "file is empty")
    try:
        return json.loads(text)
    except json.JSONDecodeError as exc:
        raise _error(name, "", f"invalid JSON at line {exc.lineno}, column {exc.colno}: {exc.msg}") from None
    except (ValueError, RecursionError) as exc:  # e.g. integers beyond Python's digit limit, deep nesting
        raise _error(name, "", f"invalid JSON: {exc}") from None


def _format_option(fmt: str | None) -> str | None:
    if fmt is None or fmt == "auto":
        return None
    if fmt not in INPUT_FORMATS:
        raise ConfigError(f"unknown input format {fmt!r}; expected one of {', '.join(INPUT_FORMATS)}")
    return fmt


def _size_option(image_size: tuple[float, float]) -> tuple[float, float]:
    try:
        width, height = (float(v) for v in image_size)
    except (TypeError, ValueError):
        raise ConfigError(f"--image-size: expected two numbers W H, got {image_size!r}") from None
    if not all(math.isfinite(v) and v > 0 for v in (width, height)):
        raise ConfigError(f"--image-size: expected two positive numbers of pixels, got {width:g} {height:g}")
    return width, height


def _join_images(kp: Keypoints2D, images: str) -> Keypoints2D:
    """Fill unknown sizes and file names from a companion COCO file's ``images[]``, joined on image_id.

    A string image_id (AlphaPose) that is not an id there is looked up as a ``file_name``.
    """
    index = _parse_images(_as_dict(_load_json(images), images, ""), images)
    by_name = {image.file_name: image for image in index.values() if image.file_name is not None}
    sizes = kp.image_sizes.copy()
    file_names = list(kp.file_names)
    for n, image_id in enumerate(kp.image_ids):
        image = index.get(image_id) or (by_name.get(image_id) if isinstance(image_id, str) else None)
        if image is None:
            raise _error(kp.path, "image_id", f"image id {image_id!r} is not among the images[] of {images}")
        if np.isnan(sizes[n]).any():
            sizes[n] = image.size
        file_names[n] = file_names[n] if file_names[n] is not None else image.file_name
    return dataclasses.replace(kp, image_sizes=sizes, file_names=file_names)


def read_keypoints(
    path: str | Path,
    *,
    format: str | None = None,
    image_size: tuple[float, float] | None = None,
    images: str | Path | None = None,
) -> Keypoints2D:
    """Read a 2D keypoint JSON file ("-" = stdin) into `Keypoints2D` (xy (N, J, 2) pixels, float64).

    `format`: one of `INPUT_FORMATS`; None or "auto" detects it. `images`: a companion COCO
    annotation file whose ``images[]`` give sizes and file names (for a results file), joined
    on image_id. `image_size`: (W, H) pixels for the instances whose size is still unknown.
    """
    name = str(path)
    fmt = _format_option(format)
    size = _size_option(image_size) if image_size is not None else None
    data = _load_json(name)
    kp = _READERS[fmt or detect_format(data, name)](data, name)
    if images is not None:
        kp = _join_images(kp, str(images))
    if size is not None:
        sizes = kp.image_sizes.copy()
        sizes[np.isnan(sizes).any(axis=1)] = size
        kp = dataclasses.replace(kp, image_sizes=sizes)
    return kp
