"""Writing a calibration as an OpenCV FileStorage file (YAML, or JSON / XML by the extension),
with the key names of OpenCV's own calibration sample, which most tools read:

    camera_matrix            3x3 (fx, 0, cx; 0, fy, cy; 0, 0, 1), pixels
    distortion_coefficients  1xN in OpenCV's order (pinhole: k1 k2 p1 p2 k3; fisheye: k1 k2 k3 k4)
    image_width, image_height
    model                    pinhole | fisheye
    rms                      RMS reprojection error, px, over every corner used
    views, board_cols, board_rows, square_m, views_without_board

`cv2.FileStorage(path, cv2.FILE_STORAGE_READ)` reads it back. The text is made in memory and
written atomically (files.py), so a failed run leaves no partial file.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import ConfigError
from ..files import write_text_atomic
from .calibration import Calibration

_FORMATS = {".yml": "yaml", ".yaml": "yaml", ".json": "json", ".xml": "xml"}


def storage_format(path: str | Path) -> str:
    """yaml, json or xml, from the output's extension."""
    suffix = Path(path).suffix.lower()
    if suffix not in _FORMATS:
        raise ConfigError(f"{path}: output must end in .yml, .yaml, .json or .xml (OpenCV FileStorage)")
    return _FORMATS[suffix]


def calibration_text(cal: Calibration, fmt: str = "yaml") -> str:
    """The FileStorage document of `cal` in `fmt` (yaml, json, xml)."""
    import cv2

    flag = {"yaml": cv2.FILE_STORAGE_FORMAT_YAML, "json": cv2.FILE_STORAGE_FORMAT_JSON,
            "xml": cv2.FILE_STORAGE_FORMAT_XML}[fmt]  # fmt: skip
    fs = cv2.FileStorage(f".{fmt}", cv2.FILE_STORAGE_WRITE | cv2.FILE_STORAGE_MEMORY | flag)
    cam = cal.camera
    width, height = cam.image_size or (0, 0)
    fs.write("camera_matrix", cam.matrix())
    fs.write("distortion_coefficients", np.asarray(cam.dist, dtype=np.float64).reshape(1, -1))
    fs.write("image_width", int(width))
    fs.write("image_height", int(height))
    fs.write("model", cam.model)
    fs.write("rms", float(cal.rms))
    fs.write("views", len(cal.view_errors))
    fs.write("per_view_errors", np.array([e for _, e in cal.view_errors], dtype=np.float64).reshape(1, -1))
    if cal.board is not None:
        fs.write("board_cols", cal.board.cols)
        fs.write("board_rows", cal.board.rows)
        fs.write("square_m", float(cal.board.square))
    fs.write("views_without_board", len(cal.views_without_board))
    return fs.releaseAndGetString()


def write_calibration(path: str | Path, cal: Calibration, *, overwrite: bool = False) -> None:
    """Write `cal` to `path` (.yml / .yaml / .json / .xml), atomically."""
    write_text_atomic(path, calibration_text(cal, storage_format(path)), overwrite=overwrite)
