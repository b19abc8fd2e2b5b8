"""Reading zedo's own 3D results back: JSON, JSON Lines, CSV (with or without its sidecar) and NPZ.

    res = read_result("clip.zedo.csv")   # or .json / .jsonl / .npz, or "-" for stdin
    res.poses            # (N, J, 3) metres, one row per (frame, person); NaN where missing

The format is told from the content, not the name (a NPZ is a zip archive; a JSON document
has `schema`; JSON Lines start with a `header` line; a CSV starts with `frame_index,`), so
`zedo lift ... -o - | zedo analyze -` works for every format lift writes to stdout. Whatever
the file's `--units` and `--frame`, poses come back in metres in the frame the file states.

Per-joint uncertainty: a person may carry `uncertainty_m`, one radius in metres per joint
(null where unknown): the ball around the reported root-relative joint that holds the true
joint with 90 % probability. JSON / JSONL persons carry it as a list, the CSV as a column
`uncertainty_m`, the NPZ as an `(N, J)` array. `ResultPoses.uncertainty_m` is None when the
file has no such field at all.

Cameras: `ResultPoses.cameras` holds each person's camera (`CameraModel`: K, lens model,
distortion coefficients, image size where stated) from the frame's `camera` block (JSON / JSONL),
the `fx_px` ... `camera_model`, `dist` columns (CSV) or the `K`, `camera_model`, `dist`,
`image_size` arrays (NPZ); None for a person whose file states no camera. Files written before
`model` and `dist` existed read as pinhole cameras without distortion.

2D input: `ResultPoses.keypoints_2d` `(N, J, 2)` holds the input's pixels per person and joint (JSON /
JSONL `keypoints_2d`, CSV `u_px`, `v_px`, NPZ `keypoints_2d`; from `record`, `LiftRecord`), NaN where missing;
None when the file has none.

Keypoints that were not lifted: `zedo lift` keeps the input's keypoints outside the lifted
skeleton (nose, eyes, ears, feet, ...) by name, 2D only, in the original image's pixels as the input
gave them: the header's `other_keypoints.joints` with each person's `other_keypoints_2d` and
`other_keypoint_confidence` (JSON / JSONL), rows with an empty `joint_index` (CSV), the
`other_keypoint*` arrays (NPZ). `ResultPoses.other_keypoints_2d` is None for a file written before
zedo kept them (and for a CSV without its sidecar and without such rows).

Errors are `InputFormatError`s (exit code 3) naming the file and the field.
"""

from __future__ import annotations

import csv
import io
import json
import sys
import zipfile
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from ...camera.model import CameraModel
from ...data.skeleton import Skeleton, get_skeleton, skeleton_from_joint_names
from ...errors import ConfigError, InputFormatError, IntrinsicsError, plural
from ...strict_json import loads
from ..result_schema import (
    SCHEMA,
    Frame,
    FrameLine,
    HeaderLine,
    Person,
    ResultHeader,
    Summary,
    SummaryLine,
    validate,
)
from .source import json_error

RESULT_FORMATS = ("json", "jsonl", "csv", "npz")
_SCALE_TO_M = {"m": 1.0, "mm": 1e-3}
_FRAMES = {"cam": "camera", "root": "root"}


@dataclass
class LiftRecord:
    """What a result file keeps of its lift beyond the 3D poses: enough to write the result again
    in another format (`formats.export`, `zedo export`). Per row of `ResultPoses`."""

    keypoints_2d: np.ndarray  # (N, J, 2) the input's pixels, in the prior's joints; NaN where missing
    confidence: np.ndarray  # (N, J) the input's confidence; 0 where missing
    reprojection_error_px: np.ndarray  # (N, J) NaN where not observed or not lifted
    status: np.ndarray  # (N,) object: "lifted" or why not (lifting.solver.NOT_LIFTED)
    image_sizes: np.ndarray  # (N, 2) width, height px; NaN where unknown
    k_sources: list[str]  # (N,) where each row's K came from: pseudo, cli, file
    instance_index: np.ndarray  # (N,) int, each row's index in the lifted input (its order)
    scores: list[float | None]  # (N,) the input's detection scores (JSON / JSON Lines; else None)
    poses_root_relative: np.ndarray | None = None  # (N, J, 3) metres, as stored (JSON / JSON Lines)
    hypotheses: np.ndarray | None = None  # (N, K, J, 3) metres, root-relative (--save-hypotheses)
    input_info: dict[str, Any] = field(default_factory=dict)  # the header's `input`
    seconds: float = 0.0  # the summary's seconds of lifting


