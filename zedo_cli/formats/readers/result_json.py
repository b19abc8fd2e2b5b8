"""Reading a zedo result back from JSON (one document: header, `frames`, `summary`) and JSON Lines (a
header line, frame lines, a summary line), each part validated against the result schema as it is read."""

from __future__ import annotations

import json
from dataclasses import replace
from typing import Any

import numpy as np

from ...errors import InputFormatError, plural
from ...strict_json import loads
from ..result_schema import SCHEMA, Frame, FrameLine, HeaderLine, Person, ResultHeader, Summary, SummaryLine, validate
from .result_common import (
    SCALE_TO_M,
    ReadParts,
    as_floats,
    camera_of,
    check_schema,
    finish,
    other_fields,
    pixels,
    refuse_keypoints,
    skeleton_of,
)
from .result_record import LiftRecord, ResultPoses
from .source import json_error


def read_jsonl(text: str, name: str) -> ResultPoses:
    """Header line, frame lines, summary line: each validated against the schema as it is read."""
    reader: _DocumentReader | None = None
    summary: Summary | None = None
    for number, line in enumerate(text.splitlines(), 1):
        if not line.strip():
            continue
        try:
            obj = loads(line)
        except json.JSONDecodeError as exc:
            raise InputFormatError(f"{name}: line {number}: not JSON ({exc.msg})") from None
        except (ValueError, RecursionError) as exc:
            raise json_error(name, f"line {number}", exc) from None
        kind = obj.get("type") if isinstance(obj, dict) else None
        where = f"line {number}"
        if reader is None:
            if kind != "header":
                refuse_keypoints(obj, name)  # a detector's JSON Lines (zedo 2D: frame, persons)
                raise InputFormatError(f"{name}: {where}: not a zedo result (expected a JSON document "
                                       f"with schema {SCHEMA}, or JSON Lines starting with a header line)")  # fmt: skip
            check_schema(obj, name)
            reader = _DocumentReader(validate(HeaderLine, obj, name, line=number), name, "jsonl")
        elif summary is not None:
            raise InputFormatError(f"{name}: {where}: a line after the summary line")
        elif kind == "frame":
            reader.add(validate(FrameLine, obj, name, line=number, joints=reader.joints,
                                other_joints=len(reader.other_names)))  # fmt: skip
        elif kind == "summary":
            summary = validate(SummaryLine, obj, name, line=number)
        else:
            raise InputFormatError(f"{name}: {where}: type: expected frame or summary, got {kind!r}")
    assert reader is not None  # the text is not blank
    if summary is None:
        raise InputFormatError(f"{name}: no summary line: the file is incomplete (a run that did not finish?)")
    return reader.finish(summary)


def read_document(doc: dict[str, Any], name: str, fmt: str) -> ResultPoses:
    """A JSON document, validated against the schema: the header, then frame by frame, then the summary."""
    check_schema(doc, name)
    header = {k: v for k, v in doc.items() if k not in ("frames", "summary")}
    reader = _DocumentReader(validate(ResultHeader, header, name), name, fmt)
    frames = doc.get("frames")
    if not isinstance(frames, list):
        raise InputFormatError(f"{name}: frames: expected a list")
    for f, frame in enumerate(frames):
        reader.add(validate(Frame, frame, name, path=f"frames[{f}]", joints=reader.joints,
                            other_joints=len(reader.other_names)))  # fmt: skip
    if "summary" not in doc:
        raise InputFormatError(f"{name}: summary: field required")
    return reader.finish(validate(Summary, doc["summary"], name, path="summary"))


