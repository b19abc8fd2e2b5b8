"""Checks shared by the 2D readers: each turns a bad JSON value into an `InputFormatError`.

Every message starts with the file and names the field as a JSON path,
``kp.json: annotations[3].keypoints: expected 51 numbers (17 joints x 3), got 50``, so a user
can find the fault without a traceback. Readers stack their instances with `build`.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..data.keypoints import Keypoints2D
from ..data.skeleton import Skeleton, joint_count_names, skeleton_for_joint_count
from ..errors import InputFormatError

ImageId = int | str
NAN_SIZE = (math.nan, math.nan)


@dataclass(frozen=True)
class Row:
    """One instance, ready to be stacked into a `Keypoints2D`."""

    image_id: ImageId
    xy: np.ndarray  # (J, 2) pixels, NaN = missing
    confidence: np.ndarray  # (J,) in [0, 1], 0 = missing
    file_name: str | None
    size: tuple[float, float]  # width, height in pixels; NaN = unknown
    score: float | None
    frame: int | None = None  # 0-based frame index where the format has one


def error(path: str, where: str, message: str) -> InputFormatError:
    """`InputFormatError` "<path>: <where>: <message>" (where = a JSON path, "" for the top level)."""
    return InputFormatError(f"{path}: {where}: {message}" if where else f"{path}: {message}")


def field(where: str, key: str) -> str:
    return f"{where}.{key}" if where else key


def kind(value: Any) -> str:
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


def as_dict(value: Any, path: str, where: str) -> dict[str, Any]:
    if not isinstance(value, dict):
        raise error(path, where, f"expected an object, got {kind(value)}")
    return value


def as_list(value: Any, path: str, where: str) -> list[Any]:
    if not isinstance(value, list):
        raise error(path, where, f"expected a list, got {kind(value)}")
    return value


def required(obj: dict[str, Any], key: str, path: str, where: str) -> Any:
    if key not in obj:
        raise error(path, field(where, key), "missing required key")
    return obj[key]


def number(value: Any, path: str, where: str) -> float:
    """A JSON number as a float (may be NaN or inf: JSON files from Python can hold those)."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise error(path, where, f"expected a number, got {kind(value)}")
    try:
        return float(value)
    except OverflowError:
        raise error(path, where, "number too large") from None


def pixels(value: Any, path: str, where: str) -> float:
    """An image width or height: a positive finite number of pixels."""
    value = number(value, path, where)
    if not (math.isfinite(value) and value > 0):
        raise error(path, where, f"expected a positive number of pixels, got {value:g}")
    return value


def size_pair(value: Any, path: str, where: str) -> tuple[float, float]:
    """A ``[W, H]`` list in pixels."""
    items = as_list(value, path, where)
    if len(items) != 2:
        raise error(path, where, f"expected [width, height], got {len(items)} values")
    return pixels(items[0], path, f"{where}[0]"), pixels(items[1], path, f"{where}[1]")


def image_id(value: Any, path: str, where: str) -> ImageId:
    if isinstance(value, str) or (isinstance(value, int) and not isinstance(value, bool)):
        return value
    raise error(path, where, f"expected an integer or string image id, got {kind(value)}")


def frame_number(value: Any, path: str, where: str) -> int:
    """A frame number: a non-negative JSON integer (2.0 is accepted, 2.5 is not)."""
    if isinstance(value, float) and value.is_integer():
        value = int(value)
    if isinstance(value, bool) or not isinstance(value, int):
        raise error(path, where, f"expected a frame number (an integer), got {kind(value)}")
    if value < 0:
        raise error(path, where, f"expected a frame number >= 0, got {value}")
    return value


def optional_str(obj: dict[str, Any], key: str, path: str, where: str) -> str | None:
    value = obj.get(key)
    if value is not None and not isinstance(value, str):
        raise error(path, field(where, key), f"expected a string, got {kind(value)}")
    return value


def optional_score(obj: dict[str, Any], path: str, where: str, key: str = "score") -> float | None:
    """The instance's detection score under `key` when present (null = absent)."""
    if obj.get(key) is None:
        return None
    score = number(obj[key], path, field(where, key))
    if not math.isfinite(score):
        raise error(path, field(where, key), f"expected a finite number, got {score:g}")
    return score


def confidence(value: Any, path: str, where: str) -> float:
    """A confidence that must already lie in [0, 1]."""
    conf = number(value, path, where)
    if not 0.0 <= conf <= 1.0:
        raise error(path, where, f"expected a confidence in [0, 1], got {conf:g}")
    return conf