@dataclass
class ResultPoses:
    """Every person of every frame of a zedo result, in file order."""

    source: str  # the path read, or "-"
    format: str  # json | jsonl | csv | npz
    skeleton: Skeleton
    poses: np.ndarray  # (N, J, 3) metres, in `coordinate_frame`; NaN where missing or not lifted
    frame_index: np.ndarray  # (N,) int, output frame of each person
    person: np.ndarray  # (N,) int, position of the person in its frame (the track in a video)
    image_ids: list[int | str]  # (N,)
    file_names: list[str | None]  # (N,)
    lifted: np.ndarray  # (N,) bool
    observed: np.ndarray  # (N, J) bool: the joint was a 2D constraint (False: filled by the prior)
    uncertainty_m: np.ndarray | None  # (N, J) 90 % ball radius in metres, NaN unknown; None: no such field
    fps: float | None  # recorded by `zedo lift --fps`
    coordinate_frame: str  # camera | root
    units_in_file: str  # m | mm (poses are converted to metres)
    params: dict[str, Any] = field(default_factory=dict)  # the lift's `params` (prior, settings, camera), if recorded
    # flags and root_translation: JSON / JSON Lines only (None for CSV and NPZ): per row, its flags and
    # its root point in the camera frame (metres; NaN when not lifted), which puts a root-frame result
    # back in the camera.
    cameras: list[CameraModel | None] | None = None  # (N,) each person's camera (any format); None: not stated
    flags: list[list[str]] | None = None
    root_translation: np.ndarray | None = None  # (N, 3); also from NPZ
    record: LiftRecord | None = None  # the lift's 2D, status, cameras' sources, ...; None where the file lacks them
    # (N,) the spread of each person's K hypotheses in metres (`hypothesis_spread_mm`), NaN where not
    # measured; None: the lift measured none (one hypothesis)
    hypothesis_spread_m: np.ndarray | None = None
    # The input's keypoints that were not lifted (face, feet, ...), by name: original image pixels as
    # the input gave them. None: the file does not say (written before zedo kept them); names () and
    # (N, 0, 2): the input had none.
    other_keypoints_2d: np.ndarray | None = None  # (N, E, 2) pixels; NaN where missing
    other_keypoint_confidence: np.ndarray | None = None  # (N, E) in [0, 1]; 0 where missing
    other_keypoint_names: tuple[str, ...] = ()

    def __len__(self) -> int:
        return len(self.poses)

    @property
    def keypoints_2d(self) -> np.ndarray | None:
        """(N, J, 2) the input's 2D in pixels, NaN where missing; None where the file does not keep them
        (an older CSV without u_px, v_px reads as all NaN)."""
        if self.record is None or not np.isfinite(self.record.keypoints_2d).any():
            return None
        return self.record.keypoints_2d


def read_result(path: str | Path) -> ResultPoses:
    """Read a zedo result file (`-` = stdin) of any format zedo lift writes."""
    name = str(path)
    if name == "-":
        data = sys.stdin.buffer.read()
    else:
        try:
            data = Path(path).read_bytes()
        except FileNotFoundError:
            raise InputFormatError(f"{name}: file not found") from None
        except IsADirectoryError:
            raise InputFormatError(f"{name}: is a folder, not a result file") from None
        except OSError as exc:
            raise InputFormatError(f"{name}: cannot read ({exc.strerror})") from None
    return read_result_bytes(data, name, sidecar=None if name == "-" else _sidecar_of(Path(path)))


def _sidecar_of(path: Path) -> Path:
    return path.with_suffix(".meta.json") if path.suffix.lower() == ".csv" else path.with_name(path.name + ".meta.json")


def read_result_bytes(data: bytes, name: str, *, sidecar: Path | None = None) -> ResultPoses:
    """Parse the bytes of a result; `name` is used in messages, `sidecar` is the CSV's
    `.meta.json` (read when the data is a CSV and the file exists)."""
    if not data.strip():
        raise InputFormatError(f"{name}: empty file (expected a zedo result: {', '.join(RESULT_FORMATS)})")
    if data[:4] == b"PK\x03\x04":
        return _read_npz(data, name)
    try:
        text = data.decode("utf-8-sig")  # a byte-order mark: a CSV that Excel saved as UTF-8
    except UnicodeDecodeError:
        raise InputFormatError(f"{name}: not a zedo result (neither UTF-8 text nor a NPZ archive)") from None
    stripped = text.lstrip()
    if stripped.startswith("frame_index,"):
        meta = _read_sidecar(sidecar) if sidecar is not None and sidecar.is_file() else None
        return _read_csv(text, name, meta)
    if stripped.startswith("{"):
        try:
            doc = loads(text)
        except json.JSONDecodeError:
            doc = None  # several lines: JSON Lines
        except (ValueError, RecursionError) as exc:  # a repeated key, a 5000-digit integer, deep nesting
            raise json_error(name, "", exc) from None
        if isinstance(doc, dict) and doc.get("type") != "header":
            _refuse_keypoints(doc, name)
            return _from_document(doc, name, "json")
        return _read_jsonl(text, name)
    if stripped.startswith("["):  # a list: a detector's (COCO results, MMPose, ...), never a result
        try:
            _refuse_keypoints(json.loads(text), name)
        except json.JSONDecodeError:
            pass
    raise InputFormatError(f"{name}: not a zedo result (expected a {SCHEMA} JSON / JSON Lines document, "
                           "a zedo CSV or a NPZ archive)")  # fmt: skip


