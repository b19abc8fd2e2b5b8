"""Settings many benchmarks and experiments share, so that none imports the calibration pipeline for a constant:
the calibration clips' `CLIP_SETTINGS` (for `clips.make_sequences`) and the known cameras drawn for the
calibration of known intrinsics (`CameraRange`, `CAMERAS`, `place_camera`)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

# The calibration clips (calibrate/calibrate_measures.py) and every benchmark that scores lifts of their kind:
# 16 clips of 5 s at 30 fps a fold, eased between 6 key poses, 3 px noise, 3 % of joints dropped, a 3-frame gap.
CLIP_SETTINGS = {"count": 16, "keyposes": 6, "transition_s": 1.0, "fps": 30.0, "noise_px": 3.0, "drop": 0.03, "gap": 3}


@dataclass(frozen=True)
class CameraRange:
    """The camera set-ups drawn for the calibration of known intrinsics (`--cameras`): a focal length
    log-uniform in `focal_px`, the infant's root `depth_m` from the camera (uniform), one of `frames`,
    and a place in the frame with the whole body at least `margin` of the frame inside it."""

    focal_px: tuple[float, float] = (600.0, 2500.0)
    depth_m: tuple[float, float] = (0.5, 2.2)  # wider than calibrate_measures.DEPTH_EDGES: lifted depths err by ~10 %
    frames: tuple[tuple[int, int], ...] = ((1280, 720), (1920, 1080))
    margin: float = 0.05


CAMERAS = CameraRange()


def place_camera(rng: np.random.Generator, rel: np.ndarray, drift: np.ndarray, cams: CameraRange
                 ) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """A camera of `cams` and the root points `(T, 3)` of root-relative poses `rel (T, J, 3)` (drifting by
    `drift (T, 3)`) with every joint of every frame inside the frame: K `(3, 3)` and the roots."""
    lo, hi = np.log(cams.focal_px)
    for attempt in range(5000):
        if attempt % 50 == 0:  # the depth is kept for 50 tries of a lens, frame and place: depths stay near uniform
            z = float(rng.uniform(*cams.depth_m))
        w, h = cams.frames[rng.integers(len(cams.frames))]
        f = float(np.exp(rng.uniform(lo, hi)))
        u, v = rng.uniform(cams.margin, 1 - cams.margin, 2) * (w, h)  # where the root appears
        root = np.array([(u - w / 2) * z / f, (v - h / 2) * z / f, z]) + drift
        cam = rel + root[:, None]  # (T, J, 3)
        if (cam[..., 2] < 0.1).any():
            continue
        px = f * cam[..., :2] / cam[..., 2:] + (w / 2, h / 2)
        m = cams.margin * np.array([w, h])
        if ((px >= m) & (px <= (w, h) - m)).all():
            return np.array([[f, 0.0, w / 2], [0.0, f, h / 2], [0.0, 0.0, 1.0]]), root
    raise RuntimeError(f"no camera of {cams} keeps the body in the frame")
