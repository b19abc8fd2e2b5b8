"""The head measures (`head_turn`, `head_tilt_deg`, the clip shares and their intervals) on synthetic
clips of an infant lying with its chest to the camera, a cot filmed from above, and the calibration
of the clip intervals (docs/clinical.md, "Head"):

    python benchmarks/calibrate/head_measures.py --syrip-dir ../shared/data/syrip [--write] [--e2e-dir DIR]

`--write` writes the fitted calibration to `zedo_cli/weights/head.json` (the bundled one), with the
held-out coverage it measured.

The clips:

- the body: SyRIP *training* poses (`load_syrip_3d(..., "train")`; never Test100, never the
  synthetic rows), each turned so that its chest faces the camera, its head towards a random
  direction of the picture, tipped by up to 10 degrees, and eased from one key pose to the next;
  the calibration clips use the even rows of the training poses, every clip measured (held out)
  the odd rows, each with its own seeds;
- the head: nose, eyes and ears at an infant's offsets from the head's centre (the tragion
  midpoint, 7 cm above the shoulders' midpoint along the trunk), every clip's head stretched by
  up to +-15 % per axis (so the measure's head model is never exactly right), with a known yaw,
  tilt and pitch per frame: the yaw holds a position (right 35-85 degrees, midline within 8, left
  35-85) for a gamma-distributed time (mean 2-6 s per clip) and moves to the next in 0.4-0.8 s,
  the side chosen with the clip's shares (the published norms at 3 and 9 weeks, or random);
- the camera: a pinhole 1920 x 1080, f = 1400 px, 0.8-1.0 m above the chest (an interpupillary
  distance of about 60 px); a point is missing where it faces away from the camera (its outward
  normal: the nose forward, the eyes 30 degrees and the ears 80 degrees out to the side), then
  1 px Gaussian noise on every point (the sweep: 0.5 and 2 px) and 2 % of the face points
  dropped at random.

Measured: the calls against the true yaw (frames where the nose or an eye was detected), the
tilt against its definition computed on the noiseless projected points, the clip shares against
the frame rows. The intervals: per process (random shares, holds, infant and set-up) its truths
from 2 hours of it (the true share of frames by the yaw, the median of the tilt's definition on
the noiseless points; also the long-run share of calls, the bootstrap's own estimand), and one
clip of 1, 3 and 10 minutes of it. The calibration (`analysis.uncertainty.head_calibration`: split conformal
on the bootstrap interval's arms) is fitted on the calibration processes' clips, and the coverage
of the bootstrap alone and calibrated is measured on the held-out processes' clips, at 1 px and
(fewer) at 0.5 and 2 px; also the bootstrap on the yaw process alone (no camera: the true
categories as calls) for holds of 2, 4 and 6 s. With `--e2e-dir`, one clip also goes through
`zedo lift` (COCO-17 with the face points) and `zedo analyze`, and the CSV's head rows are compared
with the measure computed directly. SyRIP's terms (non-commercial research) hold for its poses.
"""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from zedo_cli.analysis.pose.head import (
    FACE_JOINTS,
    HeadSettings,
    head_clip,
    head_clip_bootstrap,
    head_frames,
    head_tilt,
)
from zedo_cli.analysis.uncertainty.block_bootstrap import share_intervals
from zedo_cli.analysis.uncertainty.calibration import LEVELS
from zedo_cli.analysis.uncertainty.head_calibration import (
    BOUNDS,
    MEASURES,
    HeadCalibration,
    HeadMeasureCalibration,
    MeasureFactor,
    bundled_head_calibrations,
    bundled_path,
    conformal_factor,
    head_settings_key,
    scores,
    widened_arms,
    write_head_calibrations,
)
from zedo_cli.data.datasets import load_syrip_3d
from zedo_cli.data.skeleton import get_skeleton

SKEL = get_skeleton("syrip12")
COCO = get_skeleton("coco17")
IMAGE_W, IMAGE_H, FOCAL = 1920, 1080, 1400.0
CALLS = ("left", "right", "midline")
MIDLINE_DEG = HeadSettings().midline_deg
# The head (metres) in its own axes: x the infant's left, y the top of its head, z out of its face;
# origin the tragion midpoint. Outward normals decide what the camera sees.
HEAD_POINTS = np.array([[0.0, -0.008, 0.065], [0.0195, 0.012, 0.052], [-0.0195, 0.012, 0.052],
                        [0.0475, 0.0, 0.0], [-0.0475, 0.0, 0.0]])  # fmt: skip
