"""Files in and out: the readers of every 2D detector layout (into `data.Keypoints2D`), the
writers of 3D results (JSON, JSON Lines, CSV, NPZ; TRC and C3D marker files), their schema
(`result_schema`) and reader (`result_reader`) and the
pose plots (`formats.plots`, not imported here so that matplotlib loads only when a plot is asked for).

Builds on `lifting` (the `LiftResult` a writer writes) and `data`.
"""

from __future__ import annotations

from ..lazy import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(
    __name__,
    globals(),
    {
        "..data.keypoints": ["Keypoints2D"],
        ".readers": [
            "INPUT_FORMATS",
            "detect_format",
            "input_sha256",
            "read_keypoints",
            "read_keypoints_text",
            "read_parsed",
        ],
        ".result_reader": ["ResultPoses", "read_result"],
        ".writers": ["OUTPUT_FORMATS", "default_output_name", "write_result"],
    },
)
