"""Synthetic infant clips eased between real SyRIP key poses, for the benchmarks, experiments and tests that need
video with 3D truth: `make_sequences`, the generator. The settings most of them make clips with are in
benchmarks/lib/settings.py (`CLIP_SETTINGS`, the known cameras).

A clip eases (cosine) from one random key pose to the next, turns slowly about the vertical and the optical
axis and drifts in translation about 1 m in front of the pseudo camera (f = 2000 px, principal point at the
centre of a 1280x720 image) or before a drawn camera, is projected exactly, then given detector-like noise:
Gaussian pixel noise, dropped joints and one short gap of frames with only two joints (not liftable).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import torch

from ...data.skeleton import get_skeleton
from ...lifting.camera import Intrinsics, project
from ...lifting.detections import pose_size
from .cameras import Sway, wave

IMAGE_W, IMAGE_H = 1280, 720
SYRIP12_JOINTS = get_skeleton("syrip12").joints


def _rotation(yaw: np.ndarray, roll: np.ndarray) -> np.ndarray:
    """Rotations `(T, 3, 3)`: about the camera's vertical axis (y) by `yaw`, then the optical axis (z) by `roll`."""
    cy, sy, cr, sr = np.cos(yaw), np.sin(yaw), np.cos(roll), np.sin(roll)
    ry = np.zeros((len(yaw), 3, 3))
    ry[:, 0, 0], ry[:, 0, 2], ry[:, 1, 1], ry[:, 2, 0], ry[:, 2, 2] = cy, sy, 1.0, -sy, cy
    rz = np.zeros((len(roll), 3, 3))
    rz[:, 0, 0], rz[:, 0, 1], rz[:, 1, 0], rz[:, 1, 1], rz[:, 2, 2] = cr, -sr, sr, cr, 1.0
    return rz @ ry


def _turning(rng: np.random.Generator, t: np.ndarray, turn_scale: float, sway: Sway | None) -> np.ndarray:
    """The body's rotations `(T, 3, 3)` at times `t (T,)`: turning at constant rates scaled by `turn_scale`, or with
    `sway` lying under the camera, turning in the image (about z) and rolling about its long axis (about y)."""
    if sway is None:
        yaw = rng.uniform(-0.4, 0.4) + turn_scale * rng.uniform(-0.3, 0.3) * t  # up to ~17 deg/s
        roll = rng.uniform(-0.2, 0.2) + turn_scale * rng.uniform(-0.1, 0.1) * t
    else:
        roll = rng.uniform(-sway.offset_rad, sway.offset_rad) + wave(rng, t, sway.turn_rad, sway.period_s)
        yaw = wave(rng, t, sway.roll_rad, sway.period_s)
    return _rotation(yaw, roll)


def _pseudo_camera_root(rng: np.random.Generator, t: np.ndarray, depth_m: float, drift_scale: float,
                        sway: Sway | None) -> np.ndarray:  # fmt: skip
    """The root `(T, 3)` before the pseudo camera: about `depth_m` away, offset and drifting (at a constant speed, or
    with `sway` about its place), both scaled by `drift_scale`."""
    offset = rng.normal(0, [0.05, 0.05, 0.1])
    if sway is None:
        drift = rng.uniform(-0.05, 0.05, 3) * t[:, None]
    else:
        drift = np.stack([wave(rng, t, sway.drift_m, sway.period_s) for _ in range(3)], axis=1)
    return np.array([0.0, 0.0, depth_m]) + drift_scale * offset + drift_scale * drift


