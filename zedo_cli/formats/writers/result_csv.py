"""The 3D result as a long ("tidy") CSV (FORMATS.md 3.8c): one row per (frame, person, joint).

Metadata choice: the CSV itself is plain RFC 4180 (the first line is the column header, no
comment lines), so `pandas.read_csv`, R's `read.csv` and spreadsheets read it with their
defaults. What a row needs to be read correctly travels in the CSV itself:

- the units and the coordinate frame are in the coordinate column names, `x_cam_m` (camera
  frame, metres), `x_cam_mm`, `x_root_m` or `x_root_mm`, so a script written for one setting
  fails loudly on another instead of misreading numbers;
- the K of each row's frame (`fx_px`, `fy_px`, `cx_px`, `cy_px`; zedo's K has no skew), its
  source (`k_source`: pseudo, cli or file) and the lens (`camera_model`: pinhole or fisheye,
  `dist`: the distortion coefficients in OpenCV's order, space-separated, empty for none) are
  columns.

Everything else (schema, axes, skeleton and bones, input, parameters, summary, and per frame the
full K and image size) goes to a sidecar JSON file beside it, `<name>.meta.json` for
`<name>.csv`. On stdout there is no sidecar; the columns above still state units, frame and K,
and the axes are always OpenCV's (x right, y down, z forward).

The input's keypoints that were not lifted (nose, eyes, ears, feet, ...: `Keypoints2D.other`) follow
each person's lifted joints, one row each with their name in `joint`, an empty `joint_index`, no 3D
and no `observed`, and the input's `confidence`, `u_px`, `v_px` (original image pixels, as given):
`df[df.joint_index.notna()]` is the lifted skeleton alone.

Missing values are empty fields (read as NaN by pandas and NA by R; a literal "nan" would make
R read the column as text), never 0. Booleans are `true`/`false`. Unlifted instances keep their
rows, with empty coordinates and the reason in `status`.
"""

from __future__ import annotations

import csv
import io
import math
import sys
from collections.abc import Iterable, Iterator, Sequence
from itertools import chain
from pathlib import Path
from typing import IO, TYPE_CHECKING, Any

import numpy as np

from ...camera.sanity import check_camera_sanity
from ...data.keypoints import Keypoints2D
from ...files import atomic_path, check_writable
from ..flags import SEPARATOR, joint_flags, person_wide_flags
from .common import (
    OutputOptions,
    camera_block,
    group_frames,
    json_pieces,
    lens_at,
    output_poses,
    rounded,
    write_pieces,
)

if TYPE_CHECKING:  # the writers only read a result; importing the solver would load torch
    from ...camera.model import CameraModel
    from ...lifting.solver import LiftResult


def coordinate_columns(units: str = "m", frame: str = "camera") -> list[str]:
    """The names of the x, y, z columns for these options, e.g. `["x_cam_m", "y_cam_m", "z_cam_m"]`."""
    opts = OutputOptions(units, frame)
    tag = "cam" if opts.frame == "camera" else "root"
    return [f"{axis}_{tag}_{opts.units}" for axis in "xyz"]


def csv_columns(
    units: str = "m", frame: str = "camera", *, uncertainty: bool = False, spread: bool = False
) -> list[str]:
    """The header row; `uncertainty_m` when the result has a calibrated uncertainty, then
    `hypothesis_spread_mm` when it has K > 1 hypotheses."""
    return [
        "frame_index", "image_id", "file_name", "person", "instance_index", "joint", "joint_index",
        *coordinate_columns(units, frame), "observed", "lifted", "status", "confidence", "u_px", "v_px",
        "reprojection_error_px", "fx_px", "fy_px", "cx_px", "cy_px", "k_source", "camera_model", "dist", "flags",
        *(["uncertainty_m"] if uncertainty else []), *(["hypothesis_spread_mm"] if spread else []),
    ]  # fmt: skip


def sidecar_path(path: str | Path) -> Path:
    """`<name>.meta.json` beside `<name>.csv` (any other name: the name + ".meta.json")."""
    path = Path(path)
    return path.with_suffix(".meta.json") if path.suffix.lower() == ".csv" else path.with_name(path.name + ".meta.json")


def _cell(value: float, digits: int) -> str:
    return "" if not math.isfinite(value) else repr(rounded(float(value), digits))