def _refuse_keypoints(doc: Any, name: str) -> None:
    """Refuse a 2D keypoint file (any layout `zedo lift` reads) with what to do instead: lift it."""
    if isinstance(doc, dict) and doc.get("schema") == SCHEMA:
        return
    from .inputs import detect_format  # the 2D readers, only for a file that is not a result

    try:
        fmt = detect_format(doc, name)
    except InputFormatError:
        return  # not 2D keypoints either: the result reader says what it expected
    shown = "stdin" if name == "-" else name
    stem = "stdin" if name == "-" else Path(name).name.split(".")[0]
    raise InputFormatError(
        f"{shown}: 2D keypoints ({fmt}), not a zedo result (3D poses): lift them first "
        f"(zedo lift {shown} -o {stem}.zedo.json) and give zedo that result"
    )


# --- JSON and JSON Lines ------------------------------------------------------------------------


def _check_schema(doc: dict[str, Any], name: str) -> None:
    if doc.get("schema") != SCHEMA:
        raise InputFormatError(f"{name}: schema: expected a zedo result file (schema {SCHEMA}), "
                               f"got {doc.get('schema')!r}")  # fmt: skip


def _read_jsonl(text: str, name: str) -> ResultPoses:
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
                _refuse_keypoints(obj, name)  # a detector's JSON Lines (zedo 2D: frame, persons)
                raise InputFormatError(f"{name}: {where}: not a zedo result (expected a JSON document "
                                       f"with schema {SCHEMA}, or JSON Lines starting with a header line)")  # fmt: skip
            _check_schema(obj, name)
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


def _from_document(doc: dict[str, Any], name: str, fmt: str) -> ResultPoses:
    """A JSON document, validated against the schema: the header, then frame by frame, then the summary."""
    _check_schema(doc, name)
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


def _array(values: list[Any] | None, shape: tuple[int, ...]) -> np.ndarray:
    """A validated list (of lists) of numbers or null as floats, NaN for null; all NaN for None."""
    if values is None:
        return np.full(shape, np.nan)
    return np.array(values, dtype=float).reshape(shape)  # None -> nan


