"""What the marker-file writers (TRC, C3D) share: marker names, axes, rows and one file per track.

Biomechanics tools (OpenSim, Pose2Sim, Visual3D) read markers over time, one subject per file:

- Marker names are Pose2Sim's: a zedo joint `right_hip` is `RHip`, `left_shoulder` `LShoulder`
  (`marker_name`); syrip12 gives Pose2Sim's 12 COCO markers RHip LHip RKnee LKnee RAnkle LAnkle
  RShoulder LShoulder RElbow LElbow RWrist LWrist.
- Axes are OpenSim's, Y up (`MARKER_AXES`): `level` (a camera looking horizontally) is
  X = camera x, Y = -camera y, Z = -camera z; `overhead` (a camera looking down on a lying
  infant) is X = camera x, Y = -camera z, Z = camera y. Both are rotations (determinant +1).
- Rows are frames by their number, from the result's first frame to its last, so that a frame
  the input left empty is a row too. Frame n of the file is the result's `frame_index` n - 1
  (marker files count from 1); time = frame_index / fps, or frame_index itself (rate 1)
  without `--fps`. A result whose input has no frame numbers (a set of images: COCO image
  ids) has rows only when `--fps` says its frames are a video's, in input order.
- One file per track (the person's place in its frame: the track of `--person all`); with
  several, `<stem>_P1.trc`, `<stem>_P2.trc`, ... (P1 = the JSON's person 0). A missing joint,
  a person not lifted and a frame without the person are NaN, never 0.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ...data.keypoints import Keypoints2D
from ...errors import ConfigError
from ...files import check_writable
from .common import OutputOptions, group_frames, output_poses

if TYPE_CHECKING:  # the writers only read a result; importing the solver would load torch
    from ...lifting.solver import LiftResult

# Camera (OpenCV: x right, y down, z forward) to marker axes (Y up), as rows of a rotation.
MARKER_AXES: dict[str, np.ndarray] = {
    "level": np.array([[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]]),
    "overhead": np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]]),
}
MARKER_AXES_NOTE = {
    "level": "X = camera x (right), Y = -camera y (up), Z = -camera z (towards the camera)",
    "overhead": "X = camera x (right), Y = -camera z (up, towards a camera looking down), Z = camera y",
}


def marker_name(joint: str) -> str:
    """Pose2Sim's name of a zedo joint: `right_hip` -> `RHip`, `left_big_toe` -> `LBigToe`, `nose` -> `Nose`."""
    words = joint.split("_")
    side = {"right": "R", "left": "L"}.get(words[0])
    return (side or words[0].capitalize()) + "".join(w.capitalize() for w in words[1:])


@dataclass(frozen=True)
class MarkerTracks:
    """Every track of a result as marker trajectories, ready for a marker file.

    `tracks[t]` is `(F, M, 3)` in metres in the marker axes, NaN where missing; row f is frame
    number `frame_numbers[f]` (0-based, as the JSON's `frame_index`) at `times[f]` seconds.
    """

    markers: tuple[str, ...]
    frame_numbers: np.ndarray  # (F,) int, consecutive
    times: np.ndarray  # (F,) float seconds (frame numbers without fps)
    rate: float  # frames per second (1.0 without fps)
    fps: float | None
    axes: str
    tracks: list[np.ndarray]


def check_marker_axes(axes: str) -> None:
    if axes not in MARKER_AXES:
        raise ConfigError(f"unknown marker axes {axes!r}; choose one of: {', '.join(MARKER_AXES)}")


def marker_frame_numbers(kp: Keypoints2D, fps: float | None, fmt: str = "trc") -> np.ndarray:
    """The frame number of each instance for a marker file, or a ConfigError before any work
    when the input has no frame numbers and no `fps` says its frames are a video's."""
    groups = group_frames(kp.image_ids, kp.frame_indices)
    if not groups.numbered and fps is None and len(groups.members) > 1:
        raise ConfigError(
            f"{kp.path}: a {fmt.upper()} file is a recording over time, and this input's frames have no frame numbers "
            f"({kp.format}: image ids); pass --fps to take them as consecutive video frames in input order, "
            "or write json, jsonl, csv or npz"
        )
    return groups.frame_index


def marker_tracks(
    kp: Keypoints2D, res: LiftResult, *, fps: float | None, frame: str = "camera", axes: str = "level",
    fmt: str = "trc",
) -> MarkerTracks:  # fmt: skip
    """The result's poses per track, one row per frame number, in metres in `axes`."""
    check_marker_axes(axes)
    poses = output_poses(res, OutputOptions("m", frame))  # (N, J, 3) metres, NaN where not lifted
    poses = poses @ MARKER_AXES[axes].T
    number = marker_frame_numbers(kp, fps, fmt)  # (N,)
    person = group_frames(kp.image_ids, kp.frame_indices).person  # (N,) the track
    first, last = int(number.min()), int(number.max())
    frame_numbers = np.arange(first, last + 1, dtype=np.int64)
    tracks = []
    for t in range(int(person.max()) + 1):
        rows = np.full((len(frame_numbers), kp.skeleton.num_joints, 3), np.nan)
        mine = person == t
        rows[number[mine] - first] = poses[mine]
        tracks.append(rows)
    rate = 1.0 if fps is None else float(fps)
    times = frame_numbers / rate
    markers = tuple(marker_name(j) for j in kp.skeleton.joints)
    return MarkerTracks(markers, frame_numbers, times, rate, fps, axes, tracks)


def track_paths(out: str | Path, count: int) -> list[Path]:
    """The file of each track: `out` itself for one, `<stem>_P1<ext>`, `<stem>_P2<ext>`, ... for several."""
    out = Path(out)
    if count == 1:
        return [out]
    return [out.with_name(f"{out.stem}_P{t + 1}{out.suffix}") for t in range(count)]


def check_track_paths(paths: list[Path], overwrite: bool) -> None:
    """Every file of every track checked before any is written."""
    for path in paths:
        check_writable(path, overwrite)
