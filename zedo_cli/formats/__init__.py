"""2D keypoint input formats: the `Keypoints2D` record and the readers that produce it."""

from __future__ import annotations

from ..data.keypoints import Keypoints2D
from .readers import INPUT_FORMATS, detect_format, input_sha256, read_keypoints, read_keypoints_text, read_parsed

__all__ = [
    "INPUT_FORMATS", "Keypoints2D", "detect_format", "input_sha256", "read_keypoints", "read_keypoints_text",
    "read_parsed",
]  # fmt: skip
