"""COCO keypoint annotation files and COCO keypoint results lists (FORMATS.md 3.1, 3.2).

- ``coco-annotations``: ``{images, annotations, categories}``, e.g. SyRIP ground truth.
  Visibility v = 0 is a missing joint, v = 1 (labelled but occluded) gets confidence 0.5, v = 2
  gets 1.0; a float v in (0, 1) is taken as a confidence. An image's ``original_file_name``, when
  present, is its file name: SyRIP's real700 file renumbers its images test0.. and keeps the
  true name there, and the true name is what joins to other files.
- ``coco-results``: ``[{image_id, keypoints: [x, y, c] * 17, score}]`` from a detector (FiDIP,
  HRNet). c is a confidence clipped to [0, 1]; c == 0 is a missing joint.
"""

from __future__ import annotations

import math
from array import array
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ...data.keypoints import Keypoints2D
from ...data.skeleton import SKELETONS, JointNameMatch, Skeleton, skeleton_for_joint_count, skeleton_option_hint
from .validate import (
    NAN_SIZE,
    ImageId,
    Row,
    RowBuffer,
    as_dict,
    as_list,
    build,
    counted_skeleton,
    detector_confidence,
    error,
    file_order,
    flat_triplets,
    image_id,
    joint_names,
    joints,
    named_skeleton,
    optional_score,
    optional_str,
    pixels,
    required,
)

OCCLUDED_CONFIDENCE = 0.5  # confidence of a COCO v = 1 joint (labelled but not visible)


@dataclass(frozen=True, slots=True)  # slots: one per image of the file, 100,000 in a large one
class Image:
    """One entry of a COCO ``images`` list."""

    position: int
    size: tuple[float, float]  # width, height in pixels; NaN = unknown
    file_name: str | None  # original_file_name when given, else file_name
    names: tuple[str, ...]  # every name the entry goes by, for joining on a string image id


def parse_images(doc: dict[str, Any], path: str) -> dict[ImageId, Image]:
    """COCO ``images[]`` by id. Width/height are optional (unknown = NaN) but must be valid if given."""
    images = as_list(required(doc, "images", path, ""), path, "images")
    index: dict[ImageId, Image] = {}
    for i, entry in enumerate(images):
        where = f"images[{i}]"
        entry = as_dict(entry, path, where)
        key = image_id(required(entry, "id", path, where), path, f"{where}.id")
        if key in index:
            raise error(path, f"{where}.id", f"duplicate image id {key!r} (also images[{index[key].position}])")
        width, height = (
            math.nan if entry.get(k) is None else pixels(entry[k], path, f"{where}.{k}") for k in ("width", "height")
        )
        size = NAN_SIZE if math.isnan(width) or math.isnan(height) else (width, height)
        original = optional_str(entry, "original_file_name", path, where)
        file_name = optional_str(entry, "file_name", path, where)
        names = tuple(n for n in (original, file_name) if n is not None)
        index[key] = Image(i, size, names[0] if names else None, names)
    return index


# --- annotations ---------------------------------------------------------------------------


def _annotation_count(annotations: Sequence[Any]) -> tuple[int, int | None]:
    """(position, joint count) of the first annotation with a flat keypoint list; (0, None) if none."""
    for i, entry in enumerate(annotations):
        keypoints = entry.get("keypoints") if isinstance(entry, dict) else None
        flat = isinstance(keypoints, list) and not (keypoints and isinstance(keypoints[0], list))
        if flat and len(keypoints) % 3 == 0:
            return i, len(keypoints) // 3
    return 0, None


def _categories_skeleton(
    doc: dict[str, Any], annotations: Sequence[Any], forced: Skeleton | None, path: str
) -> tuple[JointNameMatch, str, bool]:
    """The joint set of the annotations: from ``categories[0].keypoints`` names when given, else
    from the annotations' joint count (or ``--skeleton``). Returns (match, reason, counted)."""
    categories = as_list(required(doc, "categories", path, ""), path, "categories")
    first = as_dict(categories[0], path, "categories[0]") if categories else {}
    position, count = _annotation_count(annotations)
    names = joint_names(first["keypoints"], path, "categories[0].keypoints") if "keypoints" in first else []
    if names:
        match, reason = named_skeleton(names, count, forced, path, "categories[0].keypoints")
        return match, reason, False
    where = f"annotations[{position}].keypoints"
    if count is None:  # no usable annotation: its own checks report it (or there is none)
        skeleton = forced or SKELETONS["coco17"]
    else:
        skeleton = counted_skeleton(count, None, path, where, forced)
    why = "--skeleton" if forced is not None else f"joint count {count if count is not None else 17}"
    reason = f"{why} (no categories[0].keypoints names)"
    return JointNameMatch(skeleton, tuple(range(skeleton.num_joints))), reason, forced is None


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
    raise error(path, where, f"visibility {v:g} is neither 0, 1, 2 nor a confidence in (0, 1]")


