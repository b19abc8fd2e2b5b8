"""What the result readers (`result_json`, `result_csv`, `result_npz`) share: the schema check, the
refusal of a 2D keypoint file, skeletons, units, cameras, the keypoints that were not lifted, and
`ReadParts`, the per-person columns a reader gathered, made into a `ResultPoses` by `finish`."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ...camera.model import CameraModel
from ...data.skeleton import Skeleton, get_skeleton
from ...errors import ConfigError, InputFormatError, IntrinsicsError
from ..result_schema import SCHEMA
from .result_record import LiftParams, ResultPoses

SCALE_TO_M = {"m": 1.0, "mm": 1e-3}


def refuse_keypoints(doc: Any, name: str) -> None:
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


def check_schema(doc: dict[str, Any], name: str) -> None:
    if doc.get("schema") != SCHEMA:
        raise InputFormatError(f"{name}: schema: expected a zedo result file (schema {SCHEMA}), "
                               f"got {doc.get('schema')!r}")  # fmt: skip


def as_floats(values: list[Any] | None, shape: tuple[int, ...]) -> np.ndarray:
    """A validated list (of lists) of numbers or null as floats, NaN for null; all NaN for None."""
    if values is None:
        return np.full(shape, np.nan)
    return np.array(values, dtype=float).reshape(shape)  # None -> nan


def other_fields(names: tuple[str, ...], xy: list[np.ndarray], conf: list[np.ndarray]) -> dict[str, Any]:
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


def pixels(points: list[list[float | None] | None]) -> np.ndarray:
    """A person's validated `keypoints_2d` (a point, or null where missing) as `(J, 2)` floats, NaN for null."""
    return np.array([[np.nan, np.nan] if p is None else p for p in points], dtype=float).reshape(-1, 2)


def camera_of(block: Any, where: str) -> CameraModel | None:
    """A camera block `{"K", "image_size", "source", "model", "dist"}` (None: absent)."""
    if block is None:
        return None
    try:
        return CameraModel.from_json(block)
    except KeyError as exc:
        raise InputFormatError(f"{where}.{exc.args[0]}: missing") from None
    except (TypeError, ValueError, AttributeError, IntrinsicsError) as exc:
        raise InputFormatError(f"{where}: not a camera (K, model, dist, image_size): {exc}") from None


def skeleton_of(doc: dict[str, Any], name: str) -> Skeleton:
    skel = doc.get("skeleton")
    if not isinstance(skel, dict) or not isinstance(skel.get("name"), str):
        raise InputFormatError(f"{name}: skeleton.name: missing")
    try:
        return get_skeleton(skel["name"])
    except ConfigError as exc:
        raise InputFormatError(f"{name}: skeleton.name: {exc}") from None


def units_of(value: Any, name: str, field: str = "units") -> str:
    if value not in SCALE_TO_M:
        raise InputFormatError(f"{name}: {field}: expected m or mm, got {value!r}")
    return str(value)


def params_of(doc: Any) -> dict[str, Any]:
    params = doc.get("params") if isinstance(doc, dict) else None
    return params if isinstance(params, dict) else {}


def dict_of(value: Any) -> dict[str, Any]:
    return value if isinstance(value, dict) else {}


@dataclass(frozen=True)
class ReadParts:
    """The columns a reader gathered, one entry per person of every frame, in file order."""

    name: str  # the path read, or "-"
    fmt: str  # json | jsonl | csv
    skeleton: Skeleton
    poses: list[np.ndarray]  # (J, 3) each, metres
    frame_index: list[int]
    person: list[int]
    image_ids: list[Any]
    file_names: list[Any]  # "" or None: none
    lifted: list[bool]
    observed: list[np.ndarray]  # (J,) bool each
    radii: list[np.ndarray] | None  # (J,) each; None: the file has no uncertainty_m
    coordinate_frame: str  # camera | root
    units: str  # m | mm: the file's
    params: dict[str, Any]  # the lift's raw `params` ({} when not recorded)
    cameras: list[CameraModel | None] | None = None


def finish(parts: ReadParts) -> ResultPoses:
    """The ResultPoses of `parts` (refused when there is no person); `fps` from the typed params."""
    if not parts.poses:
        raise InputFormatError(f"{parts.name}: no persons in the result")
    j, cameras = parts.skeleton.num_joints, parts.cameras
    return ResultPoses(
        source=parts.name, format=parts.fmt, skeleton=parts.skeleton,
        poses=np.asarray(parts.poses, dtype=float).reshape(-1, j, 3),
        frame_index=np.asarray(parts.frame_index, dtype=np.int64), person=np.asarray(parts.person, dtype=np.int64),
        image_ids=list(parts.image_ids), file_names=[None if not f else str(f) for f in parts.file_names],
        lifted=np.asarray(parts.lifted, dtype=bool), observed=np.asarray(parts.observed, dtype=bool).reshape(-1, j),
        uncertainty_m=None if parts.radii is None else np.asarray(parts.radii, dtype=float).reshape(-1, j),
        fps=LiftParams.from_dict(parts.params, parts.name).fps, coordinate_frame=parts.coordinate_frame,
        units_in_file=parts.units, params=parts.params,
        cameras=cameras if cameras and any(c is not None for c in cameras) else None,
    )  # fmt: skip
