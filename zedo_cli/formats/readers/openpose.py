"""OpenPose per-frame JSON, one file or a directory of them (FORMATS.md 3.3), ``openpose``.

One file per frame, ``<name>_<12-digit frame>_keypoints.json``::

    {"version": 1.3, "people": [{"person_id": [-1], "pose_keypoints_2d": [x0, y0, c0, x1, y1, c1, ...], ...}]}

The joint count gives the skeleton: 25 BODY_25, 18 OpenPose's COCO-18, and 26 / 17 for the
Halpe / COCO files that AlphaPose's ``--format open`` and Pose2Sim's converters write. It must
be the same in every file. c == 0 (OpenPose writes 0, 0, 0) is a missing joint; c is clipped to
[0, 1]. OpenPose files carry no image size (use ``--image-size``) and no detection score.

The joint count decides the skeleton, except that 25 joints are BODY_25 or BODY_25B (Pose2Sim's
default model, no mid-hip), told apart by the joint geometry (`skeleton.body25_variant`);
``--skeleton`` overrides it.

Each person is one instance; its image id is the file name without ``_keypoints.json`` and its
frame index the trailing number of that name (0 for a single file without one): frames without
people leave a gap, they never shift later frames. A directory is read in natural frame order
(by that number, as Pose2Sim sorts them); where some name lacks a number, the frame index is
the file's position in natural name order. A directory is its ``*_keypoints.json`` files, or
else (Pose2Sim's ``cam01.0030.json``) every ``*.json`` file but zedo's own outputs.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

from ...data.keypoints import Keypoints2D
from ...data.skeleton import SKELETONS, Skeleton
from ...errors import InputFormatError
from .source import load_json
from .validate import (
    NAN_SIZE,
    Row,
    RowBuffer,
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
    data: Any, path: str, key: str, frame: int, first: Skeleton | None, forced: Skeleton | None = None
) -> tuple[Skeleton | None, list[Row]]:
    """The rows of one parsed frame file; `first` is the skeleton of the earlier frames."""
    doc = as_dict(data, path, "")
    people = as_list(required(doc, "people", path, ""), path, "people")
    rows = []
    for i, person in enumerate(people):
        where = f"people[{i}]"
        person = as_dict(person, path, where)
        where_kp = f"{where}.pose_keypoints_2d"
        values = required(person, "pose_keypoints_2d", path, where)
        first, points = flat_keypoints(values, first, path, where_kp, forced)
        xy, conf = joints(points, first, path, where_kp)
        rows.append(Row(key, xy, conf, None, NAN_SIZE, None, frame))
    return first, rows


def _frame_name(path: str) -> str:
    """The frame's name: "clip_000000000012_keypoints.json" -> "clip_000000000012"."""
    stem = Path(path).stem
    return stem[: -len(_SUFFIX)] if stem.endswith(_SUFFIX) else stem


def _reason(skeleton: Skeleton | None, forced: Skeleton | None) -> str:
    return "--skeleton" if forced is not None else f"joint count {skeleton.num_joints if skeleton else 25}"


def read_openpose(data: Any, path: str, skeleton: Skeleton | None = None) -> Keypoints2D:
    """Read one parsed OpenPose frame file (every person in it); `skeleton` is ``--skeleton``."""
    key = _frame_name(path)
    found, rows = _people_rows(data, path, key, trailing_number(key) or 0, None, skeleton)
    return build(rows, found or SKELETONS["body25"], path, FORMAT, reason=_reason(found, skeleton),
                 counted=skeleton is None)  # fmt: skip


def is_zedo_output(path: Path) -> bool:
    """A file zedo wrote (``<stem>.zedo.<ext>``, a CSV's ``.meta.json``), never an input frame."""
    return ".zedo." in path.name or path.name.endswith(".meta.json")


def sequence_files(directory: Path) -> list[Path]:
    """The ``*.json`` files of a folder that may be one sequence of frame files (zedo's outputs
    aside), in natural name order; none when the folder holds JSON Lines (then it is read file by file)."""
    if any(directory.glob("*.jsonl")) or any(directory.glob("*.ndjson")):
        return []
    files = [p for p in directory.glob("*.json") if p.is_file() and not is_zedo_output(p)]
    return sorted(files, key=lambda p: natural_key(p.name))


def is_openpose_folder(directory: Path) -> bool:
    """Whether `directory` is one OpenPose sequence (`zedo lift DIR` reads it as one input):
    every ``*.json`` file in it (zedo's outputs aside, and no ``*.jsonl``) is a frame file, either
    all named ``*_keypoints.json`` or all carrying a frame number after the same name (Pose2Sim's
    ``cam01.0030.json``), and the first and last are OpenPose frames (objects with ``people``).
    Any other folder is read file by file: a COCO file named ``*_keypoints.json`` beside other
    files is not taken for a frame."""
    files = sequence_files(directory)
    if not files:
        return False
    named = sum(p.name.endswith(f"{_SUFFIX}.json") for p in files)
    if named and named != len(files):
        return False
    if not named and (any(trailing_number(p.stem) is None for p in files) or
                      len({_video_name(p.stem) for p in files}) != 1):  # fmt: skip
        return False
    return all(_is_frame(p) for p in (files[0], files[-1]))


def _is_frame(path: Path) -> bool:
    try:
        first = load_json(str(path))
    except InputFormatError:
        return False
    return isinstance(first, dict) and "people" in first


def _video_name(stem: str) -> str:
    """A frame file's name without its frame number: "cam01.0030" -> "cam01."."""
    match = re.search(r"\d+\D*$", stem)
    return stem[: match.start()] if match else stem


def frame_files(directory: Path) -> list[tuple[Path, int]]:
    """The frame files of an OpenPose output directory with their frame indices, in frame order.

    ``*_keypoints.json`` files, or every ``*.json`` file when there are none of those.
    """
    files = [p for p in directory.glob(f"*{_SUFFIX}.json") if p.is_file()]
    files = files or [p for p in directory.glob("*.json") if p.is_file() and not is_zedo_output(p)]
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


def read_openpose_dir(directory: str | Path, skeleton: Skeleton | None = None) -> Keypoints2D:
    """Read a directory of OpenPose frame files (`frame_files`), every person of every frame.

    Errors in one file name that file; the joint count must agree across files. `skeleton`
    is ``--skeleton``; without it BODY_25 and BODY_25B are told apart over all the frames.
    """
    directory = Path(directory)
    found: Skeleton | None = None
    rows = RowBuffer()
    for file, frame in frame_files(directory):
        name = str(file)
        found, frame_rows = _people_rows(load_json(name), name, _frame_name(name), frame, found, skeleton)
        rows.extend(frame_rows)
    return build(rows, found or SKELETONS["body25"], str(directory), FORMAT, reason=_reason(found, skeleton),
                 counted=skeleton is None)  # fmt: skip
