"""AlphaPose results JSON (FORMATS.md 3.2, 3.6), ``alphapose``.

A COCO-results-like list, one entry per detected person, all images in one list::

    [{"image_id": "frame_000012.jpg", "category_id": 1, "keypoints": [x, y, c] * K,
      "score": 2.87, "box": [x, y, w, h], "idx": [3]}, ...]

K = 17 is COCO-17 and K = 26 Halpe-26 (the 136- and 133-joint whole-body outputs are not read).
c is clipped to [0, 1] (AlphaPose's exceed 1), 0 = missing; ``score`` (up to ~6 for COCO
models) is kept as the detection score; ``box`` and ``idx`` are not used.

The image id is kept as given; a string id is also the file name. Instances are ordered by
image in natural order of the id ("frame_2.jpg" before "frame_10.jpg"), and within an image in
file order; the frame index is the trailing number of the id ("12.jpg" -> 12, as Pose2Sim's
converter reads it), or the id itself when it is an integer. Where two different image ids
would get the same number (timestamps such as "1650000000.5.jpg" and "1650000001.5.jpg"), or
some id has none, every image's frame index is its position in that natural order instead:
two images are never merged into one frame.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ...data.keypoints import Keypoints2D
from ...data.skeleton import SKELETONS, Skeleton, skeleton_option_hint
from .validate import (
    NAN_SIZE,
    Row,
    RowBuffer,
    as_dict,
    as_list,
    build,
    error,
    flat_keypoints,
    image_id,
    joints,
    natural_key,
    optional_score,
    required,
    trailing_number,
)

_COUNTS = {17: "coco17", 26: "halpe26"}


def _frame(key: int | str) -> int | None:
    if isinstance(key, int):
        return key if key >= 0 else None
    return trailing_number(Path(key).stem)


def _parse_entry(
    entry: Any, i: int, first: Skeleton | None, path: str, forced: Skeleton | None = None
) -> tuple[Skeleton, Row]:
    where = f"[{i}]"
    entry = as_dict(entry, path, where)
    key = image_id(required(entry, "image_id", path, where), path, f"{where}.image_id")
    where_kp = f"{where}.keypoints"
    values = required(entry, "keypoints", path, where)
    count = len(values) // 3 if isinstance(values, list) and len(values) % 3 == 0 else None
    if first is None and forced is None and count is not None and count not in _COUNTS:
        pairs = f" ({len(values)} numbers: {len(values) // 2} x, y pairs?)" if len(values) // 2 in _COUNTS else ""
        raise error(path, where_kp, f"unsupported joint count {count}{pairs} (AlphaPose: 17 COCO or 26 Halpe joints; "
                                    f"{skeleton_option_hint(count)})")  # fmt: skip
    skeleton, points = flat_keypoints(values, first, path, where_kp, forced)
    xy, conf = joints(points, skeleton, path, where_kp)
    file_name = key if isinstance(key, str) else None
    return skeleton, Row(key, xy, conf, file_name, NAN_SIZE, optional_score(entry, path, where), _frame(key))


def _distinct_frames(rows: RowBuffer) -> RowBuffer:
    """`rows` (in image order) with frame indices that never merge two images: the ids' own
    numbers when distinct images have distinct numbers, else each image's position."""
    keys = [repr(image_id) for image_id in rows.image_ids]
    images = list(dict.fromkeys(keys))
    number = dict(zip(keys, rows.frames, strict=True))
    frames = [number[key] for key in images]
    if all(f is not None for f in frames) and len(set(frames)) == len(frames):
        return rows
    position = {key: k for k, key in enumerate(images)}
    rows.frames = [position[key] for key in keys]
    return rows


def read_alphapose(data: Any, path: str, skeleton: Skeleton | None = None) -> Keypoints2D:
    """Read a parsed AlphaPose results list, every instance, in natural image order."""
    found: Skeleton | None = None
    rows = RowBuffer()
    for i, entry in enumerate(as_list(data, path, "")):
        found, row = _parse_entry(entry, i, found, path, skeleton)
        rows.append(row)
    ids = rows.image_ids
    rows.reorder(sorted(range(len(ids)), key=lambda k: natural_key(str(ids[k]))))  # stable: persons keep file order
    reason = "--skeleton" if skeleton is not None else f"joint count {found.num_joints if found else 17}"
    return build(_distinct_frames(rows), found or SKELETONS["coco17"], path, "alphapose", reason=reason)


def is_alphapose_entry(entry: dict[str, Any]) -> bool:
    """AlphaPose rather than plain COCO results: a string image_id, or ``idx``/``box`` (FORMATS.md 3.7)."""
    return isinstance(entry.get("image_id"), str) or "idx" in entry or "box" in entry