def detector_confidence(c: float, path: str, where: str) -> float:
    """A detector's joint confidence clipped to [0, 1] (AlphaPose and RTMPose exceed 1); 0 = missing."""
    if math.isnan(c):
        raise error(path, where, "expected a confidence, got NaN")
    return min(max(c, 0.0), 1.0)


def flat_triplets(value: Any, num_joints: int, path: str, where: str) -> list[tuple[float, float, float]]:
    """``[x1, y1, c1, ...]`` of exactly `num_joints` joints as (x, y, third value) triplets."""
    values = as_list(value, path, where)
    if len(values) != 3 * num_joints:
        raise error(path, where, f"expected {3 * num_joints} numbers ({num_joints} joints x 3), got {len(values)}")
    numbers = [number(v, path, f"{where}[{k}]") for k, v in enumerate(values)]
    return [(numbers[k], numbers[k + 1], numbers[k + 2]) for k in range(0, len(numbers), 3)]


def counted_skeleton(count: int, first: Skeleton | None, path: str, where: str) -> Skeleton:
    """The skeleton of an instance with `count` unnamed joints (FORMATS.md 3.7).

    `first` is the skeleton of the file's earlier instances: the count must not change within
    one input (OpenPose: "the number of keypoints is constant across files").
    """
    if first is not None:
        if count != first.num_joints:
            raise error(
                path,
                where,
                f"expected {first.num_joints} joints ({first.name}) like the rest of the input, got {count}",
            )
        return first
    skeleton = skeleton_for_joint_count(count)
    if skeleton is None:
        raise error(path, where, f"unsupported joint count {count} (expected {joint_count_names()})")
    return skeleton


def flat_keypoints(
    value: Any, first: Skeleton | None, path: str, where: str
) -> tuple[Skeleton, list[tuple[float, float, float]]]:
    """Flat ``[x, y, c] * K`` triplets of a detector, with the skeleton inferred from K."""
    values = as_list(value, path, where)
    if len(values) % 3:
        raise error(path, where, f"expected x, y, c triplets (a multiple of 3 numbers), got {len(values)}")
    skeleton = counted_skeleton(len(values) // 3, first, path, where)
    triplets = flat_triplets(values, skeleton.num_joints, path, where)
    points = [(x, y, detector_confidence(c, path, f"{where}[{3 * j + 2}]")) for j, (x, y, c) in enumerate(triplets)]
    return skeleton, points


def joints(
    points: list[tuple[float, float, float]], skeleton: Skeleton, path: str, where: str
) -> tuple[np.ndarray, np.ndarray]:
    """(x, y, confidence) per joint -> xy (J, 2) with NaN for missing, confidence (J,).

    A joint with confidence 0 is missing whatever its coordinates (COCO stores placeholders such
    as (-45, -45), OpenPose 0, 0, 0); any other joint must have finite coordinates.
    """
    xy = np.full((skeleton.num_joints, 2), np.nan, dtype=np.float64)
    conf = np.zeros(skeleton.num_joints, dtype=np.float64)
    for j, (x, y, c) in enumerate(points):
        if c <= 0.0:
            continue
        if not (math.isfinite(x) and math.isfinite(y)):
            raise error(
                path, where,
                f"joint {j} ({skeleton.joints[j]}) is not marked missing but has coordinates ({x:g}, {y:g})",
            )  # fmt: skip
        xy[j] = (x, y)
        conf[j] = c
    return xy, conf


def build(rows: list[Row], skeleton: Skeleton, path: str, fmt: str) -> Keypoints2D:
    """Stack instance rows into a `Keypoints2D`; zero rows is an error."""
    if not rows:
        raise error(path, "", "no instances found")
    frames = [r.frame for r in rows]
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
        frame_indices=None if all(f is None for f in frames) else frames,
    )


_DIGITS = re.compile(r"(\d+)")
_TRAILING_NUMBER = re.compile(r"(\d+)\D*$")


def natural_key(text: str) -> tuple[tuple[int, int | str], ...]:
    """Sort key that orders "f2" before "f10" (digit runs compare as numbers)."""
    return tuple((0, int(part)) if part.isdigit() else (1, part) for part in _DIGITS.split(text) if part)


def trailing_number(text: str) -> int | None:
    """The last run of digits in `text` ("clip_000000000012" -> 12, "12.jpg" -> 12), or None."""
    match = _TRAILING_NUMBER.search(text)
    return int(match.group(1)) if match else None
