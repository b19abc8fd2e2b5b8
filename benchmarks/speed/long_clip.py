"""A long clip for timing what a user runs on a whole recording (docs/movement.md, "Speed"): the demo's
synthetic infant (examples/infant_clip_demo.py: footage drawn with OpenCV, COCO-17 keypoints as a detector
streams them) over `--minutes` minutes at 30 fps, one key pose sampled from the bundled prior every 0.8 s
(seed 7), the body turning back and forth (at most 17 degrees about the vertical, 6 about the optical axis).

    python benchmarks/speed/long_clip.py --out /tmp/long            # 10 minutes: clip.mp4 and clip.keypoints.jsonl
    cd /tmp/long
    /usr/bin/time zedo lift clip.keypoints.jsonl --video clip.mp4 --temporal smooth -o clip.zedo.json
    /usr/bin/time zedo analyze clip.zedo.json --output-dir analysis --report analysis --video clip.mp4
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "examples"))
import infant_clip_demo as demo


def long_motion(minutes: float, seed: int = 7) -> tuple[np.ndarray, tuple[str, ...]]:
    """`(T, 12, 3)` camera-frame poses of the clip and the joint names."""
    import torch

    from zedo_cli.data.skeleton import center_on_root
    from zedo_cli.prior.sampling import sample_poses
    from zedo_cli.prior.weights import bundled_prior_path, load_prior

    prior = load_prior(bundled_prior_path())
    count = int(minutes * 60 / demo.SECONDS_PER_POSE) + 1
    keys = sample_poses(prior.model, prior.sde, (count, prior.skeleton.num_joints, 3),
                        generator=torch.Generator().manual_seed(seed))  # fmt: skip
    keys = center_on_root(keys.double().numpy(), prior.skeleton)
    frames = int(round(demo.SECONDS_PER_POSE * demo.FPS))
    ease = (1.0 - np.cos(np.pi * np.arange(frames) / frames)) / 2.0  # zero velocity at each key pose
    seq = np.concatenate([(1 - ease)[:, None, None] * a + ease[:, None, None] * b
                          for a, b in zip(keys[:-1], keys[1:], strict=True)])  # fmt: skip
    t = np.arange(len(seq)) / demo.FPS
    rel = seq @ demo._turn(0.3 * np.sin(0.2 * t), 0.1 * np.sin(0.13 * t)).transpose(0, 2, 1)
    return demo.place(rel, prior.skeleton.joints), prior.skeleton.joints


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", type=Path, required=True, help="folder for clip.mp4 and clip.keypoints.jsonl")
    ap.add_argument("--minutes", type=float, default=10.0)
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    poses, joints = long_motion(args.minutes)
    demo.write_footage(args.out / "clip.mp4", poses, joints)
    demo.write_keypoints(args.out / "clip.keypoints.jsonl", poses, joints, np.random.default_rng(3))
    print(f"wrote {args.out / 'clip.mp4'} and {args.out / 'clip.keypoints.jsonl'}: {len(poses)} frames, the infant "
          f"{poses[:, :, 2].mean():.2f} m from the camera, in {time.perf_counter() - start:.0f} s")  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
