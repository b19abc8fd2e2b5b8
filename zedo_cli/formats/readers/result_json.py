"""Reading a zedo result back from JSON (one document: header, `frames`, `summary`) and JSON Lines (a
header line, frame lines, a summary line), each part validated against the result schema as it is read."""

from __future__ import annotations

import json
from collections.abc import Iterator
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ...camera.model import CameraModel
from ...errors import InputFormatError, plural
from ...strict_json import loads
from ..result_schema import SCHEMA, Frame, FrameLine, HeaderLine, ResultHeader, Summary, SummaryLine, validate
from .jsondoc import InvalidDocument, stream_members
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
        frames[f] = None  # read: its objects go (a long clip's document would otherwise be held twice)
    if "summary" not in doc:
        raise InputFormatError(f"{name}: summary: field required")
    return reader.finish(validate(Summary, doc["summary"], name, path="summary"))


def read_streamed(text: str, name: str) -> ResultPoses | None:
    """A JSON document written as zedo writes it (`schema` first, the header's members before `frames`), its frames
    decoded and validated one at a time so that a long clip's document is never held whole; None for any other
    text (JSON Lines, another key order, malformed JSON), which the whole-document path then reads or refuses."""
    header: dict[str, Any] = {}
    reader: _DocumentReader | None = None
    summary: Any = None
    try:
        for key, value in stream_members(text, streamed="frames"):
            if not header and key != "schema" or reader is not None and key != "summary":
                return None
            if key == "summary":
                summary = value
            elif key != "frames":
                header[key] = value
            elif not isinstance(value, Iterator) or _REQUIRED - header.keys():
                return None
            else:
                check_schema(header, name)
                reader = _DocumentReader(validate(ResultHeader, header, name), name, "json")
                for f, frame in enumerate(value):
                    reader.add(validate(Frame, frame, name, path=f"frames[{f}]", joints=reader.joints,
                                        other_joints=len(reader.other_names)))  # fmt: skip
    except (InvalidDocument, ValueError, RecursionError):  # not one plain object: the whole path says what is wrong
        return None
    if reader is None or summary is None:
        return None
    return reader.finish(validate(Summary, summary, name, path="summary"))


_REQUIRED = {f.alias or n for n, f in ResultHeader.model_fields.items() if f.is_required()}