def _parse_annotation(
    entry: Any, i: int, images: Mapping[ImageId, Image], skeleton: Skeleton, path: str
) -> tuple[int, Row]:
    """One annotation -> (its image's position, the sort key with the annotation's own, row)."""
    where = f"annotations[{i}]"
    entry = as_dict(entry, path, where)
    key = image_id(required(entry, "image_id", path, where), path, f"{where}.image_id")
    image = images.get(key)
    if image is None:
        raise error(path, f"{where}.image_id", f"image id {key!r} is not in images")
    where_kp = f"{where}.keypoints"
    triplets = flat_triplets(required(entry, "keypoints", path, where), skeleton.num_joints, path, where_kp)
    points = [
        (x, y, _visibility_confidence(v, path, f"{where_kp}[{3 * j + 2}]")) for j, (x, y, v) in enumerate(triplets)
    ]
    xy, conf = joints(points, skeleton, path, where_kp)
    score = optional_score(entry, path, where)
    return image.position, Row(key, xy, conf, image.file_name, image.size, score)


def read_coco_annotations(data: Any, path: str, skeleton: Skeleton | None = None) -> Keypoints2D:
    """Read a parsed COCO keypoint annotation file (FORMATS.md 3.1).

    Instances are ordered by their image's position in ``images``, then by annotation position.
    Sizes (pixels) and file names come from ``images[]``; the joints from the names of
    ``categories[0].keypoints`` in any order (`named_skeleton`), else from the joint count;
    `skeleton` is ``--skeleton``.
    """
    doc = as_dict(data, path, "")
    images = parse_images(doc, path)
    annotations = as_list(required(doc, "annotations", path, ""), path, "annotations")
    match, reason, counted = _categories_skeleton(doc, annotations, skeleton, path)
    in_file = file_order(match)
    rows, positions = RowBuffer(), array("q")
    for i, entry in enumerate(annotations):
        position, row = _parse_annotation(entry, i, images, in_file, path)
        positions.append(position)
        rows.append(row)
    rows.reorder(np.argsort(np.asarray(positions, dtype=np.int64), kind="stable"))  # by image, then annotation
    return build(rows, match.skeleton, path, "coco-annotations", reason=reason, counted=counted, names=match)


# --- results -------------------------------------------------------------------------------


def _parse_result(entry: Any, i: int, sizes: Mapping[ImageId, tuple[float, float]], skeleton: Skeleton,
                  path: str) -> Row:  # fmt: skip
    where = f"[{i}]"
    entry = as_dict(entry, path, where)
    key = image_id(required(entry, "image_id", path, where), path, f"{where}.image_id")
    where_kp = f"{where}.keypoints"
    values = as_list(required(entry, "keypoints", path, where), path, where_kp)
    if len(values) != 3 * skeleton.num_joints and len(values) % 3 == 0 and not (values and isinstance(values[0], list)):
        known = skeleton_for_joint_count(len(values) // 3)
        hint = "use --format alphapose" if known is not None else skeleton_option_hint(len(values) // 3)
        raise error(
            path, where_kp,
            f"unsupported joint count {len(values) // 3} ({len(values)} numbers; COCO results hold "
            f"{skeleton.num_joints} joints, {skeleton.name}; for other detector outputs {hint})",
        )  # fmt: skip
    triplets = flat_triplets(values, skeleton.num_joints, path, where_kp)
    points = [(x, y, detector_confidence(c, path, f"{where_kp}[{3 * j + 2}]")) for j, (x, y, c) in enumerate(triplets)]
    xy, conf = joints(points, skeleton, path, where_kp)
    size = tuple(float(s) for s in sizes.get(key, NAN_SIZE))
    return Row(key, xy, conf, None, (size[0], size[1]), optional_score(entry, path, where))


def read_coco_results(
    data: Any,
    path: str,
    skeleton: Skeleton | None = None,
    image_sizes: Mapping[ImageId, tuple[float, float]] | None = None,
) -> Keypoints2D:
    """Read a parsed COCO keypoint results list (FORMATS.md 3.2), every instance in file order.

    The joints are COCO-17 (results carry no names), or `skeleton` (``--skeleton``).
    `image_sizes` maps image_id -> (width, height) in pixels; instances without one get NaN.
    """
    entries = as_list(data, path, "")
    used = skeleton or SKELETONS["coco17"]
    rows = RowBuffer()
    for i, entry in enumerate(entries):
        rows.append(_parse_result(entry, i, image_sizes or {}, used, path))
    reason = "--skeleton" if skeleton is not None else "COCO results: 17 unnamed joints are COCO-17"
    return build(rows, used, path, "coco-results", reason=reason)
