"""Checks shared by the 2D readers: each turns a bad JSON value into an `InputFormatError`.

Every message starts with the file and names the field as a JSON path,
``kp.json: annotations[3].keypoints: expected 51 numbers (17 joints x 3), got 50``, so a user
can find the fault without a traceback. Readers stack their instances with `build`.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...data.keypoints import Keypoints2D
from ...data.skeleton import (
    SKELETONS,
    JointNameMatch,
    Skeleton,
    SkeletonSource,
    body25_variant,
    joint_count_names,
    match_joint_names,
    skeleton_for_joint_count,
    skeleton_option_hint,
)
from ...errors import InputFormatError
from .jsondoc import JsonArray

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
    """`InputFormatError` "<path>: <where>: <message>" (where = a JSON path, "" for the top level),
    on one line: file names and JSON keys with newlines or escape sequences are shown escaped."""
    return InputFormatError(f"{path}: {where}: {message}" if where else f"{path}: {message}")  # one line: ZedoError


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
    if isinstance(value, list | JsonArray):
        return "a list"
    if isinstance(value, dict):
        return "an object"
    return type(value).__name__


def as_dict(value: Any, path: str, where: str) -> dict[str, Any]:
    if not isinstance(value, dict):
        raise error(path, where, f"expected an object, got {kind(value)}")
    return value


def is_list(value: Any) -> bool:
    """A JSON array: a list, or an array of a document decoded as it is read (`jsondoc`)."""
    return isinstance(value, list | JsonArray)


def as_list(value: Any, path: str, where: str) -> Sequence[Any]:
    if not is_list(value):
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
    if value < 0:  # a huge one cannot even be printed (Python's 4300-digit limit)
        shown = str(value) if value > -(10**18) else "a negative integer of over 18 digits"
        raise error(path, where, f"expected a frame number >= 0, got {shown}")
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


def _found_numbers(values: Sequence[Any]) -> str:
    """What a keypoint list that should be flat numbers holds, for messages."""
    if values and isinstance(values[0], list):
        sizes = sorted({len(v) for v in values if isinstance(v, list)})
        per = "/".join(str(n) for n in sizes[:3])
        return f"a list of {len(values)} nested lists of {per} values ({len(values)} points as [x, y, ...])"
    return f"{len(values)} numbers"


def flat_triplets(value: Any, num_joints: int, path: str, where: str) -> list[tuple[float, float, float]]:
    """``[x1, y1, c1, ...]`` of exactly `num_joints` joints as (x, y, third value) triplets."""
    values = as_list(value, path, where)
    if len(values) != 3 * num_joints or (values and isinstance(values[0], list)):
        found = _found_numbers(values)
        expected = f"a flat list of {3 * num_joints} numbers ({num_joints} joints x 3)"
        raise error(path, where, f"expected {expected}, got {found}")
    numbers = [number(v, path, f"{where}[{k}]") for k, v in enumerate(values)]
    return [(numbers[k], numbers[k + 1], numbers[k + 2]) for k in range(0, len(numbers), 3)]


def counted_skeleton(
    count: int, first: Skeleton | None, path: str, where: str, forced: Skeleton | None = None
) -> Skeleton:
    """The skeleton of an instance with `count` unnamed joints (FORMATS.md 3.7), or `forced`
    (``--skeleton``), whose joint count it must have.

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
    if forced is not None:
        if count != forced.num_joints:
            raise error(path, where, f"expected {forced.num_joints} joints for --skeleton {forced.name}, got {count}")
        return forced
    skeleton = skeleton_for_joint_count(count)
    if skeleton is None:
        raise error(path, where, f"unsupported joint count {count} (read by count: {joint_count_names()}; "
                                 f"{skeleton_option_hint(count)})")  # fmt: skip
    return skeleton