def _bool(value: bool) -> str:
    return "true" if value else "false"


def csv_rows(
    kp: Keypoints2D, res: LiftResult, intrinsics: np.ndarray, sources: list[str], *, units: str = "m",
    frame: str = "camera", lenses: Sequence[CameraModel | None] | None = None,
) -> Iterator[list[Any]]:  # fmt: skip
    """The CSV's rows one at a time: the header row, then frame, person and joint order."""
    opts = OutputOptions(units, frame)
    poses = output_poses(res, opts)  # (N, J, 3)
    groups = group_frames(kp.image_ids, kp.frame_indices)
    radii, spread = res.uncertainty_m, res.hypothesis_spread_m
    yield csv_columns(units, frame, uncertainty=radii is not None, spread=spread is not None)
    blanks = [""] * ((radii is not None) + (spread is not None))  # the other keypoints' last cells
    sanity = check_camera_sanity(kp.xy, res.observed, kp.image_sizes, res.root_translation, res.lifted)
    for members in groups.members:
        for i in members:
            wide = person_wide_flags(res, i, sanity)
            k = intrinsics[i]
            lens = camera_block(k, kp.image_sizes[i], sources[i], lens_at(lenses, i))
            camera = [_cell(k[0, 0], 6), _cell(k[1, 1], 6), _cell(k[0, 2], 6), _cell(k[1, 2], 6), sources[i],
                      lens["model"], " ".join(repr(c) for c in lens["dist"])]  # fmt: skip
            head = [int(groups.frame_index[i]), kp.image_ids[i], kp.file_names[i] or "", int(groups.person[i]), i]
            for j, joint in enumerate(kp.skeleton.joints):
                conf = kp.confidence[i, j]
                yield [
                    *head, joint, j, *(_cell(v, opts.digits) for v in poses[i, j]),
                    _bool(res.observed[i, j]), _bool(res.lifted[i]), str(res.status[i]),
                    _cell(conf, 4) if conf > 0 else "",
                    _cell(kp.xy[i, j, 0], 3), _cell(kp.xy[i, j, 1], 3),
                    _cell(res.reprojection_error_px[i, j], 3), *camera,
                    SEPARATOR.join(wide + joint_flags(kp, res, i, j)),
                    *([] if radii is None else [_cell(radii[i, j], 4)]),
                    *([] if spread is None else [_cell(spread[i] * 1000, 1)]),
                ]  # fmt: skip
            yield from _other_rows(kp, i, head, [_bool(res.lifted[i]), str(res.status[i])], camera,
                                   [SEPARATOR.join(wide), *blanks])  # fmt: skip


def _other_rows(
    kp: Keypoints2D, i: int, head: list[Any], instance: list[str], camera: list[Any], blanks: list[str]
) -> Iterator[list[Any]]:
    """Instance `i`'s keypoints that were not lifted (`kp.other`), one row each after its lifted
    joints: the name, an empty joint_index, no 3D, the input's confidence and pixels as given."""
    if kp.other is None:
        return
    for e, name in enumerate(kp.other.names):
        conf = kp.other.confidence[i, e]
        u, v = kp.other.xy[i, e]
        yield [
            *head, name, "", "", "", "", "", *instance, _cell(conf, 4) if conf > 0 else "", _cell(u, 3), _cell(v, 3),
            "", *camera, *blanks,
        ]  # fmt: skip


def _write_rows(rows: Iterable[list[Any]], fh: IO[str]) -> None:
    """The rows in CSV syntax, one frame's worth (a few hundred rows) at a time."""
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    for n, row in enumerate(rows, start=1):
        writer.writerow(row)
        if n % 4096 == 0:
            fh.write(buf.getvalue())
            buf.seek(0)
            buf.truncate()
    fh.write(buf.getvalue())


def csv_text(
    kp: Keypoints2D, res: LiftResult, intrinsics: np.ndarray, sources: list[str], *, units: str = "m",
    frame: str = "camera", lenses: Sequence[CameraModel | None] | None = None,
) -> str:  # fmt: skip
    """The CSV as one string (the header row, then the rows in frame, person, joint order)."""
    buf = io.StringIO()
    _write_rows(csv_rows(kp, res, intrinsics, sources, units=units, frame=frame, lenses=lenses), buf)
    return buf.getvalue()


