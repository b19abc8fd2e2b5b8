"""A stored result written again in another format (`zedo export`), by the writers of `zedo lift`.

    export_result("clip.zedo.json", "clip.trc")                 # or .c3d, .csv, .jsonl, .json, .npz
    export_result("clip.zedo.csv", "clip.c3d", marker_axes="overhead", person="largest")

The result is read back by `readers.result.read_result` (any format it reads: JSON, JSON Lines,
CSV with its sidecar, NPZ) as the lift that wrote it (`stored_lift`: the 2D input, the poses, the
status, the cameras, the settings) and written by `writers.write_result`, with the same options
and checks as `zedo lift -o` (format from the extension or `fmt`, `units`, `frame`, `marker_axes`,
an existing output refused without `overwrite`, folders made). So `zedo export x.zedo.json -o
x.trc` writes what `zedo lift ... -o x.trc` wrote in the same run, apart from the time of writing;
to the precision the source file keeps (JSON, JSON Lines and CSV: 1 µm, 0.001 px; the C3D's
float32 millimetres may then differ in the last bit; a NPZ keeps every digit).

What a format does not keep cannot come back: a CSV or NPZ result has no detection scores
(`input_score` becomes null), a CSV has no root translation (a root-frame CSV cannot be written
in the camera frame), a CSV written to stdout has no sidecar (no settings, no image sizes).
"""

from __future__ import annotations

from dataclasses import dataclass, fields, replace
from pathlib import Path
from typing import Any

import numpy as np

from ..camera.model import CameraModel
from ..data.keypoints import Keypoints2D, OtherKeypoints
from ..errors import ConfigError, InputFormatError
from ..lifting.config import LiftConfig
from ..lifting.people import PERSON_MODES, select_people
from ..lifting.result import LiftResult
from .readers.result import ResultPoses, read_result
from .writers.common import FRAMES, UNITS
from .writers.outputs import output_format, write_result


@dataclass(frozen=True)
class StoredLift:
    """A result file as the arguments of `writers.write_result`."""

    kp: Keypoints2D  # the 2D input, in the result's joint set
    res: LiftResult
    intrinsics: np.ndarray  # (N, 3, 3)
    sources: list[str]  # (N,) pseudo, cli, file
    lenses: list[CameraModel | None]  # (N,)
    params: dict[str, Any]
    input_info: dict[str, Any]
    units: str  # the file's units and coordinate frame
    frame: str


@dataclass(frozen=True)
class ExportOutcome:
    """What `export_result` did: the files written (every track's TRC / C3D, a CSV's sidecar;
    none for stdout) and the instances and lifted instances they hold."""

    written: list[Path]
    instances: int
    lifted: int
    format: str


def _numbered(frame_index: np.ndarray, person: np.ndarray, info: dict[str, Any]) -> bool:
    """Whether the result's frame numbers are the input's own (else frame positions, as for
    photos): recorded by `zedo lift` as `input.frame_numbers`; for older files, numbers that
    are not the positions 0, 1, 2, ... must be the input's."""
    if isinstance(info.get("frame_numbers"), bool):
        return bool(info["frame_numbers"])
    firsts = frame_index[person == 0]
    return not np.array_equal(firsts, np.arange(len(firsts)))


def stored_lift(r: ResultPoses) -> StoredLift:
    """The lift stored in a result read by `read_result`, rows in the lift's instance order."""
    rec = r.record
    if rec is None:
        raise InputFormatError(f"{r.source}: keeps no 2D input, status or cameras (a NPZ of an older zedo?), so it "
                               "cannot be written again; lift its input once more")  # fmt: skip
    if r.cameras is None or any(c is None for c in r.cameras):
        raise InputFormatError(f"{r.source}: a frame states no camera (K), so it cannot be written again")
    order = np.argsort(rec.instance_index, kind="stable")
    if not np.array_equal(rec.instance_index[order], np.arange(len(order))):
        order = np.arange(len(order))  # not the lift's indices (an edited file): file order
    root = r.root_translation
    rel = rec.poses_root_relative
    joints = r.skeleton.root_indices
    if r.coordinate_frame == "camera":
        cam = r.poses
        root = cam[:, joints].mean(axis=1) if root is None else root
        rel = cam - cam[:, joints].mean(axis=1)[:, None] if rel is None else rel
    else:
        rel = r.poses if rel is None else rel
        cam = rel + root[:, None] if root is not None else np.full_like(rel, np.nan)
    if root is None:
        root = np.full((len(r), 3), np.nan)
    res = LiftResult(  # the writers read every field but `config`
        poses_camera=cam,
        poses_root_relative=rel,
        root_translation=root,
        reprojection_error_px=rec.reprojection_error_px,
        observed=r.observed,
        lifted=r.lifted,
        config=LiftConfig(),
        seconds=rec.seconds,
        status=rec.status,
        hypotheses=rec.hypotheses,
        uncertainty_m=r.uncertainty_m,
        hypothesis_spread_m=r.hypothesis_spread_m,
    )
    info = rec.input_info
    frame_numbers = [int(f) for f in r.frame_index] if _numbered(r.frame_index, r.person, info) else None
    kp = Keypoints2D(rec.keypoints_2d, rec.confidence, r.skeleton, list(r.image_ids), list(r.file_names),
                     rec.image_sizes, list(rec.scores), r.source, str(info.get("format") or r.format),
                     frame_numbers, other=_other_keypoints(r))  # fmt: skip
    lenses = list(r.cameras)
    stored = StoredLift(kp, res, np.stack([c.matrix() for c in lenses]), list(rec.k_sources), lenses,
                        dict(r.params), dict(info), r.units_in_file, r.coordinate_frame)  # fmt: skip
    return subset(stored, order) if not np.array_equal(order, np.arange(len(order))) else stored


