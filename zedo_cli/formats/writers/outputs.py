"""One entry point for writing a 3D result in any output format, with the same options.

    write_result("kp.zedo.csv", kp, res, mats, sources, params, input_info, units="mm", frame="root")

Formats (`OUTPUT_FORMATS`), chosen by `fmt` or else by the output's extension:

- `json`  (.json): one document, schema zedo.pose3d/1 (result_json). The default for stdout.
- `jsonl` (.jsonl, .ndjson): header line, one line per frame, summary line (result_jsonl).
- `csv`   (.csv): one row per frame, person and joint, plus a `.meta.json` sidecar (result_csv).
- `npz`   (.npz): NumPy arrays, one row per instance (result_npz). Not on stdout.
- `trc`   (.trc): OpenSim / Pose2Sim marker files, metres, Y up, one per track (result_trc). Not on stdout.
- `c3d`   (.c3d): C3D marker files, millimetres, the TRC's axes, one per track (result_c3d). Not on stdout.

The marker files (trc, c3d; markers.py) hold the 3D joints only, in their readers' units and axes
(`units` does not apply; `frame` and `marker_axes` do); the first four hold the whole result.

Every format states units, coordinate frame, axes, the K of every frame and where K came from;
missing values are null (JSON) or NaN / empty (NPZ / CSV), never 0. Files are written atomically
and never replace an existing file unless `overwrite=True`.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ...data.keypoints import Keypoints2D
from ...errors import ConfigError
from ...files import check_writable
from .common import FRAMES, UNITS, OutputOptions, camera_block, group_frames, lens_at
from .markers import check_marker_axes, marker_tracks
from .result_c3d import write_c3d
from .result_csv import write_csv
from .result_json import build_header, build_summary, iter_frames, write_document
from .result_jsonl import write_jsonl
from .result_npz import write_npz
from .result_trc import write_trc

if TYPE_CHECKING:  # the writers only read a result; importing the solver would load torch
    from ...camera.model import CameraModel
    from ...lifting.solver import LiftResult

OUTPUT_FORMATS = ("json", "jsonl", "csv", "npz", "trc", "c3d")
MARKER_FORMATS = ("trc", "c3d")  # marker files of biomechanics tools: the 3D joints only, one file per track
_NOT_ON_STDOUT = ("npz", "trc", "c3d")
_EXTENSIONS = {".json": "json", ".jsonl": "jsonl", ".ndjson": "jsonl", ".csv": "csv", ".npz": "npz", ".trc": "trc",
               ".c3d": "c3d"}  # fmt: skip
__all__ = [
    "FRAMES", "MARKER_FORMATS", "OUTPUT_FORMATS", "UNITS", "check_stdout", "default_output_name", "output_format",
    "write_result",
]  # fmt: skip


def output_format(out: str | Path, fmt: str | None = None) -> str:
    """The format to write: `fmt` when given, else from the extension of `out` (json for "-").

    An explicit format that contradicts a known extension (`-o poses.json --format csv`) is an
    error rather than a silently mislabelled file; an unknown extension needs an explicit format.
    """
    if fmt is not None and fmt not in OUTPUT_FORMATS:
        raise ConfigError(f"unknown output format {fmt!r}; choose one of: {', '.join(OUTPUT_FORMATS)}")
    if str(out) == "-":
        return fmt or "json"
    suffix = Path(out).suffix.lower()
    by_name = _EXTENSIONS.get(suffix)
    if fmt is None:
        if by_name is None:
            raise ConfigError(
                f"{out}: cannot tell the output format from the extension {suffix or '(none)'!r}; "
                f"use .json, .jsonl, .csv, .npz, .trc or .c3d, or name the format ({', '.join(OUTPUT_FORMATS)})"
            )
        return by_name
    if by_name is not None and by_name != fmt:
        raise ConfigError(f"{out}: the extension {suffix} says {by_name}, but the format asked for is {fmt}")
    return fmt


def check_stdout(out: str | Path, fmt: str) -> None:
    """Refuse a format that cannot go to stdout ("-"): a binary archive, or marker files (one per track)."""
    if str(out) != "-" or fmt not in _NOT_ON_STDOUT:
        return
    if fmt == "npz":
        raise ConfigError("NPZ is a binary archive and cannot go to stdout; give a .npz file, "
                          "or use --format json/jsonl/csv for stdout")  # fmt: skip
    raise ConfigError(f"{fmt.upper()} marker files are written one per person and cannot go to stdout; "
                      f"give a .{fmt} file with -o, or use json/jsonl/csv for stdout")  # fmt: skip


def default_output_name(input_path: str | Path, fmt: str = "json") -> Path:
    """`<input stem>.zedo.<ext>` beside the input, e.g. `kp.zedo.csv`."""
    if fmt not in OUTPUT_FORMATS:
        raise ConfigError(f"unknown output format {fmt!r}; choose one of: {', '.join(OUTPUT_FORMATS)}")
    path = Path(input_path)
    return path.with_name(f"{path.stem}.zedo.{fmt}")


def _frame_cameras(
    kp: Keypoints2D, intrinsics: np.ndarray, sources: list[str], lenses: Sequence[CameraModel | None] | None
) -> Iterator[dict[str, Any]]:
    """Per frame: ids and the K used, for the formats whose rows do not carry a full camera
    (one at a time: the sidecar and the metadata are written as they come)."""
    groups = group_frames(kp.image_ids, kp.frame_indices)
    for f, members in enumerate(groups.members):
        i = members[0]
        yield {
            "frame_index": int(groups.number[f]), "image_id": kp.image_ids[i], "file_name": kp.file_names[i],
            "camera": camera_block(intrinsics[i], kp.image_sizes[i], sources[i], lens_at(lenses, i)),
        }  # fmt: skip


def write_result(
    out: str | Path,
    kp: Keypoints2D,
    res: LiftResult,
    intrinsics: np.ndarray,
    sources: list[str],
    params: dict[str, Any],
    input_info: dict[str, Any],
    *,
    fmt: str | None = None,
    units: str = "m",
    frame: str = "camera",
    marker_axes: str = "level",
    overwrite: bool = False,
    lenses: Sequence[CameraModel | None] | None = None,
) -> list[Path]:
    """Write the result of lifting `kp` (already in the prior's joint set) to `out` ("-" = stdout).

    `intrinsics (N, 3, 3)` and `sources (N,)` are the K and its source per instance (as from
    `camera.resolve_intrinsics`), `lenses (N,)` each one's lens model and distortion
    coefficients (`ResolvedCameras.lenses`; None: pinhole without distortion); `params` and
    `input_info` go into the metadata unchanged.
    Returns the files written (the CSV's sidecar included, every track's file of TRC / C3D; empty
    for stdout). Raises ConfigError for a bad format, units, frame or `marker_axes`, an existing
    file without `overwrite`, a missing folder, NPZ / TRC / C3D to stdout, or (TRC / C3D) frames
    without frame numbers and without `params["fps"]`; all before anything is written.
    """
    fmt = output_format(out, fmt)
    OutputOptions(units, frame)  # validate before any work
    check_marker_axes(marker_axes)
    check_stdout(out, fmt)
    if fmt in MARKER_FORMATS:  # every track's file is checked by its writer before any is written
        tracks = marker_tracks(kp, res, fps=params.get("fps"), frame=frame, axes=marker_axes, fmt=fmt)
        write = write_trc if fmt == "trc" else write_c3d
        return write(out, tracks, overwrite=overwrite)
    if str(out) != "-":
        check_writable(Path(out), overwrite)
    header = build_header(kp, intrinsics, sources, params=params, input_info=input_info, units=units, frame=frame)
    summary = build_summary(kp, res)
    if fmt in ("json", "jsonl"):  # both stream the frames as they are made, never the whole document
        frames = iter_frames(kp, res, intrinsics, sources, units=units, frame=frame, lenses=lenses)
        write = write_document if fmt == "json" else write_jsonl
        write(out, header, frames, summary, overwrite=overwrite)
        return [] if str(out) == "-" else [Path(out)]
    metadata = {**header, "frames": _frame_cameras(kp, intrinsics, sources, lenses), "summary": summary}
    write = write_csv if fmt == "csv" else write_npz
    return write(out, kp, res, intrinsics, sources, metadata, units=units, frame=frame, overwrite=overwrite,
                 lenses=lenses)  # fmt: skip