_S30, _C30, _S80, _C80 = (math.sin(math.radians(30)), math.cos(math.radians(30)), math.sin(math.radians(80)),
                          math.cos(math.radians(80)))  # fmt: skip
HEAD_NORMALS = np.array([[0, 0, 1], [_S30, 0, _C30], [-_S30, 0, _C30], [_S80, 0, _C80], [-_S80, 0, _C80]])
NORMS = {"3 weeks": (0.41, 0.40, 0.19), "9 weeks": (0.24, 0.30, 0.46)}  # left, right, midline
YAW_RANGES = {"left": (35.0, 85.0), "right": (-85.0, -35.0), "midline": (-8.0, 8.0)}


@dataclass
class Clip:
    fps: float
    body2d: np.ndarray  # (T, 12, 2) noisy pixels
    face2d: np.ndarray  # (T, 5, 2) noisy, NaN where hidden or dropped
    face_clean: np.ndarray  # (T, 5, 2) noiseless, NaN where hidden
    body_clean: np.ndarray  # (T, 12, 2)
    yaw: np.ndarray  # (T,) true, degrees, + the infant's left
    shares: tuple[float, float, float]
    dwell_s: float


def body_axes(poses: np.ndarray) -> np.ndarray:
    """`(N, 3, 3)`: columns the body's own left, headward and forward (chest) axes in the poses' frame."""
    ls, rs = poses[:, SKEL.index("left_shoulder")], poses[:, SKEL.index("right_shoulder")]
    hips = poses[:, [SKEL.index("left_hip"), SKEL.index("right_hip")]].mean(1)
    x = ls - rs
    x /= np.linalg.norm(x, axis=-1, keepdims=True)
    y = 0.5 * (ls + rs) - hips
    y -= (y * x).sum(-1, keepdims=True) * x
    y /= np.linalg.norm(y, axis=-1, keepdims=True)
    return np.stack([x, y, np.cross(x, y)], axis=-1)


def rotation(axis: int, deg: np.ndarray | float) -> np.ndarray:
    """`(..., 3, 3)` rotations about camera axis 0, 1 or 2 by `deg`."""
    a = np.radians(np.asarray(deg, dtype=float))
    c, s = np.cos(a), np.sin(a)
    out = np.zeros((*a.shape, 3, 3))
    i, j = [k for k in range(3) if k != axis]
    out[..., axis, axis] = 1.0
    out[..., i, i], out[..., i, j], out[..., j, i], out[..., j, j] = c, -s, s, c
    return out


