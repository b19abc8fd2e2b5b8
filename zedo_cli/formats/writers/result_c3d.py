"""The 3D result as C3D files, one per track (markers.py), written with the `c3d` library.

What a reader needs (INTEROP.md): POINT:LABELS (the marker names of the TRC), POINT:RATE
(`--fps`, else 1 with frame numbers as times), POINT:UNITS `mm`, POINT:SCALE -1 (float
storage), the TRC's axes (POINT:X_SCREEN +X, Y_SCREEN +Y: Y up). A missing point has residual
-1: invalid, read back as NaN by ezc3d (the `c3d` reader gives zeros with residual -1), never
a valid (0, 0, 0). The first frame (TRIAL:ACTUAL_START_FIELD and the header) is the result's
first `frame_index` + 1, as in the TRC. Files are written atomically.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np

from ...files import atomic_path
from .markers import MarkerTracks, check_track_paths, track_paths

UNITS = "mm"


def _frames(poses_m: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """The (points, analog) pairs of the `c3d` writer: points `(M, 5)` x, y, z in mm, residual
    (0 = valid, -1 = invalid) and camera mask; no analog channels."""
    points = np.zeros((*poses_m.shape[:2], 5), dtype=np.float32)  # (F, M, 5)
    points[..., :3] = np.nan_to_num(poses_m * 1000.0)
    points[..., 3] = np.where(np.isfinite(poses_m).all(-1), 0.0, -1.0)
    analog = np.zeros((0, 0), dtype=np.float32)
    return [(p, analog) for p in points]


def write_c3d(out: str | Path, tracks: MarkerTracks, *, overwrite: bool = False) -> list[Path]:
    """Write one C3D file per track (`markers.track_paths`), each atomically; every path is
    checked before any file is written. Returns the files written."""
    import c3d  # a small pure-Python library, loaded only for this format

    paths = track_paths(out, len(tracks.tracks))
    check_track_paths(paths, overwrite)
    for t, path in enumerate(paths):
        writer = c3d.Writer(point_rate=tracks.rate, point_scale=-1.0, point_units=UNITS)
        writer.set_point_labels(list(tracks.markers))
        writer.set_start_frame(int(tracks.frame_numbers[0]) + 1)
        writer.set_screen_axis("+X", "+Y")
        writer.add_frames(_frames(tracks.tracks[t]))
        with atomic_path(path, overwrite=overwrite) as tmp, open(tmp, "wb") as fh, warnings.catch_warnings():
            warnings.filterwarnings("ignore", "No analog data", UserWarning)  # none is meant: markers only
            writer.write(fh)
    return paths