class _DocumentReader:
    """The persons of validated frames, gathered into a ResultPoses."""

    def __init__(self, header: ResultHeader, name: str, fmt: str) -> None:
        self.name, self.fmt, self.header = name, fmt, header
        self.skeleton = _skeleton_of(header.model_dump(include={"skeleton"}), name)
        if tuple(header.skeleton.joints) != self.skeleton.joints:
            raise InputFormatError(f"{name}: skeleton.joints: not the joints of {self.skeleton.name} "
                                   f"({', '.join(self.skeleton.joints)})")  # fmt: skip
        self.joints = self.skeleton.num_joints
        others = header.other_keypoints
        self.other_names: tuple[str, ...] = () if others is None else tuple(others.joints)
        self.has_others = others is not None
        self.scale = _SCALE_TO_M[header.units]
        self.frames = 0
        self.persons: list[tuple[Frame, int, Person]] = []

    def add(self, frame: Frame) -> None:
        self.frames += 1
        self.persons += [(frame, p, person) for p, person in enumerate(frame.persons)]

    def finish(self, summary: Summary) -> ResultPoses:
        j = self.joints
        if summary.frames_total != self.frames or summary.instances_total != len(self.persons):
            raise InputFormatError(
                f"{self.name}: summary: {plural(summary.frames_total, 'frame')} and "
                f"{plural(summary.instances_total, 'person', 'people')}, "
                f"but the file has {self.frames} and {len(self.persons)}: an incomplete or edited file"
            )
        has_radii = any("uncertainty_m" in person.model_fields_set for _, _, person in self.persons)
        poses = [_array(person.keypoints_3d, (j, 3)) * self.scale for _, _, person in self.persons]
        radii = [_array(person.uncertainty_m, (j,)) for _, _, person in self.persons] if has_radii else None
        res = _finish(
            self.name, self.fmt, self.skeleton, poses, [frame.frame_index for frame, _, _ in self.persons],
            [p for _, p, _ in self.persons], [frame.image_id for frame, _, _ in self.persons],
            [frame.file_name for frame, _, _ in self.persons],
            [person.keypoints_3d is not None for _, _, person in self.persons],
            [np.array(person.observed, dtype=bool) for _, _, person in self.persons], radii,
            self.header.params.fps, self.header.coordinate_frame, self.header.units,
        )  # fmt: skip
        roots = [_array(person.root_translation, (3,)) * self.scale for _, _, person in self.persons]
        return replace(
            res, params=self.header.params.model_dump(),
            cameras=[_camera(frame.camera.model_dump(exclude_none=True), f"{self.name}: frame {frame.frame_index}")
                     for frame, _, _ in self.persons],
            flags=[list(person.flags) for _, _, person in self.persons],
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
                    hypotheses[i, h] = _array(points, (j, 3))
        return LiftRecord(
            keypoints_2d=np.array(xy, dtype=float).reshape(n, j, 2),
            confidence=np.nan_to_num(np.array([p.joint_confidence for p in persons], dtype=float).reshape(n, j)),
            reprojection_error_px=np.array([p.reprojection_error_px for p in persons], dtype=float).reshape(n, j),
            status=np.array([_status(p.flags) for p in persons], dtype=object),
            image_sizes=np.array([_array(f.camera.image_size, (2,)) for f, _, _ in self.persons]).reshape(n, 2),
            k_sources=[f.camera.source for f, _, _ in self.persons],
            instance_index=np.array([p.instance_index for p in persons], dtype=np.int64),
            scores=[p.input_score for p in persons],
            poses_root_relative=np.array([_array(p.keypoints_3d_root_relative, (j, 3)) * self.scale for p in persons])
            .reshape(n, j, 3),
            hypotheses=hypotheses, input_info=self.header.input.model_dump(), seconds=summary.seconds,
        )  # fmt: skip

    def _others(self) -> dict[str, Any]:
        """`other_keypoints_2d`, `other_keypoint_confidence` and their names, when the header has them."""
        if not self.has_others:
            return {}
        e = len(self.other_names)
        xy = [_pixels(person.other_keypoints_2d or [None] * e) for _, _, person in self.persons]
        conf = [_array(person.other_keypoint_confidence, (e,)) for _, _, person in self.persons]
        return _other_fields(self.other_names, xy, conf)


def _status(flags: list[str]) -> str:
    """A person's status from its flags: the reason of `not_lifted_<reason>`, else lifted."""
    return next((f.removeprefix("not_lifted_") for f in flags if f.startswith("not_lifted_")), "lifted")


def _other_fields(names: tuple[str, ...], xy: list[np.ndarray], conf: list[np.ndarray]) -> dict[str, Any]:
    """The ResultPoses fields of the keypoints that were not lifted: pixels `(N, E, 2)` NaN where
    missing, confidences `(N, E)` 0 where missing (either one unknown makes the point missing)."""
    n, e = len(xy), len(names)
    xy_a, conf_a = np.asarray(xy, dtype=float).reshape(n, e, 2), np.asarray(conf, dtype=float).reshape(n, e)
    present = np.isfinite(xy_a).all(-1) & np.isfinite(conf_a) & (conf_a > 0)  # (N, E)
    return {
        "other_keypoints_2d": np.where(present[..., None], xy_a, np.nan),
        "other_keypoint_confidence": np.where(present, conf_a, 0.0),
        "other_keypoint_names": names,
    }


def _pixels(points: list[list[float | None] | None]) -> np.ndarray:
    """A person's validated `keypoints_2d` (a point, or null where missing) as `(J, 2)` floats, NaN for null."""
    return np.array([[np.nan, np.nan] if p is None else p for p in points], dtype=float).reshape(-1, 2)


def _camera(block: Any, where: str) -> CameraModel | None:
    """A camera block `{"K", "image_size", "source", "model", "dist"}` (None: absent)."""
    if block is None:
        return None
    try:
        return CameraModel.from_json(block)
    except KeyError as exc:
        raise InputFormatError(f"{where}.{exc.args[0]}: missing") from None
    except (TypeError, ValueError, AttributeError, IntrinsicsError) as exc:
        raise InputFormatError(f"{where}: not a camera (K, model, dist, image_size): {exc}") from None


def _skeleton_of(doc: dict[str, Any], name: str) -> Skeleton:
    skel = doc.get("skeleton")
    if not isinstance(skel, dict) or not isinstance(skel.get("name"), str):
        raise InputFormatError(f"{name}: skeleton.name: missing")
    try:
        return get_skeleton(skel["name"])
    except ConfigError as exc:
        raise InputFormatError(f"{name}: skeleton.name: {exc}") from None


def _units(value: Any, name: str, field: str = "units") -> str:
    if value not in _SCALE_TO_M:
        raise InputFormatError(f"{name}: {field}: expected m or mm, got {value!r}")
    return str(value)


def _params(doc: Any) -> dict[str, Any]:
    params = doc.get("params") if isinstance(doc, dict) else None
    return params if isinstance(params, dict) else {}


def _fps(params: Any, name: str) -> float | None:
    fps = params.get("fps") if isinstance(params, dict) else None
    if fps is None:
        return None
    if not isinstance(fps, int | float) or not fps > 0:
        raise InputFormatError(f"{name}: params.fps: expected a positive number or null, got {fps!r}")
    return float(fps)


def _finish(
    name: str, fmt: str, skel: Skeleton, poses: list[np.ndarray], frame_index: list[int], person: list[int],
    ids: list[Any], files: list[Any], lifted: list[bool], observed: list[np.ndarray],
    radii: list[np.ndarray] | None, fps: float | None, coord: str, units: str,
    cameras: list[CameraModel | None] | None = None,
) -> ResultPoses:  # fmt: skip
    if not poses:
        raise InputFormatError(f"{name}: no persons in the result")
    j = skel.num_joints
    return ResultPoses(
        name, fmt, skel, np.asarray(poses, dtype=float).reshape(-1, j, 3), np.asarray(frame_index, dtype=np.int64),
        np.asarray(person, dtype=np.int64), list(ids), [None if not f else str(f) for f in files],
        np.asarray(lifted, dtype=bool), np.asarray(observed, dtype=bool).reshape(-1, j),
        None if radii is None else np.asarray(radii, dtype=float).reshape(-1, j), fps, coord, units,
        cameras=cameras if cameras and any(c is not None for c in cameras) else None,
    )  # fmt: skip


# --- CSV ----------------------------------------------------------------------------------------


def _read_sidecar(path: Path) -> dict[str, Any]:
    try:
        meta = loads(path.read_text(encoding="utf-8-sig"))
    except (OSError, UnicodeDecodeError, ValueError, RecursionError) as exc:
        raise InputFormatError(f"{path}: not a readable JSON sidecar ({exc})") from None
    if not isinstance(meta, dict):
        raise InputFormatError(f"{path}: expected a JSON object")
    _check_schema(meta, str(path))
    return meta


def _coordinate_columns(columns: list[str], name: str) -> tuple[list[str], str, str]:
    for tag, frame in _FRAMES.items():
        for units in _SCALE_TO_M:
            cols = [f"{axis}_{tag}_{units}" for axis in "xyz"]
            if all(c in columns for c in cols):
                return cols, frame, units
    raise InputFormatError(f"{name}: no coordinate columns (x_cam_m, x_cam_mm, x_root_m or x_root_mm): "
                           "not a zedo result CSV")  # fmt: skip


def _cell(value: str, where: str) -> float:
    if value == "":
        return np.nan
    try:
        return float(value)
    except ValueError:
        raise InputFormatError(f"{where}: not a number: {value!r}") from None


def _true(value: str | None) -> bool:
    """A CSV boolean: ``true`` as zedo writes it, ``TRUE`` as Excel saves it."""
    return value is not None and value.strip().lower() == "true"


def _read_csv(text: str, name: str, meta: dict[str, Any] | None) -> ResultPoses:
    rows = list(csv.DictReader(io.StringIO(text)))
    columns = list(rows[0].keys()) if rows else text.splitlines()[0].split(",")
    required = ("frame_index", "image_id", "person", "joint", "joint_index", "lifted")
    lacking = [c for c in required if c not in columns]
    if lacking:
        what = "column" if len(lacking) == 1 else "columns"
        raise InputFormatError(f"{name}: {what} {', '.join(lacking)} missing: not a zedo result CSV")
    xyz, coord, units = _coordinate_columns(columns, name)
    if not rows:
        raise InputFormatError(f"{name}: no persons in the result")
    # Rows come per (frame, person), joints in order; an instance is one (frame_index, person).
    order: dict[tuple[int, int], dict[str, Any]] = {}
    joint_names: dict[int, str] = {}
    other_names: dict[str, None] = {}  # the keypoints that were not lifted, in order of appearance
    for r, row in enumerate(rows, 2):
        where = f"{name}: line {r}"
        try:
            key = (int(row["frame_index"]), int(row["person"]))
            j = int(row["joint_index"]) if row["joint_index"] != "" else None
        except (TypeError, ValueError):
            raise InputFormatError(f"{where}: frame_index, person and joint_index must be integers") from None
        if key not in order:
            order[key] = {"image_id": row["image_id"], "file_name": row.get("file_name") or None,
                          "lifted": _true(row["lifted"]), "camera": _csv_camera(row, where),
                          "status": row.get("status") or ("lifted" if _true(row["lifted"]) else "not_lifted"),
                          "k_source": row.get("k_source") or "",
                          "instance": _int_cell(row.get("instance_index"), len(order)), "points": {}, "observed": {},
                          "radii": {}, "pixels": {}, "confidence": {}, "errors": {}, "other": {},
                          "spread": _cell(row.get("hypothesis_spread_mm") or "",
                                          f"{where}: hypothesis_spread_mm")}  # fmt: skip
        inst = order[key]
        if j is None:  # a keypoint of the input that was not lifted: 2D only
            other_names.setdefault(row["joint"])
            inst["other"][row["joint"]] = [
                _cell(row.get(c) or "", f"{where}: {c}") for c in ("u_px", "v_px", "confidence")
            ]
            continue
        joint_names.setdefault(j, row["joint"])
        inst["pixels"][j] = [_cell(row.get(c) or "", f"{where}: {c}") for c in ("u_px", "v_px")]
        inst["confidence"][j] = _cell(row.get("confidence") or "", f"{where}: confidence")
        inst["errors"][j] = _cell(row.get("reprojection_error_px") or "", f"{where}: reprojection_error_px")
        inst["points"][j] = [_cell(row[c], f"{where}: {c}") for c in xyz]
        inst["pixels"][j] = [_cell(row.get(c) or "", f"{where}: {c}") for c in ("u_px", "v_px")]
        inst["observed"][j] = _true(row.get("observed", "true"))
        if "uncertainty_m" in row:
            inst["radii"][j] = _cell(row["uncertainty_m"], f"{where}: uncertainty_m")
    names = tuple(joint_names[j] for j in sorted(joint_names))
    skel = _skeleton_of(meta, name) if meta is not None else skeleton_from_joint_names(names)
    if skel is None or skel.joints != names:
        raise InputFormatError(f"{name}: joint: the joints {', '.join(names)} are not a zedo skeleton's")
    scale = _SCALE_TO_M[units]
    poses, frame_index, person, ids, files, lifted, observed, radii = [], [], [], [], [], [], [], []
    for (f, p), inst in order.items():
        if len(inst["points"]) != skel.num_joints:
            raise InputFormatError(f"{name}: frame {f}, person {p}: expected {skel.num_joints} joint rows")
        poses.append(np.array([inst["points"][j] for j in range(skel.num_joints)]) * scale)
        frame_index.append(f)
        person.append(p)
        ids.append(int(inst["image_id"]) if inst["image_id"].lstrip("-").isdigit() else inst["image_id"])
        files.append(inst["file_name"])
        lifted.append(inst["lifted"])
        observed.append([inst["observed"][j] for j in range(skel.num_joints)])
        radii.append([inst["radii"].get(j, np.nan) for j in range(skel.num_joints)])
    fps = _fps(meta.get("params"), name) if meta is not None else None
    out = _finish(name, "csv", skel, poses, frame_index, person, ids, files, lifted,
                   [np.asarray(o) for o in observed], [np.asarray(r, dtype=float) for r in radii]
                   if "uncertainty_m" in columns else None, fps, coord, units,
                   cameras=[inst["camera"] for inst in order.values()])  # fmt: skip
    spread = np.array([inst["spread"] for inst in order.values()]) / 1000 if "hypothesis_spread_mm" in columns else None
    return replace(out, params=_params(meta), record=_csv_record(order, skel.num_joints, meta),
                   hypothesis_spread_m=spread, **_csv_others(order, other_names, meta, name))  # fmt: skip


def _int_cell(value: str | None, default: int) -> int:
    try:
        return int(value) if value else default
    except ValueError:
        return default


def _csv_record(order: dict[tuple[int, int], dict[str, Any]], joints: int, meta: dict[str, Any] | None) -> LiftRecord:
    """The CSV's 2D, confidences, errors, status and K sources; image sizes from the sidecar's frames."""
    insts = list(order.values())
    sizes: dict[int, Any] = {}
    for frame in (meta or {}).get("frames") or []:
        if isinstance(frame, dict) and isinstance(frame.get("camera"), dict):
            sizes[frame.get("frame_index")] = frame["camera"].get("image_size")
    summary = (meta or {}).get("summary")
    seconds = summary.get("seconds") if isinstance(summary, dict) else None
    return LiftRecord(
        keypoints_2d=np.array([[inst["pixels"][j] for j in range(joints)] for inst in insts], dtype=float),
        confidence=np.nan_to_num(np.array([[inst["confidence"][j] for j in range(joints)] for inst in insts])),
        reprojection_error_px=np.array([[inst["errors"][j] for j in range(joints)] for inst in insts], dtype=float),
        status=np.array([inst["status"] for inst in insts], dtype=object),
        image_sizes=np.array([_size(sizes.get(f)) for f, _ in order], dtype=float).reshape(-1, 2),
        k_sources=[inst["k_source"] for inst in insts],
        instance_index=np.array([inst["instance"] for inst in insts], dtype=np.int64),
        scores=[None] * len(insts), input_info=_dict((meta or {}).get("input")),
        seconds=float(seconds) if isinstance(seconds, int | float) else 0.0,
    )  # fmt: skip


def _size(value: Any) -> list[float]:
    """An image size `[w, h]` from a sidecar, NaN where absent or not two numbers."""
    if isinstance(value, list) and len(value) == 2 and all(isinstance(v, int | float) for v in value):
        return [float(v) for v in value]
    return [np.nan, np.nan]


def _dict(value: Any) -> dict[str, Any]:
    return value if isinstance(value, dict) else {}


def _csv_others(
    order: dict[tuple[int, int], dict[str, Any]], seen: dict[str, None], meta: dict[str, Any] | None, name: str
) -> dict[str, Any]:
    """The keypoints that were not lifted, from the rows with an empty joint_index; their names are
    the sidecar's `other_keypoints.joints` where it has them, else the rows' (none: unknown)."""
    block = meta.get("other_keypoints") if meta is not None else None
    if isinstance(block, dict) and isinstance(block.get("joints"), list):
        names = tuple(str(n) for n in block["joints"])
        stray = [n for n in seen if n not in names]
        if stray:
            raise InputFormatError(f"{name}: joint: {', '.join(stray)} not among the sidecar's other_keypoints")
    elif seen:
        names = tuple(seen)
    else:
        return {}
    nan = [np.nan, np.nan, np.nan]
    values = np.array([[inst["other"].get(n, nan) for n in names] for inst in order.values()])
    values = values.reshape(len(order), len(names), 3)
    return _other_fields(names, list(values[..., :2]), list(values[..., 2]))


def _csv_camera(row: dict[str, str], where: str) -> CameraModel | None:
    """The camera of a CSV row: fx_px, fy_px, cx_px, cy_px and, when present, camera_model and dist."""
    if not all(row.get(c) for c in ("fx_px", "fy_px", "cx_px", "cy_px")):
        return None
    fx, fy, cx, cy = (_cell(row[c], f"{where}: {c}") for c in ("fx_px", "fy_px", "cx_px", "cy_px"))
    dist = [_cell(v, f"{where}: dist") for v in (row.get("dist") or "").split()]
    k = [[fx, 0.0, cx], [0.0, fy, cy], [0.0, 0.0, 1.0]]
    return _camera({"K": k, "model": row.get("camera_model") or "pinhole", "dist": dist}, f"{where}: camera")


# --- NPZ ----------------------------------------------------------------------------------------


def _read_npz(data: bytes, name: str) -> ResultPoses:
    try:
        with np.load(io.BytesIO(data), allow_pickle=False) as npz:
            arrays = {k: npz[k] for k in npz.files}
    except (OSError, ValueError, zipfile.BadZipFile) as exc:
        raise InputFormatError(f"{name}: not a readable NPZ archive ({exc})") from None
    lacking = [k for k in ("poses", "joint_names", "units", "frame_index", "person") if k not in arrays]
    if lacking:
        what = "array" if len(lacking) == 1 else "arrays"
        raise InputFormatError(f"{name}: {what} {', '.join(lacking)} missing: not a zedo result NPZ")
    names = tuple(str(n) for n in arrays["joint_names"])
    meta: dict[str, Any] = {}
    if "metadata" in arrays:
        try:
            meta = loads(str(arrays["metadata"]))
        except json.JSONDecodeError:
            raise InputFormatError(f"{name}: metadata: not JSON") from None
        except (ValueError, RecursionError) as exc:
            raise json_error(name, "metadata", exc) from None
        _check_schema(meta, name)
    skel = _skeleton_of(meta, name) if meta else skeleton_from_joint_names(names)
    if skel is None or skel.joints != names:
        raise InputFormatError(f"{name}: joint_names: {', '.join(names)} are not a zedo skeleton's joints")
    poses = np.asarray(arrays["poses"], dtype=float)
    n = len(poses)
    if poses.shape != (n, skel.num_joints, 3):
        raise InputFormatError(f"{name}: poses: expected shape (N, {skel.num_joints}, 3), got {poses.shape}")
    scale = _SCALE_TO_M[_units(str(arrays["units"]), name)]
    radii = arrays.get("uncertainty_m")
    if radii is not None and np.shape(radii) != (n, skel.num_joints):
        raise InputFormatError(f"{name}: uncertainty_m: expected shape ({n}, {skel.num_joints})")
    ids = arrays.get("image_ids", arrays["frame_index"])
    files = arrays.get("file_names", np.array([""] * n))
    cameras = _npz_cameras(arrays, n, name)
    others = _npz_others(arrays, n, name)
    record = _npz_record(arrays, n, skel.num_joints, meta, scale, name)
    roots = arrays.get("root_translation")
    roots = None if roots is None or np.shape(roots) != (n, 3) else np.asarray(roots, dtype=float) * scale
    spread = arrays.get("hypothesis_spread_mm")
    if spread is not None and np.shape(spread) != (n,):
        raise InputFormatError(f"{name}: hypothesis_spread_mm: expected shape ({n},), got {np.shape(spread)}")
    return replace(_npz_result(arrays, name, skel, poses, scale, radii, ids, files, meta, cameras),
                   record=record, root_translation=roots,
                   hypothesis_spread_m=None if spread is None else np.asarray(spread, dtype=float) / 1000,
                   **others)  # fmt: skip


def _npz_record(
    arrays: dict[str, np.ndarray], n: int, joints: int, meta: dict[str, Any], scale: float, name: str
) -> LiftRecord | None:
    """The archive's 2D, confidences, errors, status, image sizes and K sources (None when one is missing)."""
    need = {"keypoints_2d": (n, joints, 2), "confidence": (n, joints), "reprojection_error_px": (n, joints),
            "status": (n,), "image_size": (n, 2), "k_source": (n,)}  # fmt: skip
    if any(k not in arrays for k in need):
        return None
    bad = [k for k, shape in need.items() if np.shape(arrays[k]) != shape]
    if bad:
        raise InputFormatError(f"{name}: {', '.join(bad)}: not one entry per row and joint ({n} rows, {joints} joints)")
    hypotheses = arrays.get("hypotheses")
    summary = meta.get("summary") if isinstance(meta.get("summary"), dict) else {}
    seconds = summary.get("seconds")
    return LiftRecord(
        keypoints_2d=np.asarray(arrays["keypoints_2d"], dtype=float),
        confidence=np.nan_to_num(np.asarray(arrays["confidence"], dtype=float)),
        reprojection_error_px=np.asarray(arrays["reprojection_error_px"], dtype=float),
        status=np.asarray([str(s) for s in arrays["status"]], dtype=object),
        image_sizes=np.asarray(arrays["image_size"], dtype=float), k_sources=[str(s) for s in arrays["k_source"]],
        instance_index=np.arange(n), scores=[None] * n,
        hypotheses=None if hypotheses is None else np.asarray(hypotheses, dtype=float),
        input_info=_dict(meta.get("input")), seconds=float(seconds) if isinstance(seconds, int | float) else 0.0,
    )  # fmt: skip


def _npz_result(
    arrays: dict[str, np.ndarray], name: str, skel: Skeleton, poses: np.ndarray, scale: float,
    radii: np.ndarray | None, ids: np.ndarray, files: np.ndarray, meta: dict[str, Any],
    cameras: list[CameraModel | None] | None,
) -> ResultPoses:  # fmt: skip
    n = len(poses)
    return ResultPoses(  # the lift's params come with the metadata
        name, "npz", skel, poses * scale, np.asarray(arrays["frame_index"], dtype=np.int64),
        np.asarray(arrays["person"], dtype=np.int64), [i.item() for i in np.asarray(ids)],
        [str(f) or None for f in files], np.asarray(arrays.get("lifted", np.isfinite(poses).all((1, 2))), dtype=bool),
        np.asarray(arrays.get("observed", np.ones((n, skel.num_joints))), dtype=bool),
        None if radii is None else np.asarray(radii, dtype=float), _fps(meta.get("params"), name),
        str(arrays.get("coordinate_frame", "camera")), str(arrays["units"]), _params(meta), cameras,
    )  # fmt: skip


def _npz_others(arrays: dict[str, np.ndarray], n: int, name: str) -> dict[str, Any]:
    """`other_keypoints_2d (N, E, 2)`, `other_keypoint_confidence (N, E)` (NaN where missing) and
    `other_keypoint_names (E,)`, when the archive has them."""
    if "other_keypoint_names" not in arrays:
        return {}
    names = tuple(str(v) for v in np.asarray(arrays["other_keypoint_names"]).reshape(-1))
    e = len(names)
    xy = np.asarray(arrays.get("other_keypoints_2d", np.full((n, e, 2), np.nan)), dtype=float)
    conf = np.asarray(arrays.get("other_keypoint_confidence", np.full((n, e), np.nan)), dtype=float)
    if xy.shape != (n, e, 2) or conf.shape != (n, e):
        raise InputFormatError(f"{name}: other_keypoints_2d, other_keypoint_confidence: expected shapes "
                               f"({n}, {e}, 2) and ({n}, {e}) for {e} other_keypoint_names")  # fmt: skip
    return _other_fields(names, list(xy), list(conf))


def _npz_cameras(arrays: dict[str, np.ndarray], n: int, name: str) -> list[CameraModel | None] | None:
    """Each row's camera from `K (N, 3, 3)`, `camera_model (N,)`, `dist (N, D)` (NaN-padded) and
    `image_size (N, 2)`; None when the archive has no K."""
    if "K" not in arrays:
        return None
    k = np.asarray(arrays["K"], dtype=float)
    models = arrays.get("camera_model", np.array(["pinhole"] * n))
    dist = np.asarray(arrays.get("dist", np.zeros((n, 0))), dtype=float)
    sizes = np.asarray(arrays.get("image_size", np.full((n, 2), np.nan)), dtype=float)
    if k.shape != (n, 3, 3) or len(models) != n or dist.ndim != 2 or len(dist) != n or sizes.shape != (n, 2):
        raise InputFormatError(f"{name}: K, camera_model, dist, image_size: expected one per row ({n})")
    out: list[CameraModel | None] = []
    seen: dict[tuple[bytes, str, bytes, bytes], CameraModel | None] = {}  # a clip has one or a few cameras
    for i in range(n):
        key = (k[i].tobytes(), str(models[i]), dist[i].tobytes(), sizes[i].tobytes())
        if key not in seen:
            block = {"K": k[i], "model": str(models[i]), "dist": dist[i][np.isfinite(dist[i])].tolist(),
                     "image_size": sizes[i].tolist() if np.isfinite(sizes[i]).all() else None}  # fmt: skip
            seen[key] = _camera(block, f"{name}: row {i}: camera")
        out.append(seen[key])
    return out