def chest_to_camera(poses: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Root-relative poses turned so that the chest faces the camera (forward -> -z), the head
    towards one random direction of the picture, tipped by up to 10 degrees."""
    phi = rng.uniform(0.0, 360.0)
    target = np.stack([np.zeros(3), [math.sin(math.radians(phi)), -math.cos(math.radians(phi)), 0.0],
                       [0.0, 0.0, -1.0]], axis=1)  # fmt: skip
    target[:, 0] = np.cross(target[:, 1], target[:, 2])  # own left = headward x forward (right-handed)
    tip = rotation(0, rng.uniform(-10, 10)) @ rotation(1, rng.uniform(-10, 10))
    rot = tip @ target @ body_axes(poses).transpose(0, 2, 1)  # (N, 3, 3) pose frame -> camera frame
    return np.einsum("nij,nkj->nki", rot, poses)


def ease(keys: np.ndarray, frames: int) -> np.ndarray:
    """`(frames, J, 3)`: key poses eased one into the next over the clip (cosine)."""
    pos = np.linspace(0.0, len(keys) - 1, frames)
    k = np.minimum(pos.astype(int), len(keys) - 2)
    w = (1.0 - np.cos(np.pi * (pos - k)))[:, None, None] / 2.0
    return keys[k] * (1.0 - w) + keys[k + 1] * w


def smooth_noise(rng: np.random.Generator, t: np.ndarray, amplitude: float) -> np.ndarray:
    """A slow random wobble of about `amplitude` degrees (a few sinusoids of 0.02-0.3 Hz)."""
    f = rng.uniform(0.02, 0.3, 4)
    phase = rng.uniform(0, 2 * np.pi, 4)
    return amplitude / 2.0 * np.sin(2 * np.pi * f[:, None] * t + phase[:, None]).sum(0)


def yaw_process(rng: np.random.Generator, frames: int, fps: float, shares: tuple[float, float, float],
                dwell_s: float) -> np.ndarray:  # fmt: skip
    """The head's yaw `(frames,)`: holds of gamma(2) durations of mean `dwell_s` at positions of the
    sides drawn with `shares` (left, right, midline), moved between in 0.4-0.8 s."""
    out = np.empty(frames)
    t, current = 0, 0.0
    while t < frames:
        side = CALLS[rng.choice(3, p=shares)]
        target = rng.uniform(*YAW_RANGES[side])
        move = max(1, int(rng.uniform(0.4, 0.8) * fps))
        hold = max(1, int(rng.gamma(2.0, dwell_s / 2.0) * fps))
        ramp = current + (target - current) * (1 - np.cos(np.pi * np.arange(1, move + 1) / move)) / 2
        piece = np.concatenate([ramp, np.full(hold, target)])[: frames - t]
        out[t : t + len(piece)] = piece
        t += len(piece)
        current = target
    return out


def project(points: np.ndarray) -> np.ndarray:
    """Pinhole pixels `(..., 2)` of camera-frame points `(..., 3)`."""
    return FOCAL * points[..., :2] / points[..., 2:] + np.array([IMAGE_W / 2, IMAGE_H / 2])


def make_clip(train: np.ndarray, rng: np.random.Generator, seconds: float, fps: float = 30.0, *,
              shares: tuple[float, float, float] | None = None, dwell_s: float | None = None,
              noise_px: float = 1.0, drop: float = 0.02, setup: np.random.Generator | None = None) -> Clip:  # fmt: skip
    """One synthetic clip (module docstring). `setup` draws the infant and the camera (its poses, head
    shape, place), `rng` the behaviour and the noise; by default both come from `rng`."""
    setup = setup if setup is not None else rng
    frames = int(round(seconds * fps))
    shares = shares if shares is not None else NORMS[list(NORMS)[int(setup.integers(len(NORMS)))]]
    dwell_s = dwell_s if dwell_s is not None else setup.uniform(2.0, 6.0)
    keys = chest_to_camera(train[setup.choice(len(train), 6, replace=False)], setup)
    place = np.array([setup.uniform(-0.1, 0.1), setup.uniform(-0.05, 0.05), setup.uniform(0.8, 1.0)])
    tilt0 = setup.uniform(-12, 12)
    shape = HEAD_POINTS * setup.uniform(0.85, 1.15, 3) * setup.uniform(0.9, 1.1)
    body = ease(keys, frames) + place
    t = np.arange(frames) / fps
    yaw = yaw_process(rng, frames, fps, shares, dwell_s) + smooth_noise(rng, t, 2.0)
    tilt = tilt0 + smooth_noise(rng, t, 5.0)
    pitch = smooth_noise(rng, t, 8.0)
    axes = body_axes(body)  # (T, 3, 3) the body's left, headward, forward in the camera frame
    centre = body[:, [SKEL.index("left_shoulder"), SKEL.index("right_shoulder")]].mean(1) + 0.07 * axes[..., 1]
    # the head: yaw about its long axis (y), then tilt (about z: + puts the left ear down), pitch last
    turn = np.swapaxes(rotation(1, yaw), -1, -2)  # + yaw: forward (z) towards the left (x)
    roll = np.swapaxes(rotation(2, tilt), -1, -2)  # + tilt: the left (x) towards the feet (-y)
    head_rot = axes @ roll @ turn @ rotation(0, pitch)  # (T, 3, 3) head axes -> camera frame
    points = centre[:, None] + np.einsum("tij,pj->tpi", head_rot, shape)  # (T, 5, 3)
    normals = np.einsum("tij,pj->tpi", head_rot, HEAD_NORMALS)
    visible = (normals * -points).sum(-1) > 0  # facing the camera (at the origin)
    face_clean = np.where(visible[..., None], project(points), np.nan)
    body_clean = project(body)
    face2d = face_clean + rng.normal(0.0, noise_px, face_clean.shape)
    face2d[rng.random(visible.shape) < drop] = np.nan
    body2d = body_clean + rng.normal(0.0, noise_px, body_clean.shape)
    return Clip(fps, body2d, face2d, face_clean, body_clean, yaw, shares, dwell_s)


def shoulders(body2d: np.ndarray) -> np.ndarray:
    return body2d[:, [SKEL.index("left_shoulder"), SKEL.index("right_shoulder")]]


def true_calls(yaw: np.ndarray) -> np.ndarray:
    return np.where(yaw > MIDLINE_DEG, "left", np.where(yaw < -MIDLINE_DEG, "right", "midline"))


def frame_figures(clips: list[Clip]) -> dict[str, float]:
    """Calls against the true yaw and the tilt against its noiseless definition, over every frame."""
    yaw, calls, seen, err = [], [], [], []
    for c in clips:
        h = head_frames(c.face2d, shoulders(c.body2d))
        clean, _, _ = head_tilt(c.face_clean, shoulders(c.body_clean))
        yaw.append(c.yaw)
        calls.append(h.turn_call.astype(str))
        seen.append(np.isfinite(c.face2d[:, :3]).all(-1).any(1))  # the nose or an eye detected
        err.append(np.abs(h.tilt_deg - clean))
    yaw, calls, seen, err = (np.concatenate(x) for x in (yaw, calls, seen, err))
    err = err[np.isfinite(err)]
    out = {"frames": float(len(yaw)), "face_visible": float(seen.sum())}
    for name, sel, want in (("right_of_turned_right_40", seen & (yaw <= -40), "right"),
                            ("left_of_turned_left_40", seen & (yaw >= 40), "left"),
                            ("midline_of_within_10", seen & (np.abs(yaw) <= 10), "midline")):  # fmt: skip
        out[name] = float((calls[sel] == want).mean())
        out[f"{name}_frames"] = float(sel.sum())
    out["no_call_of_face_visible"] = float((calls[seen] == "").mean())
    out["tilt_mae_deg"] = float(err.mean())
    out["tilt_p90_deg"] = float(np.percentile(err, 90))
    out["tilt_frames"] = float(len(err))
    return out


@dataclass
class Case:
    """A process (an infant's behaviour in one set-up) and its long-run truths."""

    shares: tuple[float, float, float]
    dwell_s: float
    setup_seed: int
    share_of_calls: np.ndarray  # (3,) left, right, midline of 2 hours of the process, measured as the clips are
    true_share: np.ndarray  # (3,) of 2 hours of the process, by the true yaw
    tilt_median: float  # of 2 hours: the median of head_tilt_deg on the noiseless points
    tilt_median_measured: float  # of the same 2 hours: the median of head_tilt_deg as measured

    def measured(self) -> np.ndarray:
        """`(4,)` the long-run values as measured, MEASURES' order."""
        return np.append(self.share_of_calls, self.tilt_median_measured)

    def truth(self) -> np.ndarray:
        return np.append(self.true_share, self.tilt_median)


def cases(poses: np.ndarray, rng: np.random.Generator, count: int, hours: float = 2.0) -> list[Case]:
    out = []
    for _ in range(count):
        shares = tuple(float(p) for p in rng.dirichlet([2.0, 2.0, 2.0]))
        dwell, setup_seed = float(rng.uniform(2.0, 6.0)), int(rng.integers(1 << 31))
        long = make_clip(poses, np.random.default_rng(setup_seed + 1), hours * 3600.0, shares=shares, dwell_s=dwell,
                         setup=np.random.default_rng(setup_seed))  # fmt: skip
        h = head_frames(long.face2d, shoulders(long.body2d))
        calls = h.turn_call.astype(str)
        truth = true_calls(long.yaw)
        clean, _, _ = head_tilt(long.face_clean, shoulders(long.body_clean))
        out.append(Case(shares, dwell, setup_seed, np.array([(calls == c).sum() / (calls != "").sum() for c in CALLS]),
                        np.array([(truth == c).mean() for c in CALLS]), float(np.nanmedian(clean)),
                        float(np.nanmedian(h.tilt_deg))))  # fmt: skip
    return out


def reference_spread(poses: np.ndarray, known: list[Case], hours: float = 2.0) -> dict[str, float]:
    """How much the long-run reference itself varies: a second run of `hours` of each process (same
    infant and set-up, other behaviour), the mean absolute difference of the shares of calls."""
    diffs = []
    for case in known:
        other = make_clip(poses, np.random.default_rng(case.setup_seed + 2), hours * 3600.0, shares=case.shares,
                          dwell_s=case.dwell_s, setup=np.random.default_rng(case.setup_seed))  # fmt: skip
        calls = head_frames(other.face2d, shoulders(other.body2d)).turn_call.astype(str)
        again = np.array([(calls == c).sum() / (calls != "").sum() for c in CALLS])
        diffs.extend(np.abs(again - case.share_of_calls).tolist())
    return {"cases": float(len(diffs)), "mean_abs_difference": float(np.mean(diffs))}


@dataclass
class Records:
    """The bootstrap's intervals (before calibration) of clips with known truths, per measure
    (MEASURES' order) and clip: `(4, n)` arrays."""

    estimate: np.ndarray
    low: np.ndarray
    high: np.ndarray
    truth: np.ndarray  # the long-run true share (by the yaw) / median tilt (noiseless points)
    truth_of_calls: np.ndarray  # the long-run share of calls / the same median tilt
    seconds: np.ndarray  # (n,) the clips' lengths
    binomial_width: np.ndarray  # (3, n) the shares' binomial widths over frames taken as independent

    @staticmethod
    def concat(parts: list[Records]) -> Records:
        axis = {"seconds": 0}
        return Records(**{f: np.concatenate([getattr(r, f) for r in parts], axis=axis.get(f, 1))
                          for f in Records.__dataclass_fields__})  # fmt: skip


def records(poses: np.ndarray, rng: np.random.Generator, known: list[Case], seconds: float,
            noise_px: float = 1.0) -> Records:  # fmt: skip
    """One clip of `seconds` per case (the same infant and set-up, another stretch of its
    behaviour) and its bootstrap intervals (`head_clip_bootstrap`)."""
    rows = []
    for case in known:
        behaviour, setup = np.random.default_rng(int(rng.integers(1 << 31))), np.random.default_rng(case.setup_seed)
        clip = make_clip(poses, behaviour, seconds, shares=case.shares, dwell_s=case.dwell_s, noise_px=noise_px,
                         setup=setup)  # fmt: skip
        h = head_frames(clip.face2d, shoulders(clip.body2d))
        stats = head_clip_bootstrap(np.arange(len(clip.yaw)), h, clip.fps)
        assert [st.measure for st in stats] == list(MEASURES)
        calls = h.turn_call.astype(str)
        called = int((calls != "").sum())
        p = np.array([st.value for st in stats[:3]])
        assert np.array_equal(p, [(calls == c).sum() / called for c in CALLS]), "shares are not the calls counted"
        rows.append((np.array([st.value for st in stats]), np.array([st.interval.low for st in stats]),
                     np.array([st.interval.high for st in stats]), case.truth(),
                     np.append(case.share_of_calls, case.tilt_median),
                     2 * 1.645 * np.sqrt(p * (1 - p) / called)))  # fmt: skip
    cols = [np.stack(c, axis=1) for c in zip(*rows, strict=True)]
    return Records(*cols[:5], np.full(len(known), seconds), cols[5])


def measurement_error(known: list[Case]) -> dict[str, float]:
    """Per measure, the root mean square over processes of its long-run value as measured minus
    its truth: the frames' own error, which no longer clip makes smaller."""
    diff = np.stack([c.measured() - c.truth() for c in known])  # (n, 4)
    return {name: float(np.sqrt(np.mean(diff[:, m] ** 2))) for m, name in enumerate(MEASURES)}


def fit(rec: Records, errors: dict[str, float], level: float) -> dict[str, tuple[float, int]]:
    """Per measure, the split-conformal factor of its clips' scores against the true share / median
    (the arms with the measurement error), and the number of clips it rests on."""
    out = {}
    for m, name in enumerate(MEASURES):
        score = scores(rec.estimate[m], rec.low[m], rec.high[m], rec.truth[m], errors[name])
        ok = np.isfinite(rec.low[m])
        out[name] = (conformal_factor(score[ok], level), int(ok.sum()))
    return out


def widened(rec: Records, errors: dict[str, float], factors: dict[str, float]) -> tuple[np.ndarray, np.ndarray]:
    """The intervals `(4, n)` of `rec` calibrated as `head_calibration.widen` makes them."""
    ends = [widened_arms(rec.estimate[m], rec.low[m], rec.high[m], errors[name], factors[name], BOUNDS[name])
            for m, name in enumerate(MEASURES)]  # fmt: skip
    return np.stack([e[0] for e in ends]), np.stack([e[1] for e in ends])


def coverage(rec: Records, cal: tuple[dict[str, float], dict[str, float]] | None = None
             ) -> dict[str, dict[str, float]]:  # fmt: skip
    """Per measure: the coverage of the truth (and, for the shares, of the long-run share of calls)
    by the bootstrap's intervals (`cal` None) or the calibrated ones (`cal`: the errors and factors),
    over the clips with an interval, and their median width."""
    low, high = (rec.low, rec.high) if cal is None else widened(rec, *cal)
    out = {}
    for m, name in enumerate(MEASURES):
        ok = np.isfinite(low[m])
        row = {"clips": float(ok.sum()),
               "coverage": float(np.mean((low[m][ok] <= rec.truth[m][ok]) & (rec.truth[m][ok] <= high[m][ok]))),
               "median_width": float(np.median(high[m][ok] - low[m][ok]))}  # fmt: skip
        if m < 3:
            calls = rec.truth_of_calls[m][ok]
            row["coverage_of_share_of_calls"] = float(np.mean((low[m][ok] <= calls) & (calls <= high[m][ok])))
            row["median_width_binomial_over_frames"] = float(np.median(rec.binomial_width[m][ok]))
        out[name] = row
    return out


def by_length(rec: Records, cal: tuple[dict[str, float], dict[str, float]] | None
              ) -> dict[str, dict[str, dict[str, float]]]:  # fmt: skip
    """`coverage` of every clip length and of all together."""
    out = {f"{s / 60:g} min": coverage(_select(rec, rec.seconds == s), cal) for s in np.unique(rec.seconds)}
    out["all"] = coverage(rec, cal)
    return out


def _select(rec: Records, sel: np.ndarray) -> Records:
    return Records(**{f: getattr(rec, f)[..., sel] for f in Records.__dataclass_fields__})


def bias(known: list[Case]) -> dict[str, float]:
    """The calls' own error on the long-run share: mean |share of calls - true share| over processes."""
    diff = np.abs(np.stack([c.share_of_calls - c.true_share for c in known]))  # (n, 3)
    return {f"mean_abs_{c}": float(diff[:, k].mean()) for k, c in enumerate(CALLS)} | {"processes": float(len(known))}


def process_coverage(rng: np.random.Generator, seconds: float, dwell_s: float, count: int) -> dict[str, float]:
    """Coverage of the share intervals on the yaw process alone (calls = the true categories, no
    camera): `count` clips against 10 hours of the same process, shares 0.4 / 0.3 / 0.3."""
    shares = (0.4, 0.3, 0.3)
    long = true_calls(yaw_process(np.random.default_rng(int(rng.integers(1 << 31))), 30 * 36000, 30.0, shares, dwell_s))
    ref = np.array([(long == c).mean() for c in CALLS])
    hits, widths = [], []
    for _ in range(count):
        calls = true_calls(yaw_process(rng, int(30 * seconds), 30.0, shares, dwell_s))
        ind = np.stack([(calls == c).astype(float) for c in CALLS])
        for interval, truth in zip(share_intervals(ind, 30.0), ref, strict=True):
            hits.append(interval.low <= truth <= interval.high)
            widths.append(interval.high - interval.low)
    return {"cases": float(len(hits)), "coverage": float(np.mean(hits)), "median_width": float(np.median(widths))}


def write_coco(clip: Clip, path: Path) -> None:
    """The clip as a COCO-17 annotation file: the body from its syrip12 joints, the face points."""
    images, anns = [], []
    for t in range(len(clip.yaw)):
        kp = np.zeros((17, 3))
        for j, name in enumerate(SKEL.joints):
            kp[COCO.index(name)] = [*clip.body2d[t, j], 2]
        for e, name in enumerate(FACE_JOINTS):
            if np.isfinite(clip.face2d[t, e]).all():
                kp[COCO.index(name)] = [*clip.face2d[t, e], 2]
        images.append({"id": t, "width": IMAGE_W, "height": IMAGE_H, "file_name": f"frame{t:05d}.png"})
        anns.append({"id": t, "image_id": t, "category_id": 1, "keypoints": np.round(kp, 3).ravel().tolist()})
    cats = [{"id": 1, "name": "person", "keypoints": list(COCO.joints), "skeleton": []}]
    path.write_text(json.dumps({"images": images, "annotations": anns, "categories": cats}))


def end_to_end(clip: Clip, folder: Path) -> dict[str, float]:
    """`zedo lift` (COCO-17 with the face points) and `zedo analyze` on one clip; the CSV's head rows
    against the measure computed directly from the same 2D."""
    import csv

    folder.mkdir(parents=True, exist_ok=True)
    src, res, out = folder / "clip.json", folder / "clip.zedo.json", folder / "clip.analysis.csv"
    write_coco(clip, src)
    zedo = [sys.executable, "-m", "zedo_cli"]
    start = time.perf_counter()
    subprocess.run([*zedo, "lift", str(src), "--fps", str(clip.fps), "-o", str(res), "--overwrite", "-q"], check=True)
    lift_s = time.perf_counter() - start
    subprocess.run([*zedo, "analyze", str(res), "-o", str(out), "--overwrite"], check=True)
    rows = list(csv.DictReader(out.open()))
    frame_calls = [r["call"] for r in rows if r["measure"] == "head_turn" and r["frame_index"]]
    tilts = np.array([float(r["value"] or "nan") for r in rows if r["measure"] == "head_tilt_deg" and r["frame_index"]])
    shares = {r["measure"]: r for r in rows if r["measure"].startswith("head_turn_fraction_")}
    face = np.round(np.where(np.isfinite(clip.face2d), clip.face2d, np.nan), 3)
    direct = head_frames(face, shoulders(np.round(clip.body2d, 3)))
    called = [c for c in frame_calls if c]
    agree = all(abs(float(shares[f"head_turn_fraction_{c}"]["value"]) - called.count(c) / len(called)) < 1e-3
                for c in CALLS)  # fmt: skip
    return {
        "frames": float(len(frame_calls)),
        "calls_equal_direct": float(np.mean(np.array(frame_calls) == direct.turn_call.astype(str))),
        "tilt_max_diff_deg": float(np.nanmax(np.abs(tilts - direct.tilt_deg))),
        "shares_agree_with_frame_rows": float(agree),
        "lift_seconds": lift_s,
        **{f"share_{c}": float(shares[f"head_turn_fraction_{c}"]["value"]) for c in CALLS},
        **{f"share_{c}_low": float(shares[f"head_turn_fraction_{c}"]["low"]) for c in CALLS},
        **{f"share_{c}_high": float(shares[f"head_turn_fraction_{c}"]["high"]) for c in CALLS},
    }


def speed(train: np.ndarray, rng: np.random.Generator) -> dict[str, float]:
    """Seconds of the head measures and clip intervals of a 10-minute clip at 30 fps."""
    clip = make_clip(train, rng, 600.0)
    start = time.perf_counter()
    h = head_frames(clip.face2d, shoulders(clip.body2d))
    frames_s = time.perf_counter() - start
    head_clip(np.arange(len(clip.yaw)), h, clip.fps)
    return {
        "frames": float(len(clip.yaw)),
        "per_frame_s": frames_s,
        "with_clip_intervals_s": time.perf_counter() - start,
    }


LENGTHS = (60.0, 180.0, 600.0)
CHUNK = 25  # processes per worker task


def chunk(syrip_dir: str, half: int, seed: tuple[int, int, int], count: int) -> tuple[list[Case], Records]:
    """`count` processes on the training poses' even (`half` 0: calibration) or odd rows (1: held
    out) and one clip of each of LENGTHS of each, from `seed`."""
    poses = load_syrip_3d(syrip_dir, "train").poses[half::2]
    rng = np.random.default_rng(np.random.SeedSequence(seed))
    known = cases(poses, rng, count)
    return known, Records.concat([records(poses, rng, known, s) for s in LENGTHS])


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--syrip-dir", required=True)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--clips", type=int, default=100, help="held-out processes (one clip of each length)")
    ap.add_argument(
        "--calibration-clips", type=int, default=150, help="calibration processes (one clip of each length)"
    )
    ap.add_argument("--sweep-clips", type=int, default=30, help="held-out processes at 0.5 and 2 px noise")
    ap.add_argument("--process-clips", type=int, default=100, help="clips of the yaw process alone per setting")
    ap.add_argument("--jobs", type=int, default=2, help="processes for the calibration and held-out clips")
    ap.add_argument("--write", action="store_true", help=f"write the fitted calibration to {bundled_path()}")
    ap.add_argument("--e2e-dir", type=Path, help="also lift and analyse one 10 s clip end to end here")
    args = ap.parse_args()
    train = load_syrip_3d(args.syrip_dir, "train").poses
    # Calibration and held-out clips: other poses (SyRIP training poses, alternate rows), other seeds.
    held_poses = train[1::2]  # calibration clips: the even rows (`chunk`), every clip measured: the odd
    rng_frames, rng_sweep, rng_misc = (np.random.default_rng(s) for s in np.random.SeedSequence(args.seed).spawn(3))
    with ProcessPoolExecutor(args.jobs) as pool:  # the processes in chunks, each of its own seed
        runs = {half: [pool.submit(chunk, args.syrip_dir, half, (args.seed, half, k), min(CHUNK, count - start))
                       for k, start in enumerate(range(0, count, CHUNK))]
                for half, count in ((0, args.calibration_clips), (1, args.clips))}  # fmt: skip
        done = {half: [r.result() for r in rs] for half, rs in runs.items()}
    cal_cases, held_cases = ([c for part in done[half] for c in part[0]] for half in (0, 1))
    cal, held = (Records.concat([part[1] for part in done[half]]) for half in (0, 1))
    report: dict[str, object] = {}
    clips = [make_clip(held_poses, rng_frames, 180.0) for _ in range(10)]
    report["frames (10 clips of 3 min, 1 px noise)"] = frame_figures(clips)
    for noise in (0.5, 2.0):
        noisy = [make_clip(held_poses, rng_frames, 180.0, noise_px=noise) for _ in range(5)]
        report[f"frames (5 clips of 3 min, {noise:g} px noise)"] = frame_figures(noisy)
    level = HeadSettings().bootstrap.level  # the bootstrap's, and zedo analyze's default --level
    errors = measurement_error(cal_cases)
    fitted = {lv: fit(cal, errors, lv) for lv in LEVELS}  # one bootstrap interval, a factor per level
    factors = {lv: {m: f for m, (f, _) in by_m.items()} for lv, by_m in fitted.items()}
    report["calibration: measurement errors (calibration processes)"] = errors
    report["calibration: factors (split conformal, calibration poses and seeds)"] = {
        f"{lv:g}": {m: {"factor": f, "clips": float(n)} for m, (f, n) in by_m.items()}
        for lv, by_m in fitted.items()}  # fmt: skip
    report["calls' own error on the long-run shares (held-out processes)"] = bias(held_cases)
    report["long-run reference, a second 2-hour run (10 processes)"] = reference_spread(held_poses, held_cases[:10])
    report[f"held-out coverage, bootstrap alone ({args.clips} processes x {len(LENGTHS)} lengths, 1 px)"] = (
        by_length(held, None))  # fmt: skip
    calibrated = by_length(held, (errors, factors[level]))
    report[f"held-out coverage, calibrated ({args.clips} processes x {len(LENGTHS)} lengths, 1 px)"] = calibrated
    at_levels = {lv: coverage(held, (errors, factors[lv])) for lv in LEVELS}
    report["held-out coverage, calibrated, at each level (all lengths, 1 px)"] = {
        f"{lv:g}": {m: row["coverage"] for m, row in cov.items()} for lv, cov in at_levels.items()}  # fmt: skip
    for noise in (0.5, 2.0):
        sweep_cases = held_cases[: args.sweep_clips]
        sweep = Records.concat([records(held_poses, rng_sweep, sweep_cases, s, noise) for s in LENGTHS])
        name = f"held-out coverage at {noise:g} px ({len(sweep_cases)} processes x {len(LENGTHS)} lengths)"
        report[name] = {
            "bootstrap alone": coverage(sweep, None),
            "calibrated": coverage(sweep, (errors, factors[level])),
        }
    for dwell in (2.0, 4.0, 6.0):
        for seconds in LENGTHS:
            name = (f"coverage, yaw process alone ({args.process_clips} clips of {seconds / 60:g} min, "
                    f"holds of {dwell:g} s)")  # fmt: skip
            report[name] = process_coverage(rng_misc, seconds, dwell, args.process_clips)
    if args.write:
        # The provenance names scripts by their paths in the flat benchmarks/ that wrote the shipped file: kept, so
        # that a rerun writes the same file (benchmarks/README.md maps them to today's paths).
        made = HeadCalibration(
            head_settings_key(HeadSettings().midline_deg, HeadSettings().model, HeadSettings().bootstrap),
            {m: HeadMeasureCalibration(errors[m], {lv: MeasureFactor(fitted[lv][m][0], fitted[lv][m][1],
                                                                     at_levels[lv][m]["coverage"],
                                                                     int(at_levels[lv][m]["clips"]))
                                                   for lv in LEVELS}) for m in MEASURES},
            f"python benchmarks/head_measures.py --syrip-dir SYRIP --seed {args.seed} --clips {args.clips} "
            f"--calibration-clips {args.calibration_clips} --write",
        )  # fmt: skip
        write_head_calibrations(bundled_path(), [made])
        report["written"] = str(bundled_path())
        bundled_head_calibrations.cache_clear()  # the speed and end to end: the file written
    report["speed (10 min at 30 fps)"] = speed(held_poses, rng_misc)
    if args.e2e_dir is not None:
        report["end to end (10 s clip through zedo lift and zedo analyze)"] = end_to_end(
            make_clip(held_poses, rng_misc, 10.0, dwell_s=2.0), args.e2e_dir)  # fmt: skip
    print(json.dumps(report, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
