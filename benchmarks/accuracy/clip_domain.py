"""How often the `outside calibration` check (`zedo_cli/analysis/uncertainty/domain.py`) fires, per clip source:
on sources like the calibration clips it must stay quiet, on a foreign set it must speak.

Sources: `syrip` (SyRIP training poses eased between key poses, the calibration clips' kind, pseudo camera),
`adult` (the adult motion capture made infant-like, `zedo_cli.evaluation.clips`, pseudo camera), and two foreign
sets: `syrip upside-down` (the same clips with the camera turned half a turn: head down the image) and `adult
proportions` (the adult motion with adult bone proportions, scaled to an infant's size). Each clip (10 s at 30 fps,
3 px noise, 3 % dropped) is lifted with `--temporal smooth`; printed per source: the check's statistic (the
median over the clip of the trunk's angle from the image's up) and how many clips it fires on, and the median
ratio of the lifted limb bones to the trunk (a proportion check that was measured and not adopted: it does not
separate adult proportions from infants').

    .venv/bin/python benchmarks/accuracy/clip_domain.py --syrip-dir ../shared/data/syrip --clips 12
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from zedo_cli.analysis.uncertainty.domain import MAX_TRUNK_TILT_DEG, trunk_tilt_deg
from zedo_cli.data.adult import load_adult_poses
from zedo_cli.data.datasets import load_syrip_3d
from zedo_cli.data.skeleton import get_skeleton
from zedo_cli.evaluation.clips import (
    PSEUDO_CAMERA,
    ClipSettings,
    DetectorHabits,
    adult_infant_clips,
    infant_bodies_from_poses,
    infant_bodies_from_syrip,
    load_adult_library,
)
from zedo_cli.evaluation.clips.eased import IMAGE_H, IMAGE_W, make_sequences
from zedo_cli.lifting.clip import LIMB_BONES
from zedo_cli.lifting.config import get_preset
from zedo_cli.lifting.temporal import lift_sequence
from zedo_cli.prior.weights import load_prior, resolve_prior_path

SKELETON = get_skeleton("syrip12")
ADULT_TO_INFANT = 0.35  # an adult's bone lengths scaled to about an infant's size, proportions kept


def limb_to_trunk(cam: np.ndarray) -> float:
    at = {n: SKELETON.index(n) for n in SKELETON.joints}
    shoulders = (cam[:, at["left_shoulder"]] + cam[:, at["right_shoulder"]]) / 2
    hips = (cam[:, at["left_hip"]] + cam[:, at["right_hip"]]) / 2
    limbs = np.mean([np.linalg.norm(cam[:, at[a]] - cam[:, at[b]], axis=-1) for a, b in LIMB_BONES], 0)
    return float(np.nanmedian(limbs / np.linalg.norm(shoulders - hips, axis=-1)))


def score(name: str, data: dict[str, np.ndarray], clips: int, prior, flip: bool = False) -> None:  # noqa: ANN001
    tilts, ratios = [], []
    for c in range(clips):
        idx = np.flatnonzero(data["tracks"] == c)
        xy = data["xy"][idx]
        if flip:
            xy = np.stack([IMAGE_W - xy[..., 0], IMAGE_H - xy[..., 1]], -1)
        res = lift_sequence(xy, data["conf"][idx], data["k"][idx], prior, get_preset("fast"), mode="smooth", fps=30.0)
        tilts.append(float(np.nanmedian(trunk_tilt_deg(xy, SKELETON.joints))))
        ratios.append(limb_to_trunk(res.poses_camera))
    tilts, ratios = np.array(tilts), np.array(ratios)
    print(
        f"| {name} | {np.median(tilts):.0f} ({tilts.min():.0f}-{tilts.max():.0f}) | "
        f"{int((tilts > MAX_TRUNK_TILT_DEG).sum())} of {clips} | {ratios.min():.2f}-{ratios.max():.2f} |"
    )


def adult_data(args: argparse.Namespace, bodies) -> dict[str, np.ndarray]:  # noqa: ANN001
    habits = DetectorHabits(jitter_px=3.0, dropout=0.03, swaps_per_min=0, hand_jumps_per_min=0, losses_per_min=0)
    library = load_adult_library(Path(args.syrip_dir).parent / "adult")
    clips = list(adult_infant_clips(library, bodies, 10.0, args.clips, args.seed,
                                    ClipSettings(cameras=(PSEUDO_CAMERA,), habits=habits)))  # fmt: skip
    return {"xy": np.concatenate([c.xy for c in clips]), "conf": np.concatenate([c.confidence for c in clips]),
            "k": np.concatenate([np.repeat(c.intrinsics.matrix()[None], len(c.xy), 0) for c in clips]),
            "tracks": np.concatenate([np.full(len(c.xy), i) for i, c in enumerate(clips)])}  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--syrip-dir", required=True)
    ap.add_argument("--clips", type=int, default=12)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    prior = load_prior(resolve_prior_path(None))
    rng = np.random.default_rng(args.seed)
    syrip = make_sequences(load_syrip_3d(args.syrip_dir, "train").poses, rng, count=args.clips, keyposes=9,
                           transition_s=1.0, fps=30.0, noise_px=3.0, drop=0.03, gap=3)  # fmt: skip
    print("| source | trunk from the image's up, deg: median (range) | check fires | lifted limbs / trunk |")
    print("| --- | --- | --- | --- |")
    score("syrip", syrip, args.clips, prior)
    score("adult", adult_data(args, infant_bodies_from_syrip(args.syrip_dir)), args.clips, prior)
    score("syrip upside-down (foreign)", syrip, args.clips, prior, flip=True)
    adults = load_adult_poses(Path(args.syrip_dir).parent / "adult").poses[::500][:300] * ADULT_TO_INFANT
    bodies = infant_bodies_from_poses(adults, [str(i) for i in range(len(adults))], "adult proportions")
    score("adult proportions (foreign)", adult_data(args, bodies), args.clips, prior)


if __name__ == "__main__":
    main()
