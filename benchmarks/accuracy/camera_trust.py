"""The same clips lifted without a camera (the pseudo camera) and with their camera stated (`--focal`): how many frames
get a calibrated symmetry interval, and how often it holds the truth, per clinic camera set-up.

Clips: the adult motion made infant-like (`zedo_cli.evaluation.clips`, poses the bundled prior never saw), 10 s at
30 fps, 3 px jitter, 3 % dropped joints, each set-up of `CLINIC_CAMERAS`, the pseudo camera and two set-ups 2.5-3.5 m
away in turn; each clip
lifted with `--temporal smooth` twice (no camera; `--focal <its focal length>`) and analysed with the defaults. Per
set-up and way: the share of (frame, pair) values with a 90 % interval, the share of those that hold the true
symmetry angle, and the median interval width.

    python benchmarks/accuracy/camera_trust.py --syrip-dir ../shared/data/syrip --clips 12
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # the repository root
from benchmarks.accuracy.norms_false_alarms import FPS, JITTER_PX, habits, write_2d
from zedo_cli.analysis.analyse import SYMMETRY_NAMES
from zedo_cli.analysis.pose.symmetry import symmetry_angles
from zedo_cli.data.skeleton import get_skeleton
from zedo_cli.evaluation.clips import ClipSettings, adult_infant_clips, infant_bodies_from_syrip, load_adult_library
from zedo_cli.evaluation.clips.cameras import CLINIC_CAMERAS, PSEUDO_CAMERA, CameraSetup

SKELETON = get_skeleton("syrip12")
# Further than the clinic set-ups the clips are made with: a camera on a high tripod or the ceiling, 2.5-3.5 m away
FAR_CAMERAS = (CameraSetup("far-1080p", 2000.0, 1920, 1080, (2.5, 3.5)),
               CameraSetup("far-tele-1080p", 3000.0, 1920, 1080, (2.5, 3.5)))  # fmt: skip


def held(path: Path, truth3d: np.ndarray, focal: float | None) -> tuple[int, int, int, list[float]]:
    """(values, values with an interval, intervals holding the truth, widths) over the clip's frames and pairs."""
    import zedo_cli

    lifted = zedo_cli.lift_file(str(path), skeleton="syrip12", fps=FPS, temporal="smooth", focal=focal)
    a = zedo_cli.analyze(lifted)
    truth = symmetry_angles(truth3d[a.result.frame_index[a.index]], SKELETON)
    values = with_interval = holds = 0
    widths: list[float] = []
    for name in SYMMETRY_NAMES:
        low, high = a.intervals[name]
        known = np.isfinite(a.values[name])
        has = known & np.isfinite(low) & np.isfinite(high)
        values += int(known.sum())
        with_interval += int(has.sum())
        holds += int(((low <= truth[name]) & (truth[name] <= high))[has].sum())
        widths += (high - low)[has].tolist()
    return values, with_interval, holds, widths


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--syrip-dir", required=True)
    ap.add_argument("--clips", type=int, default=12, help="clips per camera set-up")
    ap.add_argument("--work", type=Path, default=Path("camera_trust"), help="a folder for the clips' 2D")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    args.work.mkdir(parents=True, exist_ok=True)
    library = load_adult_library(Path(args.syrip_dir).parent / "adult")
    bodies = infant_bodies_from_syrip(args.syrip_dir)
    print("| camera set-up | focal length | infant's depth | lifted | values with an interval | intervals holding "
          "the truth | median width |\n| --- | --- | --- | --- | --- | --- | --- |")  # fmt: skip
    for camera in (PSEUDO_CAMERA, *CLINIC_CAMERAS, *FAR_CAMERAS):
        settings = ClipSettings(fps=FPS, cameras=(camera,), habits=habits(JITTER_PX))
        totals = {"no camera stated": [0, 0, 0, []], "--focal stated": [0, 0, 0, []]}
        for i, clip in enumerate(adult_infant_clips(library, bodies, 10.0, args.clips, args.seed, settings)):
            path = args.work / f"{camera.name}{i:02d}.jsonl"
            write_2d(path, clip.xy, clip.confidence, clip.image_size)
            for way, focal in (("no camera stated", None), ("--focal stated", camera.focal_px)):
                got = held(path, clip.poses3d, focal)
                for k in range(3):
                    totals[way][k] += got[k]
                totals[way][3] += got[3]
        depth = f"{camera.depth_m[0]:g}-{camera.depth_m[1]:g} m"
        for way, (values, with_interval, holds, widths) in totals.items():
            cover = f"{holds / with_interval:.1%}" if with_interval else "-"
            width = f"{np.median(widths):.1f} deg" if widths else "-"
            print(f"| {camera.name} | {camera.focal_px:g} px | {depth} | {way} | {with_interval / values:.1%} | "
                  f"{cover} | {width} |", flush=True)  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