def _xy_pairs(length: int, expected: Skeleton | None) -> bool:
    """Whether `length` numbers are x, y pairs of the expected (or a supported) joint count rather
    than x, y, c triplets (18 pairs = 36 numbers would otherwise read as "12 joints")."""
    if length % 2:
        return False
    if expected is not None:
        return length == 2 * expected.num_joints != 3 * expected.num_joints
    triplets = skeleton_for_joint_count(length // 3) if length % 3 == 0 else None
    return triplets is None and skeleton_for_joint_count(length // 2) is not None


def flat_keypoints(
    value: Any, first: Skeleton | None, path: str, where: str, forced: Skeleton | None = None
) -> tuple[Skeleton, list[tuple[float, float, float]]]:
    """Flat ``[x, y, c] * K`` triplets of a detector, with the skeleton inferred from K (or `forced`)."""
    values = as_list(value, path, where)
    if values and isinstance(values[0], list):
        raise error(path, where, f"expected a flat list [x1, y1, c1, x2, ...], got {_found_numbers(values)}")
    if _xy_pairs(len(values), first or forced):
        raise error(path, where, f"got {len(values)} numbers: {len(values) // 2} x, y pairs without confidences? "
                                 "expected x, y, c triplets")  # fmt: skip
    if len(values) % 3:
        raise error(path, where, f"expected x, y, c triplets (a multiple of 3 numbers), got {len(values)} numbers")
    count = len(values) // 3
    skeleton = counted_skeleton(count, first, path, where, forced)
    triplets = flat_triplets(values, skeleton.num_joints, path, where)
    points = [(x, y, detector_confidence(c, path, f"{where}[{3 * j + 2}]")) for j, (x, y, c) in enumerate(triplets)]
    return skeleton, points


def joint_names(value: Any, path: str, where: str) -> list[str]:
    """A JSON list of joint names."""
    names = as_list(value, path, where)
    for k, name in enumerate(names):
        if not isinstance(name, str):
            raise error(path, f"{where}[{k}]", f"expected a joint name, got {kind(name)}")
    return names


def _shown_names(names: list[str]) -> str:
    shown = ", ".join(repr(n[:30]) for n in names[:6])
    return shown + (f", ... ({len(names)} names)" if len(names) > 6 else "")


def named_skeleton(
    names: list[str], count: int | None, forced: Skeleton | None, path: str, where: str
) -> tuple[JointNameMatch, str]:
    """The joint set that joint `names` (in file order) are, and the reason to record.

    Names decide, in any order. `count` is the number of joints each instance holds, when
    known: a longer name list whose first `count` names are a known joint set names those
    joints (MMPose's Human-Art file lists 21 names for its 17-joint ``keypoints``). Unknown names
    are an error naming `where`, unless `forced` (``--skeleton``) says which joints these are,
    in file order. Known names that contradict `forced` are an error too.
    """
    match, reason = match_joint_names(names), f"{where} names"
    if match is None and count is not None and 0 < count < len(names):
        match = match_joint_names(names[:count])
        reason = f"the first {count} of the {len(names)} {where} names (each instance holds {count} joints)"
    if match is not None:
        if forced is not None and forced != match.skeleton:
            raise error(path, where, f"the joint names are {match.skeleton.name}'s, but --skeleton says {forced.name}")
        return match, reason + (", in the file's order" if not match.is_identity else "")
    if forced is not None:
        return JointNameMatch(forced, tuple(range(forced.num_joints))), f"--skeleton (unknown {where} names)"
    known = ", ".join(sorted(SKELETONS))
    raise error(
        path, where,
        f"unknown joint names ({_shown_names(names)}): not the joints of a known joint set ({known}); "
        "pass --skeleton NAME to read them in file order as NAME",
    )  # fmt: skip


def file_order(match: JointNameMatch) -> Skeleton:
    """The matched skeleton's joints in the file's order, to read rows (and name joints in
    messages) by file position; `build` puts them into the skeleton's order."""
    names = [""] * len(match.order)
    for joint, k in zip(match.skeleton.joints, match.order, strict=True):
        names[k] = joint
    return Skeleton(match.skeleton.name, tuple(names), (), ())


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


class RowBuffer:
    """Instances as a reader reads them, kept compact: coordinates and confidences in float64
    blocks that grow by doubling, the rest in one list per field. A `Row` is copied in by
    `append` and dropped, so a file of 100,000 instances holds no 100,000 objects with arrays."""

    def __init__(self) -> None:
        self._xy = np.empty((0, 0, 2), dtype=np.float64)  # (capacity, J, 2)
        self._conf = np.empty((0, 0), dtype=np.float64)  # (capacity, J)
        self.image_ids: list[ImageId] = []
        self.file_names: list[str | None] = []
        self.sizes: list[tuple[float, float]] = []
        self.scores: list[float | None] = []
        self.frames: list[int | None] = []

    def __len__(self) -> int:
        return len(self.image_ids)

    def append(self, row: Row) -> None:
        n = len(self)
        if n == len(self._xy):  # full (or empty): double, in the joint count of the first row
            joints, capacity = row.xy.shape[0] if n == 0 else self._xy.shape[1], max(64, 2 * n)
            xy, conf = np.empty((capacity, joints, 2)), np.empty((capacity, joints))
            if n:
                xy[:n], conf[:n] = self._xy[:n], self._conf[:n]
            self._xy, self._conf = xy, conf
        self._xy[n] = row.xy
        self._conf[n] = row.confidence
        self.image_ids.append(row.image_id)
        self.file_names.append(row.file_name)
        self.sizes.append(row.size)
        self.scores.append(row.score)
        self.frames.append(row.frame)

    def extend(self, rows: Iterable[Row]) -> None:
        for row in rows:
            self.append(row)

    @property
    def xy(self) -> np.ndarray:
        """(N, J, 2) pixels (a view)."""
        return self._xy[: len(self)]

    @property
    def confidence(self) -> np.ndarray:
        """(N, J) (a view)."""
        return self._conf[: len(self)]

    def reorder(self, order: Sequence[int] | np.ndarray) -> None:
        """Put the instances in `order` (a permutation of their indices)."""
        idx = np.asarray(order, dtype=np.int64)
        self._xy, self._conf = self.xy[idx], self.confidence[idx]
        for name in ("image_ids", "file_names", "sizes", "scores", "frames"):
            values = getattr(self, name)
            setattr(self, name, [values[i] for i in idx.tolist()])


def build(
    rows: RowBuffer | Sequence[Row],
    skeleton: Skeleton,
    path: str,
    fmt: str,
    *,
    reason: str,
    counted: bool = False,
    names: JointNameMatch | None = None,
) -> Keypoints2D:
    """Stack instance rows into a `Keypoints2D`; zero rows is an error.

    `reason` says why the rows are `skeleton` (recorded as the output's source skeleton).
    `counted`: the skeleton was inferred from the joint count alone, so 25 joints are checked
    for BODY_25 against BODY_25B (`body25_variant`); an undecidable file is an error. `names`:
    the rows are in a file's named joint order, put into `names.skeleton`'s order here.
    """
    if not isinstance(rows, RowBuffer):
        buffer = RowBuffer()
        buffer.extend(rows)
        rows = buffer
    if not len(rows):
        raise error(path, "", "no instances found")
    n = len(rows)
    xy, conf = rows.xy.copy(), rows.confidence.copy()
    if names is not None:
        xy, conf, skeleton = xy[:, list(names.order)], conf[:, list(names.order)], names.skeleton
    if counted and skeleton.name == "body25":
        skeleton, reason = _body25_or_25b(xy, conf, path, reason)
    return Keypoints2D(
        xy=xy,
        confidence=conf,
        skeleton=skeleton,
        image_ids=rows.image_ids,
        file_names=rows.file_names,
        image_sizes=np.array(rows.sizes, dtype=np.float64).reshape(n, 2),
        scores=rows.scores,
        path=path,
        format=fmt,
        frame_indices=None if all(f is None for f in rows.frames) else rows.frames,
        source=SkeletonSource(skeleton.name, reason),
    )


def _body25_or_25b(xy: np.ndarray, conf: np.ndarray, path: str, reason: str) -> tuple[Skeleton, str]:
    """BODY_25 or BODY_25B for 25 unnamed joints, from the geometry; never a silent guess."""
    variant, detail = body25_variant(xy, conf)
    if variant is None:
        raise error(
            path, "",
            f"25 joints per person, but the joint geometry does not tell OpenPose BODY_25 from BODY_25B "
            f"({detail}); pass --skeleton body25 or --skeleton body25b",
        )  # fmt: skip
    return SKELETONS[variant], f"{reason}; joint geometry says {variant} ({detail})"


_DIGITS = re.compile(r"([0-9]+)")  # ASCII digits: "²" or "٣" are text, never int()'s to read
_TRAILING_NUMBER = re.compile(r"([0-9]+)[^0-9]*$")
MAX_FRAME_DIGITS = 18  # a frame number fits numpy's int64 (ids of 1e30 or 5000 digits are not frames)


def natural_key(text: str) -> tuple[tuple[int, int | str, str], ...]:
    """Sort key that orders "f2" before "f10" (digit runs compare as numbers, of any length)."""
    return tuple((0, len(part.lstrip("0")), part.lstrip("0")) if part.isascii() and part.isdigit() else (1, 0, part)
                 for part in _DIGITS.split(text) if part)  # fmt: skip


def trailing_number(text: str) -> int | None:
    """The last run of digits in `text` ("clip_000000000012" -> 12, "12.jpg" -> 12), or None
    (also for a run too long to be a frame number)."""
    match = _TRAILING_NUMBER.search(text)
    if not match or len(match.group(1).lstrip("0")) > MAX_FRAME_DIGITS:
        return None
    return int(match.group(1))
