"""A video from start to end: footage of an infant, its 2D keypoints, the 3D lift, the overlay and the
clinical report, in about 10 s on 2 cores, with no third-party data.

    python examples/infant_clip_demo.py            # everything into out/infant_clip_demo/

1. Poses: 6 key poses sampled from the bundled syrip12 prior (seed 3; examples/make_examples.py
   samples its poses the same way), eased one into the next over 0.8 s at 30 fps (4 s, 120
   frames), the body turning slowly, placed in front of the paper's pseudo camera (f = 2000 px at
   the centre of a 960x540 frame) at the depth that keeps every joint and the head inside the
   frame (checked on every frame).
2. Footage, `clip.mp4`: each frame drawn with OpenCV, a simple infant body (a head, a trunk, a
   nappy, rounded limbs whose width follows their depth, the far parts drawn first) on a blanket.
3. 2D keypoints, `clip.keypoints.jsonl`: what a COCO-17 detector would stream (zedo JSON Lines),
   the body's joints projected with 1.5 px of noise and a detector's confidences; the face
   joints, which the body has none of, are missing.
4. The zedo commands, printed as they run:

       zedo lift clip.keypoints.jsonl --video clip.mp4 --temporal smooth -o clip.zedo.json
       zedo render clip.zedo.json --video clip.mp4 -o clip.render.mp4 --side-view
       zedo analyze clip.zedo.json --output-dir analysis --report analysis --video clip.mp4

   `--video` gives the lift the clip's frame size and frame rate and checks the keypoints against
   it; the render draws the lifted 3D skeletons back over the footage; the analysis writes the
   measures (CSV, JSON) and `analysis/clip.report.html`, whose frames to review come with thumbnails
   cut from the footage (its `--video`).

Re-running replaces the outputs (`--overwrite`). `--out DIR` writes elsewhere.
"""

from __future__ import annotations

import argparse
import json
import shlex
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

WIDTH, HEIGHT, FPS = 960, 540, 30.0
FOCAL = 2000.0  # the paper's pseudo camera, which zedo lift uses when no calibration is given
KEY_POSES, SECONDS_PER_POSE, SEED = 6, 0.8, 3
MARGIN_PX = 24  # every joint and the whole head stay this far inside the frame
HEAD_RADIUS_M, NECK_M = 0.062, 0.025
LIMB_RADIUS_M = {"upper_arm": 0.022, "forearm": 0.018, "thigh": 0.03, "shank": 0.024}
SKIN, SKIN_EDGE, NAPPY, HAIR = (150, 182, 228), (95, 125, 175), (245, 245, 240), (60, 75, 95)  # BGR
COCO17 = ("nose", "left_eye", "right_eye", "left_ear", "right_ear", "left_shoulder", "right_shoulder", "left_elbow",
          "right_elbow", "left_wrist", "right_wrist", "left_hip", "right_hip", "left_knee", "right_knee", "left_ankle",
          "right_ankle")  # fmt: skip
OUT = Path(__file__).resolve().parents[1] / "out" / "infant_clip_demo"


# --- the clip's 3D poses ------------------------------------------------------------------------


def key_poses() -> tuple[np.ndarray, tuple[str, ...]]:
    """`(KEY_POSES, 12, 3)` root-relative metres (camera axes: x right, y down, z forward), sampled
    from the bundled prior, and its joint names."""
    import torch

    from zedo_cli.data.skeleton import center_on_root
    from zedo_cli.prior.sampling import sample_poses
    from zedo_cli.prior.weights import bundled_prior_path, load_prior

    torch.set_num_threads(1)  # a batch of 6 poses gains nothing from threads, and loses much on a busy machine
    prior = load_prior(bundled_prior_path())
    poses = sample_poses(prior.model, prior.sde, (KEY_POSES, prior.skeleton.num_joints, 3),
                         generator=torch.Generator().manual_seed(SEED))  # fmt: skip
    return center_on_root(poses.double().numpy(), prior.skeleton), prior.skeleton.joints


