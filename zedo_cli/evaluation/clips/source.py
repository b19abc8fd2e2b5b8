"""Synthetic infant clips of real movement: adult motion capture retargeted to infant bones, laid
supine under a camera, projected and given a detector's habits.

What is kept of the adult: every segment's direction relative to the body's smoothed heading,
frame by frame, at the adult's own speeds (resampled onto `fps`, `motion.resample`). What is
removed: the global translation (the pelvis is placed, with a small slow drift) and the heading
(the left axis's horizontal angle smoothed over `heading_smooth_s`, undone frame by frame), so a
walk or a turn becomes body-relative movement in place. The clip's mean trunk frame is then turned
to lie supine under the camera (chest to the camera, head up the image) and swayed slowly
(`cameras.Sway`); the trunk's own tilts relative to that mean (a bow, a lean) are kept.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...data.adult import ADULT_FILES
from ...errors import ConfigError
from ...lifting.camera import Intrinsics
from .cameras import CLINIC_CAMERAS, PSEUDO_CAMERA, CameraSetup, Sway, placement, project_points
from .habits import DetectorHabits, HabitMasks, apply_habits
from .infants import InfantBodies
from .motion import (
    AdultClip,
    build_poses,
    heading,
    load_adult_clips,
    mean_rotation,
    resample,
    slerp,
    trunk_frames,
    yaw_matrices,
)

MAX_SECONDS = 600.0


@dataclass(frozen=True)
class ClipSettings:
    """How clips are made. `max_gap_s`: kept frames further apart are a still pose held
    (`motion.resample`); `min_clip_s`: shorter adult clips are skipped by `retargeted_clips` and
    only joined to others by `adult_infant_clips`; `transition_s`: the eased turn from one adult
    clip's last pose to the next one's first; `habits`: None for exact 2D."""

    fps: float = 30.0
    max_gap_s: float = 0.3
    heading_smooth_s: float = 1.0
    transition_s: float = 0.5
    min_clip_s: float = 1.0
    symmetric_infant: bool = True
    cameras: tuple[CameraSetup, ...] = (PSEUDO_CAMERA, *CLINIC_CAMERAS)
    sway: Sway = field(default_factory=Sway)
    habits: DetectorHabits | None = field(default_factory=DetectorHabits)

    def __post_init__(self) -> None:
        if not (self.fps > 0 and self.max_gap_s > 0 and self.heading_smooth_s >= 0 and self.transition_s >= 0):
            raise ConfigError("clip settings: fps and max_gap_s must be > 0, smoothing and transition >= 0")
        if not self.cameras:
            raise ConfigError("clip settings: at least one camera")


@dataclass(frozen=True)
class InfantClip:
    """One synthetic infant clip. Camera frame metres and pixels; `source_segment (T,)` indexes
    `source_clips` (-1: a transition frame), `source_time (T,)` is that adult clip's time (s; NaN in
    transitions) and `rotation (T, 3, 3)` turns the adult's world directions into the camera frame
    (NaN in transitions). `xy_exact` is the projection of `poses3d`; `xy` and `confidence` carry the
    detector's habits (`masks`)."""

    poses3d: np.ndarray  # (T, 12, 3)
    xy: np.ndarray  # (T, 12, 2), NaN: missing
    confidence: np.ndarray  # (T, 12)
    xy_exact: np.ndarray  # (T, 12, 2)
    fps: float
    intrinsics: Intrinsics
    image_size: tuple[int, int]
    camera: str
    infant_lengths: np.ndarray  # (13,) motion.SEGMENTS
    infant_source: str
    source_file: str
    source_clips: tuple[str, ...]
    source_segment: np.ndarray
    source_time: np.ndarray
    rotation: np.ndarray
    masks: HabitMasks

    def __len__(self) -> int:
        return len(self.poses3d)


@dataclass(frozen=True)
class AdultLibrary:
    """The adult clips of some files, in file order."""

    clips: tuple[AdultClip, ...]

    def files(self) -> tuple[str, ...]:
        return tuple(dict.fromkeys(c.file for c in self.clips))

    def of_file(self, file: str) -> list[int]:
        return [i for i, c in enumerate(self.clips) if c.file == file]


def load_adult_library(adult_dir: str | Path, files: tuple[str, ...] = ADULT_FILES) -> AdultLibrary:
    return AdultLibrary(tuple(c for f in files for c in load_adult_clips(Path(adult_dir) / f)))


@dataclass(frozen=True)
class _Motion:
    """Heading-free unit directions `(T, 13, 3)` with each frame's source and heading."""

    directions: np.ndarray
    heading: np.ndarray  # (T,) rad; NaN in transitions
    segment: np.ndarray  # (T,) int, -1 in transitions
    time: np.ndarray  # (T,) s; NaN in transitions


def _piece(clip: AdultClip, index: int, settings: ClipSettings) -> _Motion:
    times, dirs = resample(clip, settings.fps, settings.max_gap_s)
    angle = heading(dirs, settings.fps, settings.heading_smooth_s)
    free = np.einsum("tij,tsj->tsi", yaw_matrices(-angle), dirs)
    return _Motion(free, angle, np.full(len(times), index), times)


