"""Files in and out: the readers of every 2D detector layout (into `data.Keypoints2D`), the
writers of 3D results (JSON, JSON Lines, CSV, NPZ), their reader (`result_reader`) and the
pose plots (`formats.plots`, not imported here so that matplotlib loads only when a plot is asked for).

Builds on `lifting` (the `LiftResult` a writer writes) and `data`.
"""

from __future__ import annotations

from ..data.keypoints import Keypoints2D
from .readers import INPUT_FORMATS, detect_format, input_sha256, read_keypoints, read_keypoints_text, read_parsed
from .result_reader import ResultPoses, read_result
from .writers import OUTPUT_FORMATS, default_output_name, write_result

__all__ = [
    "INPUT_FORMATS", "OUTPUT_FORMATS", "Keypoints2D", "default_output_name", "detect_format", "input_sha256",
    "read_keypoints", "read_keypoints_text", "read_parsed", "read_result", "ResultPoses", "write_result",
]  # fmt: skip
