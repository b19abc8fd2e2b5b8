"""MMPose prediction JSON in its three layouts (FORMATS.md 3.5).

An instance is the same in all three (mmpose/structures/utils.py ``split_instances``)::

    {"keypoints": [[x, y], ...], "keypoint_scores": [s, ...], "bbox": [[x1, y1, x2, y2]], "bbox_score": s}

Keypoints are nested ``[x, y]`` pairs (3D lifter outputs, ``[x, y, z]``, are refused); a score
is a confidence clipped to [0, 1] (RTMPose's exceed 1), 0 = missing. ``bbox_score`` is the
instance's detection score; ``bbox`` is not used.

- ``mmpose-image`` (Inferencer, image input, ``pred_out_dir/<image stem>.json``): a list of
  instances. The image id is the file's stem; there is no frame index.
- ``mmpose-video`` (Inferencer, video input): ``[{"frame_id": 0, "instances": [...]}, ...]``.
  frame_id is 0-based and is both the image id and the frame index.
- ``mmpose-demo`` (demo scripts' ``--save-predictions``, ``results_<stem>.json``):
  ``{"meta_info": {...}, "instance_info": [{"frame_id": 1, "instances": [...]}, ...]}`` for a
  video, or ``instance_info`` as a flat instance list for an image. The demos count video frames
  from 1, so the frame index is frame_id - 1 (frame_id itself stays the image id); a file whose
  frame ids start at 0 is taken as 0-based. ``meta_info.keypoint_id2name`` (or ``dataset_name``)
  names the joints, in any order (unknown names are an error unless ``--skeleton``); without
  names the joint count does (17 -> coco17, 26 -> halpe26, ...), or ``--skeleton``.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

from ...data.keypoints import Keypoints2D
from ...data.skeleton import SKELETONS, JointNameMatch, Skeleton
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
    frame_number,
    is_list,
    joint_names,
    joints,
    kind,
    named_skeleton,
    number,
    optional_score,
    required,
)

# MMPose dataset names (configs/_base_/datasets/*.py) of the skeletons zedo knows.
_DATASET_SKELETONS = {"coco": "coco17", "h36m": "h36m17", "halpe26": "halpe26"}


def _instance_row(
    entry: Any, where: str, key: ImageId, frame: int | None, first: Skeleton | None, path: str,
    forced: Skeleton | None = None,
) -> tuple[Skeleton, Row]:  # fmt: skip
    """One instance -> its skeleton (`first`, or inferred from its joint count) and its row."""
    entry = as_dict(entry, path, where)
    where_kp, where_sc = f"{where}.keypoints", f"{where}.keypoint_scores"
    pairs = as_list(required(entry, "keypoints", path, where), path, where_kp)
    scores = as_list(required(entry, "keypoint_scores", path, where), path, where_sc)
    skeleton = counted_skeleton(len(pairs), first, path, where_kp, forced)
    if len(scores) != len(pairs):
        raise error(path, where_sc, f"expected {len(pairs)} scores (one per keypoint), got {len(scores)}")
    points = []
    for j, (pair, score) in enumerate(zip(pairs, scores, strict=True)):
        pair = as_list(pair, path, f"{where_kp}[{j}]")
        if len(pair) != 2:
            found = "3D keypoints; zedo reads 2D predictions" if len(pair) == 3 else f"{len(pair)} values"
            raise error(path, f"{where_kp}[{j}]", f"expected [x, y], got {found}")
        x, y = number(pair[0], path, f"{where_kp}[{j}][0]"), number(pair[1], path, f"{where_kp}[{j}][1]")
        points.append((x, y, detector_confidence(number(score, path, f"{where_sc}[{j}]"), path, f"{where_sc}[{j}]")))
    xy, conf = joints(points, skeleton, path, where_kp)
    return skeleton, Row(key, xy, conf, None, NAN_SIZE, optional_score(entry, path, where, "bbox_score"), frame)


def _instances(
    values: Any, where: str, key: ImageId, frame: int | None, first: Skeleton | None, path: str,
    forced: Skeleton | None = None, rows: RowBuffer | None = None,
) -> tuple[Skeleton | None, RowBuffer]:  # fmt: skip
    """The instances of one list, appended to `rows` (a new buffer when None)."""
    rows = RowBuffer() if rows is None else rows
    for i, entry in enumerate(as_list(values, path, where)):
        first, row = _instance_row(entry, f"{where}[{i}]", key, frame, first, path, forced)
        rows.append(row)
    return first, rows


def _frames(
    frames: Sequence[Any], where: str, offset: int, first: Skeleton | None, path: str, forced: Skeleton | None = None
) -> tuple[Skeleton | None, RowBuffer]:
    """``[{"frame_id", "instances"}, ...]``; the frame index is frame_id - `offset`."""
    rows = RowBuffer()
    for n, entry in enumerate(frames):
        at = f"{where}[{n}]" if where else f"[{n}]"
        entry = as_dict(entry, path, at)
        frame_id = frame_number(required(entry, "frame_id", path, at), path, f"{at}.frame_id")
        values = required(entry, "instances", path, at)
        first, _ = _instances(values, f"{at}.instances", frame_id, frame_id - offset, first, path, forced, rows)
    return first, rows


def _image_key(path: str, prefix: str = "") -> str:
    """The image stem an MMPose output file is named after."""
    stem = Path(path).stem
    return stem[len(prefix) :] if prefix and stem.startswith(prefix) and len(stem) > len(prefix) else stem


def _count_reason(skeleton: Skeleton | None, forced: Skeleton | None) -> str:
    return "--skeleton" if forced is not None else f"joint count {skeleton.num_joints if skeleton else 17}"


def read_mmpose_image(data: Any, path: str, skeleton: Skeleton | None = None) -> Keypoints2D:
    """Read a parsed MMPose Inferencer image output (a list of instances)."""
    found, rows = _instances(as_list(data, path, ""), "", _image_key(path), None, None, path, skeleton)
    return build(rows, found or SKELETONS["coco17"], path, "mmpose-image", reason=_count_reason(found, skeleton),
                 counted=skeleton is None)  # fmt: skip


def read_mmpose_video(data: Any, path: str, skeleton: Skeleton | None = None) -> Keypoints2D:
    """Read a parsed MMPose Inferencer video output (a list of frames, frame_id 0-based)."""
    found, rows = _frames(as_list(data, path, ""), "", 0, None, path, skeleton)
    return build(rows, found or SKELETONS["coco17"], path, "mmpose-video", reason=_count_reason(found, skeleton),
                 counted=skeleton is None)  # fmt: skip


def _id2name(value: Any, path: str, where: str) -> list[str]:
    """``keypoint_id2name`` ({"0": "nose", ...} once in JSON, or a list) as names in id order."""
    if isinstance(value, list):
        return joint_names(value, path, where)
    mapping = as_dict(value, path, where)
    items = []
    for k, name in mapping.items():
        if not (k.isascii() and k.isdigit() and len(k) < 6):
            raise error(path, f"{where}.{k[:20]}", "expected a joint id (a number) as key")
        if not isinstance(name, str):
            raise error(path, f"{where}[{k}]", f"expected a joint name, got {kind(name)}")
        items.append((int(k), name))
    items.sort()
    if [k for k, _ in items] != list(range(len(items))):
        raise error(path, where, f"expected joint ids 0..{len(items) - 1}")
    return [name for _, name in items]


def _meta_skeleton(doc: dict[str, Any], forced: Skeleton | None, path: str) -> tuple[JointNameMatch | None, str]:
    """The joints ``meta_info`` names (FORMATS.md 3.5) and why, or (None, "") to infer them from
    the joint count (or ``--skeleton``). ``keypoint_id2name`` decides, in any order; unknown
    names are an error unless `forced`; else ``dataset_name`` (coco, h36m, halpe26)."""
    if doc.get("meta_info") is None:
        return None, ""
    meta = as_dict(doc["meta_info"], path, "meta_info")
    if meta.get("keypoint_id2name") is not None:
        where = "meta_info.keypoint_id2name"
        names = _id2name(meta["keypoint_id2name"], path, where)
        if names:
            return named_skeleton(names, None, forced, path, where)
    name = meta.get("dataset_name")
    if forced is not None or name is None:
        return None, ""
    if isinstance(name, str) and name in _DATASET_SKELETONS:
        skeleton = SKELETONS[_DATASET_SKELETONS[name]]
        return JointNameMatch(skeleton, tuple(range(skeleton.num_joints))), f"meta_info.dataset_name {name!r}"
    # A data set named but not known (crowdpose, posetrack18, ...): its joints are not guessed.
    shown = repr(name[:40]) if isinstance(name, str) else kind(name)
    raise error(
        path, "meta_info.dataset_name",
        f"{shown} is not a joint set zedo knows ({', '.join(sorted(_DATASET_SKELETONS))}) and meta_info has no "
        "keypoint_id2name; pass --skeleton NAME to read the joints in file order as NAME",
    )  # fmt: skip


def read_mmpose_demo(data: Any, path: str, skeleton: Skeleton | None = None) -> Keypoints2D:
    """Read a parsed MMPose demo ``--save-predictions`` file (video frames or one image's instances)."""
    doc = as_dict(data, path, "")
    meta, reason = _meta_skeleton(doc, skeleton, path)
    first = file_order(meta) if meta is not None else None
    info = as_list(required(doc, "instance_info", path, ""), path, "instance_info")
    if info and isinstance(info[0], dict) and "frame_id" in info[0]:
        ids = [e["frame_id"] for e in info if isinstance(e, dict) and isinstance(e.get("frame_id"), int | float)]
        offset = 0 if any(i == 0 for i in ids) else 1  # the demos count frames from 1
        found, rows = _frames(info, "instance_info", offset, first, path, skeleton)
    else:
        found, rows = _instances(info, "instance_info", _image_key(path, "results_"), None, first, path, skeleton)
    if meta is not None:
        return build(rows, meta.skeleton, path, "mmpose-demo", reason=reason, names=meta)
    return build(rows, found or SKELETONS["coco17"], path, "mmpose-demo", reason=_count_reason(found, skeleton),
                 counted=skeleton is None)  # fmt: skip


def mmpose_layout(data: Any) -> str | None:
    """Which MMPose layout `data` is ("mmpose-image", "-video", "-demo"), or None (FORMATS.md 3.7)."""
    if isinstance(data, dict):
        return "mmpose-demo" if "instance_info" in data else None
    if not (is_list(data) and data and isinstance(data[0], dict)):
        return None
    first = data[0]
    if "frame_id" in first and "instances" in first:
        return "mmpose-video"
    keypoints = first.get("keypoints")
    nested = isinstance(keypoints, list) and bool(keypoints) and isinstance(keypoints[0], list)
    return "mmpose-image" if nested and "keypoint_scores" in first else None


def read_mmpose(data: Any, path: str, skeleton: Skeleton | None = None) -> Keypoints2D:
    """Read any of the three MMPose layouts, told apart by `mmpose_layout`."""
    layout = mmpose_layout(data)
    if layout is None and is_list(data) and all(isinstance(entry, dict) for entry in data[:1]):
        # Told to read MMPose: the layout's own checks give a better message than "not MMPose".
        layout = "mmpose-video" if data and "frame_id" in data[0] else "mmpose-image"
    if layout is None:
        raise error(
            path, "",
            "not an MMPose prediction file (expected a list of instances with keypoints and keypoint_scores, "
            "a list of frames with frame_id and instances, or an object with instance_info)",
        )  # fmt: skip
    return {"mmpose-image": read_mmpose_image, "mmpose-video": read_mmpose_video, "mmpose-demo": read_mmpose_demo}[
        layout
    ](data, path, skeleton)
