"""Reading: the 2D keypoint layouts of every supported detector and annotation tool (one module
per layout; `inputs` is the entry point: format names, auto-detection, files, stdin, folders) and
zedo's own 3D results (`result`). Nothing here imports the writers.
"""

from __future__ import annotations

from ...lazy import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(
    __name__,
    globals(),
    {
        ".inputs": [
            "INPUT_FORMATS",
            "detect_format",
            "fill_image_sizes",
            "input_sha256",
            "read_keypoints",
            "read_keypoints_text",
            "read_parsed",
        ],
        ".result": ["RESULT_FORMATS", "ResultPoses", "read_result", "read_result_bytes"],
    },
)
