"""The analysis as a tidy CSV and as JSON, written atomically (or to stdout for "-").

CSV (plain RFC 4180, one header line, read by pandas / R with their defaults): the columns of
`table.COLUMNS`, one row per frame, person and measure, then the per-clip features (frame
columns empty). Unknown values are empty fields, never 0. `value` is the measure's estimate,
`raw_value` the measure of the reported pose. `low` and `high` are its interval at `level` (--level), empty
where none; `interval` says how they were obtained (a code of `table.INTERVAL_METHODS`: `calibrated`,
`calibrated_filled`, `median_of_frame_interval_ends`, `block_bootstrap_and_share_calibration`,
`not_for_clip_features`, or `none`) and `interval_note` more (for `none`, why: no calibration holds for the
result, a joint filled by the prior, a joint missing, a face point missing). `flag` is `too_fast` where a joint
angle changed faster than the stated bound, and `eye_line_reversed` where the eye line points against the
shoulder line (head_tilt_deg folded).

JSON (schema `zedo.analysis/2`): the same rows, plus the input, the settings, the notes (e.g.
that no uncertainty was available), the measures' units and descriptions, and a summary.
"""

from __future__ import annotations

import itertools
import json
import math
from collections.abc import Iterator
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from ..files import atomic_path
from ..formats.writers.common import RawItems, json_pieces, rounded, write_text
from ..version import __version__
from .analyse import Analysis, summary
from .pose.symmetry import BAND_EDGES_DEG, PAIRS
from .schema import SCHEMA
from .table import COLUMNS, CSV_HEADER, DECIMALS, INTERVAL_METHODS, csv_and_json, json_rows
from .table import csv_lines as table_lines
from .uncertainty.calibration import backing


def _num(value: Any) -> Any:
    if isinstance(value, float):
        if not math.isfinite(value):
            return None
        return int(value) if float(value).is_integer() else rounded(float(value), DECIMALS)
    return value


def csv_lines(a: Analysis) -> Iterator[str]:
    """The tidy CSV, a block of rows at a time (a 10-minute clip has about half a million rows)."""
    return table_lines(a.blocks())


def csv_text(a: Analysis) -> str:
    return "".join(csv_lines(a))


def measure_descriptions() -> dict[str, str]:
    """One line per measure family, for the JSON and the report."""
    return {
        "symmetry_<pair>_deg": "angle between the left segment and the right one mirrored through the body's "
        "mid-plane (shoulders for arms, hips for legs); 0 = mirror-symmetric. Pairs: "
        + ", ".join(f"{p} ({a} -> {b})" for p, (a, b, _) in PAIRS.items()),
        "symmetry_<pair>_band": "the paper's band of that angle: 1 (< 30 deg), 2 (30 to < 60), 3 (>= 60)",
        "<side>_knee_flexion_deg, <side>_elbow_flexion_deg": "angle between the proximal and distal segment; "
        "0 = straight",
        "<side>_hip_flexion_deg, <side>_shoulder_flexion_deg": "thigh / upper arm in the trunk's sagittal plane "
        "from straight down the trunk, positive forward; [-90, 270); empty beyond 80 deg abduction",
        "<side>_hip_abduction_deg, <side>_shoulder_abduction_deg": "thigh / upper arm out of the sagittal plane, "
        "positive away from the midline",
        "<angle>_median_abs_velocity_deg_s, <angle>_abs_velocity_iqr_deg_s": "per clip: median and IQR of "
        "|angular velocity| between consecutive known frames",
        "<angle>_range_deg": "per clip: max - min of the angle",
        "<base>_left_right_correlation": "per clip: Pearson r of the left and right series",
        "symmetry_<pair>_fraction_<call>": "per clip: share of the frames called symmetric, asymmetric or "
        "uncertain (the frame rows' calls, counted)",
        "symmetry_<pair>_probability_asymmetric": "per frame: the probability that the true symmetry angle exceeds "
        "the threshold, from the frame's calibrated interval (the level at which it touches the threshold); empty "
        "without a calibrated interval",
        "symmetry_<pair>_share_asymmetric": "per clip: the share of the frames whose true symmetry angle exceeds the "
        "threshold, estimated as the mean of the frames' probability_asymmetric; its interval draws the frames' "
        "truths with errors shared by neighbouring frames (a block bootstrap, docs/clinical.md), not a binomial one",
        "symmetry_<pair>_median_deg": "per clip: the median of the frames' estimates; its interval is the median "
        "of the frames' interval ends (coverage measured on synthetic clips, docs)",
        "<angle>_frames_too_fast": "per clip: frames whose angle changed faster than the bound (left out of the "
        "movement features)",
        "<stat>_<L|R><Shoulder|Elbow|Hip|Knee>, lrCorr_angle_<part>": "per clip: the published 2D angle features "
        "of Chambers et al. 2020 from the input's 2D keypoints, computed as their code does (docs/movement.md)",
        "<stat>_<L|R><Ankle|Wrist>, lrCorr_x_<part>": "per clip: the published 2D position features (body frame, "
        "trunk lengths) of Chambers et al. 2020",
        "<Part>_<stat>": "per clip: the 38 pre-registered part-level features of Chambers et al. 2020, left and "
        "right averaged (e.g. Ankle_medianx, Knee_lrCorr_angle)",
        "3d_<stat>_<L|R><part>, 3d_lrCorr_angle_<part>": "per clip: the published angle statistics on the lifted 3D "
        "elbow and knee interior angles and the trunk-frame hip and shoulder flexion and abduction",
        "3d_mean_dispersion_<L|R><Wrist|Ankle>": "per clip: the mean distance of the joint's trunk-normalised 3D "
        "position from its clip centroid (trunk lengths)",
        "head_tilt_deg": "angle in the image between the eye line and the shoulder line (right to left), in "
        "(-90, 90]; positive: the head tilted towards the infant's own left shoulder (habitual head deviation)",
        "head_turn": "call left / right / midline (the infant's own side, from its shoulders); value: the face's "
        "yaw in degrees, positive to the infant's left, from the nose between the ears / eyes (infant head "
        "model); midline within 20 degrees; a face seen from one side only gets the call without a value",
        "head_turn_fraction_<call>": "per clip: share of the frames with a head_turn call that are left, right or "
        "midline (the frame rows' calls, counted); 90 % interval: a circular block bootstrap widened by its "
        "calibration on held-out synthetic clips (analysis.head_calibration)",
        "head_tilt_median_deg": "per clip: the median of the frames' head_tilt_deg; 90 % interval: a circular "
        "block bootstrap widened by its calibration on held-out synthetic clips (analysis.head_calibration)",
    }


