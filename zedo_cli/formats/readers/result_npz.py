"""Reading a zedo result back from its NPZ archive: one array per field, one row per (frame, person);
the skeleton, params and summary from its `metadata` JSON where it has one."""

from __future__ import annotations

import io
import json
import zipfile
from dataclasses import replace
from typing import Any

import numpy as np

from ...camera.model import CameraModel
from ...data.skeleton import Skeleton, skeleton_from_joint_names
from ...errors import InputFormatError
from ...strict_json import loads
from .result_common import SCALE_TO_M, camera_of, check_schema, dict_of, other_fields, params_of, skeleton_of, units_of
from .result_record import LiftParams, LiftRecord, ResultPoses
from .source import json_error


def read_npz(data: bytes, name: str) -> ResultPoses:
    try:
        with np.load(io.BytesIO(data), allow_pickle=False) as npz:
            arrays = {k: npz[k] for k in npz.files}
    except (OSError, ValueError, zipfile.BadZipFile) as exc:
        raise InputFormatError(f"{name}: not a readable NPZ archive ({exc})") from None
    lacking = [k for k in ("poses", "joint_names", "units", "frame_index", "person") if k not in arrays]
    if lacking:
        what = "array" if len(lacking) == 1 else "arrays"
        raise InputFormatError(f"{name}: {what} {', '.join(lacking)} missing: not a zedo result NPZ")
    names = tuple(str(n) for n in arrays["joint_names"])
    meta: dict[str, Any] = {}
    if "metadata" in arrays:
        try:
            meta = loads(str(arrays["metadata"]))
        except json.JSONDecodeError:
            raise InputFormatError(f"{name}: metadata: not JSON") from None
        except (ValueError, RecursionError) as exc:
            raise json_error(name, "metadata", exc) from None
        check_schema(meta, name)
    skel = skeleton_of(meta, name) if meta else skeleton_from_joint_names(names)
    if skel is None or skel.joints != names:
        raise InputFormatError(f"{name}: joint_names: {', '.join(names)} are not a zedo skeleton's joints")
    poses = np.asarray(arrays["poses"], dtype=float)
    n = len(poses)
    if poses.shape != (n, skel.num_joints, 3):
        raise InputFormatError(f"{name}: poses: expected shape (N, {skel.num_joints}, 3), got {poses.shape}")
    scale = SCALE_TO_M[units_of(str(arrays["units"]), name)]
    radii = arrays.get("uncertainty_m")
    if radii is not None and np.shape(radii) != (n, skel.num_joints):
        raise InputFormatError(f"{name}: uncertainty_m: expected shape ({n}, {skel.num_joints})")
    ids = arrays.get("image_ids", arrays["frame_index"])
    files = arrays.get("file_names", np.array([""] * n))
    cameras = _npz_cameras(arrays, n, name)
    others = _npz_others(arrays, n, name)
    record = _npz_record(arrays, n, skel.num_joints, meta, scale, name)
    roots = arrays.get("root_translation")
    roots = None if roots is None or np.shape(roots) != (n, 3) else np.asarray(roots, dtype=float) * scale
    spread = arrays.get("hypothesis_spread_mm")
    if spread is not None and np.shape(spread) != (n,):
        raise InputFormatError(f"{name}: hypothesis_spread_mm: expected shape ({n},), got {np.shape(spread)}")
    return replace(_npz_result(arrays, name, skel, poses, scale, radii, ids, files, meta, cameras),
                   record=record, root_translation=roots,
                   hypothesis_spread_m=None if spread is None else np.asarray(spread, dtype=float) / 1000,
                   **others)  # fmt: skip


def _npz_record(
    arrays: dict[str, np.ndarray], n: int, joints: int, meta: dict[str, Any], scale: float, name: str
) -> LiftRecord | None:
    """The archive's 2D, confidences, errors, status, image sizes and K sources (None when one is missing)."""
    need = {"keypoints_2d": (n, joints, 2), "confidence": (n, joints), "reprojection_error_px": (n, joints),
            "status": (n,), "image_size": (n, 2), "k_source": (n,)}  # fmt: skip
    if any(k not in arrays for k in need):
        return None
    bad = [k for k, shape in need.items() if np.shape(arrays[k]) != shape]
    if bad:
        raise InputFormatError(f"{name}: {', '.join(bad)}: not one entry per row and joint ({n} rows, {joints} joints)")
    hypotheses = arrays.get("hypotheses")
    summary = meta.get("summary") if isinstance(meta.get("summary"), dict) else {}
    seconds = summary.get("seconds")
    return LiftRecord(
        keypoints_2d=np.asarray(arrays["keypoints_2d"], dtype=float),
        confidence=np.nan_to_num(np.asarray(arrays["confidence"], dtype=float)),
        reprojection_error_px=np.asarray(arrays["reprojection_error_px"], dtype=float),
        status=np.asarray([str(s) for s in arrays["status"]], dtype=object),
        image_sizes=np.asarray(arrays["image_size"], dtype=float), k_sources=[str(s) for s in arrays["k_source"]],
        instance_index=np.arange(n), scores=[None] * n,
        hypotheses=None if hypotheses is None else np.asarray(hypotheses, dtype=float),
        input_info=dict_of(meta.get("input")), seconds=float(seconds) if isinstance(seconds, int | float) else 0.0,
    )  # fmt: skip


