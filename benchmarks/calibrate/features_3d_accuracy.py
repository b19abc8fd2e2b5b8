"""How close the `3d_` clip features of lifted clips and the published 2D features come to the 3D truth
(elbow and knee `mean_angle` and `median_vel_angle`), and the `3d_` features' clip calibrations (`--cases`).

For every fold prior `fold<k><weights>.safetensors` in `--folds` (benchmarks/lib/folds.py), the fold's 150
held-out SyRIP training poses make synthetic clips (zedo_cli/evaluation/clips/eased.py's generator with
settings.CLIP_SETTINGS: 16 clips of 5 s at 30 fps, eased between 6 key poses, turning and
drifting, 1 m from the pseudo camera, 3 px noise, 3 % of joints dropped, a 3-frame gap), whose 2D is
lifted with the default preset in `--temporal smooth` as calibrate_measures.py lifts them. Per clip:

- truth: `features_3d` of the clip's true 3D joints (the same smoothing and statistics);
- 3D: `features_3d` of the lifted poses (`3d_mean_angle_<L|R><Elbow|Knee>`, `3d_median_vel_angle_...`);
- 2D: `published_features` of the clip's 2D (`mean_angle_...`, `median_vel_angle_...`, the interior angle
  in the image, the same convention as the 3D one).

It prints the mean absolute error against the truth over (clip, side) of each, per fold and pooled, and the
ratio 3D / 2D (target: at most 0.5). Test100 and SyRIP's synthetic rows are never read.

    python benchmarks/calibrate/features_3d_accuracy.py --syrip-dir ../shared/data/syrip --folds folds/

With `--cases DIR` it makes the `3d_` features' clip calibrations instead: `--lift [--adult]` lifts each fold's
clip cases (the fold's held-out poses under two motions, and with `--adult` the adult motion made infant-like, a
second source), then it prints the coverage of the 90 % intervals cross-fitted over folds, per source, with each
source held out of the fit, and per kind of camera; `--write` fits on every case and writes the entry of the
shipped prior into measures.json (docs/movement.md, "Calibrated estimates and 90 % intervals").
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # the repository root
from benchmarks.lib.adult_cases import ADULT_SOURCE, ADULT_SOURCE_NAMES, adult_case_clips, adult_sources
from benchmarks.lib.pose_sources import PLACINGS, placed_poses
from zedo_cli.analysis.clip.features_3d import features_3d
from zedo_cli.analysis.clip.published_features import published_features
from zedo_cli.data.skeleton import get_skeleton

SKELETON = get_skeleton("syrip12")
FEATURES = ("mean_angle", "median_vel_angle")
JOINTS = ("LElbow", "RElbow", "LKnee", "RKnee")


def clip_errors(xy: np.ndarray, lifted: np.ndarray, truth: np.ndarray, fps: float, size: np.ndarray) -> dict:
    """Per feature and joint of one clip: |3D - truth| and |2D - truth| (degrees, deg/s)."""
    true = features_3d(truth, SKELETON, fps).values
    ours = features_3d(lifted, SKELETON, fps).values
    flat = published_features(xy, SKELETON, fps, size).values
    out = {}
    for f in FEATURES:
        for j in JOINTS:
            t = true[f"3d_{f}_{j}"]
            out[(f, j)] = (abs(ours[f"3d_{f}_{j}"] - t), abs(flat[f"{f}_{j}"] - t))
    return out


# the calibration's clips (--cases): more and longer clips than the accuracy table's, for split conformal
CASE_CLIPS = {"count": 56, "keyposes": 15}  # 56 clips of 14 s a fold
# ... lifted under both motion models between key poses (temporal.make_sequences' `interpolation`): eased
# joint positions (bones shorten while they turn) and turned segments (bones keep their length), so that
# the intervals hold under either, not only under the one they were fitted on
CASE_MOTIONS = ("positions", "segments")


# --cameras: the clips seen by known cameras instead (calibrate_measures.CAMERAS: focal lengths 600-2500 px, the
# infant 0.5-2.2 m away, 1280x720 or 1920x1080 frames), with the frame calibrations' jitter (CAMERA_CLIPS: 1.25 %
# of the body's 2D size instead of 3 px), lifted with their K as `zedo lift --focal / --intrinsics` does. The
# calibration holds for clips whose lifted root depth (the clip's median) and focal length lie in the ranges of its
# cases (`camera_domain`): the root depth within CAMERA_DEPTH_M.
CAMERA_NOISE = {"noise_px": 0.0, "noise_rel": 0.0125}
CAMERA_DEPTH_M = (0.4, 3.5)


def camera_domain(cases: dict[int, dict[str, np.ndarray]]) -> Any:
    """The CameraDomain of the known cameras' cases: from CAMERA_DEPTH_M's near end to their furthest lifted root
    depth (to 0.1 m, at most CAMERA_DEPTH_M's far end), and their focal lengths' range."""
    from zedo_cli.analysis.uncertainty.calibration import CameraDomain

    depth = np.concatenate([c["depth_m"] for c in cases.values()])
    focal = np.concatenate([c["focal_px"] for c in cases.values()])
    far = min(CAMERA_DEPTH_M[1], float(np.ceil(np.nanmax(depth) * 10) / 10))
    return CameraDomain((CAMERA_DEPTH_M[0], far), (float(np.floor(focal.min())), float(np.ceil(focal.max()))))


def lift_clip_cases(args: argparse.Namespace) -> None:
    """Per fold prior and clip source: CASE_CLIPS clips lifted by the fold's prior (the default preset, `--temporal`
    smooth or none): the fold's held-out SyRIP poses under each motion of CASE_MOTIONS, and with `--adult` as many
    clips of the adult motion made infant-like (`adult_case_clips`). Per clip every `3d_` feature of the lifted poses
    (`raw`) and of the true 3D (`truth`), the published 2D features (`flat`), and the clip's median lifted root depth
    and its focal length (`depth_m`, `focal_px`). One npz a fold and source in `--cases`
    (`fold<k>-3d-clips-<motion>.npz`, the motion `adult` for the adult source; other cameras and modes in its
    folders, `case_folder`)."""
    import torch

    from benchmarks.lib.folds import fold_priors
    from benchmarks.lib.settings import CAMERAS, CLIP_SETTINGS, place_camera
    from zedo_cli.evaluation.clips.eased import make_sequences

    folder = case_folder(args)
    folder.mkdir(parents=True, exist_ok=True)
    settings = {**CLIP_SETTINGS, **CASE_CLIPS, **(CAMERA_NOISE if args.cameras else {})}
    place = (lambda rng, rel, drift: place_camera(rng, rel, drift, CAMERAS)) if args.cameras else None
    for k, prior, truth, _ in fold_priors(args.folds, args.weights, args.syrip_dir):
        poses, sway = placed_poses(truth.poses, args.syrip_clips)
        for motion in CASE_MOTIONS:
            torch.manual_seed(k)
            seed = (700 if args.cameras else 300) + k
            clips = make_sequences(poses, np.random.default_rng(seed), **settings, place=place, interpolation=motion,
                                   sway=sway)  # fmt: skip
            save_case(folder / f"fold{k}-3d-clips-{motion}.npz", clips, prior, args.temporal)
        for name, files in adult_sources(args.adult_captures) if args.adult else ():
            torch.manual_seed(k)
            seconds = (CASE_CLIPS["keyposes"] - 1) * float(CLIP_SETTINGS["transition_s"])
            clips = adult_case_clips(args.syrip_dir, (1100 if args.cameras else 900) + k, args.cameras,
                                     CASE_CLIPS["count"], seconds, files)  # fmt: skip
            save_case(folder / f"fold{k}-3d-clips-{name}.npz", clips, prior, args.temporal)


def save_case(path: Path, clips: dict[str, np.ndarray], prior: Any, temporal: str) -> None:
    """Lift `clips` (make_sequences' arrays) with `prior` and write each clip's features (`lift_clip_cases`)."""
    from benchmarks.lib.settings import CLIP_SETTINGS
    from zedo_cli.lifting.config import DEFAULT_PRESET, get_preset
    from zedo_cli.lifting.temporal import lift_sequence

    fps = float(CLIP_SETTINGS["fps"])
    res = lift_sequence(clips["xy"], clips["conf"], clips["k"], prior, get_preset(DEFAULT_PRESET), mode=temporal,
                        tracks=clips["tracks"], fps=fps)  # fmt: skip
    lifted = np.where(res.lifted[:, None, None], res.poses_root_relative, np.nan)  # (N, J, 3)
    depth = np.where(res.lifted, res.root_translation[:, 2], np.nan)
    raw, true, flat, depths, focals = [], [], [], [], []
    for track in np.unique(clips["tracks"]):
        at = clips["tracks"] == track
        first = np.flatnonzero(at)[0]
        size = 2.0 * clips["k"][first, :2, 2]  # principal point at the frame's centre, the pseudo camera's too
        raw.append(features_3d(lifted[at], SKELETON, fps).values)
        true.append(features_3d(clips["rel"][at], SKELETON, fps).values)
        flat.append(published_features(clips["xy"][at], SKELETON, fps, size).values)
        depths.append(np.nanmedian(depth[at]))
        focals.append(clips["k"][first, 0, 0])
    names = sorted(raw[0])
    flat_names = sorted(flat[0])
    np.savez(path, names=np.array(names), flat_names=np.array(flat_names),
             raw=np.array([[r[n] for n in names] for r in raw]),
             truth=np.array([[t[n] for n in names] for t in true]),
             flat=np.array([[f[n] for n in flat_names] for f in flat]), fps=fps,
             depth_m=np.array(depths), focal_px=np.array(focals))  # fmt: skip
    print(f"{path.name}: {len(raw)} clips of {int(at.sum())} frames, {int(res.lifted.sum())}/{len(res.lifted)} "
          "frames lifted", flush=True)  # fmt: skip


def case_folder(args: argparse.Namespace) -> Path:
    """Where the clip cases are: `--cases` (the pseudo camera, `--temporal smooth`), else its folder `cameras`,
    `frames`, `clip` or `cameras-frames`, `cameras-clip` (known cameras, `--temporal none` or `clip`, both)."""
    mode = {"none": ["frames"], "clip": ["clip"]}.get(args.temporal, [])
    name = "-".join((["cameras"] if args.cameras else []) + mode)
    return args.cases / name if name else args.cases


BINS = 2  # bins of the measured value per feature (56 clips a fold)
MIN_PER_BIN = 20  # the 95 % conformal quantile (each end of the 90 % interval) needs 19 cases a bin


def load_clip_cases(folder: Path) -> dict[int, dict[str, np.ndarray]]:
    """Per fold, its clips of every motion (`motion (C,)` names each clip's) in one set of arrays."""
    out: dict[int, dict[str, np.ndarray]] = {}
    for path in sorted(folder.glob("fold*-3d-clips-*.npz")):
        fold, motion = int(path.name[4 : path.name.index("-")]), path.stem.rsplit("-", 1)[1]
        with np.load(path) as z:
            case = {k: z[k] for k in z.files} | {"motion": np.full(len(z["raw"]), motion)}
        if fold in out:
            case = {k: np.concatenate([out[fold][k], v]) if k in PER_CLIP else v for k, v in case.items()}
        out[fold] = case
    return out


PER_CLIP = ("raw", "truth", "flat", "motion", "depth_m", "focal_px")  # the arrays with a row a clip


def inside_domain(cases: dict[int, dict[str, np.ndarray]]) -> dict[int, dict[str, np.ndarray]]:
    """The known cameras' clips whose median lifted root depth lies in CAMERA_DEPTH_M (the others are left out of
    the fit and the figures, as `zedo analyze` leaves such clips uncalibrated)."""
    out = {}
    for fold, case in cases.items():
        keep = (case["depth_m"] >= CAMERA_DEPTH_M[0]) & (case["depth_m"] <= CAMERA_DEPTH_M[1])
        out[fold] = {k: v[keep] if k in PER_CLIP else v for k, v in case.items()}
        print(f"fold {fold}: {int(keep.sum())} of {len(keep)} camera clips lifted {CAMERA_DEPTH_M[0]:g}-"
              f"{CAMERA_DEPTH_M[1]:g} m from the camera")  # fmt: skip
    return out


def family(name: str) -> str:
    """`3d_mean_angle_LKnee` -> `mean_angle`; `3d_lrCorr_angle_Knee` -> `lrCorr_angle`."""
    return name.removeprefix("3d_").rsplit("_", 1)[0]


# --shrinkage: `none` (the default) keeps the measured value (weight 1) and fits only the intervals; `fitted` shrinks
# each estimate towards the calibration truths' median by the weight of least error (calibration.WEIGHT_GRID), which
# pulls a clip of another source towards the calibration clips' values
SHRINKAGE = {"fitted": None, "none": (1.0,)}


def fit_features(raw: np.ndarray, truth: np.ndarray, names: np.ndarray, shrinkage: str = "none") -> dict[str, Any]:
    """Per feature, a MeasureModel fitted on clips `raw, truth (C, F)` (fewer bins where few clips have it)."""
    from zedo_cli.analysis.uncertainty.calibration import WEIGHT_GRID, fit_measure

    weights = SHRINKAGE[shrinkage] or WEIGHT_GRID

    models = {}
    for i, n in enumerate(names):
        ok = int((np.isfinite(raw[:, i]) & np.isfinite(truth[:, i])).sum())
        if ok >= MIN_PER_BIN:
            bins = max(1, min(BINS, ok // MIN_PER_BIN))
            models[str(n)] = fit_measure(raw[:, i], truth[:, i], circular=False, bins=bins, weights=weights)
    return models


def score(models: dict[str, Any], case: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """Held-out clips `case`: per feature the calibrated estimate, the 90 % interval's hits and widths (NaN: no
    case)."""
    from zedo_cli.analysis.clip.clip_features import feature_range

    est = np.full(case["raw"].shape, np.nan)
    hit = np.full(case["raw"].shape, np.nan)
    width = np.full(case["raw"].shape, np.nan)
    for i, n in enumerate(case["names"]):
        m, v, t = models.get(str(n)), case["raw"][:, i], case["truth"][:, i]
        ok = np.isfinite(v) & np.isfinite(t)
        if m is None or not ok.any():
            continue
        lo_r, hi_r = feature_range(str(n))
        e = m.estimate(v[ok])
        low, high = (np.clip(x, lo_r, hi_r) for x in m.interval(e, v[ok], 0.9))
        est[ok, i] = np.clip(e, lo_r, hi_r)
        hit[ok, i] = (t[ok] >= low) & (t[ok] <= high)
        width[ok, i] = high - low
    return {"est": est, "hit": hit, "width": width}


def calibrate(args: argparse.Namespace) -> int:
    """Cross-fitted figures on the clip cases of `--cases`, and with `--write` the calibration of the shipped prior."""
    cases = load_clip_cases(case_folder(args))
    if len(cases) < 2:
        print(f"need the clip cases of two folds in {case_folder(args)} (--lift)", file=sys.stderr)
        return 1
    if args.cameras:
        cases = inside_domain(cases)
    names = cases[min(cases)]["names"]
    hits, hit_motion, mae, motions, clip_hits = {}, {}, {}, [], []
    fit_on = set(args.fit_folds or ())
    if fit_on and not fit_on < set(cases):
        print(
            f"--fit-folds {sorted(fit_on)}: need their cases and another fold's in {case_folder(args)}", file=sys.stderr
        )
        return 1
    scored = [k for k in cases if k not in fit_on]
    for k in scored:  # fit on the other folds' clips (or on --fit-folds'), score fold k's
        case = cases[k]
        others = [c for j, c in cases.items() if (j in fit_on if fit_on else j != k)]
        models = fit_features(np.concatenate([c["raw"] for c in others]),
                              np.concatenate([c["truth"] for c in others]), names, args.shrinkage)  # fmt: skip
        s = score(models, case)
        motions.append(case["motion"])
        clip_hits.append(s["hit"])
        for i, n in enumerate(names):
            hits.setdefault(family(str(n)), []).append(s["hit"][:, i])
            hit_motion.setdefault(family(str(n)), []).append(case["motion"])
        flat = dict(zip(case["flat_names"].tolist(), case["flat"].T, strict=True))
        for f in FEATURES:
            per_joint = []
            for j in JOINTS:
                i = names.tolist().index(f"3d_{f}_{j}")
                t = case["truth"][:, i]
                per_joint.append(np.stack([abs(s["est"][:, i] - t), abs(case["raw"][:, i] - t),
                                           abs(flat[f"{f}_{j}"] - t)], 1))  # fmt: skip
            mae.setdefault(f, []).append(np.stack(per_joint, 1))  # (clips, joints, calibrated | raw | 2D)
    how = (
        f"fitted on folds {sorted(fit_on)}, scored on folds {scored}"
        if fit_on
        else f"cross-fitted over folds {sorted(cases)}"
    )
    print(f"\n### {how}: held-out coverage of the 90 % intervals")
    print("| family | (clip, feature) cases | coverage |\n| --- | --- | --- |")
    every = []
    for fam, h in hits.items():
        h = np.concatenate(h)
        h = h[np.isfinite(h)]
        every.append(h)
        print(f"| {fam} | {len(h)} | {h.mean():.1%} |")
    every = np.concatenate(every)
    print(f"| **all** | {len(every)} | **{every.mean():.1%}** |")
    motion = np.concatenate(motions)  # (clips,) in the order of every fold's hits
    for src in np.unique(source_of(motion)):
        at = {fam: np.concatenate(h)[source_of(np.concatenate(hit_motion[fam])) == src] for fam, h in hits.items()}
        fams = " ".join(f"{fam} {v[np.isfinite(v)].mean():.1%}" for fam, v in at.items())
        alls = np.concatenate([v[np.isfinite(v)] for v in at.values()])
        print(f"clips of source {src}: all {alls.mean():.1%} ({fams})")
    for m in np.unique(motion):
        at = {fam: np.concatenate(h)[np.concatenate(hit_motion[fam]) == m] for fam, h in hits.items()}
        fams = " ".join(f"{fam} {v[np.isfinite(v)].mean():.1%}" for fam, v in at.items())
        allm = np.concatenate([v[np.isfinite(v)] for v in at.values()])
        print(f"clips of motion {m}: all {allm.mean():.1%} ({fams})")
    if args.cameras:
        camera_coverage(np.concatenate(clip_hits), *(np.concatenate([cases[k][key] for k in scored])
                                                     for key in ("depth_m", "focal_px")))  # fmt: skip
    by_source = held_out_by_source(cases, names, args.shrinkage) if len(set(source_of(motion))) > 1 else {}
    print("\n### MAE against the 3D truth, (clip, side, joint) cases of both folds held out")
    print("| feature | calibrated 3d_ | raw 3d_ | 2D (published) | calibrated / 2D | raw / 2D |")
    print("| --- | --- | --- | --- | --- | --- |")
    for f, e in mae.items():
        by_clip = np.concatenate(e)  # (clips, joints, 3) in the order of `motion`
        cal, raw, flat = np.nanmean(by_clip.reshape(-1, 3), axis=0)
        print(f"| {f} | {cal:.2f} | {raw:.2f} | {flat:.2f} | **{cal / flat:.2f}** | {raw / flat:.2f} |")
        for m in np.unique(motion):
            cal, raw, flat = np.nanmean(by_clip[motion == m].reshape(-1, 3), axis=0)
            print(f"|   {f}, motion {m} | {cal:.2f} | {raw:.2f} | {flat:.2f} | {cal / flat:.2f} | {raw / flat:.2f} |")
    if args.write:
        fitted = {k: c for k, c in cases.items() if k in fit_on} if fit_on else cases
        write_calibration(args, fitted, names, {fam: float(np.nanmean(np.concatenate(h))) for fam, h in hits.items()},
                          by_source)  # fmt: skip
    return 0


SYRIP_SOURCE = "SyRIP poses"


def source_of(motion: np.ndarray) -> np.ndarray:
    """The clip source of each case's motion: the adult motion (or with `--adult-captures` each of its captures,
    ADULT_SOURCE_NAMES), or SyRIP's poses (both motions: they share poses, so they are left out together)."""
    names = np.array([ADULT_SOURCE_NAMES.get(str(m), SYRIP_SOURCE) for m in np.ravel(motion)], dtype=object)
    return names.astype(str).reshape(np.shape(motion))


def held_out_by_source(
    cases: dict[int, dict[str, np.ndarray]], names: np.ndarray, shrinkage: str = "none"
) -> dict[str, dict[str, float]]:
    """Each source's clips (every fold's) scored by a fit on the other sources' clips only: per family the coverage
    of the 90 % intervals and their median width, printed as a table; returned as {source: {family: coverage}}."""
    pooled = {key: np.concatenate([c[key] for c in cases.values()]) for key in ("raw", "truth", "motion")}
    source = source_of(pooled["motion"])
    fams = sorted({family(str(n)) for n in names})
    fam_of = np.array([family(str(n)) for n in names])
    out: dict[str, dict[str, float]] = {}
    print("\n### held out by source: each source's clips scored by a fit on the other sources' clips only")
    print("| source left out | clips | " + " | ".join(fams) + " | all |")
    print("| --- | --- | " + " | ".join("---" for _ in fams) + " | --- |")
    for s in np.unique(source):
        fit, held = source != s, source == s
        models = fit_features(pooled["raw"][fit], pooled["truth"][fit], names, shrinkage)
        got = score(models, {"names": names, "raw": pooled["raw"][held], "truth": pooled["truth"][held]})
        cells, out[str(s)] = [], {}
        for fam in fams:
            h, w = got["hit"][:, fam_of == fam], got["width"][:, fam_of == fam]
            h, w = h[np.isfinite(h)], w[np.isfinite(w)]
            out[str(s)][fam] = float(h.mean()) if len(h) else float("nan")
            cells.append(f"{h.mean():.1%} (width {np.median(w):.3g})" if len(h) else "-")
        every = got["hit"][np.isfinite(got["hit"])]
        out[str(s)]["all"] = float(every.mean())
        print(f"| {s} | {int(held.sum())} | " + " | ".join(cells) + f" | **{every.mean():.1%}** |")
    return out


def camera_coverage(hit: np.ndarray, depth_m: np.ndarray, focal_px: np.ndarray) -> None:
    """Held-out coverage of the 90 % intervals `hit (clips, features)` by kind of camera set-up: lifted root
    depth (near, middle, far) and focal length (short, middle, long), and the issue's f = 1000 px, ~1 m."""
    groups = {
        "lifted 0.4-0.8 m away": depth_m < 0.8,
        "lifted 0.8-1.4 m away": (depth_m >= 0.8) & (depth_m < 1.4),
        "lifted 1.4-2.0 m away": (depth_m >= 1.4) & (depth_m < 2.0),
        "lifted 2.0-3.5 m away": depth_m >= 2.0,
        "focal length 600-1000 px": focal_px < 1000,
        "focal length 1000-1600 px": (focal_px >= 1000) & (focal_px < 1600),
        "focal length 1600-2500 px": (focal_px >= 1600) & (focal_px < 2500),
        "focal length 2500-3000 px": focal_px >= 2500,
        "f 800-1250 px, lifted 0.8-1.2 m away": (focal_px >= 800) & (focal_px <= 1250) & (depth_m >= 0.8)
        & (depth_m <= 1.2),
    }  # fmt: skip
    print("\n### held-out coverage of the 90 % intervals by kind of camera")
    print("| camera set-up | clips | (clip, feature) cases | coverage |\n| --- | --- | --- | --- |")
    for name, sel in groups.items():
        h = hit[sel]
        h = h[np.isfinite(h)]
        print(f"| {name} | {int(sel.sum())} | {len(h)} | {h.mean():.1%} |" if len(h) else f"| {name} | 0 | 0 | - |")


def write_calibration(
    args: argparse.Namespace, cases: dict, names: np.ndarray, coverage: dict[str, float],
    by_source: dict[str, dict[str, float]],
) -> None:  # fmt: skip
    """Fit on every fold's clips; add the clip-scope calibration of the shipped prior to `--out` (the others stay)."""
    from benchmarks.lib.settings import CLIP_SETTINGS
    from zedo_cli.analysis.uncertainty.calibration import (
        MeasureCalibration,
        bundled_path,
        read_calibrations,
        write_calibrations,
    )
    from zedo_cli.lifting.config import DEFAULT_PRESET, calibration_settings, get_preset
    from zedo_cli.prior.weights import load_prior, resolve_prior_path

    shipped = load_prior(resolve_prior_path(None))
    models = fit_features(np.concatenate([c["raw"] for c in cases.values()]),
                          np.concatenate([c["truth"] for c in cases.values()]), names, args.shrinkage)  # fmt: skip
    # The provenance names scripts by their paths in the flat benchmarks/ that wrote the shipped file: kept, so
    # that a rerun writes the same file (benchmarks/README.md maps them to today's paths).
    provenance = {
        "data": "SyRIP training poses held out of fold priors (benchmarks/folds.py), as synthetic 30 fps clips of "
        "each fold's held-out poses lifted by its prior; never Test100 or the synthetic rows",
        "recipe": "benchmarks/features_3d_accuracy.py --cases",
        "folds": sorted(cases),
        "cases": int(sum(len(c["raw"]) for c in cases.values())),
        "fps": float(CLIP_SETTINGS["fps"]),
        "clips": {**CLIP_SETTINGS, **CASE_CLIPS, "interpolation": list(CASE_MOTIONS)},
        "cross_fitted_coverage_90": {k: round(v, 4) for k, v in coverage.items()},
        "shrinkage": args.shrinkage,
    }
    motions = np.unique(np.concatenate([c["motion"] for c in cases.values()]))
    if ADULT_SOURCE in motions:
        provenance["data"] += ("; and as many clips a fold of the adult motion made infant-like (zedo_cli."
                               "evaluation.clips, SyRIP training infants' bones, 3 px jitter), lifted by the same "
                               "fold priors")  # fmt: skip
        provenance["recipe"] += " --adult"
        provenance["sources"] = sorted(str(s) for s in np.unique(source_of(motions)))
        provenance["held_out_by_source_coverage_90"] = {
            s: {k: round(v, 4) for k, v in fams.items()} for s, fams in by_source.items()
        }
    cameras, domain = ("pseudo",), None
    if args.cameras:
        from benchmarks.lib.settings import CAMERAS

        cameras, domain = ("cli", "file"), camera_domain(cases)
        provenance["data"] += (f"; the clips seen by known cameras (focal length {CAMERAS.focal_px[0]:g}-"
                               f"{CAMERAS.focal_px[1]:g} px, the infant {CAMERAS.depth_m[0]:g}-{CAMERAS.depth_m[1]:g} "
                               "m away) and lifted with their K")  # fmt: skip
        if ADULT_SOURCE in motions:
            provenance["data"] += "; the adult motion's clips before the clinic set-ups and two 2.5-3.5 m away"
        provenance["recipe"] += " --cameras"
        provenance["clips"].update({**CAMERA_NOISE, "cameras": dataclasses.asdict(CAMERAS)})
        provenance["domain_rule"] = "the clip's median lifted root depth and its focal length"
    if args.temporal != "smooth":
        provenance["recipe"] += f" --temporal {args.temporal}"
    cal = MeasureCalibration(shipped.sha256, calibration_settings(get_preset(DEFAULT_PRESET)), args.temporal, cameras,
                             shipped.skeleton.joints, models, provenance, domain=domain, scope="clips")  # fmt: skip
    out = args.out or bundled_path()
    old = read_calibrations(out) if out.exists() else []
    # one clip calibration per prior, temporal mode and kind of camera: a refit replaces it whatever its camera range
    keep = [c for c in old if (c.prior_sha256, c.temporal_mode, c.cameras, c.scope)
            != (cal.prior_sha256, cal.temporal_mode, cal.cameras, cal.scope)]  # fmt: skip
    write_calibrations(out, [*keep, cal])
    print(f"\nwrote {out}: {len(keep) + 1} calibrations ({len(models)} 3d_ features in the new one)")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--syrip-dir", required=True)
    ap.add_argument("--folds", type=Path, required=True)
    ap.add_argument("--weights", default="", help="suffix of the fold priors' files (fold<k><weights>.safetensors)")
    ap.add_argument(
        "--interpolation",
        choices=("segments", "positions"),
        default="segments",
        help="the clips' motion between key poses (temporal.make_sequences; positions: the old clips)",
    )
    ap.add_argument("--cases", type=Path, default=None, help="calibrate: the folds' clip cases' folder")
    ap.add_argument("--lift", action="store_true", help="--cases: lift the clip cases first")
    ap.add_argument("--adult", action="store_true", help="--lift: also the adult motion made infant-like")
    ap.add_argument(
        "--adult-captures",
        action="store_true",
        help="--lift --adult: the adult motion as two sources, Bandai-Namco and CMU with DeepMimic",
    )
    ap.add_argument("--syrip-clips", choices=PLACINGS, default="photo",
                    help="--lift: the SyRIP clips' key poses each in its photo's orientation, tumbling (photo), or "
                    "turned chest to the camera, swaying (supine)")  # fmt: skip
    ap.add_argument("--shrinkage", choices=tuple(SHRINKAGE), default="none",
                    help="--cases: estimates shrunk to the calibration clips' median or not")  # fmt: skip
    ap.add_argument("--write", action="store_true", help="--cases: write the calibration for the shipped prior")
    ap.add_argument("--out", type=Path, default=None, help="--write: calibration file (default: the package's)")
    ap.add_argument("--cameras", action="store_true", help="--cases: the clips seen by known cameras (--focal)")
    ap.add_argument("--fit-folds", type=int, nargs="+", default=None,
                    help="--cases: fit on these folds' clips only and score the other folds' (default: each fold "
                         "scored by a fit on the others)")  # fmt: skip
    ap.add_argument("--temporal", choices=("smooth", "none", "clip"), default="smooth",
                    help="--cases: the lift's temporal mode (none: frame by frame, zedo lift's default)")  # fmt: skip
    args = ap.parse_args()
    if args.cases is not None:
        if args.lift:
            lift_clip_cases(args)
        return calibrate(args)

    import torch

    from benchmarks.lib.folds import fold_priors
    from benchmarks.lib.settings import CLIP_SETTINGS
    from zedo_cli.evaluation.clips.eased import IMAGE_H, IMAGE_W, make_sequences
    from zedo_cli.lifting.config import DEFAULT_PRESET, get_preset
    from zedo_cli.lifting.temporal import lift_sequence

    cfg = get_preset(DEFAULT_PRESET)
    size = np.array([IMAGE_W, IMAGE_H], dtype=float)
    fps = float(CLIP_SETTINGS["fps"])
    errors: dict[int, list[dict]] = {}
    for k, prior, truth, _ in fold_priors(args.folds, args.weights, args.syrip_dir):
        torch.manual_seed(k)
        clips = make_sequences(truth.poses, np.random.default_rng(100 + k), **CLIP_SETTINGS,
                               interpolation=args.interpolation)  # fmt: skip
        res = lift_sequence(clips["xy"], clips["conf"], clips["k"], prior, cfg, mode="smooth", tracks=clips["tracks"])
        lifted = np.where(res.lifted[:, None, None], res.poses_root_relative, np.nan)  # (N, J, 3)
        errors[k] = []
        for track in np.unique(clips["tracks"]):
            at = clips["tracks"] == track
            errors[k].append(clip_errors(clips["xy"][at], lifted[at], clips["rel"][at], fps, size))
        print(f"fold {k}: {int(at.sum())} frames a clip, {len(errors[k])} clips, "
              f"{int(res.lifted.sum())}/{len(res.lifted)} frames lifted", flush=True)  # fmt: skip
    if not errors:
        print(f"no fold prior fold<k>{args.weights}.safetensors in {args.folds}", file=sys.stderr)
        return 1

    def table(name: str, runs: list[dict]) -> None:
        print(f"\n### {name}: MAE against the 3D truth over {len(runs)} clips x 2 sides")
        print("| feature | joint | 3D (3d_) | 2D (published) | 3D / 2D |")
        print("| --- | --- | --- | --- | --- |")
        for f in FEATURES:
            unit = "deg" if f == "mean_angle" else "deg/s"
            both = []
            for part in ("Elbow", "Knee"):
                e = np.array([r[(f, s + part)] for r in runs for s in "LR"])  # (clips x 2, 2)
                both.append(e)
                m3, m2 = np.nanmean(e, axis=0)
                print(f"| {f} ({unit}) | {part} | {m3:.1f} | {m2:.1f} | {m3 / m2:.2f} |")
            m3, m2 = np.nanmean(np.concatenate(both), axis=0)
            print(f"| {f} ({unit}) | both | **{m3:.1f}** | **{m2:.1f}** | **{m3 / m2:.2f}** |")

    for k, runs in errors.items():
        table(f"fold {k}", runs)
    if len(errors) > 1:
        table(f"folds {', '.join(map(str, errors))} pooled", [r for runs in errors.values() for r in runs])
    return 0


if __name__ == "__main__":
    sys.exit(main())
