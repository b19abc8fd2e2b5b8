"""Calibrate the measure-level estimates and intervals of `zedo analyze` on held-out lifts.

1. `--lift`: every fold prior `fold<k><weights>.safetensors` in `--folds` (benchmarks/lib/folds.py)
   lifts its fold's held-out SyRIP training poses with the default preset and the pseudo camera,
   from ground-truth and FiDIP 2D (images), and synthetic clips made from the same held-out poses
   (zedo_cli/evaluation/clips/eased.py's generator, 30 fps, 3 px noise) in `--temporal smooth` (videos). For
   every case it saves the raw measures of the lift, their depth sensitivities and the measures
   of the truth (`--cases DIR`, one npz per fold, input and mode).
2. Then, per mode, it cross-fits (leave one fold out; with one fold, two halves of its poses or
   clips) and prints, on the cases each model never saw: the mean absolute error of the raw and
   the calibrated estimates, the coverage of the intervals per measure, and for the symmetry pairs
   the share of decisive calls and their agreement with the truth's call at every level.
3. `--write`: fits on every case and writes the calibrations (default: the package's
   weights/measures.json) for the shipped prior.

    python benchmarks/lib/folds.py --syrip-dir ../shared/data/syrip --out folds/
    zedo fit-prior folds/fold0-train.npz --recipe weights_spec/syrip12-scratch.toml --out folds/fold0.safetensors
    python benchmarks/calibrate/calibrate_measures.py --syrip-dir ../shared/data/syrip --folds folds/ --cases cases/ \\
        --lift --write

Test100 and SyRIP's synthetic rows are never read.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # the repository root
from benchmarks.lib.adult_cases import ADULT_SOURCE, ADULT_SOURCE_NAMES, adult_case_clips, adult_sources
from benchmarks.lib.pose_sources import PLACINGS, placed_poses
from benchmarks.lib.settings import CAMERAS, CLIP_SETTINGS, CameraRange, place_camera
from zedo_cli.analysis.analyse import SYMMETRY_NAMES, all_measures
from zedo_cli.analysis.pose.joint_angles import CIRCULAR_ANGLES
from zedo_cli.analysis.pose.symmetry import DEFAULT_THRESHOLD_DEG
from zedo_cli.analysis.uncertainty.calibration import (
    LEVELS,
    CameraDomain,
    MeasureCalibration,
    MeasureModel,
    MeasureModelEntry,
    bundled_path,
    fit_measure,
    measure_joints,
    read_calibrations,
    residuals,
    write_calibrations,
)
from zedo_cli.data.skeleton import get_skeleton
from zedo_cli.evaluation.metrics import decisive_calls

SKELETON = get_skeleton("syrip12")
BINS = {"none": 2, "smooth": 4, "clip": 4}  # bins of the measured value per measure (images: ~300 a fold, clips: ~2400)
MODES = ("none", "smooth", "clip")  # the temporal modes calibrated: frame by frame, --temporal smooth, --temporal clip
# The second source, the adult motion made infant-like (benchmarks/lib/adult_cases.py), in about as many cases a fold
# as the SyRIP poses give, so that neither source outweighs the other in the shipped fit: before the pseudo camera
# 16 clips of 5 s (2400 frames, as the SyRIP clips), frame by frame every 8th of their frames (300, as the SyRIP
# images); before the clinic cameras 24 clips of 10 s (7200 frames, as the SyRIP camera cases of either mode).
ADULT_CLIPS = {"count": 16, "seconds": 5.0}
ADULT_IMAGE_STRIDE = 8
ADULT_CAMERA_CLIPS = {"count": 24, "seconds": 10.0}
SOURCES = ("syrip", "adult")
SOURCE_NAMES = {"syrip": "SyRIP poses", "adult": "adult motion"}


def source_of(kind: np.ndarray) -> np.ndarray:
    """The clip source `(n,)` of cases of input kinds `kind (n,)`: the adult motion's kinds end in ADULT_SOURCE, or
    with `--adult-captures` in one of ADULT_CAPTURES' names; the others are SyRIP's poses."""
    kind = kind.astype(str)
    out = np.full(kind.shape, SOURCE_NAMES["syrip"], dtype=object)
    for suffix, name in ADULT_SOURCE_NAMES.items():
        out[np.char.endswith(kind, suffix)] = name
    return out.astype(str)


def measures(p: np.ndarray) -> dict[str, np.ndarray]:
    return all_measures(p, SKELETON)


def case_arrays(lifted: np.ndarray, observed: np.ndarray, ok: np.ndarray, truth: np.ndarray) -> dict[str, np.ndarray]:
    """Per measure: raw value and truth of every case; the raw value NaN where a joint it uses was
    filled by the prior or the pose was not lifted (such cases are calibrated apart: `filled_raw`, the
    raw value of the lifted cases with a filled joint, NaN elsewhere)."""
    raw, true = measures(lifted), measures(truth)
    uses = measure_joints(SKELETON, measures, list(raw))
    out = {}
    for name in raw:
        usable = ok & observed[:, uses[name]].all(1)
        out[f"{name}|raw"] = np.where(usable, raw[name], np.nan)
        out[f"{name}|truth"] = true[name]
        out[f"{name}|filled_raw"] = np.where(ok & ~usable, raw[name], np.nan)
    return out


DIFFICULTY = "reprojection_px"  # the key of each case's difficulty: its lift's mean reprojection error (px)
LIFTED = "lifted_root_relative"  # the key of each case's lifted pose (metres, camera axes), for experiments


def lift_arrays(res: Any, truth: np.ndarray, keep: slice = slice(None)) -> dict[str, np.ndarray]:
    """`case_arrays` of a lift `res` (a LiftResult) against the true poses `truth` (of the kept cases), with each
    case's difficulty: the mean reprojection error of its observed joints, what the lift knows of its own fit."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # a pose not lifted: NaN
        difficulty = np.nanmean(res.reprojection_error_px[keep], axis=1)
    return {**case_arrays(res.poses_root_relative[keep], res.observed[keep], res.lifted[keep], truth),
            DIFFICULTY: difficulty, LIFTED: np.asarray(res.poses_root_relative[keep], dtype=np.float32)}  # fmt: skip


def difficulty_terciles(cases: dict[str, np.ndarray], kind: np.ndarray) -> np.ndarray:
    """Per case `(n,)` its source and tercile of the difficulty within that source (`<source>, easiest third`,
    ...; `<source>, unknown` where no difficulty was saved or the pose was not lifted)."""
    src = source_of(kind)
    d = cases.get(DIFFICULTY, np.full(len(kind), np.nan))
    label = np.char.add(src.astype(str), ", unknown").astype(object)
    for s in np.unique(src):
        mine = (src == s) & np.isfinite(d)
        if mine.sum() < 3:
            continue
        edges = np.quantile(d[mine], [1 / 3, 2 / 3])
        third = np.searchsorted(edges, d[mine], side="right")
        label[mine] = [f"{s}, {('easiest', 'middle', 'hardest')[t]} third" for t in third]
    return label.astype(str)


def lift_cases(args: argparse.Namespace) -> None:
    import torch

    from benchmarks.lib.folds import fold_priors
    from zedo_cli.lifting.camera import resolve_intrinsics
    from zedo_cli.lifting.config import DEFAULT_PRESET, get_preset
    from zedo_cli.lifting.solver import lift
    from zedo_cli.lifting.temporal import lift_sequence

    cfg = get_preset(DEFAULT_PRESET)
    args.cases.mkdir(parents=True, exist_ok=True)
    for k, prior, truth, inputs in fold_priors(args.folds, args.weights, args.syrip_dir, args.fold_ids):
        if "adult" in args.sources:
            lift_adult_cases(args, k, prior)
        if "syrip" not in args.sources:
            continue
        for key, kp in inputs.items() if "none" in args.temporal_modes else ():
            kp = kp.to_skeleton(prior.skeleton)
            mats, _ = resolve_intrinsics(kp.image_sizes, kp.image_ids, kp.file_names)
            res = lift(kp.xy, kp.confidence, mats, prior, cfg, seed=0)
            arrays = lift_arrays(res, truth.poses)
            np.savez(args.cases / f"fold{k}-none-{key}.npz", group=np.arange(len(kp)), **arrays)
            print(f"fold {k} {key}: {int(res.lifted.sum())}/{len(kp)} lifted")
        torch.manual_seed(k)
        clips = syrip_clips(truth.poses, np.random.default_rng(100 + k), args.syrip_clips)
        for mode in (m for m in ("smooth", "clip") if m in args.temporal_modes):
            res = lift_sequence(clips["xy"], clips["conf"], clips["k"], prior, cfg, mode=mode, tracks=clips["tracks"])
            arrays = lift_arrays(res, clips["rel"])
            np.savez(args.cases / f"fold{k}-{mode}-clips.npz", group=clips["tracks"], **arrays)
            print(f"fold {k} clips, {mode}: {int(res.lifted.sum())}/{len(res.lifted)} frames lifted")