class _DocumentReader:
    """The persons of validated frames, gathered into a ResultPoses."""

    def __init__(self, header: ResultHeader, name: str, fmt: str) -> None:
        self.name, self.fmt, self.header = name, fmt, header
        self.skeleton = skeleton_of(header.model_dump(include={"skeleton"}), name)
        if tuple(header.skeleton.joints) != self.skeleton.joints:
            raise InputFormatError(f"{name}: skeleton.joints: not the joints of {self.skeleton.name} "
                                   f"({', '.join(self.skeleton.joints)})")  # fmt: skip
        self.joints = self.skeleton.num_joints
        others = header.other_keypoints
        self.other_names: tuple[str, ...] = () if others is None else tuple(others.joints)
        self.has_others = others is not None
        self.scale = SCALE_TO_M[header.units]
        self.frames = 0
        self.persons: list[tuple[Frame, int, Person]] = []

    def add(self, frame: Frame) -> None:
        self.frames += 1
        self.persons += [(frame, p, person) for p, person in enumerate(frame.persons)]

    def finish(self, summary: Summary) -> ResultPoses:
        j, persons = self.joints, self.persons
        if summary.frames_total != self.frames or summary.instances_total != len(self.persons):
            raise InputFormatError(
                f"{self.name}: summary: {plural(summary.frames_total, 'frame')} and "
                f"{plural(summary.instances_total, 'person', 'people')}, "
                f"but the file has {self.frames} and {len(self.persons)}: an incomplete or edited file"
            )
        has_radii = any("uncertainty_m" in person.model_fields_set for _, _, person in persons)
        radii = [as_floats(person.uncertainty_m, (j,)) for _, _, person in persons] if has_radii else None
        parts = ReadParts(
            name=self.name, fmt=self.fmt, skeleton=self.skeleton,
            poses=[as_floats(person.keypoints_3d, (j, 3)) * self.scale for _, _, person in persons],
            frame_index=[frame.frame_index for frame, _, _ in persons], person=[p for _, p, _ in persons],
            image_ids=[frame.image_id for frame, _, _ in persons],
            file_names=[frame.file_name for frame, _, _ in persons],
            lifted=[person.keypoints_3d is not None for _, _, person in persons],
            observed=[np.array(person.observed, dtype=bool) for _, _, person in persons], radii=radii,
            coordinate_frame=self.header.coordinate_frame, units=self.header.units,
            params=self.header.params.model_dump(),
        )  # fmt: skip
        roots = [as_floats(person.root_translation, (3,)) * self.scale for _, _, person in persons]
        return replace(
            finish(parts),
            cameras=[camera_of(frame.camera.model_dump(exclude_none=True), f"{self.name}: frame {frame.frame_index}")
                     for frame, _, _ in persons],
            flags=[list(person.flags) for _, _, person in persons],
            root_translation=np.asarray(roots).reshape(-1, 3), record=self._record(summary),
            hypothesis_spread_m=self._spread(), **self._others(),
        )  # fmt: skip

    def _spread(self) -> np.ndarray | None:
        """The persons' `hypothesis_spread_mm` in metres (NaN: null), or None when no person has the field."""
        if not any("hypothesis_spread_mm" in person.model_fields_set for _, _, person in self.persons):
            return None
        spread = [person.hypothesis_spread_mm for _, _, person in self.persons]
        return np.array([np.nan if v is None else v for v in spread], dtype=float) / 1000

    def _record(self, summary: Summary) -> LiftRecord:
        j, persons = self.joints, [person for _, _, person in self.persons]
        n = len(persons)
        xy = [[p if p is not None else [None, None] for p in person.keypoints_2d] for person in persons]
        hypotheses = None
        if any(person.hypotheses_m is not None for person in persons):
            count = max(len(person.hypotheses_m or []) for person in persons)
            hypotheses = np.full((n, count, j, 3), np.nan)
            for i, person in enumerate(persons):
                for h, points in enumerate(person.hypotheses_m or []):
                    hypotheses[i, h] = as_floats(points, (j, 3))
        return LiftRecord(
            keypoints_2d=np.array(xy, dtype=float).reshape(n, j, 2),
            confidence=np.nan_to_num(np.array([p.joint_confidence for p in persons], dtype=float).reshape(n, j)),
            reprojection_error_px=np.array([p.reprojection_error_px for p in persons], dtype=float).reshape(n, j),
            status=np.array([_status(p.flags) for p in persons], dtype=object),
            image_sizes=np.array([as_floats(f.camera.image_size, (2,)) for f, _, _ in self.persons]).reshape(n, 2),
            k_sources=[f.camera.source for f, _, _ in self.persons],
            instance_index=np.array([p.instance_index for p in persons], dtype=np.int64),
            scores=[p.input_score for p in persons],
            poses_root_relative=np.array([as_floats(p.keypoints_3d_root_relative, (j, 3)) for p in persons])
            .reshape(n, j, 3) * self.scale,
            hypotheses=hypotheses, input_info=self.header.input.model_dump(), seconds=summary.seconds,
        )  # fmt: skip

    def _others(self) -> dict[str, Any]:
        """`other_keypoints_2d`, `other_keypoint_confidence` and their names, when the header has them."""
        if not self.has_others:
            return {}
        e = len(self.other_names)
        xy = [pixels(person.other_keypoints_2d or [None] * e) for _, _, person in self.persons]
        conf = [as_floats(person.other_keypoint_confidence, (e,)) for _, _, person in self.persons]
        return other_fields(self.other_names, xy, conf)


def _status(flags: list[str]) -> str:
    """A person's status from its flags: the reason of `not_lifted_<reason>`, else lifted."""
    return next((f.removeprefix("not_lifted_") for f in flags if f.startswith("not_lifted_")), "lifted")
