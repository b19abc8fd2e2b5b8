"""The 3D result as JSON (FORMATS.md 3.8a, schema `zedo.pose3d/1`), written atomically.

Every document states units (m), frame (camera), axes and the K used per frame. Missing
values are `null`, never 0. Instances are grouped into frames by `image_id`, in input order.
"""

from __future__ import annotations

import json
import math
import os
import sys
import tempfile
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np

from .. import __version__
from ..lifting import LiftResult
from ..skeleton import Skeleton
from .keypoints import Keypoints2D

SCHEMA = "zedo.pose3d/1"
AXES = {"x": "right", "y": "down", "z": "forward (away from the camera)"}


def _num(value: float, digits: int) -> float | None:
    return None if not math.isfinite(value) else round(float(value), digits)


def _points(points: np.ndarray, digits: int = 6) -> list[list[float | None]] | None:
    if not np.isfinite(points).any():
        return None
    return [[_num(v, digits) for v in p] for p in points]


def _skeleton_doc(skeleton: Skeleton) -> dict[str, Any]:
    return {"name": skeleton.name, "joints": list(skeleton.joints), "bones": [list(b) for b in skeleton.bones],
            "root": " + ".join(skeleton.root) + (" (midpoint)" if len(skeleton.root) > 1 else "")}  # fmt: skip


def _person(kp: Keypoints2D, res: LiftResult, i: int) -> dict[str, Any]:
    flags = [] if res.lifted[i] else ["not_lifted_too_few_observed_joints"]
    missing = [kp.skeleton.joints[j] for j in np.flatnonzero(~res.observed[i])]
    if missing and res.lifted[i]:
        flags.append("joints_filled_by_prior: " + ", ".join(missing))
    return {
        "instance_index": i,
        "input_score": None if kp.scores[i] is None else _num(kp.scores[i], 4),
        "keypoints_3d": _points(res.poses_camera[i]),
        "keypoints_3d_root_relative": _points(res.poses_root_relative[i]),
        "root_translation": None if not res.lifted[i] else [_num(v, 6) for v in res.root_translation[i]],
        "observed": [bool(o) for o in res.observed[i]],
        "joint_confidence": [_num(c, 4) if c > 0 else None for c in kp.confidence[i]],
        "keypoints_2d": [[_num(v, 3) for v in p] if np.isfinite(p).all() else None for p in kp.xy[i]],
        "reprojection_error_px": [_num(e, 3) for e in res.reprojection_error_px[i]],
        "flags": flags,
    }


def build_result_document(
    kp: Keypoints2D,
    res: LiftResult,
    intrinsics: np.ndarray,
    sources: list[str],
    *,
    params: dict[str, Any],
    input_info: dict[str, Any],
) -> dict[str, Any]:
    """The JSON-ready result for instances `kp` (already in the prior's joint set)."""
    frames: dict[str, dict[str, Any]] = {}
    for i in range(len(kp)):
        key = repr(kp.image_ids[i])
        if key not in frames:
            size = kp.image_sizes[i]
            frames[key] = {
                "frame_index": len(frames),
                "image_id": kp.image_ids[i],
                "file_name": kp.file_names[i],
                "camera": {
                    "K": intrinsics[i].round(6).tolist(),
                    "image_size": [_num(v, 1) for v in size] if np.isfinite(size).all() else None,
                    "source": sources[i],
                },
                "persons": [],
            }
        frames[key]["persons"].append(_person(kp, res, i))
    unique_sources = sorted(set(sources))
    lifted = int(res.lifted.sum())
    return {
        "schema": SCHEMA,
        "zedo_version": __version__,
        "created": datetime.now(UTC).isoformat(timespec="seconds"),
        "skeleton": _skeleton_doc(kp.skeleton),
        "units": "m",
        "coordinate_frame": "camera",
        "axes": AXES,
        "camera": {
            "source": unique_sources[0] if len(unique_sources) == 1 else "mixed",
            "note": "pseudo = f 2000 px at the image centre: absolute depth and scale are only as good "
            "as this guess and the prior" if "pseudo" in unique_sources else None,
        },
        "input": input_info,
        "params": params,
        "frames": list(frames.values()),
        "summary": {
            "instances_total": len(kp),
            "instances_lifted": lifted,
            "instances_skipped": len(kp) - lifted,
            "frames_total": len(frames),
            "mean_reprojection_error_px": _num(float(np.nanmean(res.reprojection_error_px))
                                               if lifted else float("nan"), 3),  # fmt: skip
            "seconds": round(res.seconds, 2),
        },
    }


def write_json(doc: dict[str, Any], out: str | Path) -> None:
    """Write `doc` to `out` atomically (temporary file in the same folder, then rename), or to
    stdout when `out` is "-"."""
    text = json.dumps(doc, indent=1, allow_nan=False)
    if str(out) == "-":
        sys.stdout.write(text + "\n")
        sys.stdout.flush()
        return
    out = Path(out)
    fd, tmp = tempfile.mkstemp(prefix=f".{out.name}.", suffix=".tmp", dir=out.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text + "\n")
        os.replace(tmp, out)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