def syrip_clips(poses: np.ndarray, rng: np.random.Generator, placing: str) -> dict[str, np.ndarray]:
    """The SyRIP calibration clips (CLIP_SETTINGS) of held-out `poses (P, 12, 3)`, their key poses placed by `placing`
    (`pose_sources.placed_poses`: "photo", the shipped clips; "supine")."""
    from zedo_cli.evaluation.clips.eased import make_sequences

    placed, sway = placed_poses(poses, placing)
    return make_sequences(placed, rng, **CLIP_SETTINGS, sway=sway)


def lift_adult_cases(args: argparse.Namespace, k: int, prior: Any) -> None:
    """The adult source's cases of fold `k` before the pseudo camera (ADULT_CLIPS): `--temporal smooth` and `clip`
    (`fold<k>-<mode>-adult.npz`) and frame by frame, every ADULT_IMAGE_STRIDE-th frame (`fold<k>-none-adult.npz`);
    the modes of `--temporal-modes`."""
    import torch

    from zedo_cli.lifting.config import DEFAULT_PRESET, get_preset
    from zedo_cli.lifting.temporal import lift_sequence

    every, stride = slice(None), slice(None, None, ADULT_IMAGE_STRIDE)
    for name, files in adult_sources(args.adult_captures):
        torch.manual_seed(k)
        clips = adult_case_clips(args.syrip_dir, 1300 + k, False, **ADULT_CLIPS, files=files)
        for mode, keep in ((m, kept) for m, kept in (("smooth", every), ("none", stride), ("clip", every))
                           if m in args.temporal_modes):  # fmt: skip
            res = lift_sequence(clips["xy"], clips["conf"], clips["k"], prior, get_preset(DEFAULT_PRESET), mode=mode,
                                tracks=clips["tracks"])  # fmt: skip
            arrays = lift_arrays(res, clips["rel"][keep], keep)
            np.savez(args.cases / f"fold{k}-{mode}-{name}.npz", group=clips["tracks"][keep], **arrays)
            print(f"fold {k} {name} {mode}: {int(res.lifted[keep].sum())}/{len(arrays[next(iter(arrays))])} "
                  "frames lifted", flush=True)  # fmt: skip


F1000 = CameraRange(focal_px=(1000.0, 1000.0), depth_m=(0.9, 1.1))  # the target set-up
CAMERA_DRAWS = 6  # cameras per held-out pose and 2D input (images)
# More cases for the near range of lifted root depths (below NEAR_BELOW_M), where CAMERAS gives few: the same
# cameras at true depths of 0.5-1.1 m. A pose lifted that near comes from a true depth under about 1.1 m (lifted
# depths under half the true one are about 1 in 1000), where CAMERAS draws uniformly too, so these draws give the
# near range the same mix of close poses and poses lifted too near as CAMERAS; they fit only the near range.
NEAR = CameraRange(depth_m=(0.5, 1.1))
NEAR_BELOW_M = 0.6
NEAR_DRAWS, NEAR_CLIP_COUNT = 12, 48  # per held-out pose and 2D input; clips per fold and 2D input
# per fold and 2D input; the jitter (noise_rel of the body's 2D size) is the pseudo clips' 3 px at 1 m
CAMERA_CLIPS = {"count": 16, "keyposes": 8, "transition_s": 1.0, "fps": 30.0, "noise_px": 0.0, "drop": 0.03,
                "gap": 3, "noise_rel": 0.0125}  # fmt: skip
# clips per camera kind: (kind, cameras drawn (None: the pseudo camera), temporal modes lifted)
CLIP_KINDS = (("intrinsics", CAMERAS, ("smooth", "none", "clip")), ("f1000", F1000, ("smooth",)),
              ("pseudo", None, ("none",)))  # fmt: skip
YAW, ROLL = 0.4, 0.2  # rad: the images turn as the clips do (temporal.make_sequences)


def relative_errors(gt: np.ndarray, detected: np.ndarray) -> np.ndarray:
    """A detector's error per joint `(N, J, 2)` relative to the 2D size of the ground truth (NaN: missed)."""
    from zedo_cli.lifting.detections import pose_size

    return (detected - gt) / pose_size(gt)[:, None, None]


def camera_images(rel: np.ndarray, errors: np.ndarray | None, confidence: np.ndarray | None,
                  rng: np.random.Generator, draws: int, cams: CameraRange) -> dict[str, np.ndarray]:  # fmt: skip
    """Each pose of `rel (P, J, 3)` turned a little and seen by `draws` cameras of `cams`, projected exactly
    (errors None: the ground-truth 2D) or with the pose's own detector error `(P, J, 2)` scaled to its size
    there and its confidences `(P, J)`."""
    from zedo_cli.evaluation.clips.eased import _rotation
    from zedo_cli.lifting.detections import pose_size

    idx = np.repeat(np.arange(len(rel)), draws)
    turn = _rotation(rng.uniform(-YAW, YAW, len(idx)), rng.uniform(-ROLL, ROLL, len(idx)))
    poses = rel[idx] @ turn.transpose(0, 2, 1)  # (N, J, 3)
    placed = [place_camera(rng, p[None], np.zeros((1, 3)), cams) for p in poses]
    k = np.stack([pk for pk, _ in placed])
    cam = poses + np.stack([r[0] for _, r in placed])[:, None]
    xy = np.einsum("nij,nkj->nki", k, cam)
    xy = xy[..., :2] / xy[..., 2:]
    if errors is not None:
        xy = xy + errors[idx] * pose_size(xy)[:, None, None]
    conf = np.ones(xy.shape[:2]) if confidence is None else confidence[idx].copy()
    conf[~np.isfinite(xy).all(-1)] = 0.0
    return {"xy": xy, "conf": conf, "k": k, "rel": poses, "cam": cam, "group": idx}


