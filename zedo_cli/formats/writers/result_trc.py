"""The 3D result as OpenSim / Pose2Sim marker files (`.trc`), one per track (markers.py).

The layout OpenSim's `TimeSeriesTableVec3` and Pose2Sim's `read_trc` read (INTEROP.md), tabs only:

    PathFileType<TAB>4<TAB>(X/Y/Z)<TAB>clip.trc
    DataRate<TAB>CameraRate<TAB>NumFrames<TAB>NumMarkers<TAB>Units<TAB>OrigDataRate<TAB>OrigDataStartFrame<TAB>OrigNumFrames
    30<TAB>30<TAB>61<TAB>12<TAB>m<TAB>30<TAB>1<TAB>61
    Frame#<TAB>Time<TAB>RHip<TAB><TAB><TAB>LHip<TAB><TAB><TAB>...<TAB>LWrist
    <TAB><TAB>X1<TAB>Y1<TAB>Z1<TAB>X2<TAB>...<TAB>Z12
    1<TAB>0.000000<TAB>0.101234<TAB>...

Units are always metres (Pose2Sim ignores `Units` and assumes metres), six decimals (a micrometre).
A missing marker is `NaN` in its three fields; no row ends with a tab (OpenSim rejects an
empty last field, Pose2Sim's `convert_to_c3d` a trailing tab). Times strictly increase.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import numpy as np

from ...files import atomic_path
from .common import rounded_array, write_pieces
from .markers import MarkerTracks, check_track_paths, track_paths

HEADER_KEYS = (
    "DataRate", "CameraRate", "NumFrames", "NumMarkers", "Units", "OrigDataRate", "OrigDataStartFrame", "OrigNumFrames",
)  # fmt: skip
_ROWS_PER_PIECE = 2048


def _rate(rate: float) -> str:
    return f"{rate:g}" if float(rate).is_integer() else f"{rate:.6f}".rstrip("0")


def trc_header(name: str, tracks: MarkerTracks) -> str:
    """The five header lines (with their newlines) of a TRC file called `name`."""
    rate, frames, count = _rate(tracks.rate), len(tracks.frame_numbers), len(tracks.markers)
    values = (rate, rate, frames, count, "m", rate, int(tracks.frame_numbers[0]) + 1, frames)
    names = "\t".join(f"{m}\t\t" for m in tracks.markers[:-1]) + ("\t" if count > 1 else "") + tracks.markers[-1]
    axes = "\t".join(f"X{m}\tY{m}\tZ{m}" for m in range(1, count + 1))
    return (
        f"PathFileType\t4\t(X/Y/Z)\t{name}\n" + "\t".join(HEADER_KEYS) + "\n" + "\t".join(str(v) for v in values) + "\n"
        f"Frame#\tTime\t{names}\n\t\t{axes}\n"
    )


def trc_rows(tracks: MarkerTracks, track: int) -> Iterator[str]:
    """The data rows of one track, a few thousand at a time."""
    poses = tracks.tracks[track]  # (F, M, 3) metres
    count = poses.shape[1]
    line = "%d\t%.6f" + "\t%.6f" * (3 * count) + "\n"
    flat = rounded_array(poses.reshape(len(poses), -1), 6)  # as the JSON holds them: exports print alike
    for start in range(0, len(flat), _ROWS_PER_PIECE):
        stop = start + _ROWS_PER_PIECE
        block = np.column_stack([tracks.frame_numbers[start:stop] + 1, tracks.times[start:stop], flat[start:stop]])
        # Python prints NaN as "nan" (never "-nan"); OpenSim and Pose2Sim read "NaN".
        yield "".join(line % tuple(row) for row in block.tolist()).replace("nan", "NaN")


def write_trc(out: str | Path, tracks: MarkerTracks, *, overwrite: bool = False) -> list[Path]:
    """Write one TRC file per track (`markers.track_paths`), each atomically; every path is
    checked before any file is written. Returns the files written."""
    paths = track_paths(out, len(tracks.tracks))
    check_track_paths(paths, overwrite)
    for t, path in enumerate(paths):
        with atomic_path(path, overwrite=overwrite) as tmp, open(tmp, "w", encoding="utf-8", newline="\n") as fh:
            fh.write(trc_header(path.name, tracks))
            write_pieces(trc_rows(tracks, t), fh)
    return paths
