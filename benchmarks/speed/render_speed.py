"""Frames per second of `zedo render` on a 1280x720 clip with a person in every frame.

A synthetic clip (a moving textured background, mp4v) and a zedo.pose3d/1 result of a syrip12
pose moving through it, lifted through a lens with distortion, are written to a temporary
folder; then the clip is only decoded and re-encoded (the floor any renderer pays), rendered,
and rendered with --side-view. Each figure is the best of --repeats runs, with the CPU time it
took (all threads): decoding, drawing and encoding run on three threads, so on an idle machine
with 2 cores the frame rate can exceed 1000 / (ms CPU per frame).

    python benchmarks/speed/render_speed.py                 # 300 frames, 1280x720
    python benchmarks/speed/render_speed.py --frames 600 --size 1920 1080
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
import time
from pathlib import Path

import cv2
import numpy as np

from zedo_cli.camera.video import iter_frames
from zedo_cli.data.skeleton import get_skeleton
from zedo_cli.footage.render import RenderSettings, render_video
from zedo_cli.formats.readers.result import read_result

# A syrip12 infant lying on its back, seen from above (metres, camera frame before placing).
POSE = {
    "right_hip": [-0.05, 0.0, 0.0], "right_knee": [-0.07, 0.12, -0.04], "right_ankle": [-0.08, 0.22, 0.0],
    "left_hip": [0.05, 0.0, 0.0], "left_knee": [0.07, 0.12, -0.04], "left_ankle": [0.08, 0.22, 0.0],
    "left_shoulder": [0.07, -0.2, 0.0], "left_elbow": [0.15, -0.12, -0.02], "left_wrist": [0.18, -0.04, -0.05],
    "right_shoulder": [-0.07, -0.2, 0.0], "right_elbow": [-0.15, -0.12, -0.02], "right_wrist": [-0.18, -0.04, -0.05],
}  # fmt: skip


def write_clip(path: Path, frames: int, width: int, height: int, fps: float) -> None:
    u, v = np.meshgrid(np.arange(width), np.arange(height))
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"mp4v"), fps, (width, height))
    for i in range(frames):
        g = 110 + 50 * np.sin((u + 3 * i) / 37.0) * np.cos((v - 2 * i) / 53.0)
        writer.write(np.dstack([g, 0.8 * g + 20, 200 - 0.5 * g]).astype(np.uint8))
    writer.release()


def result_document(frames: int, width: int, height: int, fps: float) -> dict:
    """A zedo.pose3d/1 document written by zedo's own writer: a pose moving through a wide lens."""
    from zedo_cli.camera.model import CameraModel
    from zedo_cli.data.keypoints import Keypoints2D
    from zedo_cli.data.skeleton import root_point
    from zedo_cli.formats.writers.result_json import build_result_document
    from zedo_cli.lifting.config import LiftConfig
    from zedo_cli.lifting.solver import LiftResult

    skeleton = get_skeleton("syrip12")
    base = np.array([POSE[j] for j in skeleton.joints])
    f = 0.8 * width
    lens = CameraModel(f, f, width / 2, height / 2, (-0.3, 0.1, 0.0, 0.0, 0.0), image_size=(width, height))
    poses = np.array([base + [0.15 * np.sin(i / 40), 0.05 * np.cos(i / 30), 1.0] for i in range(frames)])
    observed = np.ones(poses.shape[:2], bool)
    observed[np.arange(frames), np.arange(frames) % len(base)] = False  # one hollow joint per frame
    kp = Keypoints2D(lens.project(poses), observed.astype(float), skeleton, list(range(frames)), [None] * frames,
                     np.array([[width, height]] * frames, float), [None] * frames, "bench", "zedo-2d")  # fmt: skip
    root = root_point(poses, skeleton)
    res = LiftResult(poses, poses - root[:, None], root, np.zeros(observed.shape), observed, np.ones(frames, bool),
                     LiftConfig(), 0.0)  # fmt: skip
    doc = build_result_document(kp, res, np.stack([lens.matrix()] * frames), ["file"] * frames,
                                params={"fps": fps}, input_info={"path": "bench"}, lenses=[lens] * frames)  # fmt: skip
    for i in range(0, frames, 10):
        doc["frames"][i]["persons"][0]["flags"].append("poor_fit")
    return doc


def copy_only(src: Path, dst: Path, width: int, height: int, fps: float) -> None:
    writer = cv2.VideoWriter(str(dst), cv2.VideoWriter_fourcc(*"mp4v"), fps, (width, height))
    for frame in iter_frames(src):
        writer.write(frame)
    writer.release()


def best_of(repeats: int, run) -> tuple[float, float]:  # noqa: ANN001
    """The shortest wall time of `repeats` runs, and the CPU time (every thread) of that run. On a
    busy machine the wall time grows with the load; the CPU time much less."""
    times = []
    for _ in range(repeats):
        start, cpu = time.perf_counter(), time.process_time()
        run()
        times.append((time.perf_counter() - start, time.process_time() - cpu))
    return min(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--frames", type=int, default=300)
    parser.add_argument("--size", type=int, nargs=2, default=(1280, 720), metavar=("W", "H"))
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    width, height, fps = *args.size, 30.0
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        clip, doc = folder / "clip.mp4", folder / "clip.zedo.json"
        write_clip(clip, args.frames, width, height, fps)
        doc.write_text(json.dumps(result_document(args.frames, width, height, fps)))
        result = read_result(doc)
        rows = {
            "decode + encode only": lambda: copy_only(clip, folder / "copy.mp4", width, height, fps),
            "zedo render": lambda: render_video(result, clip, folder / "r.mp4", RenderSettings(overwrite=True)),
            "zedo render --side-view": lambda: render_video(result, clip, folder / "s.mp4",
                                                            RenderSettings(side_view=True, overwrite=True)),
        }  # fmt: skip
        load = os.getloadavg()[0]
        print(f"{args.frames} frames of {width}x{height}, cv2 {cv2.__version__}, {os.cpu_count()} CPUs, "
              f"load average {load:.1f} at the start")  # fmt: skip
        for name, run in rows.items():
            seconds, cpu = best_of(args.repeats, run)
            print(f"{name:28s} {args.frames / seconds:7.1f} frames/s  ({seconds:.2f} s wall, "
                  f"{1e3 * cpu / args.frames:.1f} ms CPU per frame)")  # fmt: skip


if __name__ == "__main__":
    main()
