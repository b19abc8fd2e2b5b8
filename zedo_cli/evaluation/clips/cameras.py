"""Cameras that film infants from above, and the supine placement of a clip before one.

Camera frame (zedo's, OpenCV's): x right, y down, z forward, metres. An infant lying on its back
under the camera shows its chest (the trunk's forward axis points to -z), its head up the image
(the trunk's up axis to -y) and therefore its own left on the image's right (+x).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import torch

from ...errors import ConfigError
from ...lifting.camera import PSEUDO_FOCAL_PX, Intrinsics, project
from .stillness import trunk_axes

# A trunk frame's columns (left, up, forward) -> camera axes (+x, -y, -z): supine, head up the image.
SUPINE = np.diag([1.0, -1.0, -1.0])


@dataclass(frozen=True)
class CameraSetup:
    """A camera: focal length (px, square pixels, principal point at the image centre), image size
    (px) and the range of the pelvis's depth (m) a clip is drawn from."""

    name: str
    focal_px: float
    width: int
    height: int
    depth_m: tuple[float, float]

    def __post_init__(self) -> None:
        lo, hi = self.depth_m
        if not (self.focal_px > 0 and self.width > 0 and self.height > 0 and 0 < lo <= hi):
            raise ConfigError(f"camera {self.name!r}: focal, image size and depth range must be positive")

    def intrinsics(self) -> Intrinsics:
        if self.name == "pseudo":
            return Intrinsics.pseudo(self.width, self.height, self.focal_px)
        return Intrinsics(self.focal_px, self.focal_px, self.width / 2.0, self.height / 2.0, f"synthetic:{self.name}")


# The pseudo camera as benchmarks/temporal.make_sequences places it (about 1 m, which overfills a
# 1280x720 frame with a stretched infant), and set-ups clinics use, each far enough for the infant
# to fit in the frame most of the time.
PSEUDO_CAMERA = CameraSetup("pseudo", PSEUDO_FOCAL_PX, 1280, 720, (0.9, 1.1))
CLINIC_CAMERAS: tuple[CameraSetup, ...] = (
    CameraSetup("wide-720p", 600.0, 1280, 720, (0.8, 1.0)),
    CameraSetup("webcam-720p", 900.0, 1280, 720, (0.8, 1.2)),
    CameraSetup("phone-1080p", 1500.0, 1920, 1080, (0.9, 1.3)),
    CameraSetup("tripod-1080p", 2200.0, 1920, 1080, (1.2, 1.5)),
    CameraSetup("tele-1080p", 3000.0, 1920, 1080, (1.4, 1.5)),
)
# Further than the clinic set-ups: a camera on a high tripod or the ceiling, 2.5-3.5 m away
FAR_CAMERAS: tuple[CameraSetup, ...] = (
    CameraSetup("far-1080p", 2000.0, 1920, 1080, (2.5, 3.5)),
    CameraSetup("far-tele-1080p", 3000.0, 1920, 1080, (2.5, 3.5)),
)


def axis_rotations(axis: int, angle: np.ndarray) -> np.ndarray:
    """Rotations `(T, 3, 3)` by `angle (T,)` about camera axis `axis` (0 x, 1 y, 2 z), right-handed."""
    i, j = [a for a in range(3) if a != axis]
    c, s = np.cos(angle), np.sin(angle)
    out = np.zeros((len(angle), 3, 3))
    out[:, axis, axis] = 1.0
    out[:, i, i], out[:, i, j], out[:, j, i], out[:, j, j] = c, -s, s, c
    return out


@dataclass(frozen=True)
class Sway:
    """A lying infant's slow whole-body movement: an in-image turn (about the optical axis) within
    +-`turn_rad` of a random angle up to +-`offset_rad`, a roll about its long axis within
    +-`roll_rad`, both sinusoids of `period_s` (drawn in the range); and a pelvis drift within
    +-`drift_m` per axis."""

    offset_rad: float = 0.4
    turn_rad: float = 0.15
    roll_rad: float = 0.15
    period_s: tuple[float, float] = (15.0, 60.0)
    drift_m: float = 0.02


def wave(rng: np.random.Generator, t: np.ndarray, amplitude: float, period_s: tuple[float, float]) -> np.ndarray:
    """A sinusoid of `amplitude` at times `t (T,)`, its period drawn in `period_s` and its phase at random."""
    period = rng.uniform(*period_s)
    return amplitude * np.sin(2 * np.pi * t / period + rng.uniform(0, 2 * np.pi))


def placement(
    rng: np.random.Generator, t: np.ndarray, body_mean: np.ndarray, camera: CameraSetup, sway: Sway
) -> tuple[np.ndarray, np.ndarray]:
    """For frames at times `t (T,)`: rotations `(T, 3, 3)` from the (heading-free) body frame into
    the camera frame, and the pelvis `(T, 3)` in the camera frame. `body_mean`: the clip's mean
    trunk frame (columns left, up, forward), turned to lie supine (`SUPINE`) before the sway."""
    fixed = SUPINE @ body_mean.T
    turn = rng.uniform(-sway.offset_rad, sway.offset_rad) + wave(rng, t, sway.turn_rad, sway.period_s)
    roll = wave(rng, t, sway.roll_rad, sway.period_s)
    rot = axis_rotations(2, turn) @ axis_rotations(1, roll) @ fixed
    depth = rng.uniform(*camera.depth_m)
    centre = np.array([rng.normal(0.0, 0.02), 0.05 + rng.normal(0.0, 0.02), depth])
    drift = np.stack([wave(rng, t, sway.drift_m, sway.period_s) for _ in range(3)], axis=1)
    return rot, centre + drift


def turned_supine(poses: np.ndarray, joints: Sequence[str]) -> np.ndarray:
    """Each pose of `poses (P, J, 3)` turned about its own origin so that its trunk lies as `SUPINE` places it:
    chest to the camera (-z), head up the image (-y), its left on the image's right."""
    axes, _ = trunk_axes(poses, joints)  # rows: left, up, forward
    return np.einsum("ij,pjk,pmk->pmi", SUPINE, axes, poses)


def project_points(points: np.ndarray, intrinsics: Intrinsics) -> np.ndarray:
    """Pixels `(..., J, 2)` of camera-frame points `(..., J, 3)` through zedo's `project`."""
    k = torch.tensor(intrinsics.matrix(), dtype=torch.float64)
    return project(torch.as_tensor(points, dtype=torch.float64), k).numpy()