# A camera placement for one synthetic clip: (rng, root-relative camera-frame poses (T, J, 3), their
# root's drift (T, 3) about its mean) -> (K (3, 3), root points (T, 3) in the camera frame).
Placement = Callable[[np.random.Generator, np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]


def _eased_error(e0: np.ndarray, e1: np.ndarray, ease: np.ndarray) -> np.ndarray:
    """A detector's relative error `(T, J, 2)` eased from key pose e0 `(J, 2)` to e1; a joint missed at
    the nearer key pose is missed (NaN)."""
    mix = (1 - ease)[:, None, None] * np.nan_to_num(e0) + ease[:, None, None] * np.nan_to_num(e1)
    missed = np.where(ease[:, None] < 0.5, np.isnan(e0).any(-1), np.isnan(e1).any(-1))  # (T, J)
    mix[missed] = np.nan
    return mix


# The syrip12 joints as a tree for `interpolation="segments"`: (parent, child); "root" is the hips' midpoint,
# "neck" the shoulders' midpoint (the two halves of each girdle stay opposite, so those midpoints stay).
_SEGMENTS = (("root", "left_hip"), ("root", "right_hip"), ("root", "neck"), ("neck", "left_shoulder"),
             ("neck", "right_shoulder"), ("left_hip", "left_knee"), ("left_knee", "left_ankle"),
             ("right_hip", "right_knee"), ("right_knee", "right_ankle"), ("left_shoulder", "left_elbow"),
             ("left_elbow", "left_wrist"), ("right_shoulder", "right_elbow"),
             ("right_elbow", "right_wrist"))  # fmt: skip


def _segment_vectors(poses: np.ndarray, joints: tuple[str, ...]) -> np.ndarray:
    """`(P, S, 3)` parent-to-child vectors of `_SEGMENTS` of syrip12 poses `(P, J, 3)`."""
    at = {n: poses[:, i] for i, n in enumerate(joints)}
    at["root"] = (at["left_hip"] + at["right_hip"]) / 2
    at["neck"] = (at["left_shoulder"] + at["right_shoulder"]) / 2
    return np.stack([at[c] - at[p] for p, c in _SEGMENTS], 1)


def _slerp(a: np.ndarray, b: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Unit directions `(T, S, 3)` turned from unit `a (S, 3)` to unit `b` along great circles, fraction `t (T,)`."""
    theta = np.arccos(np.clip((a * b).sum(-1), -1.0, 1.0))  # (S,)
    sin = np.sin(theta)
    turns = sin > 1e-9  # (S,) else (nearly) the same direction: a straight mix
    safe = np.where(turns, sin, 1.0)
    wa = np.where(turns, np.sin((1 - t)[:, None] * theta) / safe, (1 - t)[:, None])  # (T, S)
    wb = np.where(turns, np.sin(t[:, None] * theta) / safe, t[:, None])
    out = wa[..., None] * a + wb[..., None] * b
    return out / np.linalg.norm(out, axis=-1, keepdims=True)


def segment_interpolation(keys: np.ndarray, ease: np.ndarray, joints: tuple[str, ...]) -> np.ndarray:
    """Root-relative poses `((K - 1) * T, J, 3)` from syrip12 key poses `(K, J, 3)` that keep one infant's
    bones: every segment keeps its length in the first key pose and turns, at `ease (T,)`, along a great
    circle from one key pose's direction to the next. (Easing the joints' positions instead shortens a
    turning bone: half-way through a 90 degree turn to 71 % of its length.)"""
    vec = _segment_vectors(keys, joints)  # (K, S, 3)
    length = np.linalg.norm(vec[0], axis=-1)  # (S,) the clip's infant
    unit = vec / np.linalg.norm(vec, axis=-1, keepdims=True)
    dirs = np.concatenate([_slerp(unit[i], unit[i + 1], ease) for i in range(len(keys) - 1)])  # (N, S, 3)
    seg = dirs * length[:, None]
    out = {"root": np.zeros((len(seg), 3))}
    for s, (parent, child) in enumerate(_SEGMENTS):  # every parent comes before its children
        out[child] = out[parent] + seg[:, s]
    return np.stack([out[n] for n in joints], 1)


def make_sequences(
    poses: np.ndarray, rng: np.random.Generator, *, count: int, keyposes: int, transition_s: float, fps: float,
    noise_px: float, drop: float, gap: int, place: Placement | None = None, key_noise: np.ndarray | None = None,
    noise_rel: float = 0.0, depth_m: float = 1.0, drift_scale: float = 1.0, interpolation: str = "positions",
    turn_scale: float = 1.0, sway: Sway | None = None,
) -> dict[str, np.ndarray]:  # fmt: skip
    """Synthetic videos: truth (root-relative and camera frame), noisy 2D, confidences, track labels.

    By default about 1 m in front of the pseudo camera. `place` puts each clip before another camera
    (its K and root points; the root drifts up to 2 cm/s about its place there). `key_noise (P, J, 2)`:
    a detector's error of each pose of `poses`, relative to the pose's 2D size (`lifting.detections.pose_size`; NaN: the
    joint was missed), eased from key pose to key pose like the poses and scaled to each frame's 2D
    size. `noise_rel`: Gaussian pixel noise as a fraction of the frame's 2D size, on top of `noise_px`.

    `depth_m` and `drift_scale` place the body before the pseudo camera: about `depth_m` in front of it,
    its random offset and drift scaled by `drift_scale`. The defaults (1 m, 1) are the calibration clips'
    geometry (benchmarks/calibrate/calibrate_measures.py), which overfills a 1280x720 frame; the demo clip
    (benchmarks/clips/demo_clip.py) stands further back and drifts less, to stay inside it. `turn_scale`
    scales the rates at which the body turns about the vertical and the optical axis (0: it keeps its first
    orientation). The random draws are the same whatever the three values. With `sway`, the body instead sways
    about its first place as the adult motion's clips do (`cameras.Sway`: an in-image turn about the optical axis, a
    roll about the vertical, a drift, each a slow sinusoid), so that every stretch of a long clip is placed like a
    short clip; `turn_scale` is then unused.

    `interpolation`: "positions" eases every joint's position from key pose to key pose (the clips every
    shipped calibration except the `3d_` clip features' was fitted on): a turning bone shortens half-way,
    in the calibration clips thighs to a median 79 % of their key poses' length and in 5 % of frames below
    27 %. "segments" keeps the first key pose's bone lengths through the clip and turns each segment
    (`segment_interpolation`), as a real infant's limbs move. The random draws are the same for both."""
    frames = int(round(transition_s * fps))
    rel_all, cam_all, tracks, k_all, err_all = [], [], [], [], []
    for track in range(count):
        picked = rng.choice(len(poses), keyposes, replace=False)
        keys = poses[picked]
        u = np.arange(frames) / frames
        ease = (1.0 - np.cos(np.pi * u)) / 2.0  # zero velocity at every key pose: smooth motion
        if interpolation == "segments":
            seq = segment_interpolation(keys, ease, SYRIP12_JOINTS)
        else:
            seq = np.concatenate([(1 - ease)[:, None, None] * keys[i] + ease[:, None, None] * keys[i + 1]
                                  for i in range(keyposes - 1)])  # fmt: skip
        if key_noise is not None:
            err_all.append(np.concatenate([_eased_error(key_noise[picked[i]], key_noise[picked[i + 1]], ease)
                                           for i in range(keyposes - 1)]))  # fmt: skip
        t = np.arange(len(seq)) / fps
        rel = seq @ _turning(rng, t, turn_scale, sway).transpose(0, 2, 1)
        if place is None:
            root = _pseudo_camera_root(rng, t, depth_m, drift_scale, sway)
            k_all.append(np.repeat(Intrinsics.pseudo(IMAGE_W, IMAGE_H).matrix()[None], len(seq), 0))
        else:
            kmat, root = place(rng, rel, rng.uniform(-0.02, 0.02, 3) * (t - t.mean())[:, None])
            k_all.append(np.repeat(kmat[None], len(seq), 0))
        rel_all.append(rel)
        cam_all.append(rel + root[:, None])
        tracks.append(np.full(len(seq), track))
    rel, cam, track, k = np.concatenate(rel_all), np.concatenate(cam_all), np.concatenate(tracks), np.concatenate(k_all)
    xy = project(torch.tensor(cam), torch.tensor(k)).numpy()
    size = pose_size(xy)[:, None, None]  # (T, 1, 1) px
    if key_noise is not None:
        xy = xy + np.concatenate(err_all) * size  # NaN (a missed joint) stays NaN: confidence 0 below
    xy = xy + rng.normal(0.0, noise_px, cam.shape[:2] + (2,))
    if noise_rel:
        xy = xy + rng.normal(0.0, 1.0, cam.shape[:2] + (2,)) * noise_rel * size
    conf = np.where(np.isfinite(xy).all(-1), 1.0, 0.0)
    conf[rng.random(conf.shape) < drop] = 0.0
    for tr in range(count):  # one short gap per sequence: two joints only, not liftable
        idx = np.flatnonzero(track == tr)
        at = rng.integers(10, len(idx) - 10 - gap)
        conf[idx[at : at + gap], 2:] = 0.0
    xy[conf == 0] = np.nan
    return {"rel": rel, "cam": cam, "xy": xy, "conf": conf, "k": k, "tracks": track}
