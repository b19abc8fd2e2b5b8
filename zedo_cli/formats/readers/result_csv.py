"""Reading a zedo result back from its CSV: one row per (frame, person, joint), the keypoints that were
not lifted as rows with an empty `joint_index`; the skeleton, params, image sizes and names of those
keypoints from the `.meta.json` sidecar where there is one."""

from __future__ import annotations

import csv
import io
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from ...camera.model import CameraModel
from ...data.skeleton import skeleton_from_joint_names
from ...errors import InputFormatError
from ...strict_json import loads
from ..flags import flags_from_rows
from .result_common import (
    SCALE_TO_M,
    ReadParts,
    camera_of,
    check_schema,
    dict_of,
    finish,
    other_fields,
    params_of,
    skeleton_of,
)
from .result_record import LiftRecord, ResultPoses

_FRAMES = {"cam": "camera", "root": "root"}


def read_sidecar(path: Path) -> dict[str, Any]:
    try:
        meta = loads(path.read_text(encoding="utf-8-sig"))
    except (OSError, UnicodeDecodeError, ValueError, RecursionError) as exc:
        raise InputFormatError(f"{path}: not a readable JSON sidecar ({exc})") from None
    if not isinstance(meta, dict):
        raise InputFormatError(f"{path}: expected a JSON object")
    check_schema(meta, str(path))
    return meta


def _coordinate_columns(columns: list[str], name: str) -> tuple[list[str], str, str]:
    for tag, frame in _FRAMES.items():
        for units in SCALE_TO_M:
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


def read_csv(text: str, name: str, meta: dict[str, Any] | None) -> ResultPoses:
    """A result CSV (`meta`: its sidecar, None without one)."""
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
    order, joint_names, other_names = _instances(rows, name, xyz)
    names = tuple(joint_names[j] for j in sorted(joint_names))
    skel = skeleton_of(meta, name) if meta is not None else skeleton_from_joint_names(names)
    if skel is None or skel.joints != names:
        raise InputFormatError(f"{name}: joint: the joints {', '.join(names)} are not a zedo skeleton's")
    for (f, p), inst in order.items():
        if len(inst["points"]) != skel.num_joints:
            raise InputFormatError(f"{name}: frame {f}, person {p}: expected {skel.num_joints} joint rows")
    insts, j = list(order.values()), skel.num_joints
    parts = ReadParts(
        name=name, fmt="csv", skeleton=skel,
        poses=[np.array([inst["points"][i] for i in range(j)]) * SCALE_TO_M[units] for inst in insts],
        frame_index=[f for f, _ in order], person=[p for _, p in order],
        image_ids=[int(inst["image_id"]) if inst["image_id"].lstrip("-").isdigit() else inst["image_id"]
                   for inst in insts],
        file_names=[inst["file_name"] for inst in insts], lifted=[inst["lifted"] for inst in insts],
        observed=[np.asarray([inst["observed"][i] for i in range(j)]) for inst in insts],
        radii=[np.asarray([inst["radii"].get(i, np.nan) for i in range(j)], dtype=float) for inst in insts]
        if "uncertainty_m" in columns else None,
        coordinate_frame=coord, units=units, params=params_of(meta), cameras=[inst["camera"] for inst in insts],
    )  # fmt: skip
    spread = np.array([inst["spread"] for inst in insts]) / 1000 if "hypothesis_spread_mm" in columns else None
    flags = [flags_from_rows(names, inst["flags"]) for inst in insts] if "flags" in columns else None
    return replace(finish(parts), record=_csv_record(order, j, meta), hypothesis_spread_m=spread, flags=flags,
                   **_csv_others(order, other_names, meta, name))  # fmt: skip


def _instances(
    rows: list[dict[str, str]], name: str, xyz: list[str]
) -> tuple[dict[tuple[int, int], dict[str, Any]], dict[int, str], dict[str, None]]:
    """The rows gathered per instance, one (frame_index, person): rows come per (frame, person), joints in
    order. With the lifted joints' names by index and the names of the keypoints that were not lifted, in
    order of appearance."""
    order: dict[tuple[int, int], dict[str, Any]] = {}
    joint_names: dict[int, str] = {}
    other_names: dict[str, None] = {}
    for r, row in enumerate(rows, 2):
        where = f"{name}: line {r}"
        try:
            key = (int(row["frame_index"]), int(row["person"]))
            j = int(row["joint_index"]) if row["joint_index"] != "" else None
        except (TypeError, ValueError):
            raise InputFormatError(f"{where}: frame_index, person and joint_index must be integers") from None
        if key not in order:
            order[key] = _new_instance(row, where, len(order))
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
        inst["observed"][j] = _true(row.get("observed", "true"))
        if "uncertainty_m" in row:
            inst["radii"][j] = _cell(row["uncertainty_m"], f"{where}: uncertainty_m")
        inst["flags"][j] = row.get("flags") or ""
    return order, joint_names, other_names


def _new_instance(row: dict[str, str], where: str, count: int) -> dict[str, Any]:
    """An instance from its first row: what is stated once per (frame, person); its joints still to come."""
    return {"image_id": row["image_id"], "file_name": row.get("file_name") or None,
            "lifted": _true(row["lifted"]), "camera": _csv_camera(row, where),
            "status": row.get("status") or ("lifted" if _true(row["lifted"]) else "not_lifted"),
            "k_source": row.get("k_source") or "", "instance": _int_cell(row.get("instance_index"), count),
            "points": {}, "observed": {}, "radii": {}, "pixels": {}, "confidence": {}, "errors": {}, "other": {},
            "flags": {},
            "spread": _cell(row.get("hypothesis_spread_mm") or "", f"{where}: hypothesis_spread_mm")}  # fmt: skip


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
        scores=[None] * len(insts), input_info=dict_of((meta or {}).get("input")),
        seconds=float(seconds) if isinstance(seconds, int | float) else 0.0,
    )  # fmt: skip


def _size(value: Any) -> list[float]:
    """An image size `[w, h]` from a sidecar, NaN where absent or not two numbers."""
    if isinstance(value, list) and len(value) == 2 and all(isinstance(v, int | float) for v in value):
        return [float(v) for v in value]
    return [np.nan, np.nan]


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
    return other_fields(names, list(values[..., :2]), list(values[..., 2]))


def _csv_camera(row: dict[str, str], where: str) -> CameraModel | None:
    """The camera of a CSV row: fx_px, fy_px, cx_px, cy_px and, when present, camera_model and dist."""
    if not all(row.get(c) for c in ("fx_px", "fy_px", "cx_px", "cy_px")):
        return None
    fx, fy, cx, cy = (_cell(row[c], f"{where}: {c}") for c in ("fx_px", "fy_px", "cx_px", "cy_px"))
    dist = [_cell(v, f"{where}: dist") for v in (row.get("dist") or "").split()]
    k = [[fx, 0.0, cx], [0.0, fy, cy], [0.0, 0.0, 1.0]]
    return camera_of({"K": k, "model": row.get("camera_model") or "pinhole", "dist": dist}, f"{where}: camera")


# --- NPZ ----------------------------------------------------------------------------------------
