"""What a zedo result holds once read back, whatever its format: `ResultPoses` (every person of every
frame, in metres), `LiftRecord` (what the file keeps of its lift beyond the 3D poses) and `LiftParams`
(a typed view of the lift's recorded `params`, built once from the raw dict, which stays in
`ResultPoses.params`). The format readers are `result_json`, `result_csv` and `result_npz`; the entry
point is `result.read_result`."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ...camera.model import CameraModel
from ...data.skeleton import Skeleton
from ...errors import InputFormatError


@dataclass(frozen=True)
class LiftParams:
    """The fields of a result's `params` that zedo reads back, typed. Built from the raw dict with the
    tolerance older and hand-edited files need: a missing key, or one of another type, reads as None."""

    fps: float | None = None  # `zedo lift --fps`
    temporal_mode: str | None = None  # `temporal.mode`; None: not recorded (images: "none")
    camera_sources: tuple[Any, ...] | None = None  # where the frames' K came from (pseudo, cli, file)
    prior_sha256: str | None = None  # `prior.sha256`
    config: Mapping[str, Any] | None = None  # the lifting settings
    min_confidence: float | None = None  # `zedo lift --min-confidence`

    @classmethod
    def from_dict(cls, params: Any, name: str | None = None) -> LiftParams:
        """The typed view of `params` (anything but a dict: all None). With `name` (the file, for the
        message) a bad `fps` is refused, as the result readers always have; without, it reads as None."""
        if not isinstance(params, dict):
            return cls()
        prior, temporal = params.get("prior"), params.get("temporal")
        mode = temporal.get("mode") if isinstance(temporal, dict) else None
        sha = prior.get("sha256") if isinstance(prior, dict) else None
        sources, config, conf = params.get("camera_sources"), params.get("config"), params.get("min_confidence")
        return cls(
            fps=_fps(params.get("fps"), name),
            temporal_mode=mode if isinstance(mode, str) else None,
            camera_sources=tuple(sources) if isinstance(sources, list) else None,
            prior_sha256=sha if isinstance(sha, str) else None,
            config=config if isinstance(config, dict) else None,
            min_confidence=float(conf) if isinstance(conf, int | float) else None,
        )


def _fps(fps: Any, name: str | None) -> float | None:
    """A positive `fps`, or None (null, or not one without a `name` to refuse it with)."""
    if fps is None:
        return None
    if not isinstance(fps, int | float) or not fps > 0:
        if name is None:
            return None
        raise InputFormatError(f"{name}: params.fps: expected a positive number or null, got {fps!r}")
    return float(fps)


@dataclass
class LiftRecord:
    """What a result file keeps of its lift beyond the 3D poses: enough to write the result again
    in another format (`formats.export`, `zedo export`). Per row of `ResultPoses`."""

    keypoints_2d: np.ndarray  # (N, J, 2) the input's pixels, in the prior's joints; NaN where missing
    confidence: np.ndarray  # (N, J) the input's confidence; 0 where missing
    reprojection_error_px: np.ndarray  # (N, J) NaN where not observed or not lifted
    status: np.ndarray  # (N,) object: "lifted" or why not (lifting.solver.NOT_LIFTED)
    image_sizes: np.ndarray  # (N, 2) width, height px; NaN where unknown
    k_sources: list[str]  # (N,) where each row's K came from: pseudo, cli, file
    instance_index: np.ndarray  # (N,) int, each row's index in the lifted input (its order)
    scores: list[float | None]  # (N,) the input's detection scores (JSON / JSON Lines; else None)
    poses_root_relative: np.ndarray | None = None  # (N, J, 3) metres, as stored (JSON / JSON Lines)
    hypotheses: np.ndarray | None = None  # (N, K, J, 3) metres, root-relative (--save-hypotheses)
    input_info: dict[str, Any] = field(default_factory=dict)  # the header's `input`
    seconds: float = 0.0  # the summary's seconds of lifting


@dataclass
class ResultPoses:
    """Every person of every frame of a zedo result, in file order."""

    source: str  # the path read, or "-"
    format: str  # json | jsonl | csv | npz
    skeleton: Skeleton
    poses: np.ndarray  # (N, J, 3) metres, in `coordinate_frame`; NaN where missing or not lifted
    frame_index: np.ndarray  # (N,) int, output frame of each person
    person: np.ndarray  # (N,) int, position of the person in its frame (the track in a video)
    image_ids: list[int | str]  # (N,)
    file_names: list[str | None]  # (N,)
    lifted: np.ndarray  # (N,) bool
    observed: np.ndarray  # (N, J) bool: the joint was a 2D constraint (False: filled by the prior)
    uncertainty_m: np.ndarray | None  # (N, J) 90 % ball radius in metres, NaN unknown; None: no such field
    fps: float | None  # recorded by `zedo lift --fps`
    coordinate_frame: str  # camera | root
    units_in_file: str  # m | mm (poses are converted to metres)
    params: dict[str, Any] = field(default_factory=dict)  # the lift's `params` (prior, settings, camera), if recorded
    # flags: JSON, JSON Lines and CSV with a `flags` column (None for NPZ); root_translation: JSON / JSON Lines
    # only (None for CSV and NPZ): per row, its flags and
    # its root point in the camera frame (metres; NaN when not lifted), which puts a root-frame result
    # back in the camera.
    cameras: list[CameraModel | None] | None = None  # (N,) each person's camera (any format); None: not stated
    flags: list[list[str]] | None = None
    root_translation: np.ndarray | None = None  # (N, 3); also from NPZ
    record: LiftRecord | None = None  # the lift's 2D, status, cameras' sources, ...; None where the file lacks them
    # (N,) the spread of each person's K hypotheses in metres (`hypothesis_spread_mm`), NaN where not
    # measured; None: the lift measured none (one hypothesis)
    hypothesis_spread_m: np.ndarray | None = None
    # The input's keypoints that were not lifted (face, feet, ...), by name: original image pixels as
    # the input gave them. None: the file does not say (written before zedo kept them); names () and
    # (N, 0, 2): the input had none.
    other_keypoints_2d: np.ndarray | None = None  # (N, E, 2) pixels; NaN where missing
    other_keypoint_confidence: np.ndarray | None = None  # (N, E) in [0, 1]; 0 where missing
    other_keypoint_names: tuple[str, ...] = ()

    def __len__(self) -> int:
        return len(self.poses)

    @property
    def keypoints_2d(self) -> np.ndarray | None:
        """(N, J, 2) the input's 2D in pixels, NaN where missing; None where the file does not keep them
        (an older CSV without u_px, v_px reads as all NaN)."""
        if self.record is None or not np.isfinite(self.record.keypoints_2d).any():
            return None
        return self.record.keypoints_2d

    @property
    def lift_params(self) -> LiftParams:
        """`params` typed (`LiftParams`, fps already checked by the reader): built from the dict as it
        is now, so a copy made with `dataclasses.replace(res, params=...)` reads its own."""
        return LiftParams.from_dict(self.params)
