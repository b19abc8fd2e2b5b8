"""The same clips lifted without a camera (the pseudo camera) and with their camera stated (`--focal`): how many frames
get a calibrated symmetry interval, and how often it holds the truth, per clinic camera set-up.

Clips: the adult motion made infant-like (`zedo_cli.evaluation.clips`, poses the bundled prior never saw), 10 s at
30 fps, 3 px jitter, 3 % dropped joints, each set-up of `CLINIC_CAMERAS`, the pseudo camera and two set-ups 2.5-3.5 m
away in turn; each clip
lifted with `--temporal smooth` twice (no camera; `--focal <its focal length>`) and analysed with the defaults. Per
set-up and way: the share of (frame, pair) values with a 90 % interval, the share of those that hold the true
symmetry angle, and the median interval width; the same for the clips' `3d_` features against the features of the
true 3D.

    python benchmarks/accuracy/camera_trust.py --syrip-dir ../shared/data/syrip --clips 12
    python benchmarks/accuracy/camera_trust.py --syrip-dir ../shared/data/syrip --clips 8 --seconds 180 --setups pseudo
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # the repository root
from benchmarks.accuracy.norms_false_alarms import FPS, JITTER_PX, habits, write_2d
from zedo_cli.analysis.analyse import SYMMETRY_NAMES
from zedo_cli.analysis.clip.features_3d import PREFIX as PREFIX_3D
from zedo_cli.analysis.clip.features_3d import features_3d
from zedo_cli.analysis.pose.symmetry import symmetry_angles
from zedo_cli.data.skeleton import get_skeleton
from zedo_cli.evaluation.clips import ClipSettings, adult_infant_clips, infant_bodies_from_syrip, load_adult_library
from zedo_cli.evaluation.clips.cameras import CLINIC_CAMERAS, FAR_CAMERAS, PSEUDO_CAMERA

SKELETON = get_skeleton("syrip12")


def held(path: Path, truth3d: np.ndarray, focal: float | None, families: dict[str, Count]) -> tuple[Count, Count]:
    """The clip's frame symmetry values and its `3d_` clip features, each as (values, with an interval, intervals
    holding the truth, widths); the features also counted per family into `families`."""
    import zedo_cli

    lifted = zedo_cli.lift_file(str(path), skeleton="syrip12", fps=FPS, temporal="smooth", focal=focal)
    a = zedo_cli.analyze(lifted)
    truth = symmetry_angles(truth3d[a.result.frame_index[a.index]], SKELETON)
    frames = Count()
    for name in SYMMETRY_NAMES:
        low, high = a.intervals[name]
        frames.add(np.isfinite(a.values[name]), low, high, truth[name])
    true_features = features_3d(truth3d, SKELETON, FPS).values
    rows = [r for r in a.rows if r.frame_index is None and r.measure.startswith(PREFIX_3D) and np.isfinite(r.value)]
    features = Count()
    features.add(np.ones(len(rows), bool), np.array([r.low_90 for r in rows]), np.array([r.high_90 for r in rows]),
                 np.array([true_features[r.measure] for r in rows]))  # fmt: skip
    for r in rows:
        family = r.measure.removeprefix(PREFIX_3D).rsplit("_", 1)[0]
        families.setdefault(family, Count()).add(np.ones(1, bool), np.array([r.low_90]), np.array([r.high_90]),
                                                 np.array([true_features[r.measure]]))  # fmt: skip
    return frames, features


@dataclass
class Count:
    """Values, those with an interval, the intervals holding the truth and their widths."""

    values: int = 0
    with_interval: int = 0
    holds: int = 0
    widths: list[float] = field(default_factory=list)

    def add(self, known: np.ndarray, low: np.ndarray, high: np.ndarray, truth: np.ndarray) -> None:
        has = known & np.isfinite(low) & np.isfinite(high)
        self.values += int(known.sum())
        self.with_interval += int(has.sum())
        self.holds += int(((low <= truth) & (truth <= high))[has].sum())
        self.widths += (high - low)[has].tolist()

    def merge(self, other: Count) -> None:
        self.values += other.values
        self.with_interval += other.with_interval
        self.holds += other.holds
        self.widths += other.widths

    def cells(self, unit: str | None) -> str:
        """The table's cells: with an interval, holding the truth and (with a `unit`) the median width."""
        if not self.values:
            return "- | -" + (" | -" if unit else "")
        cover = f"{self.holds / self.with_interval:.1%}" if self.with_interval else "-"
        width = (f" | {np.median(self.widths):.1f} {unit}" if self.widths else " | -") if unit else ""
        return f"{self.with_interval / self.values:.1%} | {cover}{width}"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--syrip-dir", required=True)
    ap.add_argument("--clips", type=int, default=12, help="clips per camera set-up")
    ap.add_argument("--work", type=Path, default=Path("camera_trust"), help="a folder for the clips' 2D")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--seconds", type=float, default=10.0, help="each clip's length")
    ap.add_argument("--setups", nargs="+", default=None, help="only these camera set-ups (names of the table)")
    args = ap.parse_args()
    args.work.mkdir(parents=True, exist_ok=True)
    library = load_adult_library(Path(args.syrip_dir).parent / "adult")
    bodies = infant_bodies_from_syrip(args.syrip_dir)
    print("| camera set-up | focal length | infant's depth | lifted | frame values with an interval | holding the "
          "truth | median width | `3d_` features with an interval | holding the truth |")  # fmt: skip
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    families: dict[str, Count] = {}
    for camera in (PSEUDO_CAMERA, *CLINIC_CAMERAS, *FAR_CAMERAS):
        if args.setups and camera.name not in args.setups:
            continue
        settings = ClipSettings(fps=FPS, cameras=(camera,), habits=habits(JITTER_PX))
        totals = {way: (Count(), Count()) for way in ("no camera stated", "--focal stated")}
        for i, clip in enumerate(adult_infant_clips(library, bodies, args.seconds, args.clips, args.seed, settings)):
            path = args.work / f"{camera.name}{i:02d}.jsonl"
            write_2d(path, clip.xy, clip.confidence, clip.image_size)
            for way, focal in (("no camera stated", None), ("--focal stated", camera.focal_px)):
                for total, got in zip(totals[way], held(path, clip.poses3d, focal, families), strict=True):
                    total.merge(got)
        depth = f"{camera.depth_m[0]:g}-{camera.depth_m[1]:g} m"
        for way, (frames, features) in totals.items():
            print(f"| {camera.name} | {camera.focal_px:g} px | {depth} | {way} | {frames.cells('deg')} | "
                  f"{features.cells(None)} |", flush=True)  # fmt: skip
    print("\n| `3d_` family, every set-up and way | with an interval | holding the truth |\n| --- | --- | --- |")
    for family, count in sorted(families.items()):
        print(f"| {family} | {count.cells(None)} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