def _npz_result(
    arrays: dict[str, np.ndarray], name: str, skel: Skeleton, poses: np.ndarray, scale: float,
    radii: np.ndarray | None, ids: np.ndarray, files: np.ndarray, meta: dict[str, Any],
    cameras: list[CameraModel | None] | None,
) -> ResultPoses:  # fmt: skip
    n, params = len(poses), params_of(meta)  # the lift's params come with the metadata
    return ResultPoses(
        source=name, format="npz", skeleton=skel, poses=poses * scale,
        frame_index=np.asarray(arrays["frame_index"], dtype=np.int64),
        person=np.asarray(arrays["person"], dtype=np.int64), image_ids=[i.item() for i in np.asarray(ids)],
        file_names=[str(f) or None for f in files],
        lifted=np.asarray(arrays.get("lifted", np.isfinite(poses).all((1, 2))), dtype=bool),
        observed=np.asarray(arrays.get("observed", np.ones((n, skel.num_joints))), dtype=bool),
        uncertainty_m=None if radii is None else np.asarray(radii, dtype=float),
        fps=LiftParams.from_dict(params, name).fps, coordinate_frame=str(arrays.get("coordinate_frame", "camera")),
        units_in_file=str(arrays["units"]), params=params, cameras=cameras,
    )  # fmt: skip


def _npz_others(arrays: dict[str, np.ndarray], n: int, name: str) -> dict[str, Any]:
    """`other_keypoints_2d (N, E, 2)`, `other_keypoint_confidence (N, E)` (NaN where missing) and
    `other_keypoint_names (E,)`, when the archive has them."""
    if "other_keypoint_names" not in arrays:
        return {}
    names = tuple(str(v) for v in np.asarray(arrays["other_keypoint_names"]).reshape(-1))
    e = len(names)
    xy = np.asarray(arrays.get("other_keypoints_2d", np.full((n, e, 2), np.nan)), dtype=float)
    conf = np.asarray(arrays.get("other_keypoint_confidence", np.full((n, e), np.nan)), dtype=float)
    if xy.shape != (n, e, 2) or conf.shape != (n, e):
        raise InputFormatError(f"{name}: other_keypoints_2d, other_keypoint_confidence: expected shapes "
                               f"({n}, {e}, 2) and ({n}, {e}) for {e} other_keypoint_names")  # fmt: skip
    return other_fields(names, list(xy), list(conf))


def _npz_cameras(arrays: dict[str, np.ndarray], n: int, name: str) -> list[CameraModel | None] | None:
    """Each row's camera from `K (N, 3, 3)`, `camera_model (N,)`, `dist (N, D)` (NaN-padded) and
    `image_size (N, 2)`; None when the archive has no K."""
    if "K" not in arrays:
        return None
    k = np.asarray(arrays["K"], dtype=float)
    models = arrays.get("camera_model", np.array(["pinhole"] * n))
    dist = np.asarray(arrays.get("dist", np.zeros((n, 0))), dtype=float)
    sizes = np.asarray(arrays.get("image_size", np.full((n, 2), np.nan)), dtype=float)
    if k.shape != (n, 3, 3) or len(models) != n or dist.ndim != 2 or len(dist) != n or sizes.shape != (n, 2):
        raise InputFormatError(f"{name}: K, camera_model, dist, image_size: expected one per row ({n})")
    out: list[CameraModel | None] = []
    seen: dict[tuple[bytes, str, bytes, bytes], CameraModel | None] = {}  # a clip has one or a few cameras
    for i in range(n):
        key = (k[i].tobytes(), str(models[i]), dist[i].tobytes(), sizes[i].tobytes())
        if key not in seen:
            block = {"K": k[i], "model": str(models[i]), "dist": dist[i][np.isfinite(dist[i])].tolist(),
                     "image_size": sizes[i].tolist() if np.isfinite(sizes[i]).all() else None}  # fmt: skip
            seen[key] = camera_of(block, f"{name}: row {i}: camera")
        out.append(seen[key])
    return out
