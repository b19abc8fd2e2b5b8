"""The published schema of the result file (`zedo.pose3d/1`): pydantic models of the JSON
document and of its JSON Lines, and the JSON Schema generated from them (`zedo schema result`).

The JSON document is `ResultDocument`: the header (`ResultHeader`), `frames` (`Frame`, each with
its `camera` and `persons`) and `summary`. JSON Lines carry the same objects, one per line, with
`type` = "header", "frame" or "summary". Per-joint lists have one entry per joint of `skeleton`
(checked when the models validate with `context={"joints": J}`, as `read_result` does; a JSON
Schema cannot say it). Missing values are null, never 0; numbers are finite (JSON has no NaN).

Frames, persons and their cameras are closed (an unknown field is refused), so that a writer
that drifts from the schema fails its tests; `input` and `params` record the run's settings and
are open, with the fields a reader relies on typed (`params.fps`).
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError, ValidationInfo, field_validator

from ..errors import InputFormatError

SCHEMA = "zedo.pose3d/1"

Coordinate = float | None  # null: not finite
Point3 = Annotated[list[Coordinate], Field(min_length=3, max_length=3, description="[x, y, z], null where unknown")]
Point2 = Annotated[list[Coordinate], Field(min_length=2, max_length=2, description="[u, v] pixels")]
NonNegative = Annotated[float, Field(ge=0)]


class _Closed(BaseModel):
    model_config = ConfigDict(strict=True, extra="forbid")


class _Open(BaseModel):
    model_config = ConfigDict(strict=True, extra="allow")


def _per_joint(value: list[Any] | None, info: ValidationInfo) -> list[Any] | None:
    joints = (info.context or {}).get("joints")
    if value is not None and joints is not None and len(value) != joints:
        raise ValueError(f"expected {joints} entries (one per skeleton joint), got {len(value)}")
    return value


def _per_other(value: list[Any] | None, info: ValidationInfo) -> list[Any] | None:
    others = (info.context or {}).get("other_joints")
    if value is not None and others is not None and len(value) != others:
        raise ValueError(f"expected {others} entries (one per other_keypoints.joints name), got {len(value)}")
    return value


class Skeleton(_Closed):
    name: str = Field(description="a zedo skeleton (syrip12, h36m17, coco17, ...)")
    joints: list[str] = Field(description="joint names, in the order of every per-joint list")
    bones: list[Annotated[list[Annotated[int, Field(ge=0)]], Field(min_length=2, max_length=2)]]
    root: str = Field(description="the root point, e.g. 'right_hip + left_hip (midpoint)'")


class OtherKeypoints(_Closed):
    """The input's keypoints that were not lifted (face, feet, ...): the names that every
    person's `other_keypoints_2d` and `other_keypoint_confidence` follow."""

    joints: list[str] = Field(description="joint names of the input outside `skeleton`; empty: the input had none")
    note: str | None = None


class Axes(_Closed):
    x: str
    y: str
    z: str


class CameraSummary(_Open):
    """The header's camera: where K came from for the whole result."""

    source: str = Field(description="pseudo | cli | file, or mixed")
    note: str | None = None


class FrameCamera(_Closed):
    """The camera of one frame."""

    K: Annotated[list[Annotated[list[float], Field(min_length=3, max_length=3)]], Field(min_length=3, max_length=3)]
    image_size: Annotated[list[float], Field(min_length=2, max_length=2)] | None = Field(
        description="[width, height] pixels; null where unknown"
    )
    source: str = Field(description="pseudo (f 2000 px at the image centre) | cli | file")
    model: Literal["pinhole", "fisheye"] | None = Field(None, description="lens model (OpenCV)")
    dist: list[float] | None = Field(None, description="distortion coefficients (OpenCV order)")


class Person(_Closed):
    """One person (instance) of a frame; per-joint lists follow `skeleton.joints`."""

    instance_index: Annotated[int, Field(ge=0)]
    input_score: float | None
    keypoints_3d: list[Point3] | None = Field(description="in `units`, `coordinate_frame`; null: not lifted")
    keypoints_3d_root_relative: list[Point3] | None
    root_translation: Point3 | None = Field(description="the root point in the camera frame, in `units`")
    observed: list[bool] = Field(description="the joint was a 2D constraint (false: filled by the prior)")
    joint_confidence: list[float | None]
    keypoints_2d: list[Point2 | None]
    reprojection_error_px: list[NonNegative | None]
    flags: list[str] = Field(
        description="e.g. not_lifted_<reason>, joints_filled_by_prior: <joints>, unstable_solution"
    )
    uncertainty_m: list[NonNegative | None] | None = Field(
        None, description="90 % ball radius per joint in metres (root-relative); absent when not calibrated"
    )
    hypotheses_m: list[list[Point3] | None] | None = Field(
        None, description="the K hypotheses, root-relative, metres (--save-hypotheses)"
    )
    hypothesis_spread_mm: NonNegative | None = Field(
        None,
        description="with --hypotheses K > 1: the hypotheses' RMS distance (mm) from the reported pose at their most "
        "different joint; over 80 mm the flags say unstable_solution; null where not measured; absent with K = 1",
    )
    other_keypoints_2d: list[Point2 | None] | None = Field(
        None,
        description="the input's keypoints outside the skeleton (the header's other_keypoints.joints), "
        "pixels of the original image as the input gave them; null where missing; absent in older results",
    )
    other_keypoint_confidence: list[float | None] | None = Field(
        None, description="their input confidences; null where missing"
    )

    _joints = field_validator(
        "keypoints_3d", "keypoints_3d_root_relative", "observed", "joint_confidence", "keypoints_2d",
        "reprojection_error_px", "uncertainty_m",
    )(_per_joint)  # fmt: skip
    _others = field_validator("other_keypoints_2d", "other_keypoint_confidence")(_per_other)


