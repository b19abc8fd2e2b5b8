"""The 3D result as a NumPy `.npz` archive (FORMATS.md 3.8d), one row per instance.

Arrays (N instances, J joints); NaN marks every missing value, never 0:

    poses                  (N, J, 3) float64  in `units`, in `coordinate_frame`; NaN where not lifted
    root_translation       (N, 3)    float64  the root point in the camera frame, in `units`
    observed               (N, J)    bool     joints used as 2D constraints (False: filled by the prior)
    lifted                 (N,)      bool     False: not lifted (poses all NaN), `status` says why
    status                 (N,)      str      "lifted", or the reason (lifting.solver.NOT_LIFTED)
    confidence             (N, J)    float64  input confidence; NaN where missing
    keypoints_2d           (N, J, 2) float64  input pixels; NaN where missing
    reprojection_error_px  (N, J)    float64  NaN where not observed
    K                      (N, 3, 3) float64  intrinsics of each instance's frame, pixels
    k_source               (N,)      str      pseudo | cli | file
    camera_model           (N,)      str      pinhole | fisheye (OpenCV's lens models)
    dist                   (N, D)    float64  distortion coefficients, OpenCV's order; D the most any camera has
                                              (0: none), NaN past an instance's own
    image_size             (N, 2)    float64  width, height in pixels; NaN where unknown
    frame_index, person    (N,)      int64    frame (the input's frame number, else the output frame) and position in it
    image_ids              (N,)      int64 when every id is an integer within int64's range, else str
    file_names             (N,)      str      "" where the input has none
    joint_names            (J,) str, bones (B, 2) int64
    other_keypoints_2d     (N, E, 2) float64  the input's keypoints that were not lifted (face, feet, ...), original
                                              image pixels as the input gave them; NaN where missing
    other_keypoint_confidence (N, E) float64  their input confidences; NaN where missing
    other_keypoint_names   (E,) str           their names (E = 0: the input had none)
    uncertainty_m          (N, J)    float64  only when calibrated: 90 % radius in metres; NaN where not lifted
    hypotheses             (N, K, J, 3) float64  only with --save-hypotheses: root-relative, metres, camera axes
    hypothesis_spread_mm   (N,)      float64  only with --hypotheses K > 1: the hypotheses' spread; NaN: not measured
    unstable_solution      (N,)      bool     only with K > 1: spread over 80 mm (lifting.result.UNSTABLE_SPREAD_M)
    units, coordinate_frame  0-d str; axes (3,) str: the directions of x, y, z
    metadata               0-d str: JSON of the result's header and summary (skeleton, input, params, ...)

Nothing needs pickle: `np.load(path)` (allow_pickle=False) reads it all. NPZ is binary, so it is
never written to stdout.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ...data.keypoints import Keypoints2D
from ...errors import ConfigError
from ...files import atomic_path
from .common import AXES, OutputOptions, group_frames, json_pieces, lens_at, output_poses

if TYPE_CHECKING:  # the writers only read a result; importing the solver would load torch
    from ...camera.model import CameraModel
    from ...lifting.solver import LiftResult


_INT64 = np.iinfo(np.int64)


def _ids(image_ids: list[int | str]) -> np.ndarray:
    """int64 when every id is an integer that fits (COCO's ids do); else each id's text, so that an id
    such as 10**30, which JSON holds, is kept whole rather than refused by numpy."""
    if all(isinstance(i, int | np.integer) and not isinstance(i, bool) and _INT64.min <= i <= _INT64.max
           for i in image_ids):  # fmt: skip
        return np.asarray(image_ids, dtype=np.int64)
    return np.asarray([str(i) for i in image_ids], dtype=np.str_)


def _lens_arrays(lenses: Sequence[CameraModel | None] | None, n: int) -> dict[str, np.ndarray]:
    """`camera_model (N,)` and `dist (N, D)`, NaN-padded to the longest coefficient list."""
    chosen = [lens_at(lenses, i) for i in range(n)]
    width = max((len(c.dist) for c in chosen if c is not None), default=0)
    dist = np.full((n, width), np.nan)
    for i, c in enumerate(chosen):
        if c is not None:
            dist[i, : len(c.dist)] = c.dist
    return {"camera_model": np.asarray([c.model if c else "pinhole" for c in chosen], dtype=np.str_), "dist": dist}


def npz_arrays(
    kp: Keypoints2D, res: LiftResult, intrinsics: np.ndarray, sources: list[str], metadata: dict[str, Any], *,
    units: str = "m", frame: str = "camera", lenses: Sequence[CameraModel | None] | None = None,
) -> dict[str, np.ndarray]:  # fmt: skip
    """The archive's arrays by name (see the module docstring)."""
    opts = OutputOptions(units, frame)
    groups = group_frames(kp.image_ids, kp.frame_indices)
    return {
        "poses": output_poses(res, opts).astype(np.float64),
        "root_translation": np.where(res.lifted[:, None], res.root_translation * opts.scale, np.nan),
        "observed": res.observed.astype(bool),
        "lifted": res.lifted.astype(bool),
        "status": np.asarray(res.status, dtype=np.str_),  # "lifted" or why not (lifting.solver.NOT_LIFTED)
        "confidence": np.where(kp.confidence > 0, kp.confidence, np.nan),
        "keypoints_2d": kp.xy.astype(np.float64),
        "reprojection_error_px": res.reprojection_error_px.astype(np.float64),
        "K": np.asarray(intrinsics, dtype=np.float64).reshape(-1, 3, 3),
        "k_source": np.asarray(sources, dtype=np.str_),
        **_lens_arrays(lenses, len(kp)),
        "image_size": kp.image_sizes.astype(np.float64),
        "frame_index": groups.frame_index,
        "person": groups.person,
        "image_ids": _ids(kp.image_ids),
        "file_names": np.asarray([f or "" for f in kp.file_names], dtype=np.str_),
        "joint_names": np.asarray(kp.skeleton.joints, dtype=np.str_),
        "bones": np.asarray(kp.skeleton.bones, dtype=np.int64).reshape(-1, 2),
        "units": np.asarray(opts.units),
        "coordinate_frame": np.asarray(opts.frame),
        "axes": np.asarray([AXES["x"], AXES["y"], AXES["z"]], dtype=np.str_),
        # json.dumps(metadata)'s text, made piece by piece: `metadata["frames"]` may be an iterator
        "metadata": np.asarray("".join(json_pieces(metadata.items(), indent=None))),
        **_other_arrays(kp),
        **_uncertainty_arrays(res),
    }


def _other_arrays(kp: Keypoints2D) -> dict[str, np.ndarray]:
    """The input's keypoints outside the skeleton, when the record carries them (`kp.other`)."""
    if kp.other is None:
        return {}
    conf = kp.other.confidence
    return {
        "other_keypoints_2d": kp.other.xy.astype(np.float64),
        "other_keypoint_confidence": np.where(conf > 0, conf, np.nan),
        "other_keypoint_names": np.asarray(kp.other.names, dtype=np.str_).reshape(-1),
    }


def _uncertainty_arrays(res: LiftResult) -> dict[str, np.ndarray]:
    """`uncertainty_m (N, J)` when the lift has it; `hypotheses (N, K, J, 3)` when they were kept."""
    out = {}
    if res.uncertainty_m is not None:
        out["uncertainty_m"] = res.uncertainty_m.astype(np.float64)
    if res.hypotheses is not None:
        out["hypotheses"] = res.hypotheses.astype(np.float64)
    unstable = res.unstable()
    if res.hypothesis_spread_m is not None and unstable is not None:
        out["hypothesis_spread_mm"] = res.hypothesis_spread_m.astype(np.float64) * 1000
        out["unstable_solution"] = unstable
    return out


def write_npz(
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
    """Write the compressed archive to `out` atomically. Returns the path written."""
    if str(out) == "-":
        raise ConfigError("NPZ is a binary archive and cannot go to stdout; give a .npz file, "
                          "or use --format json/jsonl/csv for stdout")  # fmt: skip
    arrays = npz_arrays(kp, res, intrinsics, sources, metadata, units=units, frame=frame, lenses=lenses)
    path = Path(out)
    with atomic_path(path, overwrite=overwrite) as tmp, open(tmp, "wb") as fh:
        np.savez_compressed(fh, **arrays)  # a file object: numpy would append ".npz" to a name
    return [path]
