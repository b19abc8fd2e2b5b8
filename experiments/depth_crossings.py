"""Can continuity through time tell which side of the camera's depth axis a limb is on? (docs/movement.md,
"What limits the knee's mean angle"). A segment's depth sign can change only when it passes through the
image plane; between two stretches ("runs") where it points clearly along the depth axis it either crosses
the plane (the sign changes) or comes back to it and turns back (the sign stays). A model of motion across
frames, hand-made or learnt, can carry a run's side to the next only if it can tell these apart.

On the fold priors' synthetic clips (features_3d_accuracy.py's table clips: 16 clips of 5 s a fold, both
motions of temporal.make_sequences, lifted by `fold<k>.safetensors` in `--folds` with the default preset and
`--temporal smooth`), for every thigh and shank, per gap between two runs of the truth (|unit z| > 0.3):

- whether the truth crossed or turned back, and whether the lift's majority side changed between the runs;
- how well a crossing is told from a turn-back by the sharpness of the dip of |unit z| at its lowest frame
  (`v_depth`: a crossing at speed is a V, a turn-back slows to a U), as the area under the ROC curve, from
  the true |unit z|, from the lifted segment's |unit z|, and from the sign-free estimate of
  depth_sign_vote.py (image-plane length against the clip's median length).

Test100 and SyRIP's synthetic rows are never read.

    OMP_NUM_THREADS=2 .venv/bin/python experiments/depth_crossings.py --syrip-dir ../shared/data/syrip --folds FOLDS
"""

from __future__ import annotations

import sys
from collections import Counter
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository root
from benchmarks.accuracy.limb_depth_flips import CLEAR_DEPTH, JOINT, SEGMENTS
from benchmarks.lib.folds import fold_clip_args, fold_priors
from benchmarks.lib.settings import CLIP_SETTINGS
from experiments.depth_sign_vote import runs, sign_free_depth
from zedo_cli.evaluation.clips.eased import make_sequences

HALF_WIDTH = 4  # frames either side of the dip's lowest frame (0.13 s at 30 fps)
SOURCES = ("true |unit z|", "lifted |unit z|", "estimate from the image-plane length")


def v_depth(series: np.ndarray, start: int, stop: int, half_width: int = HALF_WIDTH) -> float:
    """How sharp the dip of `series` is at its lowest frame in [start, stop): the rise `half_width` frames
    either side of it (clipped to the series). A V (a crossing at speed) rises fast, a U (a turn-back) slowly."""
    low = start + int(np.argmin(series[start:stop]))
    before, after = series[max(low - half_width, 0)], series[min(low + half_width, len(series) - 1)]
    return float(before + after - 2.0 * series[low])


def roc_auc(score: np.ndarray, positive: np.ndarray) -> float:
    """The chance that a random positive case scores above a random negative one (ties count half)."""
    pos, neg = score[positive], score[~positive]
    above = (pos[:, None] > neg[None, :]).mean() + 0.5 * (pos[:, None] == neg[None, :]).mean()
    return float(above)


def _filled(values: np.ndarray) -> np.ndarray:
    """`values (N,)` with NaN (frames not lifted) linearly interpolated."""
    ok = np.isfinite(values)
    t = np.arange(len(values))
    return np.interp(t, t[ok], values[ok]) if ok.any() else np.zeros_like(values)


def unit_depths(true: np.ndarray, lifted: np.ndarray, side: str, segment: str) -> tuple[np.ndarray, ...]:
    """The segment's signed true unit z, and the three sources' |unit z| (N,) of one clip."""
    a, b = (JOINT[f"{side}_{name}"] for name in SEGMENTS[segment])
    vt, vl = true[:, b] - true[:, a], lifted[:, b] - lifted[:, a]
    true_z = vt[:, 2] / np.linalg.norm(vt, axis=-1)
    estimate, length = sign_free_depth(vl)
    return true_z, np.abs(true_z), _filled(np.abs(vl[:, 2]) / length), _filled(estimate)


def main() -> int:
    args = fold_clip_args(__doc__)

    import torch

    from zedo_cli.lifting.config import DEFAULT_PRESET, get_preset
    from zedo_cli.lifting.temporal import lift_sequence

    cfg = get_preset(DEFAULT_PRESET)
    transitions: Counter[tuple[str, str]] = Counter()
    crossed, dips = [], []
    for interpolation in ("positions", "segments"):
        for k, prior, truth, _ in fold_priors(args.folds, "", args.syrip_dir):
            torch.manual_seed(k)
            clips = make_sequences(truth.poses, np.random.default_rng(100 + k), **CLIP_SETTINGS,
                                   interpolation=interpolation)  # fmt: skip
            res = lift_sequence(clips["xy"], clips["conf"], clips["k"], prior, cfg, mode="smooth",
                                tracks=clips["tracks"])  # fmt: skip
            lifted_all = np.where(res.lifted[:, None, None], res.poses_root_relative, np.nan)
            for track in np.unique(clips["tracks"]):
                at = clips["tracks"] == track
                for side in ("left", "right"):
                    for segment in ("thigh", "shank"):
                        true_z, *sources = unit_depths(clips["rel"][at], lifted_all[at], side, segment)
                        a, b = (JOINT[f"{side}_{name}"] for name in SEGMENTS[segment])
                        lifted_sign = np.sign(lifted_all[at][:, b, 2] - lifted_all[at][:, a, 2])
                        spans = runs(np.abs(true_z) > CLEAR_DEPTH)
                        for (start0, stop0), (start1, stop1) in zip(spans[:-1], spans[1:], strict=True):
                            truth_crossed = np.sign(true_z[stop0 - 1]) != np.sign(true_z[start1])
                            before = np.sign(np.nansum(lifted_sign[start0:stop0]))
                            after = np.sign(np.nansum(lifted_sign[start1:stop1]))
                            transitions[("crossed" if truth_crossed else "turned back",
                                         "changed" if before != after else "kept")] += 1  # fmt: skip
                            crossed.append(truth_crossed)
                            dips.append([v_depth(s, stop0 - 1, start1 + 1) for s in sources])
        print(f"{interpolation} clips lifted", file=sys.stderr, flush=True)

    crossed_arr, dips_arr = np.array(crossed), np.array(dips)
    print(f"thigh and shank gaps between runs of |unit z| > {CLEAR_DEPTH} in the truth: {len(crossed_arr)}, "
          f"{crossed_arr.mean():.0%} crossings of the image plane")  # fmt: skip
    for (truth_move, lift_move), n in sorted(transitions.items()):
        print(f"  truth {truth_move:11s} lift's majority side {lift_move:7s} {n:4d}")
    print(f"telling a crossing from a turn-back by the dip's sharpness (+-{HALF_WIDTH} frames), ROC AUC:")
    for j, source in enumerate(SOURCES):
        print(f"  {source:38s} {roc_auc(dips_arr[:, j], crossed_arr):.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