def camera_cases(res: Any, data: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """`case_arrays` of a lift of camera cases, with each case's camera: focal length (px), true and lifted root
    depth (m), the body's 2D size (px) and frame width."""
    from zedo_cli.lifting.detections import pose_size

    return {**lift_arrays(res, data["rel"]),
            "focal": data["k"][:, 0, 0], "depth": root_depth(data),
            "lifted_depth": res.root_translation[:, 2], "size_px": pose_size(data["xy"]),
            "width": 2 * data["k"][:, 0, 2]}  # fmt: skip


def root_depth(data: dict[str, np.ndarray]) -> np.ndarray:
    """The true root depth `(N,)` of camera cases (their root point is the root-relative origin)."""
    return (data["cam"] - data["rel"])[:, 0, 2]


def lift_camera_cases(args: argparse.Namespace) -> None:
    """Held-out poses seen by drawn cameras (`CAMERAS`), lifted with their true K: images from GT and FiDIP
    2D (mode none), clips in `--temporal smooth` and frame by frame; the f = 1000 px set-up (`F1000`) as
    clips; the pseudo camera's clips frame by frame (`--camera-kinds base`); and the near draws (`NEAR`,
    `lift_near_cases`: `--camera-kinds near`). One npz per fold, camera kind, mode and input in
    `--cases`/cameras."""
    import time

    import torch

    from benchmarks.lib.folds import fold_priors
    from zedo_cli.evaluation.clips.eased import make_sequences
    from zedo_cli.lifting.config import DEFAULT_PRESET, get_preset
    from zedo_cli.lifting.solver import lift
    from zedo_cli.lifting.temporal import lift_sequence

    cfg = get_preset(DEFAULT_PRESET)
    out = args.cases / "cameras"
    out.mkdir(parents=True, exist_ok=True)
    for k, prior, truth, inputs in fold_priors(args.folds, args.weights, args.syrip_dir, args.fold_ids):
        start = time.perf_counter()
        kp = {key: v.to_skeleton(prior.skeleton) for key, v in inputs.items()}
        errors = relative_errors(kp["gt"].xy, kp["detected"].xy)
        if "adult" in args.sources:
            lift_adult_camera_cases(args, out, k, prior)
        if "syrip" not in args.sources:
            continue
        if "near" in args.camera_kinds:
            lift_near_cases(out, k, prior, truth.poses, kp, errors, args.temporal_modes)
        if "base" not in args.camera_kinds:
            print(f"fold {k}: near camera cases lifted in {time.perf_counter() - start:.0f} s")
            continue
        rng = np.random.default_rng(1000 + k)
        for key in ("gt", "detected"):
            detected = key == "detected"
            data = camera_images(truth.poses, errors if detected else None, kp[key].confidence if detected else None,
                                 rng, CAMERA_DRAWS, CAMERAS)  # fmt: skip
            if "none" in args.temporal_modes:  # drawn either way: the clips below come next in the stream
                res = lift(data["xy"], data["conf"], data["k"], prior, cfg, seed=0)
                np.savez(out / f"fold{k}-intrinsics-none-{key}.npz", group=data["group"], **camera_cases(res, data))
        for kind, cams, modes in CLIP_KINDS:
            for key in ("gt", "detected"):
                torch.manual_seed(k)
                clips = make_sequences(truth.poses, rng, **CAMERA_CLIPS,
                                       place=None if cams is None else lambda r, p, d, c=cams: place_camera(r, p, d, c),
                                       key_noise=errors if key == "detected" else None)  # fmt: skip
                for mode in (m for m in modes if m in args.temporal_modes):
                    res = lift_sequence(clips["xy"], clips["conf"], clips["k"], prior, cfg, mode=mode,
                                        tracks=clips["tracks"])  # fmt: skip
                    np.savez(out / f"fold{k}-{kind}-{mode}-clips_{key}.npz", group=clips["tracks"],
                             **camera_cases(res, clips))  # fmt: skip
        print(f"fold {k}: camera cases lifted in {time.perf_counter() - start:.0f} s")


def lift_adult_camera_cases(args: argparse.Namespace, out: Path, k: int, prior: Any) -> None:
    """The adult source's cases of fold `k` before the clinic cameras and two far ones (ADULT_CAMERA_CLIPS), lifted
    with their true K frame by frame, in `--temporal smooth` and `clip` (`fold<k>-intrinsics-<mode>-clips_adult.npz`;
    the modes of `--temporal-modes`)."""
    import torch

    from zedo_cli.lifting.config import DEFAULT_PRESET, get_preset
    from zedo_cli.lifting.temporal import lift_sequence

    torch.manual_seed(k)
    clips = adult_case_clips(args.syrip_dir, 1500 + k, True, **ADULT_CAMERA_CLIPS)
    for mode in (m for m in ("smooth", "none", "clip") if m in args.temporal_modes):
        res = lift_sequence(clips["xy"], clips["conf"], clips["k"], prior, get_preset(DEFAULT_PRESET), mode=mode,
                            tracks=clips["tracks"])  # fmt: skip
        np.savez(out / f"fold{k}-intrinsics-{mode}-clips_{ADULT_SOURCE}.npz", group=clips["tracks"],
                 **camera_cases(res, clips))  # fmt: skip
        print(f"fold {k} {ADULT_SOURCE} known cameras {mode}: {int(res.lifted.sum())}/{len(res.lifted)} frames lifted",
              flush=True)  # fmt: skip


def lift_near_cases(out: Path, k: int, prior: Any, poses: np.ndarray, kp: dict, errors: np.ndarray,
                    modes: Sequence[str] = MODES) -> None:  # fmt: skip
    """The near draws (`NEAR`) of fold `k`'s held-out `poses (P, J, 3)`: images from GT and FiDIP 2D, and clips in
    `--temporal smooth`, `clip` and frame by frame (those of `modes`), saved as the kinds `near_<input>` of the
    intrinsics cases. Their own random stream, so the other camera cases are the same with or without them."""
    import torch

    from zedo_cli.evaluation.clips.eased import make_sequences
    from zedo_cli.lifting.config import DEFAULT_PRESET, get_preset
    from zedo_cli.lifting.solver import lift
    from zedo_cli.lifting.temporal import lift_sequence

    cfg = get_preset(DEFAULT_PRESET)
    rng = np.random.default_rng(3000 + k)
    for key in ("gt", "detected"):
        detected = key == "detected"
        data = camera_images(poses, errors if detected else None, kp[key].confidence if detected else None, rng,
                             NEAR_DRAWS, NEAR)  # fmt: skip
        if "none" in modes:  # drawn either way: the clips below come next in the stream
            res = lift(data["xy"], data["conf"], data["k"], prior, cfg, seed=0)
            np.savez(out / f"fold{k}-intrinsics-none-near_{key}.npz", group=data["group"], **camera_cases(res, data))
    for key in ("gt", "detected"):
        torch.manual_seed(k)
        clips = make_sequences(poses, rng, **{**CAMERA_CLIPS, "count": NEAR_CLIP_COUNT},
                               place=lambda r, p, d: place_camera(r, p, d, NEAR),
                               key_noise=errors if key == "detected" else None)  # fmt: skip
        for mode in (m for m in ("smooth", "none", "clip") if m in modes):
            res = lift_sequence(clips["xy"], clips["conf"], clips["k"], prior, cfg, mode=mode, tracks=clips["tracks"])
            np.savez(out / f"fold{k}-intrinsics-{mode}-near_clips_{key}.npz", group=clips["tracks"],
                     **camera_cases(res, clips))  # fmt: skip


def load_cases(folder: Path, mode: str) -> tuple[dict[str, np.ndarray], np.ndarray, np.ndarray, np.ndarray]:
    """Pooled cases of `mode`: arrays by key, and per case its fold, input and group (pose or clip)."""
    pooled: dict[str, list[np.ndarray]] = {}
    fold, kind, group = [], [], []
    for path in sorted(folder.glob(f"fold*-{mode}-*.npz")):
        k = int(path.name[4 : path.name.index("-")])
        with np.load(path) as data:
            for key in data.files:
                if key != "group":
                    pooled.setdefault(key, []).append(data[key])
            n = len(data["group"])
            fold.append(np.full(n, k))
            kind.append(np.full(n, path.stem.rsplit("-", 1)[1]))
            group.append(data["group"])
    if not fold:
        raise SystemExit(f"{folder}: no cases of mode {mode}: run with --lift first")
    return ({k: np.concatenate(v) for k, v in pooled.items()}, np.concatenate(fold), np.concatenate(kind),
            np.concatenate(group))  # fmt: skip


def splits(fold: np.ndarray, group: np.ndarray) -> list[tuple[np.ndarray, np.ndarray]]:
    """(fit, evaluate) masks: leave one fold out, or with one fold two halves of its groups."""
    folds = np.unique(fold)
    if len(folds) > 1:
        return [(fold != f, fold == f) for f in folds]
    groups = np.unique(group)
    half = np.isin(group, np.random.default_rng(0).permutation(groups)[: len(groups) // 2])
    return [(half, ~half), (~half, half)]


def names_of(cases: dict[str, np.ndarray]) -> list[str]:
    return sorted({k.split("|")[0] for k in cases if "|" in k}, key=lambda n: (n not in SYMMETRY_NAMES, n))


MIN_CASES = 100  # a model only from this many cases (a range without them, as a source leaves it, has none)


def fit_all(cases: dict[str, np.ndarray], mask: np.ndarray, bins: int) -> dict[str, MeasureModel]:
    if mask.sum() < MIN_CASES:
        return {}
    return {n: fit_measure(cases[f"{n}|raw"][mask], cases[f"{n}|truth"][mask], circular=n in CIRCULAR_ANGLES,
                           bins=bins) for n in names_of(cases)}  # fmt: skip


HeldOutModels = list[tuple[dict[str, MeasureModel], np.ndarray]]  # per split: the models and the cases they never saw


def cross_fitted_models(cases: dict[str, np.ndarray], fold: np.ndarray, group: np.ndarray, bins: int) -> HeldOutModels:
    """The models of every cross-fitting split, each with the mask of the cases it was not fitted on."""
    return [(fit_all(cases, fit, bins), evaluate) for fit, evaluate in splits(fold, group)]


def scored(held_out: list[tuple[dict[str, MeasureModel], np.ndarray]], cases: dict[str, np.ndarray],
           kind: np.ndarray, threshold: float) -> dict:  # fmt: skip
    """Figures of models on the cases they never saw (`held_out`: each models and the mask of its cases),
    pooled, per label of `kind (n,)`: MAE raw and estimate, coverage, width, decisive share and agreement."""
    out: dict = {}
    per: dict[tuple[str, str], dict[str, list]] = {}
    for models, evaluate in held_out:
        for n, model in models.items():
            raw, truth = (cases[f"{n}|{x}"][evaluate] for x in ("raw", "truth"))
            ok = np.isfinite(raw) & np.isfinite(truth)
            est = model.estimate(raw[ok])
            for kd in np.unique(kind[evaluate]):
                sel = kind[evaluate][ok] == kd
                if not sel.any():
                    continue
                d = per.setdefault((n, kd), {"raw": [], "est": [], "truth": [], "low": {}, "high": {}})
                d["raw"].append(raw[ok][sel])
                d["est"].append(est[sel])
                d["truth"].append(truth[ok][sel])
                for lv in LEVELS:
                    lo, hi = model.interval(est[sel], raw[ok][sel], lv)
                    d["low"].setdefault(lv, []).append(lo)
                    d["high"].setdefault(lv, []).append(hi)
    for (n, kd), d in per.items():
        raw, est, truth = (np.concatenate(d[x]) for x in ("raw", "est", "truth"))
        circ = n in CIRCULAR_ANGLES
        row = {"cases": int(len(truth)),
               "mae_raw": float(np.abs(residuals(truth, raw, circ)).mean()),
               "mae_est": float(np.abs(residuals(truth, est, circ)).mean())}  # fmt: skip
        for lv in LEVELS:
            lo, hi = np.concatenate(d["low"][lv]), np.concatenate(d["high"][lv])
            r = residuals(truth, est, circ)
            inside = (r >= lo - est) & (r <= hi - est)
            row[f"coverage_{lv}"] = float(inside.mean())
            row[f"width_{lv}"] = float(np.median(hi - lo))
            if n in SYMMETRY_NAMES:
                decisive, agree = decisive_calls(np.clip(lo, 0, 180), np.clip(hi, 0, 180), truth, threshold)
                row[f"decisive_{lv}"] = float(decisive.mean())
                row[f"agreement_{lv}"] = float(agree.sum() / decisive.sum()) if decisive.any() else float("nan")
        out.setdefault(kd, {})[n] = row
    return out


def clip_median_coverage(held: HeldOutModels, cases: dict[str, np.ndarray], kind: np.ndarray, group: np.ndarray
                         ) -> dict:  # fmt: skip
    """Per symmetry pair, cross-fitted (`held`, `cross_fitted_models`): how often a clip's median of the true angle
    lies within the median of its frames' 90 % interval ends (the interval `zedo analyze` gives a clip's median)."""
    hits: dict[str, list[bool]] = {}
    clip = np.char.add(np.char.add(kind.astype(str), "/"), group.astype(str))  # a clip: its kind and group
    for models, evaluate in held:
        for n in SYMMETRY_NAMES:
            raw, truth = cases[f"{n}|raw"], cases[f"{n}|truth"]
            for g in np.unique(clip[evaluate]):
                sel = evaluate & (clip == g) & np.isfinite(raw)
                if sel.sum() < 3:
                    continue
                est = models[n].estimate(raw[sel])
                lo, hi = (np.clip(x, 0, 180) for x in models[n].interval(est, raw[sel], 0.9))
                t = np.median(truth[sel])
                hits.setdefault(n, []).append(bool(np.median(lo) <= t <= np.median(hi)))
    return {n: {"clips": len(h), "coverage": float(np.mean(h))} for n, h in hits.items()}


def print_table(figures: dict, mode: str) -> None:
    for kd, rows in figures.items():
        print(f"\n### {mode}, input {kd} (cross-fitted: cases no model saw)")
        print(
            "| measure | cases | MAE raw | MAE estimate | coverage 90 % | median width 90 % | decisive 90 % | agree |"
        )
        print("| --- | --- | --- | --- | --- | --- | --- | --- |")
        for n, r in rows.items():
            dec = f"{100 * r['decisive_0.9']:.0f} % | {100 * r['agreement_0.9']:.0f} %" if n in SYMMETRY_NAMES else "| "
            print(f"| {n} | {r['cases']} | {r['mae_raw']:.1f} | {r['mae_est']:.1f} | "
                  f"{100 * r['coverage_0.9']:.1f} % | {r['width_0.9']:.0f} | {dec} |")  # fmt: skip
        sym = [rows[n] for n in SYMMETRY_NAMES if n in rows]
        if sym:
            print("\nrisk-coverage (symmetry pairs pooled): level | decisive | agreement")
            for lv in LEVELS:
                w = np.array([r["cases"] for r in sym], float)
                dec = np.array([r[f"decisive_{lv}"] for r in sym])
                agr = np.array([r[f"agreement_{lv}"] for r in sym])
                ok = np.isfinite(agr)
                pooled_agree = float((agr[ok] * dec[ok] * w[ok]).sum() / max((dec[ok] * w[ok]).sum(), 1e-9))
                print(f"  {lv:.2f} | {100 * (dec * w).sum() / w.sum():.1f} % | {100 * pooled_agree:.1f} %")


# m: the calibrations of known cameras, one per range of the lifted root depth; the near one (below NEAR_BELOW_M)
# holds the poses lifted closer than the drawn 0.5 m allows, mostly ones lifted too near (their truth 0.5-1.1 m)
# and one beyond 2 m (the drawn cameras' poses lifted there, and the adult motion's far cameras, 2.5-3.5 m away)
DEPTH_EDGES = (0.4, NEAR_BELOW_M, 2.0, 3.5)
FOCAL_EDGES = (600.0, 1000.0, 1600.0, 2500.0, 3000.0)  # px: bins the held-out figures are reported by
DEPTH_EDGES_REPORT = (0.0, 0.4, 0.5, 0.6, 0.9, 1.2, 1.6, 2.0, 2.5, 3.5, 9.0)  # m: likewise (the lifted root depth)
SIZE_EDGES = (0.0, 60.0, 120.0, 1e9)  # px: the body's 2D size (RMS distance of the joints from their mean)
# what each mode is fitted on: frame by frame, images and clips' frames; --temporal smooth, clips
CAMERA_FITS = {"none": ("gt", "detected", "clips_gt", "clips_detected", f"clips_{ADULT_SOURCE}"),
               "smooth": ("clips_gt", "clips_detected", f"clips_{ADULT_SOURCE}"),
               "clip": ("clips_gt", "clips_detected", f"clips_{ADULT_SOURCE}")}  # fmt: skip
# the near draws' kinds (lift_near_cases), fitted and scored only in the ranges below NEAR_BELOW_M
NEAR_FITS = {mode: tuple(f"near_{k}" for k in kinds) for mode, kinds in CAMERA_FITS.items()}


@dataclass
class HeldOut:
    """Per cross-fitting split: the models of each depth range, fitted without `fold` (None: a half of one
    fold's groups, `evaluate` the other half)."""

    models: list[dict[str, MeasureModel]]  # per range of DEPTH_EDGES
    filled: list[dict[str, MeasureModel]]  # the same, of the cases with a joint the prior filled
    fold: int | None
    evaluate: np.ndarray  # (n,) bool, over the cases they were fitted from
    cases: list[np.ndarray]  # per range, (n,) bool: the cases of its kinds lifted inside it (range_cases)


FILLED_BINS, MIN_FILLED = 1, 100  # cases with a filled joint: one bin, and a model only from this many cases


def filled_view(cases: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The cases with a joint the prior filled, as `cases` (their raw values under `raw`)."""
    return {k.replace("|filled_raw", "|raw"): v for k, v in cases.items() if not k.endswith("|raw")}


def fit_filled(cases: dict[str, np.ndarray], mask: np.ndarray) -> dict[str, MeasureModel]:
    if mask.sum() < MIN_CASES:
        return {}
    view = filled_view(cases)
    enough = [n for n in names_of(view) if (mask & np.isfinite(view[f"{n}|raw"])).sum() >= MIN_FILLED]
    return {n: fit_measure(view[f"{n}|raw"][mask], view[f"{n}|truth"][mask], circular=n in CIRCULAR_ANGLES,
                           bins=FILLED_BINS) for n in enough}  # fmt: skip


def depth_bin(depth: np.ndarray) -> np.ndarray:
    """The range of DEPTH_EDGES of each lifted root depth `(n,)`, -1 outside (no calibration there)."""
    b = np.searchsorted(np.asarray(DEPTH_EDGES), depth, side="right") - 1
    b[depth == DEPTH_EDGES[-1]] = len(DEPTH_EDGES) - 2
    return np.where((b >= 0) & (b < len(DEPTH_EDGES) - 1), b, -1)


def range_cases(lifted_depth: np.ndarray, kind: np.ndarray, mode: str) -> list[np.ndarray]:
    """Per range of DEPTH_EDGES, `(n,)` bool: the cases lifted inside it of the kinds it is fitted on (CAMERA_FITS;
    below NEAR_BELOW_M also NEAR_FITS)."""
    b = depth_bin(lifted_depth)
    base, near = np.isin(kind, CAMERA_FITS[mode]), np.isin(kind, NEAR_FITS[mode])
    return [(b == r) & (base | (near & (DEPTH_EDGES[r + 1] <= NEAR_BELOW_M))) for r in range(len(DEPTH_EDGES) - 1)]


def camera_fits(cases: dict[str, np.ndarray], fold: np.ndarray, kind: np.ndarray, group: np.ndarray, mode: str
                ) -> tuple[list[HeldOut], HeldOut]:  # fmt: skip
    """The cross-fitted models of mode `mode` (one per split and depth range) and the models on every case."""
    every = range_cases(cases["lifted_depth"], kind, mode)
    folds = np.unique(fold)
    held = []
    for fit, evaluate in splits(fold, group):
        models = [fit_all(cases, fit & m, BINS[mode]) for m in every]
        filled = [fit_filled(cases, fit & m) for m in every]
        held.append(HeldOut(models, filled, int(fold[evaluate][0]) if len(folds) > 1 else None, evaluate, every))
    final = HeldOut([fit_all(cases, m, BINS[mode]) for m in every], [fit_filled(cases, m) for m in every], None,
                    np.zeros(len(fold), bool), every)  # fmt: skip
    return held, final


def apply_held_out(held: list[HeldOut], cases: dict[str, np.ndarray], fold: np.ndarray, same: bool,
                   filled: bool = False) -> list[tuple[dict[str, MeasureModel], np.ndarray]]:  # fmt: skip
    """(models, mask) of the held-out models on `cases`: on their own held-out part (`same`: the cases they were
    fitted from, each range on its own kinds), else on the cases of the fold they never saw (one fold: the first
    half's models)."""
    b = depth_bin(cases["lifted_depth"])
    out = []
    for i, h in enumerate(held):
        if same:
            inside = h.cases
        else:
            mask = np.full(len(fold), i == 0) if h.fold is None else fold == h.fold
            inside = [mask & (b == r) for r in range(len(DEPTH_EDGES) - 1)]
        out += [(m, (h.evaluate if same else True) & inside[r]) for r, m in enumerate(h.filled if filled else h.models)]
    return out


def bin_labels(x: np.ndarray, edges: tuple[float, ...], unit: str) -> np.ndarray:
    i = np.clip(np.searchsorted(np.asarray(edges), x, side="right") - 1, 0, len(edges) - 2)
    names = np.array([f"{edges[k]:g}-{edges[k + 1]:g} {unit}".replace("-1e+09", "+") for k in range(len(edges) - 1)])
    return names[i]


def pooled(rows: dict[str, dict], level: float = 0.9, call_level: float = 0.8) -> dict[str, float]:
    """Symmetry pairs pooled (weighted by cases): MAE raw and estimate, coverage, decisive share and agreement;
    and the joint angles' coverage range."""
    sym = [rows[n] for n in SYMMETRY_NAMES if n in rows]
    w = np.array([r["cases"] for r in sym], float)

    def avg(key: str) -> float:
        return float((np.array([r[key] for r in sym]) * w).sum() / w.sum())

    dec = np.array([r[f"decisive_{call_level}"] for r in sym])
    agr = np.nan_to_num(np.array([r[f"agreement_{call_level}"] for r in sym]))
    angles = [r[f"coverage_{level}"] for n, r in rows.items() if n not in SYMMETRY_NAMES]
    return {"pair_cases": int(w.sum()), "mae_raw": avg("mae_raw"), "mae_est": avg("mae_est"),
            "coverage": avg(f"coverage_{level}"), "coverage_pairs": [r[f"coverage_{level}"] for r in sym],
            "decisive": float((dec * w).sum() / w.sum()),
            "agreement": float((agr * dec * w).sum() / max((dec * w).sum(), 1e-9)),
            "angles_coverage": [min(angles, default=np.nan), max(angles, default=np.nan)]}  # fmt: skip


def family_coverage(rows: dict[str, dict], level: float = 0.9) -> dict[str, float]:
    """Coverage at `level` of the measures of `rows` (scored's rows of one stratum), weighted by their cases: all of
    them, the symmetry pairs and the joint angles (the shape of a calibration's `held_out_by_source_coverage_90`)."""
    families = {"all": list(rows), "symmetry": [n for n in rows if n in SYMMETRY_NAMES],
                "joint_angles": [n for n in rows if n not in SYMMETRY_NAMES]}  # fmt: skip
    out = {}
    for family, names in families.items():
        cases = np.array([rows[n]["cases"] for n in names], float)
        if cases.sum():
            out[family] = float((np.array([rows[n][f"coverage_{level}"] for n in names]) * cases).sum() / cases.sum())
    return out


def print_pooled(title: str, figures: dict[str, dict]) -> None:
    print(f"\n### {title} (cross-fitted)")
    print("| stratum | pair-cases | symmetry MAE raw -> estimate | 90 % coverage (pairs) | per pair | "
          "decisive at 0.8 (agreement) | joint angles 90 % coverage |")  # fmt: skip
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for label, rows in figures.items():
        if not any(n in rows for n in SYMMETRY_NAMES):
            continue
        r = pooled(rows)
        pairs = " / ".join(f"{100 * c:.1f}" for c in r["coverage_pairs"])
        print(f"| {label} | {r['pair_cases']} | {r['mae_raw']:.1f} -> {r['mae_est']:.1f} | {100 * r['coverage']:.1f} % "
              f"| {pairs} | {100 * r['decisive']:.1f} % ({100 * r['agreement']:.1f} %) | "
              f"{100 * r['angles_coverage'][0]:.1f}-{100 * r['angles_coverage'][1]:.1f} % |")  # fmt: skip


def frame_probabilities(pairs: list[tuple[dict[str, MeasureModel], np.ndarray]], cases: dict[str, np.ndarray],
                        name: str, threshold: float) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """Per case `(n,)`, under the held-out model that covers it: P(truth > threshold) and the rank of the truth
    in the case's calibrated distribution (NaN: no calibrated value)."""
    from zedo_cli.analysis.uncertainty.clip_share import probability_above

    raw, truth = cases[f"{name}|raw"], cases[f"{name}|truth"]
    p, rank = np.full(len(raw), np.nan), np.full(len(raw), np.nan)
    for models, mask in pairs:
        sel = mask & np.isfinite(raw) & np.isfinite(truth)
        if sel.any() and name in models:  # a range without enough cases has no models
            p[sel] = probability_above(models[name], raw[sel], threshold)
            rank[sel] = 1.0 - probability_above(models[name], raw[sel], truth[sel])
    return p, rank


def share_figures(pairs: list[tuple[dict[str, MeasureModel], np.ndarray]], cases: dict[str, np.ndarray],
                  fold: np.ndarray, kind: np.ndarray, group: np.ndarray, threshold: float, fps: float,
                  level: float = 0.9, filled: list | None = None) -> dict[str, float]:  # fmt: skip
    """Clip-level shares asymmetric (analysis.uncertainty.clip_share) on held-out clips: per (clip, pair) the share's
    interval against the true share of the same frames; also the frames' probabilities' calibration and how long errors
    persist (the integrated autocorrelation time of the truth's ranks, seconds)."""
    from zedo_cli.analysis.uncertainty.clip_share import block_frames, integrated_autocorrelation, share_interval

    hits, widths, errors, persist, p_all, t_all, blocks = [], [], [], [], [], [], []
    clip = np.char.add(np.char.add(fold.astype(str), kind.astype(str)), group.astype(str))
    for n in SYMMETRY_NAMES:
        p, rank = frame_probabilities(pairs, cases, n, threshold)
        if filled:  # the frames with a joint the prior filled, under their own models
            fp, frank = frame_probabilities([(m, k) for m, k in filled if n in m], filled_view(cases), n, threshold)
            p, rank = np.where(np.isnan(p), fp, p), np.where(np.isnan(rank), frank, rank)
        for c in np.unique(clip[np.isfinite(p)]):
            sel = np.flatnonzero((clip == c) & np.isfinite(p))  # time order within a clip
            if len(sel) < 30:
                continue
            truth = cases[f"{n}|truth"][sel] > threshold
            block = block_frames(p[sel], fps)
            share = share_interval(p[sel], block, level, seed=len(hits))
            hits.append(share.low <= truth.mean() <= share.high)
            widths.append(share.high - share.low)
            errors.append(abs(share.value - truth.mean()))
            persist.append(integrated_autocorrelation(rank[sel]) / fps)
            blocks.append(block / fps)
            p_all.append(p[sel])
            t_all.append(truth)
    p_cat, t_cat = np.concatenate(p_all), np.concatenate(t_all)
    calib = []  # frames by their probability: the mean probability against the share truly asymmetric
    for lo, hi in ((0, 0.1), (0.1, 0.5), (0.5, 0.9), (0.9, 1.01)):
        sel = (p_cat >= lo) & (p_cat < hi)
        if sel.any():
            calib.append((lo, hi, int(sel.sum()), float(p_cat[sel].mean()), float(t_cat[sel].mean())))
    return {"clip_pairs": len(hits), "coverage": float(np.mean(hits)), "median_width": float(np.median(widths)),
            "mae": float(np.mean(errors)), "persistence_s_median": float(np.median(persist)),
            "persistence_s_p90": float(np.percentile(persist, 90)), "block_s_median": float(np.median(blocks)),
            "probability_bins": calib}  # fmt: skip


def covered_pairs(pairs: list, filled: list, cases: dict[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Per symmetry pair and case `(4, n)`: lifted (a value, with observed joints or a filled one), and given an
    interval by one of the held-out models."""
    lifted = np.stack([np.isfinite(cases[f"{n}|raw"]) | np.isfinite(cases[f"{n}|filled_raw"]) for n in SYMMETRY_NAMES])
    covered = np.zeros_like(lifted)
    for k, n in enumerate(SYMMETRY_NAMES):
        for models, mask in pairs:
            covered[k] |= mask & np.isfinite(cases[f"{n}|raw"]) & (n in models)
        for models, mask in filled:
            covered[k] |= mask & np.isfinite(cases[f"{n}|filled_raw"]) & (n in models)
    return lifted, covered


def interval_share(pairs: list, filled: list, cases: dict[str, np.ndarray], among: np.ndarray | None = None
                   ) -> tuple[float, int]:  # fmt: skip
    """The share of the lifted symmetry frame-pairs (of the cases `among`, default all) that get an interval
    (observed joints or filled ones), and how many frame-pairs were lifted."""
    lifted, covered = covered_pairs(pairs, filled, cases)
    if among is not None:
        lifted = lifted & among
    return float(covered[lifted].mean()), int(lifted.sum())


def missing_intervals(pairs: list, filled: list, cases: dict[str, np.ndarray]) -> dict[str, int]:
    """The lifted symmetry frame-pairs without an interval, counted by why: lifted nearer or further than
    DEPTH_EDGES, or a joint the prior filled where no model of such cases was fitted (`MIN_FILLED`)."""
    lifted, covered = covered_pairs(pairs, filled, cases)
    missing = lifted & ~covered
    depth = np.broadcast_to(cases["lifted_depth"], missing.shape)
    with_filled = np.stack([np.isfinite(cases[f"{n}|filled_raw"]) for n in SYMMETRY_NAMES])
    near, far = missing & (depth < DEPTH_EDGES[0]), missing & (depth > DEPTH_EDGES[-1])
    return {f"lifted nearer than {DEPTH_EDGES[0]:g} m": int(near.sum()),
            f"lifted further than {DEPTH_EDGES[-1]:g} m": int(far.sum()),
            "a filled joint, no model of such cases": int((missing & ~near & ~far & with_filled).sum()),
            "other": int((missing & ~near & ~far & ~with_filled).sum())}  # fmt: skip


def camera_calibrations(args: argparse.Namespace, shipped: Any, settings: dict[str, Any]) -> list[MeasureCalibration]:
    """The calibrations of known cameras (one per mode and depth range) and their held-out figures per camera kind."""
    folder = args.cases / "cameras"
    fps = CAMERA_CLIPS["fps"]
    out = []
    report: dict[str, Any] = {}
    for mode in (m for m in MODES if any(folder.glob(f"fold*-intrinsics-{m}-*.npz"))):
        cases, fold, kind, group = load_cases(folder, f"intrinsics-{mode}")
        held, final = camera_fits(cases, fold, kind, group, mode)
        adult = bool(np.isin(kind, f"clips_{ADULT_SOURCE}").any())
        pairs = apply_held_out(held, cases, fold, same=True)
        filled = apply_held_out(held, cases, fold, same=True, filled=True)
        depth = cases["lifted_depth"]
        inside = depth_bin(depth) >= 0
        print(f"\n## mode {mode}: {int((~inside).sum())} of {len(depth)} cases lifted outside {DEPTH_EDGES[0]:g}-"
              f"{DEPTH_EDGES[-1]:g} m (no interval)")  # fmt: skip
        strata = {"input": kind, "source": source_of(kind), "focal": bin_labels(cases["focal"], FOCAL_EDGES, "px"),
                  "depth": bin_labels(depth, DEPTH_EDGES_REPORT, "m"),
                  "size": bin_labels(cases["size_px"], SIZE_EDGES, "px")}  # fmt: skip
        figures = {by: scored(pairs, cases, labels, args.threshold) for by, labels in strata.items()}
        figures["filled joint"] = scored(filled, filled_view(cases), kind, args.threshold)
        for by, f in figures.items():
            print_pooled(f"known intrinsics, {mode}, by {by}", f)
        report[mode] = {by: {k: pooled(v) for k, v in f.items()} for by, f in figures.items()}
        by_source = camera_by_source(cases, fold, kind, group, mode, args.threshold, fps) if adult else {}
        report[f"{mode}_held_out_by_source"] = by_source
        base = np.isin(kind, CAMERA_FITS[mode])  # the near draws cover only the near range: left out here
        report[mode]["interval_share"], report[mode]["lifted_pairs"] = interval_share(pairs, filled, cases, base)
        clips = np.char.startswith(kind.astype(str), "clips")
        if clips.any():
            sh = share_figures([(m, k & clips) for m, k in pairs], cases, fold, kind, group, args.threshold, fps,
                               filled=[(m, k & clips) for m, k in filled])  # fmt: skip
            print(f"clip shares asymmetric, known intrinsics, {mode}:", sh)
            report[mode]["shares"] = sh
        if mode == "smooth":  # the target set-up: f = 1000 px, about 1 m away
            ext, efold, ekind, egroup = load_cases(folder, "f1000-smooth")
            epairs = apply_held_out(held, ext, efold, same=False)
            efilled = apply_held_out(held, ext, efold, same=False, filled=True)
            f1000 = scored(epairs, ext, ekind, args.threshold)
            print_pooled("f = 1000 px, 0.9-1.1 m, smooth clips", f1000)
            report["f1000"] = {k: pooled(v) for k, v in f1000.items()}
            f1000_filled = scored(efilled, filled_view(ext), ekind, args.threshold)
            print_pooled("f = 1000 px, 0.9-1.1 m, smooth clips, frame-pairs with a filled joint", f1000_filled)
            report["f1000"]["filled joint"] = {k: pooled(v) for k, v in f1000_filled.items()}
            share, lifted = interval_share(epairs, efilled, ext)
            report["f1000"]["interval_share"], report["f1000"]["lifted_pairs"] = share, lifted
            report["f1000"]["missing"] = missing_intervals(epairs, efilled, ext)
            print(f"f1000: {100 * share:.1f} % of the {lifted} lifted frame-pairs have an interval; without one:",
                  report["f1000"]["missing"])  # fmt: skip
            # by the range that holds the pose: at about 1 m, a pose lifted under NEAR_BELOW_M is lifted too near
            near = np.where(ext["lifted_depth"] < NEAR_BELOW_M, f"under {NEAR_BELOW_M:g} m", f"{NEAR_BELOW_M:g} m +")
            for title, fig in (
                ("", scored(epairs, ext, near, args.threshold)),
                (", a filled joint", scored(efilled, filled_view(ext), near, args.threshold)),
            ):
                print_pooled(f"f = 1000 px, smooth clips{title}, by the range of the lifted root depth", fig)
                report["f1000"]["by range" + title] = {k: pooled(v) for k, v in fig.items()}
            report["f1000"]["shares"] = share_figures(epairs, ext, efold, ekind, egroup, args.threshold, fps,
                                                      filled=efilled)  # fmt: skip
            print("clip shares asymmetric, f1000:", report["f1000"]["shares"])
        for r, (models, filled_models) in enumerate(zip(final.models, final.filled, strict=True)):
            focal = cases["focal"][np.isin(kind, CAMERA_FITS[mode])]
            domain = CameraDomain((DEPTH_EDGES[r], DEPTH_EDGES[r + 1]), (float(focal.min()), float(focal.max())))
            fitted = final.cases[r]
            near = DEPTH_EDGES[r + 1] <= NEAR_BELOW_M
            # The provenance names scripts by their paths in the flat benchmarks/ that wrote the shipped file: kept, so
            # that a rerun writes the same file (benchmarks/README.md maps them to today's paths).
            provenance = {
                "data": "SyRIP training poses held out of fold priors (benchmarks/folds.py), seen by drawn known "
                f"cameras (focal {CAMERAS.focal_px[0]:g}-{CAMERAS.focal_px[1]:g} px, root depth "
                f"{CAMERAS.depth_m[0]:g}-{CAMERAS.depth_m[1]:g} m"
                + (f", and more at {NEAR.depth_m[0]:g}-{NEAR.depth_m[1]:g} m for the poses lifted nearer than "
                   f"{NEAR_BELOW_M:g} m" if near else "")
                + ", 1280x720 and 1920x1080), from their projected GT "
                "2D and with their own FiDIP error, " + ("as images and synthetic 30 fps clips lifted frame by frame"
                                                        if mode == "none" else "as synthetic 30 fps clips")
                + "; never Test100 or the synthetic rows"
                + ("; and the adult motion made infant-like (benchmarks/lib/adult_cases.py: "
                   f"{ADULT_CAMERA_CLIPS['count']} clips of {ADULT_CAMERA_CLIPS['seconds']:g} s a fold, 3 px jitter) "
                   "before the clinic cameras and two 2.5-3.5 m away (zedo_cli/evaluation/clips/cameras.py)"
                   if adult else ""),
                "recipe": "benchmarks/calibrate_measures.py --cameras",
                "folds": sorted(int(f) for f in np.unique(fold)),
                "sources": sorted({str(x) for x in source_of(kind[fitted])}),
                "cases": int((fitted & np.isfinite(cases["symmetry_thigh_deg|raw"])).sum()),
                "cases_filled": int((fitted & np.isfinite(cases["symmetry_thigh_deg|filled_raw"])).sum()),
                "bins": BINS[mode],
                "bins_filled": FILLED_BINS,
                "cameras": {"focal_px": list(CAMERAS.focal_px), "depth_m": list(CAMERAS.depth_m),
                            "frames": [list(f) for f in CAMERAS.frames], "draws": CAMERA_DRAWS,
                            **({"near": {"depth_m": list(NEAR.depth_m), "draws": NEAR_DRAWS,
                                         "clips": NEAR_CLIP_COUNT}} if near else {})},
                "clips": CAMERA_CLIPS,
                "cross_fitted": report[mode],
                "held_out_by_source": by_source,
                "held_out_by_source_coverage_90": {s: r["families"] for s, r in by_source.items()},
            }  # fmt: skip
            out.append(MeasureCalibration(shipped.sha256, settings, mode, ("cli", "file"), shipped.skeleton.joints,
                                          models, provenance, domain, filled_models))  # fmt: skip
    report["pseudo"] = pseudo_share_figures(args)
    args.camera_report = report
    return out


def camera_by_source(cases: dict[str, np.ndarray], fold: np.ndarray, kind: np.ndarray, group: np.ndarray, mode: str,
                     threshold: float, fps: float) -> dict[str, Any]:  # fmt: skip
    """Each source's cases scored by models fitted on the other source's only (per depth range as shipped): pooled
    symmetry and joint-angle figures, per depth and focal bin, and the clip shares asymmetric."""
    every = range_cases(cases["lifted_depth"], kind, mode)
    src = source_of(kind)
    out: dict[str, Any] = {}
    for s in np.unique(src):
        pairs = [(fit_all(cases, m & (src != s), BINS[mode]), m & (src == s)) for m in every]
        filled = [(fit_filled(cases, m & (src != s)), m & (src == s)) for m in every]
        rows = scored(pairs, cases, np.full(len(kind), s), threshold)[s]
        row = {"all": pooled(rows), "families": family_coverage(rows)}
        for by, labels in (("depth", bin_labels(cases["lifted_depth"], DEPTH_EDGES_REPORT, "m")),
                           ("focal", bin_labels(cases["focal"], FOCAL_EDGES, "px"))):  # fmt: skip
            row[by] = {k: pooled(v) for k, v in scored(pairs, cases, labels, threshold).items()
                       if any(n in v for n in SYMMETRY_NAMES)}  # fmt: skip
        clips = np.char.startswith(kind.astype(str), "clips")
        row["shares"] = share_figures([(m, k & clips) for m, k in pairs], cases, fold, kind, group, threshold, fps,
                                      filled=[(m, k & clips) for m, k in filled])  # fmt: skip
        out[str(s)] = row
        print_by_source(f"known intrinsics, {mode}", str(s), row)
    return out


def print_by_source(title: str, source: str, row: dict[str, Any]) -> None:
    r = row["all"]
    print(f"\n{title}, {source} left out (fitted on the other sources): symmetry 90 % coverage "
          f"{100 * r['coverage']:.1f} % (pairs {' / '.join(f'{100 * c:.1f}' for c in r['coverage_pairs'])}), decisive "
          f"at 0.8 {100 * r['decisive']:.1f} % ({100 * r['agreement']:.1f} %), joint angles "
          f"{100 * r['angles_coverage'][0]:.1f}-{100 * r['angles_coverage'][1]:.1f} %, MAE {r['mae_raw']:.1f} -> "
          f"{r['mae_est']:.1f}; clip shares: {100 * row['shares']['coverage']:.1f} % of "
          f"{row['shares']['clip_pairs']} (clip, pair), median width {row['shares']['median_width']:.2f}")  # fmt: skip
    for by in ("depth", "focal"):
        for label, b in row.get(by, {}).items():
            print(f"  {by} {label}: {b['pair_cases']} pair-cases, coverage {100 * b['coverage']:.1f} %, joint angles "
                  f"{100 * b['angles_coverage'][0]:.1f}-{100 * b['angles_coverage'][1]:.1f} %")  # fmt: skip


def difficulty_coverage(held: HeldOutModels, cases: dict[str, np.ndarray], kind: np.ndarray, threshold: float
                        ) -> dict[str, dict[str, float]]:  # fmt: skip
    """Cross-fitted (`held`, `cross_fitted_models`) coverage of the 90 % intervals per source and tercile of the
    lift's difficulty (its mean reprojection error; `difficulty_terciles`), by family; printed as a table."""
    figures = scored(held, cases, difficulty_terciles(cases, kind), threshold)
    out = {label: family_coverage(rows) for label, rows in sorted(figures.items())}
    print("\n| source, tercile of the reprojection error | all | symmetry | joint angles |\n| --- | --- | --- | --- |")
    for label, cov in out.items():
        print(f"| {label} | " + " | ".join(f"{100 * cov.get(f, np.nan):.1f} %" for f in ("all", "symmetry",
              "joint_angles")) + " |")  # fmt: skip
    return out


def pseudo_by_source(cases: dict[str, np.ndarray], fold: np.ndarray, kind: np.ndarray, group: np.ndarray, mode: str,
                     threshold: float) -> dict[str, Any]:  # fmt: skip
    """The pseudo camera's calibration of `mode` held out by source: each source's cases scored by a fit on the
    other's, pooled figures and (clips) the clip shares asymmetric."""
    src = source_of(kind)
    out: dict[str, Any] = {}
    for s in np.unique(src):
        pairs = [(fit_all(cases, src != s, BINS[mode]), src == s)]
        rows = scored(pairs, cases, np.full(len(kind), s), threshold)[s]
        row: dict[str, Any] = {"all": pooled(rows), "families": family_coverage(rows)}
        no_shares = {"coverage": float("nan"), "clip_pairs": 0, "median_width": 0.0}  # images are no clips
        fps = float(CLIP_SETTINGS["fps"])
        row["shares"] = share_figures(pairs, cases, fold, kind, group, threshold, fps) if mode != "none" else no_shares
        out[str(s)] = row
        print_by_source(f"pseudo camera, {mode}", str(s), row)
    return out


def pseudo_share_figures(args: argparse.Namespace) -> dict[str, Any]:
    """Clip shares on the pseudo camera: the recipe's smooth clips and the camera clips lifted frame by frame,
    under the pseudo calibrations cross-fitted as the recipe fits them."""
    out = {}
    fps = CLIP_SETTINGS["fps"]
    images, ifold, ikind, igroup = load_cases(args.cases, "none")
    clips, cfold, ckind, cgroup = load_cases(args.cases, "smooth")
    held = cross_fitted_models(clips, cfold, cgroup, BINS["smooth"])
    out["smooth"] = share_figures(held, clips, cfold, ckind, cgroup, args.threshold, fps)
    ext, efold, ekind, egroup = load_cases(args.cases / "cameras", "pseudo-none")
    folds = np.unique(ifold)
    pairs = []
    for fit, ev in splits(ifold, igroup):
        models = fit_all(images, fit, BINS["none"])
        pairs.append((models, efold == ifold[ev][0] if len(folds) > 1 else np.full(len(efold), not pairs)))
    out["none"] = share_figures(pairs, ext, efold, ekind, egroup, args.threshold, fps)
    out["none_frames"] = {k: pooled(v) for k, v in scored(pairs, ext, ekind, args.threshold).items()}
    print("clip shares asymmetric, pseudo camera:", out)
    return out


def replace_calibrations(old: list[MeasureCalibration], new: list[MeasureCalibration]) -> list[MeasureCalibration]:
    """`old` with every calibration of the same prior, mode, cameras and scope as one of `new` (whatever its range
    of cameras) replaced by `new`, in the place of the first replaced; the others stay as they are, in their order."""

    def key(c: MeasureCalibration) -> tuple:
        return c.prior_sha256, c.temporal_mode, c.cameras, c.scope

    if not new:
        return list(old)
    replaced = {key(c) for c in new}
    out: list[MeasureCalibration] = []
    for c in old:
        if key(c) not in replaced:
            out.append(c)
        elif not any(n is new[0] for n in out):
            out += new
    return out if any(n is new[0] for n in out) else out + new


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--syrip-dir", required=True)
    ap.add_argument("--folds", type=Path, required=True)
    ap.add_argument("--weights", default="", help="suffix of the fold priors' files (fold<k><weights>.safetensors)")
    ap.add_argument("--cases", type=Path, required=True)
    ap.add_argument("--lift", action="store_true", help="lift the held-out cases first")
    ap.add_argument("--cameras", action="store_true",
                    help="the calibrations of known intrinsics (CAMERAS) instead of the pseudo camera's")  # fmt: skip
    ap.add_argument("--lift-only", action="store_true", help="lift the held-out cases, then stop")
    ap.add_argument("--camera-kinds", nargs="+", choices=("base", "near"), default=["base", "near"],
                    help="--cameras --lift: the CAMERAS, F1000 and pseudo cases (base), NEAR's (near)")  # fmt: skip
    ap.add_argument("--fold-ids", type=int, nargs="+", default=None, help="--lift: these folds only (default all)")
    ap.add_argument("--temporal-modes", nargs="+", choices=MODES, default=list(MODES),
                    help="--lift: the temporal modes lifted (frame by frame, smooth, clip)")  # fmt: skip
    ap.add_argument(
        "--sources",
        nargs="+",
        choices=SOURCES,
        default=list(SOURCES),
        help="--lift: the clip sources lifted (SyRIP poses; the adult motion made infant-like)",
    )
    ap.add_argument("--syrip-clips", choices=PLACINGS, default="photo",
                    help="--lift: the SyRIP clips' key poses turned chest to the camera, swaying (supine), or each in "
                    "its photo's orientation, tumbling (photo)")  # fmt: skip
    ap.add_argument("--adult-captures", action="store_true",
                    help="--lift: the adult motion as two sources, Bandai-Namco and CMU with DeepMimic "
                    "(ADULT_CAPTURES, for the table with a source left out; pseudo camera)")  # fmt: skip
    ap.add_argument("--write", action="store_true", help="write the calibrations for the shipped prior")
    ap.add_argument("--out", type=Path, default=None, help="calibration file (default: the package's)")
    ap.add_argument("--threshold", type=float, default=DEFAULT_THRESHOLD_DEG)
    ap.add_argument("--report", type=Path, default=None, help="--cameras: the held-out figures as JSON")
    args = ap.parse_args()
    if args.lift or args.lift_only:
        (lift_camera_cases if args.cameras else lift_cases)(args)
    if args.lift_only:
        return 0
    from zedo_cli.lifting.config import DEFAULT_PRESET, calibration_settings, get_preset
    from zedo_cli.prior.weights import load_prior, resolve_prior_path

    shipped = load_prior(resolve_prior_path(None))
    settings = calibration_settings(get_preset(DEFAULT_PRESET))
    calibrations = camera_calibrations(args, shipped, settings) if args.cameras else []
    for mode in () if args.cameras else (m for m in MODES if any(args.cases.glob(f"fold*-{m}-*.npz"))):
        cases, fold, kind, group = load_cases(args.cases, mode)
        bins = BINS[mode]
        held = cross_fitted_models(cases, fold, group, bins)  # fitted once for every held-out figure below
        figures = scored(held, cases, kind, args.threshold)
        print_table(figures, mode)
        held_filled = [(fit_filled(cases, fit), evaluate) for fit, evaluate in splits(fold, group)]
        figures_filled = scored(held_filled, filled_view(cases), source_of(kind), args.threshold)
        if figures_filled:
            print_pooled(f"pseudo camera, {mode}, frame-pairs with a filled joint, per source", figures_filled)
        sources = sorted({str(x) for x in source_of(kind)})
        by_difficulty = difficulty_coverage(held, cases, kind, args.threshold)
        by_source = pseudo_by_source(cases, fold, kind, group, mode, args.threshold) if len(sources) > 1 else {}
        if mode != "none":
            figures["clip_medians"] = clip_median_coverage(held, cases, kind, group)
            print("\nclip medians inside the median of the frames' 90 % interval ends:", figures["clip_medians"])
        models = fit_all(cases, np.ones(len(fold), bool), bins)
        filled_models = fit_filled(cases, np.ones(len(fold), bool))
        # The provenance names scripts by their paths in the flat benchmarks/ that wrote the shipped file: kept, so
        # that a rerun writes the same file (benchmarks/README.md maps them to today's paths).
        provenance = {
            "data": "SyRIP training poses held out of fold priors (benchmarks/folds.py), GT and FiDIP 2D"
            + (", as synthetic 30 fps clips" if mode != "none" else "")
            + "; never Test100 or the synthetic rows"
            + (
                f"; and the adult motion made infant-like (benchmarks/lib/adult_cases.py: {ADULT_CLIPS['count']} clips "
                f"of {ADULT_CLIPS['seconds']:g} s a fold, 3 px jitter"
                + (f", every {ADULT_IMAGE_STRIDE}th frame lifted frame by frame" if mode == "none" else "")
                + ")"
                if by_source
                else ""
            ),
            "recipe": "benchmarks/calibrate_measures.py",
            "folds": sorted(int(f) for f in np.unique(fold)),
            "sources": sources,
            "cases": int(len(fold)),
            "cases_filled": int(np.isfinite(cases["symmetry_thigh_deg|filled_raw"]).sum()),
            "bins": bins,
            "bins_filled": FILLED_BINS,
            "clips": CLIP_SETTINGS if mode != "none" else None,
            "cross_fitted": {
                kd: {n: {k: round(v, 4) for k, v in r.items()} for n, r in rows.items()} for kd, rows in figures.items()
            },  # fmt: skip
            "held_out_by_source": by_source,
            "held_out_by_source_coverage_90": {s: r["families"] for s, r in by_source.items()},
            "cross_fitted_by_difficulty_coverage_90": by_difficulty,
            "cross_fitted_filled_joint": {s: pooled(rows) for s, rows in figures_filled.items()},
        }
        calibrations.append(MeasureCalibration(shipped.sha256, settings, mode, ("pseudo",), shipped.skeleton.joints,
                                               models, provenance, None, filled_models))  # fmt: skip
    if args.report is not None and args.cameras:
        args.report.write_text(json.dumps(args.camera_report, indent=1, default=float) + "\n")
    if args.write:
        out = args.out or bundled_path()

        old = read_calibrations(out) if out.exists() else []
        merged = replace_calibrations(old, calibrations)
        write_calibrations(out, merged)
        print(f"\nwrote {out}: {len(merged)} calibrations")
    else:
        first = {c.temporal_mode: list(c.measures.items())[:2] for c in calibrations}
        print(json.dumps({mode: {n: MeasureModelEntry.of(m).model_dump() for n, m in models}
                          for mode, models in first.items()}, indent=1))  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