def _turn(yaw: np.ndarray, roll: np.ndarray) -> np.ndarray:
    """`(T, 3, 3)`: about the camera's vertical axis by `yaw`, then about its optical axis by `roll`."""
    cy, sy, cr, sr = np.cos(yaw), np.sin(yaw), np.cos(roll), np.sin(roll)
    zero, one = np.zeros_like(yaw), np.ones_like(yaw)
    ry = np.stack([np.stack([cy, zero, sy], -1), np.stack([zero, one, zero], -1), np.stack([-sy, zero, cy], -1)], 1)
    rz = np.stack([np.stack([cr, -sr, zero], -1), np.stack([sr, cr, zero], -1), np.stack([zero, zero, one], -1)], 1)
    return rz @ ry


def clip_motion(keys: np.ndarray) -> np.ndarray:
    """`(T, 12, 3)` root-relative: the key poses eased one into the next (zero velocity at each), the
    body turning slowly (about 10 degrees a second about the vertical, 3 about the optical axis)."""
    frames = int(round(SECONDS_PER_POSE * FPS))
    ease = (1.0 - np.cos(np.pi * np.arange(frames) / frames)) / 2.0  # (F,)
    steps = [(1 - ease)[:, None, None] * a + ease[:, None, None] * b for a, b in zip(keys[:-1], keys[1:], strict=True)]
    seq = np.concatenate([*steps, keys[-1:]])  # (T, 12, 3): the last key pose ends the clip
    t = np.arange(len(seq)) / FPS
    return seq @ _turn(0.17 * t - 0.3, 0.05 * t - 0.1).transpose(0, 2, 1)


def _joint(poses: np.ndarray, joints: tuple[str, ...], name: str) -> np.ndarray:
    return poses[..., joints.index(name), :]


def head_centres(poses: np.ndarray, joints: tuple[str, ...]) -> np.ndarray:
    """`(..., 3)`: the head above the shoulders, along the trunk (hips -> shoulders); syrip12 has no head joint."""
    shoulders = (_joint(poses, joints, "left_shoulder") + _joint(poses, joints, "right_shoulder")) / 2
    hips = (_joint(poses, joints, "left_hip") + _joint(poses, joints, "right_hip")) / 2
    up = shoulders - hips
    up /= np.linalg.norm(up, axis=-1, keepdims=True)
    return shoulders + (NECK_M + HEAD_RADIUS_M) * up


def project(points: np.ndarray) -> np.ndarray:
    """Camera-frame points `(..., 3)` -> pixels `(..., 2)` through the pseudo camera."""
    return FOCAL * points[..., :2] / points[..., 2:] + np.array([WIDTH / 2, HEIGHT / 2])


def place(rel: np.ndarray, joints: tuple[str, ...]) -> np.ndarray:
    """Camera-frame poses: the clip at the nearest depth (in 5 cm steps) at which every joint and the
    whole head stay MARGIN_PX inside the frame on every frame, drifting 2 cm over the clip."""
    drift = np.linspace(0.0, 1.0, len(rel))[:, None] * np.array([0.02, -0.01, 0.0])  # (T, 3)
    for depth in np.arange(1.0, 6.0, 0.05):
        cam = rel + (drift + [0.0, 0.0, depth])[:, None]
        head = head_centres(cam, joints)
        px, head_px = project(cam), project(head)
        head_r = FOCAL * HEAD_RADIUS_M / head[:, 2]
        low = np.minimum(px.min(1), head_px - head_r[:, None]).min(0)
        high = np.maximum(px.max(1), head_px + head_r[:, None]).max(0)
        if (low >= MARGIN_PX).all() and (high <= np.array([WIDTH, HEIGHT]) - MARGIN_PX).all():
            return cam
    raise SystemExit("no depth up to 6 m keeps the clip inside the frame")


# --- footage ------------------------------------------------------------------------------------


