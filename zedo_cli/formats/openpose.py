"""OpenPose per-frame JSON, one file or a directory of them (FORMATS.md 3.3), ``openpose``.

One file per frame, ``<name>_<12-digit frame>_keypoints.json``::

    {"version": 1.3, "people": [{"person_id": [-1], "pose_keypoints_2d": [x0, y0, c0, x1, y1, c1, ...], ...}]}

The joint count gives the skeleton: 25 BODY_25, 18 OpenPose's COCO-18, and 26 / 17 for the
Halpe / COCO files that AlphaPose's ``--format open`` and Pose2Sim's converters write. It must
be the same in every file. c == 0 (OpenPose writes 0, 0, 0) is a missing joint; c is clipped to
[0, 1]. OpenPose files carry no image size (use ``--image-size``) and no detection score.

Each person is one instance; its image id is the file name without ``_keypoints.json`` and its
frame index the trailing number of that name (0 for a single file without one). A directory is
read in natural frame order (by that number, as Pose2Sim sorts them); where some name lacks a
number, the frame index is the file's position in natural name order.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ..data.keypoints import Keypoints2D
from ..data.skeleton import SKELETONS, Skeleton
from .source import load_json
from .validate import (
    NAN_SIZE,
    Row,
    as_dict,
    as_list,
    build,
    error,
    flat_keypoints,
    joints,
    natural_key,
    required,
    trailing_number,
)

FORMAT = "openpose"
_SUFFIX = "_keypoints"


def _people_rows(
    data: Any, path: str, key: str, frame: int, first: Skeleton | None
) -> tuple[Skeleton | None, list[Row]]:
    """The rows of one parsed frame file; `first` is the skeleton of the earlier frames."""
    doc = as_dict(data, path, "")
    people = as_list(required(doc, "people", path, ""), path, "people")
    rows = []
    for i, person in enumerate(people):
        where = f"people[{i}]"
        person = as_dict(person, path, where)
        where_kp = f"{where}.pose_keypoints_2d"
        first, points = flat_keypoints(required(person, "pose_keypoints_2d", path, where), first, path, where_kp)
        xy, conf = joints(points, first, path, where_kp)
        rows.append(Row(key, xy, conf, None, NAN_SIZE, None, frame))
    return first, rows


def _frame_name(path: str) -> str:
    """The frame's name: "clip_000000000012_keypoints.json" -> "clip_000000000012"."""
    stem = Path(path).stem
    return stem[: -len(_SUFFIX)] if stem.endswith(_SUFFIX) else stem


def read_openpose(data: Any, path: str) -> Keypoints2D:
    """Read one parsed OpenPose frame file (every person in it)."""
    key = _frame_name(path)
    skeleton, rows = _people_rows(data, path, key, trailing_number(key) or 0, None)
    return build(rows, skeleton or SKELETONS["body25"], path, FORMAT)


def frame_files(directory: Path) -> list[tuple[Path, int]]:
    """The frame files of an OpenPose output directory with their frame indices, in frame order.

    ``*_keypoints.json`` files, or every ``*.json`` file when there are none of those.
    """
    files = [p for p in directory.glob(f"*{_SUFFIX}.json") if p.is_file()]
    files = files or [p for p in directory.glob("*.json") if p.is_file()]
    if not files:
        raise error(str(directory), "", f"is a directory without OpenPose *{_SUFFIX}.json files")
    files.sort(key=lambda p: natural_key(p.name))
    numbered = [(p, n) for p in files if (n := trailing_number(_frame_name(p.name))) is not None]
    if len(numbered) < len(files):
        return [(p, k) for k, p in enumerate(files)]
    by_frame: dict[int, Path] = {}
    for p, n in numbered:
        if n in by_frame:
            raise error(str(p), "", f"frame {n} also comes from {by_frame[n].name} (two videos in one directory?)")
        by_frame[n] = p
    return sorted(((p, n) for n, p in by_frame.items()), key=lambda item: item[1])


def read_openpose_dir(directory: str | Path) -> Keypoints2D:
    """Read a directory of OpenPose frame files (`frame_files`), every person of every frame.

    Errors in one file name that file; the joint count must agree across files.
    """
    directory = Path(directory)
    skeleton: Skeleton | None = None
    rows: list[Row] = []
    for file, frame in frame_files(directory):
        name = str(file)
        skeleton, frame_rows = _people_rows(load_json(name), name, _frame_name(name), frame, skeleton)
        rows.extend(frame_rows)
    return build(rows, skeleton or SKELETONS["body25"], str(directory), FORMAT)
