"""The same clips lifted without a camera (the pseudo camera) and with their camera stated (`--focal`): how many frames
get a calibrated interval, and how often it holds the truth, per clinic camera set-up and clip source.

Sources (`--source`), each clip one infant, 30 fps, 3 px jitter, 3 % dropped joints:
- `adult`: the adult motion made infant-like (`zedo_cli.evaluation.clips`, poses the bundled prior never saw), a
  source every calibration was fitted on (other draws);
- `syrip-synthetic`: SyRIP's synthetic poses (`benchmarks/lib/pose_sources.py`), each segment turned from key pose to
  key pose 1 s apart with the first key pose's bones, placed before each set-up: a pose source outside every fit,
  for an independent check only; `syrip-synthetic-supine`: the same poses turned chest to the camera, the body
  swaying about one place, as infants are filmed.
Set-ups: each of `CLINIC_CAMERAS`, the pseudo camera and two set-ups 2.5-3.5 m away in turn; each clip lifted with
`--temporal smooth` (or `--temporal`'s mode) twice (no camera; `--focal <its focal length>`) and analysed with the
defaults. Per set-up and way: the share of (frame, pair) symmetry values with a 90 % interval, the share of those
that hold the true symmetry angle, the median interval width and the share of calls decisive at level 0.8 (the 80 %
interval on one side of the threshold) with their agreement; the same coverage for the joint angles and for the
clips' `3d_` features against the features of the true 3D.

    python benchmarks/accuracy/camera_trust.py --syrip-dir ../shared/data/syrip --clips 12
    python benchmarks/accuracy/camera_trust.py --syrip-dir ../shared/data/syrip --clips 8 --seconds 180 --setups pseudo
    python benchmarks/accuracy/camera_trust.py --syrip-dir ../shared/data/syrip --clips 8 --source syrip-synthetic
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # the repository root
from benchmarks.accuracy.norms_false_alarms import FPS, JITTER_PX, habits, write_2d
from benchmarks.lib.pose_sources import SUPINE, eased_source_poses, source_sway
from zedo_cli.analysis.analyse import SYMMETRY_NAMES
from zedo_cli.analysis.clip.features_3d import PREFIX as PREFIX_3D
from zedo_cli.analysis.clip.features_3d import features_3d
from zedo_cli.analysis.pose.joint_angles import ANGLE_NAMES, CIRCULAR_ANGLES, joint_angles
from zedo_cli.analysis.pose.symmetry import DEFAULT_THRESHOLD_DEG, symmetry_angles
from zedo_cli.analysis.uncertainty.calibration import wrap_deg
from zedo_cli.data.skeleton import get_skeleton
from zedo_cli.evaluation.clips import ClipSettings, adult_infant_clips, infant_bodies_from_syrip, load_adult_library
from zedo_cli.evaluation.clips.cameras import CLINIC_CAMERAS, FAR_CAMERAS, PSEUDO_CAMERA, CameraSetup
from zedo_cli.evaluation.clips.eased import make_sequences
from zedo_cli.evaluation.metrics import decisive_calls
from zedo_cli.formats.readers.result_record import ResultPoses

SKELETON = get_skeleton("syrip12")
SOURCES = ("adult", "syrip-synthetic", "syrip-synthetic" + SUPINE)
CALL_LEVEL = 0.8  # the level of the decisive calls (docs/clinical.md)
MIN_FEATURE_CASES = 100  # a single `3d_` feature's coverage is reported from this many intervals
Clip = tuple[np.ndarray, np.ndarray, np.ndarray, tuple[int, int]]  # 3D truth (T, 12, 3), 2D, confidence, image size


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


@dataclass
class Calls:
    """Symmetry values, those called decisively at CALL_LEVEL, and the calls agreeing with the truth."""

    values: int = 0
    decisive: int = 0
    agree: int = 0

    def add(self, known: np.ndarray, low: np.ndarray, high: np.ndarray, truth: np.ndarray) -> None:
        decisive, agree = decisive_calls(low, high, truth, DEFAULT_THRESHOLD_DEG)
        self.values += int(known.sum())
        self.decisive += int((known & decisive).sum())
        self.agree += int((known & agree).sum())

    def merge(self, other: Calls) -> None:
        self.values += other.values
        self.decisive += other.decisive
        self.agree += other.agree

    def cells(self) -> str:
        if not self.decisive:
            return "- | -"
        return f"{self.decisive / self.values:.1%} | {self.agree / self.decisive:.1%}"


@dataclass
class Tally:
    """One clip's (or one set-up's) counts: per-joint radii, symmetry, its calls, joint angles and `3d_` features."""

    joints: Count = field(default_factory=Count)
    symmetry: Count = field(default_factory=Count)
    calls: Calls = field(default_factory=Calls)
    angles: Count = field(default_factory=Count)
    features: Count = field(default_factory=Count)

    def merge(self, other: Tally) -> None:
        for name in ("joints", "symmetry", "calls", "angles", "features"):
            getattr(self, name).merge(getattr(other, name))

    def cells(self) -> str:
        return " | ".join((self.joints.cells(None), self.symmetry.cells("deg"), self.calls.cells(),
                           self.angles.cells(None), self.features.cells(None)))  # fmt: skip


HEADER = ("| camera set-up | focal length | infant's depth | lifted | joints with a 90 % ball | holding the truth | "
          "symmetry values with an interval | holding the truth | median width | decisive at 0.8 | agreeing | "
          "joint angles with an interval | holding the truth | `3d_` features with an interval | holding the truth |\n"
          + "| --- " * 15 + "|")  # fmt: skip


def root_relative(poses: np.ndarray) -> np.ndarray:
    """`poses (..., 12, 3)` relative to the hip midpoint (syrip12's root)."""
    hips = (poses[..., SKELETON.index("left_hip"), :] + poses[..., SKELETON.index("right_hip"), :]) / 2
    return poses - hips[..., None, :]


def joint_balls(result: ResultPoses, truth3d: np.ndarray) -> tuple[np.ndarray, ...]:
    """Each lifted joint's 90 % ball (`uncertainty_m`) as an interval of its distance from the true root-relative
    joint: (known, low 0, high radius, the distance), flat."""
    error = np.linalg.norm(root_relative(result.poses) - root_relative(truth3d[result.frame_index]), axis=-1)
    radius = np.full(error.shape, np.nan) if result.uncertainty_m is None else result.uncertainty_m
    known = np.isfinite(error) & result.observed
    return known.ravel(), np.zeros(error.size), radius.ravel(), error.ravel()


def held(path: Path, truth3d: np.ndarray, focal: float | None, temporal: str, families: dict[str, Count],
         features: dict[str, Count]) -> Tally:  # fmt: skip
    """The clip's frame symmetry values (with their decisive calls), joint angles and `3d_` clip features against
    the truth; the features also counted per family into `families` and one by one into `features`."""
    import zedo_cli

    lifted = zedo_cli.lift_file(str(path), skeleton="syrip12", fps=FPS, temporal=temporal, focal=focal)
    a = zedo_cli.analyze(lifted)
    calls = zedo_cli.analyze(lifted, level=CALL_LEVEL)
    frames = truth3d[a.result.frame_index[a.index]]
    tally = Tally()
    tally.joints.add(*joint_balls(a.result, truth3d))
    truth = symmetry_angles(frames, SKELETON)
    for name in SYMMETRY_NAMES:
        known = np.isfinite(a.values[name])
        tally.symmetry.add(known, *a.intervals[name], truth[name])
        tally.calls.add(known, *calls.intervals[name], truth[name])
    true_angles = joint_angles(frames, SKELETON)
    for name in ANGLE_NAMES:
        value = a.values[name]
        truth_near = value + wrap_deg(true_angles[name] - value) if name in CIRCULAR_ANGLES else true_angles[name]
        tally.angles.add(np.isfinite(value) & np.isfinite(truth_near), *a.intervals[name], truth_near)
    true_features = features_3d(truth3d, SKELETON, FPS).values
    rows = [r for r in a.rows if r.frame_index is None and r.measure.startswith(PREFIX_3D) and np.isfinite(r.value)]
    low, high = np.array([r.low for r in rows]), np.array([r.high for r in rows])
    tally.features.add(np.ones(len(rows), bool), low, high, np.array([true_features[r.measure] for r in rows]))
    for r in rows:
        family = r.measure.removeprefix(PREFIX_3D).rsplit("_", 1)[0]
        features.setdefault(r.measure, Count()).add(np.ones(1, bool), np.array([r.low]), np.array([r.high]),
                                                    np.array([true_features[r.measure]]))  # fmt: skip
        families.setdefault(family, Count()).add(np.ones(1, bool), np.array([r.low]), np.array([r.high]),
                                                 np.array([true_features[r.measure]]))  # fmt: skip
    return tally


def adult_source(args: argparse.Namespace, camera: CameraSetup) -> Iterator[Clip]:
    library = load_adult_library(Path(args.syrip_dir).parent / "adult")
    settings = ClipSettings(fps=FPS, cameras=(camera,), habits=habits(JITTER_PX))
    for clip in adult_infant_clips(library, infant_bodies_from_syrip(args.syrip_dir), args.seconds, args.clips,
                                   args.seed, settings):  # fmt: skip
        yield clip.poses3d, clip.xy, clip.confidence, clip.image_size


def eased_source(args: argparse.Namespace, camera: CameraSetup) -> Iterator[Clip]:
    """Clips of one infant each: the source's poses, each segment turned from key pose to key pose 1 s apart with the
    first key pose's bones, the pelvis at a depth of `camera`'s range near the optical axis (the pseudo camera: about
    1 m before it, as the calibration clips); joints leaving the frame are kept, as the adult source keeps them."""
    poses = eased_source_poses(args.syrip_dir, args.source)
    kmat = camera.intrinsics().matrix()

    def place(rng: np.random.Generator, rel: np.ndarray, drift: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        centre = np.array([rng.normal(0.0, 0.02), 0.05 + rng.normal(0.0, 0.02), rng.uniform(*camera.depth_m)])
        return kmat, centre + drift

    sway = source_sway(args.source)
    for i in range(args.clips):
        rng = np.random.default_rng([args.seed, i])
        seq = make_sequences(poses, rng, count=1, keyposes=int(args.seconds) + 1, transition_s=1.0, fps=FPS,
                             noise_px=JITTER_PX, drop=0.03, gap=0, place=None if camera is PSEUDO_CAMERA else place,
                             interpolation="segments", sway=sway)  # fmt: skip
        yield seq["cam"], seq["xy"], seq["conf"], (camera.width, camera.height)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--syrip-dir", required=True)
    ap.add_argument("--source", choices=SOURCES, default="adult")
    ap.add_argument("--clips", type=int, default=12, help="clips per camera set-up")
    ap.add_argument("--work", type=Path, default=Path("camera_trust"), help="a folder for the clips' 2D")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--seconds", type=float, default=10.0, help="each clip's length")
    ap.add_argument("--temporal", choices=("none", "smooth", "clip"), default="smooth", help="how the clips are lifted")
    ap.add_argument("--setups", nargs="+", default=None, help="only these camera set-ups (names of the table)")
    args = ap.parse_args()
    args.work.mkdir(parents=True, exist_ok=True)
    make = adult_source if args.source == "adult" else eased_source
    print(f"source {args.source}, {args.clips} clips of {args.seconds:g} s a set-up, --temporal {args.temporal}\n")
    print(HEADER)
    families: dict[str, Count] = {}
    features: dict[str, Count] = {}
    every = Tally()
    for camera in (PSEUDO_CAMERA, *CLINIC_CAMERAS, *FAR_CAMERAS):
        if args.setups and camera.name not in args.setups:
            continue
        totals = {way: Tally() for way in ("no camera stated", "--focal stated")}
        for i, (truth3d, xy, confidence, size) in enumerate(make(args, camera)):
            path = args.work / f"{camera.name}{i:02d}.jsonl"
            write_2d(path, xy, confidence, size)
            for way, focal in (("no camera stated", None), ("--focal stated", camera.focal_px)):
                totals[way].merge(held(path, truth3d, focal, args.temporal, families, features))
        depth = f"{camera.depth_m[0]:g}-{camera.depth_m[1]:g} m"
        for way, t in totals.items():
            every.merge(t)
            print(f"| {camera.name} | {camera.focal_px:g} px | {depth} | {way} | {t.cells()} |", flush=True)
    print(f"| every set-up | | | both | {every.cells()} |")
    print("\n| `3d_` family, every set-up and way | with an interval | holding the truth |\n| --- | --- | --- |")
    for family, count in sorted(families.items()):
        print(f"| {family} | {count.cells(None)} |")
    held_out = {n: c.holds / c.with_interval for n, c in features.items() if c.with_interval >= MIN_FEATURE_CASES}
    worst = sorted(held_out, key=held_out.get)[:8]
    print(f"\n{len(held_out)} `3d_` features with at least {MIN_FEATURE_CASES} intervals; "
          f"{sum(v < 0.8 for v in held_out.values())} hold the truth in under 80 %; the least: "
          + ", ".join(f"{n} {held_out[n]:.1%}" for n in worst))  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
