"""The scores and feature sets tried for the calibrated p of the comparison with typical infants (docs/decisions.md,
"A calibrated p for the comparison with typical infants"); the one shipped is the left-right asymmetry set with
the mean squared robust z (`zedo_cli/analysis/norms/calibrated.py`).

Every variant is a full conformal p (the clip ranked among the reference clips, each scored against the others),
so each holds its false-alarm rate on clips like the reference's; what differs is what it finds and whether it
holds on longer clips. Reads the clips that `benchmarks/accuracy/norms_false_alarms.py lift` wrote; prints per
variant the share of cases with p < 0.05 for typical 10 s clips, typical 60 s clips, still arms and still legs.

    python experiments/norms_scores.py --work /tmp/nfa --source syrip-train [--draws 8 --reference 20]
"""

from __future__ import annotations

import argparse
import re
import sys
from collections.abc import Callable
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the repository root
from benchmarks.accuracy.norms_false_alarms import SOURCES, clip_rows, retest_icc, retest_pairs
from zedo_cli.analysis.clip.published_features import PREREGISTERED
from zedo_cli.analysis.norms.calibrated import RELIABLE_ICC, _robust_z, bundled_reliability, reliable_features
from zedo_cli.analysis.norms.norms import extended_names, is_asymmetry_feature

Score = Callable[[list[np.ndarray]], float]  # the robust z of each part of the feature set -> the clip's score

SCORES: dict[str, Callable[[np.ndarray], float]] = {
    "mean z^2": lambda z: float(np.mean(z**2)),
    "mean min(z^2, 9)": lambda z: float(np.mean(np.minimum(z**2, 9))),
    "mean log(1 + z^2)": lambda z: float(np.mean(np.log1p(z**2))),
    "mean of the 10 largest z^2": lambda z: float(np.mean(np.sort(z**2)[-10:])),
}
ARM = re.compile(r"Elbow|Wrist|upper_arm|forearm")
# Per-side features whose left/right log ratio the shipped asymmetry set lacks, by prefix of the ratio's name:
# the 3D angle spreads (how much each joint angle moves relative to the trunk over the clip) and zedo's own joint
# angles' smoothed speeds and ranges. Each pair is (left feature, right feature).
_ANGLES_3D = ("Elbow", "Knee", "ShoulderFlexion", "ShoulderAbduction", "HipFlexion", "HipAbduction")
_ANGLES_OWN = tuple(
    f"{j}_{m}"
    for j, m in (
        ("elbow", "flexion"),
        ("knee", "flexion"),
        ("shoulder", "flexion"),
        ("shoulder", "abduction"),
        ("hip", "flexion"),
        ("hip", "abduction"),
    )
)
_OWN_STATS = ("median_abs_velocity_deg_s", "abs_velocity_iqr_deg_s", "range_deg")
RATIOS: dict[str, dict[str, tuple[str, str]]] = {
    "spread_logratio_": {a: (f"3d_stdev_angle_L{a}", f"3d_stdev_angle_R{a}") for a in _ANGLES_3D},
    "own_logratio_": {f"{a}_{s}": (f"left_{a}_{s}", f"right_{a}_{s}") for a in _ANGLES_OWN for s in _OWN_STATS},
}


def with_ratios(values: dict[str, float]) -> dict[str, float]:
    """`values` and the log(left / right) of each RATIOS pair (NaN where a side is not > 0)."""
    out = dict(values)
    for prefix, pairs in RATIOS.items():
        for name, (left_name, right_name) in pairs.items():
            left, right = values.get(left_name, np.nan), values.get(right_name, np.nan)
            out[prefix + name] = float(np.log(left / right)) if left > 0 and right > 0 else np.nan
    return out


def reliable_ratios(clips: dict[str | int, dict[str, float]]) -> list[str]:
    """The RATIOS log ratios whose ICC between the typical clips and their retests (`<i>r`) is at least
    RELIABLE_ICC, as the shipped features were kept (the bundled reliability file has no entry for them)."""
    pairs = retest_pairs(clips)
    icc = retest_icc(pairs, sorted(n for n in pairs[0][0] if n.startswith(tuple(RATIOS))))
    print("added log ratios, ICC: " + ", ".join(f"{n} {v:.3f}" for n, v in icc.items()))
    return [n for n, v in icc.items() if v >= RELIABLE_ICC]


ELBOW_SPEEDS = {"3D, as published": "3d_median_vel_angle_{}Elbow", "zedo's own, smoothed":
                "{}_elbow_flexion_median_abs_velocity_deg_s"}  # fmt: skip


