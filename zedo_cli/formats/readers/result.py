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

This module is the entry point: it tells the format and hands the data to `result_json` (JSON and
JSON Lines), `result_csv` or `result_npz`; what they return (`ResultPoses`, `LiftRecord`, the typed
`LiftParams`) is defined in `result_record` and importable from here.
"""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

from ...collection import paused_collection
from ...errors import InputFormatError
from ...strict_json import loads
from ..result_schema import SCHEMA
from .result_common import refuse_keypoints
from .result_csv import read_csv, read_sidecar
from .result_json import read_document, read_jsonl, read_streamed
from .result_npz import read_npz
from .result_record import LiftParams, LiftRecord, ResultPoses
from .source import json_error

__all__ = ["RESULT_FORMATS", "LiftParams", "LiftRecord", "ResultPoses", "read_result", "read_result_bytes"]

RESULT_FORMATS = ("json", "jsonl", "csv", "npz")


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
    sidecar = None if name == "-" else _sidecar_of(Path(path))
    with paused_collection():
        if _blank(data) or data[:4] == _NPZ:
            return read_result_bytes(data, name, sidecar=sidecar)
        text = _text_of(data, name)
        del data  # a long clip's bytes go before its text is parsed
        return read_result_text(text, name, sidecar=sidecar)


def _sidecar_of(path: Path) -> Path:
    return path.with_suffix(".meta.json") if path.suffix.lower() == ".csv" else path.with_name(path.name + ".meta.json")


_NPZ = b"PK\x03\x04"


def _blank(data: bytes) -> bool:
    return re.fullmatch(rb"\s*", data) is not None


def _text_of(data: bytes, name: str) -> str:
    try:
        return data.decode("utf-8-sig")  # a byte-order mark: a CSV that Excel saved as UTF-8
    except UnicodeDecodeError:
        raise InputFormatError(f"{name}: not a zedo result (neither UTF-8 text nor a NPZ archive)") from None


def read_result_bytes(data: bytes, name: str, *, sidecar: Path | None = None) -> ResultPoses:
    """Parse the bytes of a result; `name` is used in messages, `sidecar` is the CSV's
    `.meta.json` (read when the data is a CSV and the file exists)."""
    if _blank(data):
        raise InputFormatError(f"{name}: empty file (expected a zedo result: {', '.join(RESULT_FORMATS)})")
    if data[:4] == _NPZ:
        return read_npz(data, name)
    return read_result_text(_text_of(data, name), name, sidecar=sidecar)


def read_result_text(text: str, name: str, *, sidecar: Path | None = None) -> ResultPoses:
    """Parse the text of a result (CSV, a JSON document or JSON Lines)."""
    stripped = text.lstrip()
    if stripped.startswith("frame_index,"):
        meta = read_sidecar(sidecar) if sidecar is not None and sidecar.is_file() else None
        return read_csv(text, name, meta)
    if stripped.startswith("{"):
        streamed = read_streamed(text, name)
        if streamed is not None:
            return streamed
        try:
            doc = loads(text)
        except json.JSONDecodeError:
            doc = None  # several lines: JSON Lines
        except (ValueError, RecursionError) as exc:  # a repeated key, a 5000-digit integer, deep nesting
            raise json_error(name, "", exc) from None
        if isinstance(doc, dict) and doc.get("type") != "header":
            refuse_keypoints(doc, name)
            return read_document(doc, name, "json")
        return read_jsonl(text, name)
    if stripped.startswith("["):  # a list: a detector's (COCO results, MMPose, ...), never a result
        try:
            refuse_keypoints(json.loads(text), name)
        except json.JSONDecodeError:
            pass
    raise InputFormatError(f"{name}: not a zedo result (expected a {SCHEMA} JSON / JSON Lines document, "
                           "a zedo CSV or a NPZ archive)")  # fmt: skip