def _column_notes(units: str, frame: str) -> dict[str, str]:
    x, y, z = coordinate_columns(units, frame)
    where = "camera frame" if frame == "camera" else "relative to the person's root point"
    return {
        "frame_index": (
            "the input's frame number (OpenPose file name, MMPose frame_id, JSONL frame) where it has one, "
            "else the 0-based output frame (instances grouped by image_id, in input order)"
        ),
        "person": "0-based position of the instance within its frame",
        "joint, joint_index": "the joint's name and its index in the skeleton; joint_index empty for the input's "
        "keypoints that were not lifted (the sidecar's other_keypoints: 2D only, after each person's lifted joints)",
        "instance_index": "0-based index of the instance in the input",
        f"{x}, {y}, {z}": f"3D joint position in {units}, {where}; empty where not lifted",
        "observed": "the joint was a 2D constraint (false: filled by the prior); empty for a keypoint not lifted",
        "lifted": "the instance was lifted (false: coordinates empty, `status` says why)",
        "status": "'lifted', or why the instance was not (too_few_observed_joints, ray_out_of_range, "
        "degenerate_geometry, non_finite_result, behind_camera, poor_fit, implausible_skeleton; docs/outputs.md)",
        "confidence": "input joint confidence; empty where missing",
        "u_px, v_px": "input 2D keypoint in pixels of the original image, as the input gave it; empty where missing",
        "reprojection_error_px": "pixel distance between the 2D input and the projected 3D joint; empty if unobserved",
        "fx_px, fy_px, cx_px, cy_px": "intrinsics K of the row's frame (no skew)",
        "k_source": "where K came from: pseudo (f 2000 px at the image centre), cli or file",
        "camera_model": "the lens model: pinhole (OpenCV's, with distortion coefficients) or fisheye",
        "dist": "distortion coefficients in OpenCV's order, space-separated; empty: none (2D undistorted "
        "before lifting when there are some; reprojection errors are in the original image)",
        "flags": "'; '-separated: the person's flags (implausible_distance, keypoints_outside_image, "
        "unstable_solution, left_right_swapped_in_2d) and this joint's own (--temporal clip: detection_outlier, "
        "depth_ambiguous, at an ankle or wrist with the other side's knee or elbow flexion); empty: none",
        "uncertainty_m": "only when calibrated: radius in metres (whatever the units) of the ball around the "
        "root-relative joint that holds the true joint with 90 % probability; empty where not lifted",
        "hypothesis_spread_mm": "only with --hypotheses K > 1: the person's hypotheses' RMS distance (mm) from the "
        "reported pose at their most different joint; over 80 mm the pose may be another solution (a depth "
        "flip; the JSON's unstable_solution flag); empty where not measured",
    }


def write_csv(
    out: str | Path,
    kp: Keypoints2D,
    res: LiftResult,
    intrinsics: np.ndarray,
    sources: list[str],
    metadata: dict[str, Any],
    *,
    units: str = "m",
    frame: str = "camera",
    overwrite: bool = False,
    lenses: Sequence[CameraModel | None] | None = None,
) -> list[Path]:
    """Write the CSV and its sidecar (`metadata` = the JSON header plus summary and per-frame
    cameras; a value may be an iterator, written as a list as it yields) to `out`, or the CSV
    alone to stdout ("-"). Both are written row by row, never held whole. Returns the paths written."""
    rows = csv_rows(kp, res, intrinsics, sources, units=units, frame=frame, lenses=lenses)
    if str(out) == "-":
        _write_rows(rows, sys.stdout)
        sys.stdout.flush()
        return []
    path, meta = Path(out), sidecar_path(out)
    check_writable(path, overwrite)  # both checked before either is written
    check_writable(meta, overwrite)
    sidecar = {**metadata, "data_file": path.name, "columns": _column_notes(units, frame)}
    with atomic_path(meta, overwrite=overwrite) as tmp_meta, atomic_path(path, overwrite=overwrite) as tmp_csv:
        with open(tmp_meta, "w", encoding="utf-8") as fh:
            write_pieces(chain(json_pieces(sidecar.items()), "\n"), fh)
        with open(tmp_csv, "w", encoding="utf-8") as fh:
            _write_rows(rows, fh)
    return [path, meta]