@dataclass(frozen=True, slots=True)
class _PersonRead:
    """What a result reader keeps of one validated person: arrays in metres (per-joint NaN for null), not the
    model's lists, so that a long clip's persons take little memory."""

    frame_index: int
    image_id: int | str
    file_name: str | None
    camera: CameraModel | None
    image_size: np.ndarray  # (2,)
    k_source: str
    place: int  # the person's place in its frame
    lifted: bool
    pose: np.ndarray  # (J, 3)
    root_relative: np.ndarray  # (J, 3)
    root: np.ndarray  # (3,)
    observed: np.ndarray  # (J,) bool
    radii: np.ndarray | None  # (J,); None: the field is absent
    spread_m: float | None  # hypothesis_spread_mm in metres, NaN for null; None: absent
    flags: list[str]
    keypoints_2d: np.ndarray  # (J, 2)
    confidence: np.ndarray  # (J,)
    reprojection: np.ndarray  # (J,)
    instance_index: int
    input_score: float | None
    hypotheses: np.ndarray | None  # (H, J, 3) metres, or None
    other_xy: np.ndarray | None  # (E, 2)
    other_confidence: np.ndarray | None  # (E,)


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
        self.persons: list[_PersonRead] = []
        self._cameras: dict[str, CameraModel | None] = {}  # a clip's frames share one camera: read it once

    def _camera(self, frame: Frame) -> CameraModel | None:
        block = frame.camera.model_dump(exclude_none=True)
        key = json.dumps(block, sort_keys=True)
        if key not in self._cameras:
            self._cameras[key] = camera_of(block, f"{self.name}: frame {frame.frame_index}")
        return self._cameras[key]

    def add(self, frame: Frame) -> None:
        self.frames += 1
        if not frame.persons:
            return
        j, e, scale = self.joints, len(self.other_names), self.scale
        camera, size = self._camera(frame), as_floats(frame.camera.image_size, (2,))
        for place, person in enumerate(frame.persons):
            fields = person.model_fields_set
            spread = person.hypothesis_spread_mm
            hypotheses = None
            if person.hypotheses_m is not None:
                hypotheses = np.array([as_floats(points, (j, 3)) for points in person.hypotheses_m]).reshape(-1, j, 3)
            self.persons.append(_PersonRead(
                frame.frame_index, frame.image_id, frame.file_name, camera, size, frame.camera.source, place,
                person.keypoints_3d is not None, as_floats(person.keypoints_3d, (j, 3)) * scale,
                as_floats(person.keypoints_3d_root_relative, (j, 3)) * scale,
                as_floats(person.root_translation, (3,)) * scale, np.array(person.observed, dtype=bool),
                as_floats(person.uncertainty_m, (j,)) if "uncertainty_m" in fields else None,
                (np.nan if spread is None else spread / 1000) if "hypothesis_spread_mm" in fields else None,
                list(person.flags), pixels(person.keypoints_2d),
                np.nan_to_num(np.array(person.joint_confidence, dtype=float).reshape(j)),
                np.array(person.reprojection_error_px, dtype=float).reshape(j), person.instance_index,
                person.input_score, hypotheses,
                pixels(person.other_keypoints_2d or [None] * e) if self.has_others else None,
                as_floats(person.other_keypoint_confidence, (e,)) if self.has_others else None,
            ))  # fmt: skip

    def finish(self, summary: Summary) -> ResultPoses:
        j, persons = self.joints, self.persons
        if summary.frames_total != self.frames or summary.instances_total != len(persons):
            raise InputFormatError(
                f"{self.name}: summary: {plural(summary.frames_total, 'frame')} and "
                f"{plural(summary.instances_total, 'person', 'people')}, "
                f"but the file has {self.frames} and {len(persons)}: an incomplete or edited file"
            )
        has_radii = any(p.radii is not None for p in persons)
        radii = [np.full(j, np.nan) if p.radii is None else p.radii for p in persons] if has_radii else None
        parts = ReadParts(
            name=self.name, fmt=self.fmt, skeleton=self.skeleton, poses=[p.pose for p in persons],
            frame_index=[p.frame_index for p in persons], person=[p.place for p in persons],
            image_ids=[p.image_id for p in persons], file_names=[p.file_name for p in persons],
            lifted=[p.lifted for p in persons], observed=[p.observed for p in persons], radii=radii,
            coordinate_frame=self.header.coordinate_frame, units=self.header.units,
            params=self.header.params.model_dump(exclude_unset=True),  # as recorded
        )  # fmt: skip
        others = {}
        if self.has_others:
            xy, conf = [p.other_xy for p in persons], [p.other_confidence for p in persons]
            others = other_fields(self.other_names, xy, conf)  # type: ignore[arg-type]
        return replace(
            finish(parts), cameras=[p.camera for p in persons], flags=[list(p.flags) for p in persons],
            root_translation=np.asarray([p.root for p in persons]).reshape(-1, 3), record=self._record(summary),
            hypothesis_spread_m=self._spread(), **others,
        )  # fmt: skip

    def _spread(self) -> np.ndarray | None:
        """The persons' `hypothesis_spread_mm` in metres (NaN: null), or None when no person has the field."""
        if all(p.spread_m is None for p in self.persons):
            return None
        return np.array([np.nan if p.spread_m is None else p.spread_m for p in self.persons], dtype=float)

    def _record(self, summary: Summary) -> LiftRecord:
        j, persons = self.joints, self.persons
        n = len(persons)
        hypotheses = None
        if any(p.hypotheses is not None for p in persons):
            count = max(0 if p.hypotheses is None else len(p.hypotheses) for p in persons)
            hypotheses = np.full((n, count, j, 3), np.nan)
            for i, p in enumerate(persons):
                if p.hypotheses is not None:
                    hypotheses[i, : len(p.hypotheses)] = p.hypotheses
        return LiftRecord(
            keypoints_2d=np.array([p.keypoints_2d for p in persons], dtype=float).reshape(n, j, 2),
            confidence=np.array([p.confidence for p in persons], dtype=float).reshape(n, j),
            reprojection_error_px=np.array([p.reprojection for p in persons], dtype=float).reshape(n, j),
            status=np.array([_status(p.flags) for p in persons], dtype=object),
            image_sizes=np.array([p.image_size for p in persons]).reshape(n, 2),
            k_sources=[p.k_source for p in persons],
            instance_index=np.array([p.instance_index for p in persons], dtype=np.int64),
            scores=[p.input_score for p in persons],
            poses_root_relative=np.array([p.root_relative for p in persons]).reshape(n, j, 3),
            hypotheses=hypotheses, input_info=self.header.input.model_dump(), seconds=summary.seconds,
        )  # fmt: skip


def _status(flags: list[str]) -> str:
    """A person's status from its flags: the reason of `not_lifted_<reason>`, else lifted."""
    return next((f.removeprefix("not_lifted_") for f in flags if f.startswith("not_lifted_")), "lifted")
