"""Camera models (OpenCV's pinhole with distortion, and its fisheye model): undistorting 2D
keypoints before lifting and projecting 3D points back into the original (distorted) image.
The camera work itself is OpenCV's; this package holds the typed models around it.

Builds on `errors` only (numpy, OpenCV and pydantic): `model` (the camera), `files` (calibration
files), `sanity` (the checks that a lift's camera fits its input). docs/cameras.md.
"""

from __future__ import annotations

from ..lazy import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(
    __name__,
    globals(),
    {
        ".model": ["CameraModel", "UNDISTORT_CRITERIA", "lens_groups", "undistort_instances"],
        ".files": ["CameraFile", "read_camera_file"],
        ".sanity": ["CameraSanity", "check_camera_sanity"],
    },
)
