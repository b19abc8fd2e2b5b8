"""The 3D result as JSON (FORMATS.md 3.8a, schema `zedo.pose3d/1`), written atomically.

Every document states units, coordinate frame, axes and the K used per frame (and its source).
Missing values are `null`, never 0. Instances are grouped into frames by `image_id`, in input
order. By default coordinates are in metres in the camera frame; `units="mm"` and
`frame="root"` (common) change `keypoints_3d`, `keypoints_3d_root_relative` and
`root_translation` alike (the last stays the root point's camera-frame position).

The document is assembled from three parts that the writers stream one by one: `build_header`
(everything but frames and summary), `iter_frames` and `build_summary`. `write_document` writes
them frame by frame into the (temporary) file, so that neither the frames nor the document's
text is ever held whole; the bytes are those of ``json.dumps(document, indent=1)``.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator, Sequence
from datetime import UTC, datetime
from itertools import chain
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ...camera.sanity import CameraSanity, check_camera_sanity
from ...data.keypoints import Keypoints2D
from ...data.skeleton import Skeleton
from ...version import __version__
from ..flags import person_flags
from .common import (
    AXES,
    OutputOptions,
    camera_block,
    frame_origin,
    group_frames,
    json_pieces,
    lens_at,
    output_poses,
    rounded,
    write_text,
)

if TYPE_CHECKING:  # the writers only read a result; importing the solver would load torch
    from ...camera.model import CameraModel
    from ...lifting.solver import LiftResult

SCHEMA = "zedo.pose3d/1"
__all__ = [
    "AXES", "SCHEMA", "build_header", "build_result_document", "build_summary", "iter_frames", "write_document",
    "write_json",
]  # fmt: skip


def _num(value: float, digits: int) -> float | None:
    return None if not math.isfinite(value) else rounded(float(value), digits)


def _points(points: np.ndarray, digits: int = 6) -> list[list[float | None]] | None:
    if not np.isfinite(points).any():
        return None
    return [[_num(v, digits) for v in p] for p in points]


def _skeleton_doc(skeleton: Skeleton) -> dict[str, Any]:
    return {"name": skeleton.name, "joints": list(skeleton.joints), "bones": [list(b) for b in skeleton.bones],
            "root": " + ".join(skeleton.root) + (" (midpoint)" if len(skeleton.root) > 1 else "")}  # fmt: skip


def _person(
    kp: Keypoints2D, res: LiftResult, i: int, poses: np.ndarray, opts: OutputOptions, sanity: CameraSanity
) -> dict[str, Any]:
    flags = person_flags(kp, res, i, sanity)
    d = opts.digits
    return {
        "instance_index": i,
        "input_score": None if kp.scores[i] is None else _num(kp.scores[i], 4),
        "keypoints_3d": _points(poses[i], d),
        "keypoints_3d_root_relative": _points(res.poses_root_relative[i] * opts.scale, d),
        "root_translation": None if not res.lifted[i] else [_num(v * opts.scale, d) for v in res.root_translation[i]],
        "observed": [bool(o) for o in res.observed[i]],
        "joint_confidence": [_num(c, 4) if c > 0 else None for c in kp.confidence[i]],
        "keypoints_2d": [[_num(v, 3) for v in p] if np.isfinite(p).all() else None for p in kp.xy[i]],
        "reprojection_error_px": [_num(e, 3) for e in res.reprojection_error_px[i]],
        "flags": flags,
        **_other_fields(kp, i),
        **_uncertainty_fields(res, i),
    }


def _other_fields(kp: Keypoints2D, i: int) -> dict[str, Any]:
    """The input's keypoints outside the skeleton (`kp.other`, in the header's `other_keypoints`
    order): pixels as the input gave them, and confidences; null where missing. Absent when the
    record carries none (a caller's own `Keypoints2D`)."""
    if kp.other is None:
        return {}
    xy, conf = kp.other.xy[i], kp.other.confidence[i]
    return {
        "other_keypoints_2d": [[_num(v, 3) for v in p] if np.isfinite(p).all() else None for p in xy],
        "other_keypoint_confidence": [_num(c, 4) if c > 0 else None for c in conf],
    }


OTHER_NOTE = (
    "the input's keypoints that were not lifted (2D only): each person's other_keypoints_2d (pixels of the "
    "original image as the input gave them, not undistorted) and other_keypoint_confidence follow these names"
)


def other_keypoints_block(kp: Keypoints2D) -> dict[str, Any] | None:
    """The header's `other_keypoints` (names of the input's keypoints outside the skeleton); None
    when `kp` carries none (then the persons have no `other_keypoints_2d` either)."""
    if kp.other is None:
        return None
    return {"joints": list(kp.other.names), "note": OTHER_NOTE}


def _uncertainty_fields(res: LiftResult, i: int) -> dict[str, Any]:
    """`uncertainty_m` (per joint, metres, whatever the units) when the lift has it, the K
    hypotheses `hypotheses_m` (root-relative, metres) when they were kept (--save-hypotheses), and
    with K > 1 their `hypothesis_spread_mm` (null where not measured)."""
    out: dict[str, Any] = {}
    if res.uncertainty_m is not None:
        out["uncertainty_m"] = [_num(r, 4) for r in res.uncertainty_m[i]]
    if res.hypotheses is not None:
        out["hypotheses_m"] = [_points(h) for h in res.hypotheses[i]] if res.lifted[i] else None
    if res.hypothesis_spread_m is not None:
        out["hypothesis_spread_mm"] = _num(res.hypothesis_spread_m[i] * 1000, 1)
    return out


def build_header(
    kp: Keypoints2D,
    intrinsics: np.ndarray,
    sources: list[str],
    *,
    params: dict[str, Any],
    input_info: dict[str, Any],
    units: str = "m",
    frame: str = "camera",
) -> dict[str, Any]:
    """Everything of the document but `frames` and `summary`, in the document's key order.

    `intrinsics (N, 3, 3)` and `sources (N,)` are only summarised here (the per-frame K is in
    each frame).
    """
    opts = OutputOptions(units, frame)
    unique_sources = sorted(set(sources))
    header: dict[str, Any] = {
        "schema": SCHEMA,
        "zedo_version": __version__,
        "created": datetime.now(UTC).isoformat(timespec="seconds"),
        "skeleton": _skeleton_doc(kp.skeleton),
    }
    other = other_keypoints_block(kp)
    if other is not None:  # only then: a caller's own record writes the document as before
        header["other_keypoints"] = other
    header["units"], header["coordinate_frame"] = opts.units, opts.frame
    if opts.frame != "camera":  # only then, so that the default document stays as it was
        header["origin"] = frame_origin(opts.frame, kp.skeleton.root)
    header.update({
        "axes": AXES,
        "camera": {
            "source": unique_sources[0] if len(unique_sources) == 1 else "mixed",
            "note": "pseudo = f 2000 px at the image centre: absolute depth and scale are only as good "
            "as this guess and the prior" if "pseudo" in unique_sources else None,
        },
        "input": input_info,
        "params": params,
    })  # fmt: skip
    return header


def iter_frames(
    kp: Keypoints2D, res: LiftResult, intrinsics: np.ndarray, sources: list[str], *, units: str = "m",
    frame: str = "camera", lenses: Sequence[CameraModel | None] | None = None,
) -> Iterator[dict[str, Any]]:  # fmt: skip
    """The frames of the document one at a time (a frame = the instances of one image id);
    `lenses (N,)` as in `writers.write_result`."""
    opts = OutputOptions(units, frame)
    poses = output_poses(res, opts)  # (N, J, 3)
    groups = group_frames(kp.image_ids, kp.frame_indices)
    sanity = check_camera_sanity(kp.xy, res.observed, kp.image_sizes, res.root_translation, res.lifted)
    for f, members in enumerate(groups.members):
        first = members[0]
        yield {
            "frame_index": int(groups.number[f]),
            "image_id": kp.image_ids[first],
            "file_name": kp.file_names[first],
            "camera": camera_block(intrinsics[first], kp.image_sizes[first], sources[first], lens_at(lenses, first)),
            "persons": [_person(kp, res, i, poses, opts, sanity) for i in members],
        }


def build_summary(kp: Keypoints2D, res: LiftResult) -> dict[str, Any]:
    lifted = int(res.lifted.sum())
    mean_error = float(np.nanmean(res.reprojection_error_px)) if lifted else float("nan")
    summary: dict[str, Any] = {
        "instances_total": len(kp),
        "instances_lifted": lifted,
        "instances_skipped": len(kp) - lifted,
    }
    if lifted < len(kp):  # why, by reason (only then, so that a fully lifted document stays as it was)
        reasons, counts = np.unique(res.status[~res.lifted], return_counts=True)
        summary["not_lifted"] = {str(r): int(c) for r, c in zip(reasons, counts, strict=True)}
    summary.update({
        "frames_total": len(group_frames(kp.image_ids).members),
        "mean_reprojection_error_px": _num(mean_error, 3),
        "seconds": rounded(res.seconds, 2),
    })  # fmt: skip
    return summary


def build_result_document(
    kp: Keypoints2D,
    res: LiftResult,
    intrinsics: np.ndarray,
    sources: list[str],
    *,
    params: dict[str, Any],
    input_info: dict[str, Any],
    units: str = "m",
    frame: str = "camera",
    lenses: Sequence[CameraModel | None] | None = None,
) -> dict[str, Any]:
    """The JSON-ready result for instances `kp` (already in the prior's joint set)."""
    header = build_header(kp, intrinsics, sources, params=params, input_info=input_info, units=units, frame=frame)
    frames = list(iter_frames(kp, res, intrinsics, sources, units=units, frame=frame, lenses=lenses))
    return {**header, "frames": frames, "summary": build_summary(kp, res)}


def write_document(
    out: str | Path,
    header: dict[str, Any],
    frames: Iterable[dict[str, Any]],
    summary: dict[str, Any],
    *,
    overwrite: bool = True,
) -> None:
    """Write the document ``{**header, "frames": [...], "summary": summary}`` to `out` as
    `write_json` does, one frame at a time as `frames` yields them (e.g. `iter_frames`)."""
    members = [*header.items(), ("frames", iter(frames)), ("summary", summary)]
    write_text(out, chain(json_pieces(members), "\n"), overwrite=overwrite)


def write_json(doc: dict[str, Any], out: str | Path, *, overwrite: bool = True) -> None:
    """Write `doc` to `out` atomically (temporary file in the same folder, then rename), or to
    stdout when `out` is "-". `overwrite` defaults to True here for the callers that check the
    path themselves; `writers.write_result` passes the caller's choice."""
    write_text(out, chain(json_pieces(doc.items()), "\n"), overwrite=overwrite)