def _join(pieces: list[_Motion], settings: ClipSettings) -> _Motion:
    """The pieces one after another, each pair joined by an eased (cosine) turn of `transition_s`."""
    n = int(round(settings.transition_s * settings.fps))
    parts: list[_Motion] = []
    for i, piece in enumerate(pieces):
        if i and n:
            u = (1 - np.cos(np.pi * np.arange(1, n + 1) / (n + 1))) / 2
            a, b = pieces[i - 1].directions[-1], piece.directions[0]
            turn = slerp(np.broadcast_to(a, (n, *a.shape)), np.broadcast_to(b, (n, *b.shape)), u)
            parts.append(_Motion(turn, np.full(n, np.nan), np.full(n, -1), np.full(n, np.nan)))
        parts.append(piece)
    return _Motion(
        *(np.concatenate([getattr(p, k) for p in parts]) for k in ("directions", "heading", "segment", "time"))
    )


def _crop(motion: _Motion, start: int, frames: int) -> _Motion:
    s = slice(start, start + frames)
    return _Motion(motion.directions[s], motion.heading[s], motion.segment[s], motion.time[s])


def _assemble(
    motion: _Motion, names: tuple[str, ...], file: str, infants: InfantBodies, settings: ClipSettings,
    rng: np.random.Generator,
) -> InfantClip:  # fmt: skip
    """Place, size, project and detect one clip's heading-free motion."""
    lengths, infant = infants.draw(rng, settings.symmetric_infant)
    camera = settings.cameras[int(rng.integers(len(settings.cameras)))]
    t = np.arange(len(motion.directions)) / settings.fps
    body_mean = mean_rotation(trunk_frames(motion.directions))
    rot, pelvis = placement(rng, t, body_mean, camera, settings.sway)
    directions = np.einsum("tij,tsj->tsi", rot, motion.directions)
    poses3d = build_poses(pelvis, directions, lengths)
    intrinsics = camera.intrinsics()
    exact = project_points(poses3d, intrinsics)
    if settings.habits is None:
        xy, conf, masks = exact.copy(), np.ones(exact.shape[:2]), HabitMasks.none(*exact.shape[:2])
    else:
        xy, conf, masks = apply_habits(exact, settings.fps, settings.habits, rng)
    world = rot @ yaw_matrices(-np.nan_to_num(motion.heading))
    world[motion.segment < 0] = np.nan
    return InfantClip(poses3d, xy, conf, exact, settings.fps, intrinsics, (camera.width, camera.height), camera.name,
                      lengths, infant, file, names, motion.segment, motion.time, world, masks)  # fmt: skip


def retargeted_clips(
    library: AdultLibrary, infants: InfantBodies, seed: int, settings: ClipSettings | None = None
) -> Iterator[InfantClip]:
    """One clip per adult clip of at least `min_clip_s`, at its own length, in library order
    (shorter ones are skipped); each its own infant and camera. Same seed, same clips."""
    settings = settings or ClipSettings()
    rng = np.random.default_rng(seed)
    for clip in library.clips:
        if clip.duration_s >= settings.min_clip_s:
            yield _assemble(_piece(clip, 0, settings), (clip.name,), clip.file, infants, settings, rng)


def adult_infant_clips(
    library: AdultLibrary, infants: InfantBodies, seconds: float, count: int, seed: int,
    settings: ClipSettings | None = None,
) -> Iterator[InfantClip]:  # fmt: skip
    """`count` clips of `seconds` (at most 10 minutes) each, one infant per clip. A clip starts at
    a random frame of a random adult clip (the file drawn in proportion to its clips' duration) and
    goes on with the same file's next clips (wrapping round to its first), joined by eased
    transitions; short adult clips are joined like any other. Same seed, same clips. The arguments
    are checked at the call, the clips made as they are taken."""
    settings = settings or ClipSettings()
    if not 0 < seconds <= MAX_SECONDS or count < 0:
        raise ConfigError(f"clips must last (0, {MAX_SECONDS:g}] s and count >= 0, got {seconds} s, {count}")
    frames = max(int(round(seconds * settings.fps)), 1)
    rng = np.random.default_rng(seed)
    files = library.files()
    if not files:
        raise ConfigError("no adult clips to make infant clips from")
    weight = np.array([sum(library.clips[i].duration_s for i in library.of_file(f)) for f in files])
    return _generate(library, infants, frames, count, settings, rng, files, weight / weight.sum())


def _generate(
    library: AdultLibrary, infants: InfantBodies, frames: int, count: int, settings: ClipSettings,
    rng: np.random.Generator, files: tuple[str, ...], chance: np.ndarray,
) -> Iterator[InfantClip]:  # fmt: skip
    for _ in range(count):
        file = files[int(rng.choice(len(files), p=chance))]
        motion, names = _follow_on(library, library.of_file(file), frames, settings, rng)
        yield _assemble(motion, names, file, infants, settings, rng)


def _follow_on(
    library: AdultLibrary, rows: list[int], frames: int, settings: ClipSettings, rng: np.random.Generator
) -> tuple[_Motion, tuple[str, ...]]:
    """`frames` of motion from a random frame of a random clip of `rows` on through the next ones."""
    at = int(rng.integers(len(rows)))
    first = library.clips[rows[at]]
    pieces = [_piece(first, 0, settings)]
    names = [first.name]
    start = int(rng.integers(len(pieces[0].time)))
    total = len(pieces[0].time) - start
    joint = int(round(settings.transition_s * settings.fps))
    while total < frames:
        clip = library.clips[rows[(at + len(pieces)) % len(rows)]]
        pieces.append(_piece(clip, len(pieces), settings))
        names.append(clip.name)
        total += joint + len(pieces[-1].time)
    return _crop(_join(pieces, settings), start, frames), tuple(names)