def _other_keypoints(r: ResultPoses) -> OtherKeypoints | None:
    """The input's keypoints that were not lifted, as the result keeps them (None: a file from before)."""
    if r.other_keypoints_2d is None or r.other_keypoint_confidence is None:
        return None
    return OtherKeypoints(r.other_keypoint_names, r.other_keypoints_2d, r.other_keypoint_confidence)


def subset(stored: StoredLift, index: np.ndarray) -> StoredLift:
    """The rows `index` of a stored lift (reordered, or the people `--person` keeps)."""
    idx = np.asarray(index, dtype=np.int64)
    res = stored.res
    arrays = {f.name: getattr(res, f.name)[idx] for f in fields(res)
              if isinstance(getattr(res, f.name), np.ndarray)}  # fmt: skip
    return replace(stored, kp=stored.kp.subset(idx), res=replace(res, **arrays), intrinsics=stored.intrinsics[idx],
                   sources=[stored.sources[i] for i in idx], lenses=[stored.lenses[i] for i in idx])  # fmt: skip


def export_result(
    source: str | Path,
    out: str | Path,
    *,
    fmt: str | None = None,
    units: str | None = None,
    frame: str | None = None,
    marker_axes: str = "level",
    person: str = "all",
    fps: float | None = None,
    overwrite: bool = False,
) -> ExportOutcome:
    """Write the result `source` ("-": stdin) to `out` ("-": stdout, for JSON, JSON Lines, CSV) in
    `fmt` (else from the extension). `units` and `frame` default to the source's; `person` keeps
    every person (`all`) or one per frame as `zedo lift --person` chooses, from the result's 2D;
    `fps` gives a result without one its frame rate (a marker file of photos: consecutive frames).
    Raises ConfigError for options that do not fit (before anything is written) and
    InputFormatError for a source that is not a result."""
    fmt = output_format(out, fmt)
    if person not in PERSON_MODES:
        raise ConfigError(f"--person: unknown mode {person!r}; choose one of: {', '.join(PERSON_MODES)}")
    if units is not None and units not in UNITS:
        raise ConfigError(f"--units: unknown units {units!r}; choose one of: {', '.join(UNITS)}")
    if frame is not None and frame not in FRAMES:
        raise ConfigError(f"--frame: unknown coordinate frame {frame!r}; choose one of: {', '.join(FRAMES)}")
    stored = stored_lift(read_result(source))
    frame = frame or stored.frame
    if frame == "camera" and not np.isfinite(stored.res.poses_camera[stored.res.lifted]).all():
        raise ConfigError(f"{source}: holds root-relative poses without their root translation (a root-frame CSV), "
                          "so it cannot be written in the camera frame: give --frame root")  # fmt: skip
    params = dict(stored.params)
    if fps is not None:
        recorded = params.get("fps")
        if recorded is not None and float(recorded) != float(fps):
            raise ConfigError(f"--fps {fps:g}: {source} was lifted at {recorded:g} fps; leave --fps out")
        params["fps"] = float(fps)
    if person != "all":
        stored = subset(stored, select_people(stored.kp, person).index)
    res = stored.res
    written = write_result(out, stored.kp, res, stored.intrinsics, stored.sources, params, stored.input_info,
                           fmt=fmt, units=units or stored.units, frame=frame, marker_axes=marker_axes,
                           overwrite=overwrite, lenses=stored.lenses)  # fmt: skip
    return ExportOutcome(written, len(stored.kp), int(res.lifted.sum()), fmt)