def blanket() -> np.ndarray:
    """The background: a pale blanket with soft stripes, `(H, W, 3)` BGR."""
    y = np.arange(HEIGHT)[:, None, None]
    x = np.arange(WIDTH)[None, :, None]
    stripes = 8.0 * np.sin(2 * np.pi * (x + 0.4 * y) / 90.0)
    base = np.array([214.0, 206.0, 196.0]) + stripes + 10.0 * (y / HEIGHT)
    return np.clip(base, 0, 255).astype(np.uint8)


def _px(point: np.ndarray) -> tuple[int, int]:
    u, v = project(point)
    return int(round(u * 16)), int(round(v * 16))  # 4 fractional bits: OpenCV's sub-pixel drawing


def _capsule(frame: np.ndarray, a: np.ndarray, b: np.ndarray, radius_m: float, colour: tuple, edge: tuple) -> None:
    import cv2

    width = max(2, int(round(2 * FOCAL * radius_m / ((a[2] + b[2]) / 2))))
    cv2.line(frame, _px(a), _px(b), edge, width + 3, cv2.LINE_AA, 4)
    cv2.line(frame, _px(a), _px(b), colour, width, cv2.LINE_AA, 4)


def _shade(colour: tuple, depth: float, near: float, far: float) -> tuple:
    """Farther parts a little darker, so crossing limbs stay apart."""
    k = 1.0 - 0.18 * np.clip((depth - near) / max(far - near, 1e-6), 0.0, 1.0)
    return tuple(int(c * k) for c in colour)


def draw_infant(frame: np.ndarray, pose: np.ndarray, joints: tuple[str, ...]) -> None:
    """One infant, camera-frame pose `(12, 3)`, painted far to near."""
    import cv2

    j = {name: pose[i] for i, name in enumerate(joints)}
    near, far = float(pose[:, 2].min()), float(pose[:, 2].max())
    parts = []  # (depth, painter)
    for side in ("left", "right"):
        for limb, (p, d) in {"upper_arm": ("shoulder", "elbow"), "forearm": ("elbow", "wrist"),
                             "thigh": ("hip", "knee"), "shank": ("knee", "ankle")}.items():  # fmt: skip
            a, b = j[f"{side}_{p}"], j[f"{side}_{d}"]
            colour = _shade(SKIN, (a[2] + b[2]) / 2, near, far)
            parts.append(((a[2] + b[2]) / 2, lambda a=a, b=b, r=LIMB_RADIUS_M[limb], c=colour: _capsule(
                frame, a, b, r, c, SKIN_EDGE)))  # fmt: skip
    trunk = np.array([j["left_shoulder"], j["right_shoulder"], j["right_hip"], j["left_hip"]])

    def draw_trunk() -> None:
        pts = np.array([_px(p) for p in trunk], dtype=np.int32).reshape(-1, 1, 2)
        cv2.fillPoly(frame, [pts], SKIN, cv2.LINE_AA, 4)
        for a, b in zip(trunk, np.roll(trunk, -1, 0), strict=True):
            _capsule(frame, a, b, 0.035, SKIN, SKIN_EDGE)
        cv2.fillPoly(frame, [pts], SKIN, cv2.LINE_AA, 4)  # the edges' inner halves covered again
        _capsule(frame, j["left_hip"], j["right_hip"], 0.045, NAPPY, (200, 200, 195))  # the nappy

    parts.append((float(trunk[:, 2].mean()), draw_trunk))
    head = head_centres(pose, joints)

    def draw_head() -> None:
        r = int(round(16 * FOCAL * HEAD_RADIUS_M / head[2]))
        cv2.circle(frame, _px(head), r + 24, SKIN_EDGE, -1, cv2.LINE_AA, 4)
        cv2.circle(frame, _px(head), r, SKIN, -1, cv2.LINE_AA, 4)
        away = project(head) - project((j["left_shoulder"] + j["right_shoulder"]) / 2)  # from the neck, in the image
        angle = float(np.degrees(np.arctan2(away[1], away[0])))
        centre = project(head) + 0.3 * (r / 16) * away / max(float(np.linalg.norm(away)), 1e-6)
        cv2.ellipse(frame, (int(round(centre[0] * 16)), int(round(centre[1] * 16))), (int(0.75 * r), int(0.95 * r)),
                    angle, -90, 90, HAIR, -1, cv2.LINE_AA, 4)  # fmt: skip  # hair: the half away from the neck

    parts.append((float(head[2]), draw_head))
    for _, paint in sorted(parts, key=lambda item: -item[0]):
        paint()


