"""zedo's own 2D JSON layout, ``zedo-2d``::

    {"schema": "zedo.keypoints2d/1",        # optional; when present exactly this string
     "skeleton": "h36m17",                  # a zedo skeleton name (h36m17, coco17, syrip12, body25, ...)
     "image_size": [W, H],                  # optional default for every instance, pixels
     "instances": [
       {"image_id": 0,                      # int or str
        "file_name": "frame0000.png",       # optional
        "image_size": [W, H],               # optional, overrides the default
        "score": 0.93,                      # optional detection score
        "keypoints": [[x, y], [x, y, c], null, ...]}]}   # one entry per skeleton joint

``[x, y]`` has confidence 1, ``[x, y, c]`` a confidence c in [0, 1]; ``null`` or c == 0 is a
missing joint. With ``"skeleton": "h36m17"`` this is the "H36M-style 2D JSON". The point
syntax is shared with zedo JSON Lines (`jsonl.py`).
"""

from __future__ import annotations

import math
from typing import Any

from ...data.keypoints import Keypoints2D
from ...data.skeleton import SKELETONS, Skeleton
from .validate import (
    NAN_SIZE,
    Row,
    RowBuffer,
    as_dict,
    as_list,
    build,
    confidence,
    error,
    image_id,
    joints,
    kind,
    number,
    optional_score,
    optional_str,
    required,
    size_pair,
)

ZEDO_2D_SCHEMA = "zedo.keypoints2d/1"


def skeleton_name(value: Any, path: str, where: str) -> Skeleton:
    """A zedo skeleton named by a JSON string."""
    if not isinstance(value, str):
        raise error(path, where, f"expected a skeleton name, got {kind(value)}")
    if value not in SKELETONS:
        known = ", ".join(sorted(SKELETONS))
        raise error(path, where, f"unknown skeleton {value[:40]!r}; expected one of {known}")
    return SKELETONS[value]


def zedo_point(value: Any, path: str, where: str) -> tuple[float, float, float]:
    """``null`` | ``[x, y]`` | ``[x, y, c]`` -> (x, y, confidence); null is missing."""
    if value is None:
        return math.nan, math.nan, 0.0
    items = as_list(value, path, where)
    if len(items) not in (2, 3):
        raise error(path, where, f"expected [x, y] or [x, y, c], got {len(items)} values")
    x, y = number(items[0], path, f"{where}[0]"), number(items[1], path, f"{where}[1]")
    conf = confidence(items[2], path, f"{where}[2]") if len(items) == 3 else 1.0
    return x, y, conf


def _parse_instance(entry: Any, i: int, skeleton: Skeleton, default_size: tuple[float, float], path: str) -> Row:
    where = f"instances[{i}]"
    entry = as_dict(entry, path, where)
    key = image_id(required(entry, "image_id", path, where), path, f"{where}.image_id")
    where_kp = f"{where}.keypoints"
    points = as_list(required(entry, "keypoints", path, where), path, where_kp)
    if len(points) != skeleton.num_joints:
        raise error(
            path, where_kp, f"expected {skeleton.num_joints} joints for skeleton {skeleton.name}, got {len(points)}"
        )
    xy, conf = joints([zedo_point(p, path, f"{where_kp}[{j}]") for j, p in enumerate(points)], skeleton, path, where_kp)
    size = size_pair(entry["image_size"], path, f"{where}.image_size") if "image_size" in entry else default_size
    file_name = optional_str(entry, "file_name", path, where)
    return Row(key, xy, conf, file_name, size, optional_score(entry, path, where))


def read_zedo_2d(data: Any, path: str, skeleton: Skeleton | None = None) -> Keypoints2D:
    """Read a parsed zedo 2D document (layout in the module docstring), instances in file order.
    Its ``skeleton`` field names the joints; `skeleton` (``--skeleton``) must agree with it."""
    doc = as_dict(data, path, "")
    if "schema" in doc and doc["schema"] != ZEDO_2D_SCHEMA:
        found = repr(doc["schema"][:40]) if isinstance(doc["schema"], str) else kind(doc["schema"])
        raise error(path, "schema", f"expected {ZEDO_2D_SCHEMA!r}, got {found}")
    named = skeleton_name(required(doc, "skeleton", path, ""), path, "skeleton")
    if skeleton is not None and named != skeleton:
        raise error(path, "skeleton", f"the file says {named.name}, but --skeleton says {skeleton.name}")
    skeleton = named
    default_size = size_pair(doc["image_size"], path, "image_size") if "image_size" in doc else NAN_SIZE
    instances = as_list(required(doc, "instances", path, ""), path, "instances")
    rows = RowBuffer()
    for i, entry in enumerate(instances):
        rows.append(_parse_instance(entry, i, skeleton, default_size, path))
    return build(rows, skeleton, path, "zedo-2d", reason="skeleton field")
