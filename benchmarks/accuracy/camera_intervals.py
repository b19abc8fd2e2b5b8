"""Which symmetry values of the f = 1000 px clips get an interval, end to end through `zedo analyze`.

benchmarks/calibrate/calibrate_measures.py --cameras counts the frame-pairs with an interval from its own bookkeeping
of the cases; this runs the real thing. For each fold and 2D input it makes the recipe's f = 1000 px clips again (the
same random draws, checked against the lifted root depths saved in `--cases`/cameras), lifts them with the fold
prior in `--temporal smooth` with their K (what `zedo lift --focal 1000 --temporal smooth` does), writes the
result document and analyses it with `analysis.analyse` under each calibration file given, whose prior sha256 is
set to the fold prior's (the fold priors stand in for the bundled prior, as in the recipe). It prints, per file,
how many lifted symmetry values there are and the `interval` column's reasons with their counts, and for the
values without an interval the lifted and the true root depths of their poses.

    python benchmarks/accuracy/camera_intervals.py --syrip-dir ../shared/data/syrip --folds folds/ --cases cases/ \\
        zedo_cli/weights/measures.json

About 30 s a fold and input on one thread. Test100 and SyRIP's synthetic rows are never read.
"""

from __future__ import annotations

import argparse
import collections
import json
import sys
import tempfile
from dataclasses import replace
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # the repository root
from benchmarks.calibrate.calibrate_measures import (
    CAMERA_CLIPS,
    CAMERA_DRAWS,
    CLIP_KINDS,
    camera_images,
    relative_errors,
)
from benchmarks.lib.settings import CAMERAS, place_camera
from zedo_cli.analysis.analyse import SYMMETRY_NAMES, analyse
from zedo_cli.analysis.uncertainty.calibration import read_calibrations


def f1000_clips(truth: np.ndarray, kp: dict, k: int, key: str) -> dict[str, np.ndarray]:
    """The recipe's f = 1000 px clips of fold `k` and input `key`: its random stream replayed up to them
    (calibrate_measures.lift_camera_cases; nothing it lifts draws from that stream)."""
    import torch

    from zedo_cli.evaluation.clips.eased import make_sequences

    errors = relative_errors(kp["gt"].xy, kp["detected"].xy)
    rng = np.random.default_rng(1000 + k)
    for x in ("gt", "detected"):
        detected = x == "detected"
        camera_images(truth, errors if detected else None, kp[x].confidence if detected else None, rng, CAMERA_DRAWS,
                      CAMERAS)  # fmt: skip
    for kind, cams, _ in CLIP_KINDS:
        for x in ("gt", "detected"):
            torch.manual_seed(k)
            clips = make_sequences(truth, rng, **CAMERA_CLIPS,
                                   place=None if cams is None else lambda r, p, d, c=cams: place_camera(r, p, d, c),
                                   key_noise=errors if x == "detected" else None)  # fmt: skip
            if (kind, x) == ("f1000", key):
                return clips
    raise AssertionError("CLIP_KINDS has no f1000 clips")


def reason(text: str) -> str:
    """The `interval` column without its pose's numbers: one line per kind of reason."""
    return text.split(" (")[0] if text.startswith("none: camera") else text.split(": ")[0] + (
        ": " + text.split(": ")[1] if text.startswith("none") else "")  # fmt: skip


def main() -> int:
    from benchmarks.lib.folds import fold_priors
    from zedo_cli.data.keypoints import Keypoints2D
    from zedo_cli.formats.readers.result import read_result
    from zedo_cli.formats.writers.result_json import build_result_document
    from zedo_cli.lifting.config import DEFAULT_PRESET, get_preset
    from zedo_cli.lifting.temporal import lift_sequence

    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--syrip-dir", required=True)
    ap.add_argument("--folds", type=Path, required=True)
    ap.add_argument("--cases", type=Path, required=True, help="the recipe's cases (their lifted depths are checked)")
    ap.add_argument("--fold-ids", type=int, nargs="+", default=None)
    ap.add_argument("calibrations", type=Path, nargs="+", help="measure calibration files (zedo.measures)")
    args = ap.parse_args()
    cfg = get_preset(DEFAULT_PRESET)
    totals: dict[Path, collections.Counter] = {c: collections.Counter() for c in args.calibrations}
    with tempfile.TemporaryDirectory() as tmp:
        for k, prior, truth, inputs in fold_priors(args.folds, "", args.syrip_dir, args.fold_ids):
            kp = {key: v.to_skeleton(prior.skeleton) for key, v in inputs.items()}
            for key in ("gt", "detected"):
                clips = f1000_clips(truth.poses, kp, k, key)
                res = lift_sequence(clips["xy"], clips["conf"], clips["k"], prior, cfg, mode="smooth",
                                    tracks=clips["tracks"])  # fmt: skip
                with np.load(args.cases / "cameras" / f"fold{k}-f1000-smooth-clips_{key}.npz") as saved:
                    depth = saved["lifted_depth"]
                    ok = np.isfinite(depth)
                    if not np.allclose(res.root_translation[ok, 2], depth[ok], atol=1e-6):
                        raise SystemExit(f"fold {k} {key}: not the recipe's lift (its saved root depths differ)")
                n = len(clips["xy"])
                k2d = Keypoints2D(clips["xy"], clips["conf"], prior.skeleton, list(range(n)),
                                  [f"f{i:05d}.png" for i in range(n)], np.array([[1280.0, 720.0]] * n), [None] * n,
                                  "clips.json", "zedo-2d", frame_indices=list(range(n)))  # fmt: skip
                params = {"prior": {"sha256": prior.sha256}, "config": cfg.to_dict(), "temporal": {"mode": "smooth"},
                          "camera_sources": ["cli"]}  # fmt: skip
                doc = build_result_document(k2d, res, clips["k"], ["cli"] * n, params=params,
                                            input_info={"path": "clips.json"})  # fmt: skip
                path = Path(tmp) / f"fold{k}-{key}.zedo.json"
                path.write_text(json.dumps(doc))
                result = read_result(path)
                for calibration_file in args.calibrations:
                    cals = [replace(c, prior_sha256=prior.sha256) for c in read_calibrations(calibration_file)]
                    a = analyse(result, calibrations=cals)
                    rows = [r for r in a.rows if r.measure in SYMMETRY_NAMES and r.frame_index is not None
                            and np.isfinite(r.value)]  # fmt: skip
                    count = collections.Counter(reason(r.how) for r in rows)
                    totals[calibration_file].update(count)
                    print(f"fold {k} {key}, {calibration_file}: {len(a.index)} of {n} poses lifted, {len(rows)} "
                          f"symmetry values: {dict(count.most_common())}")  # fmt: skip
                    without = sorted({r.frame_index for r in rows if r.interval.startswith("none")})
                    if without:
                        lifted = res.root_translation[without, 2]
                        true = (clips["cam"] - clips["rel"])[without, 0, 2]  # the root point's depth
                        print(f"  {len(without)} poses without: lifted root depth {lifted.min():.2f}-"
                              f"{lifted.max():.2f} m, true {true.min():.2f}-{true.max():.2f} m, clips "
                              f"{sorted(set(clips['tracks'][without].tolist()))}")  # fmt: skip
    for calibration_file, count in totals.items():
        values = sum(count.values())
        with_interval = sum(c for r, c in count.items() if not r.startswith("none"))
        print(f"{calibration_file}: {with_interval} of {values} symmetry values have an interval "
              f"({100 * with_interval / values:.2f} %): {dict(count.most_common())}")  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