def write_footage(path: Path, poses: np.ndarray, joints: tuple[str, ...]) -> None:
    import cv2

    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"mp4v"), FPS, (WIDTH, HEIGHT))
    if not writer.isOpened():
        raise SystemExit(f"{path}: OpenCV cannot write an mp4v video here")
    background = blanket()
    for pose in poses:
        frame = background.copy()
        draw_infant(frame, pose, joints)
        writer.write(frame)
    writer.release()


# --- 2D keypoints -------------------------------------------------------------------------------


def write_keypoints(path: Path, poses: np.ndarray, joints: tuple[str, ...], rng: np.random.Generator) -> None:
    """zedo JSON Lines, one frame a line, 17 COCO points a person (x, y, confidence; null = missing)."""
    xy = project(poses) + rng.normal(0.0, 1.5, poses.shape[:2] + (2,))  # (T, 12, 2)
    confidence = rng.uniform(0.75, 0.98, poses.shape[:2])
    with path.open("w") as out:
        for t in range(len(poses)):
            points = [None] * len(COCO17)
            for k, name in enumerate(joints):
                points[COCO17.index(name)] = [round(float(xy[t, k, 0]), 2), round(float(xy[t, k, 1]), 2),
                                              round(float(confidence[t, k]), 3)]  # fmt: skip
            out.write(json.dumps({"frame": t, "persons": [{"keypoints": points, "score": 0.95}]}) + "\n")


# --- the zedo commands --------------------------------------------------------------------------


def zedo(*args: str, cwd: Path) -> None:
    """Run `zedo ARGS` in `cwd` (as `python -m zedo_cli`, the same program), printing the command first."""
    print(f"\n$ zedo {shlex.join(args)}", flush=True)
    subprocess.run([sys.executable, "-m", "zedo_cli", *args], cwd=cwd, check=True)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=Path, default=OUT, help=f"output folder (default: {OUT})")
    args = ap.parse_args()
    out: Path = args.out
    out.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    keys, joints = key_poses()
    poses = place(clip_motion(keys), joints)
    write_footage(out / "clip.mp4", poses, joints)
    write_keypoints(out / "clip.keypoints.jsonl", poses, joints, np.random.default_rng(SEED))
    print(f"wrote {out / 'clip.mp4'} ({len(poses)} frames, {WIDTH}x{HEIGHT}, {FPS:g} fps; the infant "
          f"{poses[:, :, 2].mean():.2f} m from the camera) and {out / 'clip.keypoints.jsonl'} "
          f"in {time.perf_counter() - start:.1f} s")  # fmt: skip
    zedo("lift", "clip.keypoints.jsonl", "--video", "clip.mp4", "--temporal", "smooth", "-o", "clip.zedo.json",
         "--overwrite", cwd=out)  # fmt: skip
    zedo("render", "clip.zedo.json", "--video", "clip.mp4", "-o", "clip.render.mp4", "--side-view", "--overwrite",
         cwd=out)  # fmt: skip
    zedo("analyze", "clip.zedo.json", "--output-dir", "analysis", "--report", "analysis", "--video", "clip.mp4",
         "--overwrite", cwd=out)  # fmt: skip
    print(f"\ndone in {time.perf_counter() - start:.0f} s: open {out / 'clip.render.mp4'} and "
          f"{out / 'analysis' / 'clip.report.html'}")  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