class Frame(_Closed):
    """The persons of one image (frame), in input order."""

    frame_index: int = Field(description="the input's frame number where it has one, else the frame's position")
    image_id: int | str
    file_name: str | None
    camera: FrameCamera
    persons: list[Person]


class Summary(_Closed):
    instances_total: Annotated[int, Field(ge=0)]
    instances_lifted: Annotated[int, Field(ge=0)]
    instances_skipped: Annotated[int, Field(ge=0)]
    not_lifted: dict[str, int] | None = Field(None, description="reason -> count; absent when all were lifted")
    frames_total: Annotated[int, Field(ge=0)]
    mean_reprojection_error_px: float | None
    seconds: NonNegative


class BoneLength(_Closed):
    """One limb bone of a clip-mode track: its length and its share of the eight limb bones' sum."""

    length_m: NonNegative = Field(description="in the lift's own scale")
    share: NonNegative
    share_low: NonNegative = Field(description="the share's interval at the skeleton's `level`")
    share_high: NonNegative


class TrackSkeleton(_Closed):
    """The skeleton `--temporal clip` estimated for one track, or why the track kept its two-pass poses."""

    track: int | str = Field(description="the track's label")
    frames: Annotated[int, Field(ge=0)] = Field(description="frames the lengths were measured on")
    fallback: str | None = Field(None, description="why the track was lifted two-pass; then nothing else is given")
    bones: dict[str, BoneLength] | None = None
    torso: dict[str, NonNegative] | None = Field(None, description="hip and shoulder widths, trunk length (metres)")
    level: Annotated[float, Field(gt=0, lt=1)] | None = None
    method: str | None = Field(None, description="how the lengths and the shares' intervals were estimated")


class TemporalParams(_Open):
    """How the frames of a sequence were lifted together; open."""

    mode: str | None = Field(None, description="--temporal: none, smooth, two-pass or clip")
    skeletons: list[TrackSkeleton] | None = Field(None, description="clip mode: one per track")


class Params(_Open):
    """The run's settings (preset, steps, seed, prior, ...); open."""

    fps: Annotated[float, Field(gt=0)] | None = Field(None, description="frame rate given to zedo lift --fps")
    temporal: TemporalParams | None = None


class InputInfo(_Open):
    """The input that was lifted (path, format, skeleton, sha256, ...); open."""

    path: str | None = None
    format: str | None = None


class ResultHeader(_Closed):
    """Everything of the document but `frames` and `summary` (the JSON Lines header line)."""

    schema_: Literal["zedo.pose3d/1"] = Field(alias="schema")
    zedo_version: str
    created: str = Field(description="ISO 8601 time of writing")
    skeleton: Skeleton
    other_keypoints: OtherKeypoints | None = Field(
        None, description="the input's keypoints that were not lifted; absent in results written before zedo kept them"
    )
    units: Literal["m", "mm"]
    coordinate_frame: Literal["camera", "root"]
    origin: str | None = Field(None, description="where the origin of a root frame is")
    axes: Axes
    camera: CameraSummary
    input: InputInfo
    params: Params


class ResultDocument(ResultHeader):
    """The JSON document `zedo lift` writes (`-o result.json`)."""

    model_config = ConfigDict(
        strict=True, extra="forbid", title="zedo result (zedo.pose3d/1)",
        json_schema_extra={"$schema": "https://json-schema.org/draft/2020-12/schema"},
    )  # fmt: skip
    frames: list[Frame]
    summary: Summary


class HeaderLine(ResultHeader):
    type: Literal["header"]


class FrameLine(Frame):
    type: Literal["frame"]


class SummaryLine(Summary):
    type: Literal["summary"]


def result_json_schema() -> dict[str, Any]:
    """The JSON Schema (draft 2020-12) of the result document."""
    return ResultDocument.model_json_schema(by_alias=True)


def _where(loc: tuple[int | str, ...]) -> str:
    """`frames[3].persons[0].keypoints_3d[2][1]` from a pydantic location (union member tags dropped)."""
    out = ""
    for part in loc:
        if isinstance(part, int):
            out += f"[{part}]"
        elif not any(c in part for c in "[]-,") and part not in ("int", "str", "float", "bool", "list", "none"):
            out += ("." if out else "") + part
    return out


def field_error(exc: ValidationError, name: str, path: str = "", line: int | None = None) -> InputFormatError:
    """One line naming the file (and line) and the first field that does not fit; `path` is the
    location of the validated object in the document (e.g. `frames[3]`)."""
    err = exc.errors(include_url=False)[0]
    inner = _where(err["loc"])
    where = path + ("." if path and inner and not inner.startswith("[") else "") + inner
    if line is not None:
        name = f"{name}: line {line}"
    message = err["msg"].removeprefix("Value error, ")
    message = message[0].lower() + message[1:]
    if err["type"] not in ("missing", "value_error"):
        message += f", got {err['input']!r:.60}"
    return InputFormatError(f"{name}: {where or 'document'}: {message}")


def validate(
    model: type[BaseModel], obj: Any, name: str, *, path: str = "", line: int | None = None, joints: int | None = None,
    other_joints: int | None = None,
) -> Any:  # fmt: skip
    """`model` validated from `obj`, or an InputFormatError naming the file and the field; `joints`
    and `other_joints` are the lengths the per-joint and the other-keypoint lists must have."""
    try:
        return model.model_validate(obj, context={"joints": joints, "other_joints": other_joints})
    except ValidationError as exc:
        raise field_error(exc, name, path, line) from None