def analysis_document(a: Analysis) -> dict[str, Any]:
    """The JSON document (schema `zedo.analysis/2`) as a dict, every row in it."""
    return {key: [json.loads(row) for part in value for row in part] if key == "rows" else value
            for key, value in _document_members(a)}  # fmt: skip


def used_calibrations(a: Analysis) -> list[dict[str, Any]]:
    """What backs the analysis's intervals: each measure calibration used (frames, then clips), by id."""
    used = [] if a.assignment is None else a.assignment.used()
    if a.clip_calibration is not None:
        used.append(a.clip_calibration)
    return [backing(c) for c in used]


def _document_members(a: Analysis, rows: Iterator[RawItems] | None = None) -> Iterator[tuple[str, Any]]:
    """The document's (key, value) pairs in order; "rows" an iterator of the rows' text a part at a time (`rows`,
    default `json_rows`), so that the writer streams them (`json_pieces`) instead of holding half a million rows."""
    res = a.result
    uncertainty = {
        "available": a.uncertainty_available,
        "note": a.calibration_note,
        "level": a.settings.level,
        "calibrations": used_calibrations(a),
        "method": "per measure: the estimate and its interval from a split-conformal calibration on held-out "
        "lifts, by bins of the measured value (analysis.calibration, docs/clinical.md); the interval column of "
        "each row says how its interval was obtained (interval_methods), interval_note more, or why it has none",
        "interval_methods": INTERVAL_METHODS,
    }
    yield from {
        "schema": SCHEMA,
        "zedo_version": __version__,
        "created": datetime.now(UTC).isoformat(timespec="seconds"),
        "input": {
            "path": res.source,
            "format": res.format,
            "skeleton": res.skeleton.name,
            "coordinate_frame": res.coordinate_frame,
            "units_in_file": res.units_in_file,
            "persons": len(res),
            "persons_analysed": len(a.index),
            "frames": len(set(res.frame_index.tolist())),
        },  # fmt: skip
        "settings": {
            "symmetry_threshold_deg": a.settings.threshold_deg,
            "symmetry_bands_deg": list(BAND_EDGES_DEG),
            "fps": a.fps,
            "fps_source": a.fps_source,
            "interval_level": a.settings.level,
            "max_angular_velocity_deg_s": a.settings.max_velocity_deg_s,
        },  # fmt: skip
        "uncertainty": uncertainty,
        "notes": list(a.notes),
        "columns": list(COLUMNS),
        "measures": measure_descriptions(),
        "summary": {k: {s: _num(v) for s, v in d.items()} for k, d in summary(a).items()},
    }.items()
    yield "rows", map(RawItems, json_rows(a.blocks())) if rows is None else rows


def write_csv(a: Analysis, out: str | Path, *, overwrite: bool = False) -> None:
    """The tidy CSV to `out` ("-" = stdout), atomically; an existing file only with `overwrite`."""
    write_text(out, csv_lines(a), overwrite=overwrite)


def write_json(a: Analysis, out: str | Path, *, overwrite: bool = False) -> None:
    """The JSON document to `out` ("-" = stdout), atomically; an existing file only with `overwrite`.
    Indented, each row on a line of its own; written a row at a time."""
    _write_document(a, out, None, overwrite)


def _write_document(a: Analysis, out: str | Path, rows: Iterator[RawItems] | None, overwrite: bool) -> None:
    pieces = json_pieces(_document_members(a, rows), indent=1, one_line_items=True)
    write_text(out, itertools.chain(pieces, ["\n"]), overwrite=overwrite)


def write_csv_and_json(a: Analysis, csv_out: Path, json_out: Path, *, overwrite: bool = False) -> None:
    """`write_csv` and `write_json` to two files in one pass over the rows, each number formatted once: the CSV is
    written as the JSON's rows are."""
    with atomic_path(csv_out, overwrite=overwrite) as tmp, open(tmp, "w", encoding="utf-8") as fh:

        def rows() -> Iterator[RawItems]:
            fh.write(CSV_HEADER)
            for lines, part in csv_and_json(a.blocks()):
                fh.write(lines)
                yield RawItems(part)

        _write_document(a, json_out, rows(), overwrite)