def print_elbow_speeds(groups: dict[str, list[dict[str, float]]]) -> None:
    """Per group, the median over its clips of each elbow's median angular speed (the still arm holds the left)."""
    for group, clips in groups.items():
        cells = []
        for label, pattern in ELBOW_SPEEDS.items():
            sides = [pattern.format(s) for s in (("L", "R") if "3d_" in pattern else ("left", "right"))]
            left, right = (np.nanmedian([c.get(n, np.nan) for c in clips]) if clips else np.nan for n in sides)
            cells.append(f"{label} left {left:.1f} / right {right:.1f} deg/s")
        print(f"{group} ({len(clips)} clips), elbows' median speed: " + "; ".join(cells))


def feature_sets(names: list[str]) -> dict[str, list[list[str]]]:
    """Each set as its parts (one part but for the arms-or-legs variant, whose score is the larger part's)."""
    asym = [n for n in names if is_asymmetry_feature(n)]
    spreads, own = ([n for n in names if n.startswith(p)] for p in RATIOS)
    side = re.compile(r"_[LR](Ankle|Wrist|Knee|Elbow|Hip|Shoulder)$")
    return {
        "every reliable published and extended feature": [names],
        "per-side published features": [[n for n in names if side.search(n) and not n.startswith("3d_")]],
        "`3d_` features": [[n for n in names if n.startswith("3d_")]],
        "left-right asymmetry features": [asym],
        "the same and `lrCorr_`": [asym + [n for n in names if n.startswith("lrCorr_")]],
        "the same and the 3D angle spreads' log ratios": [asym + spreads],
        "zedo's own speeds' and ranges' log ratios": [own],
        "the asymmetry set and those": [asym + own],
        "asymmetry, the larger of the arms' and the legs' scores": [[n for n in asym if ARM.search(n)],
                                                                    [n for n in asym if not ARM.search(n)]],
    }  # fmt: skip


def conformal_p(reference: np.ndarray, clip: np.ndarray, parts: list[np.ndarray], score: Callable) -> float:
    both = np.vstack([reference, clip[None]])
    scores = []
    for j in range(len(both)):
        z = _robust_z(both[j], np.delete(both, j, axis=0))
        scores.append(max(score(z[p][np.isfinite(z[p])]) for p in parts))
    return float(np.mean(np.array(scores) >= scores[-1]))


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--work", type=Path, required=True)
    ap.add_argument("--source", choices=SOURCES, default="syrip-train")
    ap.add_argument("--draws", type=int, default=8)
    ap.add_argument("--reference", type=int, default=20)
    ap.add_argument("--tested", type=int, default=80, help="typical clips tested per draw")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    folder = args.work / args.source
    every = {i: with_ratios(v) for i, v in clip_rows(folder, "typical").items()}
    typical = [v for i, v in every.items() if isinstance(i, int)]
    groups = {g: [with_ratios(v) for v in clip_rows(folder, g).values()]
              for g in ("long", "still_arm", "still_leg")}  # fmt: skip
    added = reliable_ratios(every)
    names = reliable_features(sorted(set(PREREGISTERED) | set(extended_names(typical[0]))), bundled_reliability())
    names += added

    def matrix(clips: list[dict[str, float]]) -> np.ndarray:
        return np.array([[c.get(n, np.nan) for n in names] for c in clips])

    pool, tested = matrix(typical), {g: matrix(v) for g, v in groups.items()}
    still_body = list(clip_rows(folder, "still_body").values())  # where lifted (--groups still_body)
    print_elbow_speeds({"typical": typical, **groups, **({"still_body": still_body} if still_body else {})})
    rng = np.random.default_rng(args.seed)
    draws = [rng.permutation(len(pool)) for _ in range(args.draws)]
    print("| features | score | typical | 60 s | still arm | still leg |\n| --- | --- | --- | --- | --- | --- |")
    for set_name, parts in feature_sets(names).items():
        columns = np.array([names.index(n) for part in parts for n in part])
        bounds = np.cumsum([0, *map(len, parts)])
        slices = [np.arange(a, b) for a, b in zip(bounds[:-1], bounds[1:], strict=True)]
        for score_name, score in SCORES.items():
            flagged: dict[str, list[bool]] = {g: [] for g in ("typical", *tested)}
            for order in draws:
                reference = pool[order[: args.reference]][:, columns]
                cases = {"typical": pool[order[args.reference : args.reference + args.tested]], **tested}
                for group, clips in cases.items():
                    flagged[group] += [conformal_p(reference, c[columns], slices, score) < 0.05 for c in clips]
            cells = " | ".join(f"{np.mean(flagged[g]):.1%}" for g in ("typical", "long", "still_arm", "still_leg"))
            print(f"| {set_name} ({len(columns)}) | {score_name} | {cells} |", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
