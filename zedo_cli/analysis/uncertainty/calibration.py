"""Measure-level estimates and calibrated intervals of `zedo analyze`.

A lifted pose's symmetry and joint angles are only as good as its depth, and the 2D alone leaves
the depth of limbs that point towards or away from the camera to the prior. For every measure m
the calibration, fitted on lifts of poses the lifting prior never saw (fold priors, held-out
SyRIP training poses, `benchmarks/calibrate/calibrate_measures.py`), holds:

- the estimate: the measured value shrunk towards the calibration truths' median c,
  est = c + w (m - c), with w of WEIGHT_GRID the one with the least mean absolute error on the
  held-out lifts (w = 1 keeps the measured value). Lifted angles scatter more than true ones, so a
  measured extreme is, on average, less extreme in truth; the chosen w and the held-out error of
  both estimators are in the calibration's provenance and docs/clinical.md;
- the interval, conditional on the case: Mondrian split conformal with the measured value's range
  cut into bins of equal count. In the bin of the case, q_hi is the conformal (1 + level) / 2
  quantile of (truth - est) and q_lo that of (est - truth); the interval [est - q_lo, est + q_hi]
  misses on each side at most (1 - level) / 2 of the time for cases like the bin's, so it holds
  the truth with probability at least `level`. Its width depends on the measured value: a thigh
  pair measured at 5 degrees gets a narrower interval than one measured at 60;
- estimates and intervals are clipped to the measure's range (analysis.analyse.measure_ranges).

Angles with a wrap (the hip and shoulder flexions) take their residuals and shrinkage on the circle.

A calibration holds only for the prior, lifting settings, temporal mode and camera it was made
with (`MeasureCalibration.mismatch`). A measure that uses a joint the 2D did not give (filled by
the prior) is calibrated apart, where the calibration has such cases (`MeasureCalibration.filled`,
the calibrations of known cameras); otherwise it gets no interval.

Cameras: a calibration made with the pseudo camera (`cameras` ("pseudo",)) holds for results lifted
with it. One made over a range of known cameras (`cameras` ("cli", "file"): `--focal`,
`--principal-point` or `--intrinsics`) states that range (`CameraDomain`: the infant's root depth in
metres and the focal length in pixels it was calibrated over) and holds, pose by pose, for the poses
inside it (`assign_calibrations`); a pose outside says so in each measure's `interval` column.
The bundled file is `zedo_cli/weights/measures.json`.

Scope: a calibration's models are of frame measures (`scope` "frames", one case a pose) or of clip
features (`scope` "clips", one case a person's clip, e.g. the `3d_` features of `clip_features`, fitted
on clips of `provenance["fps"]` frames a second); `find_calibration` and `assign_calibrations` look only
at calibrations of the scope asked for. A clip-scope calibration over known cameras holds, clip by clip, where
the clip's median lifted root depth and focal length lie in its domain (`clip_camera_mismatch`).
"""

from __future__ import annotations

import functools
import hashlib
import json
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import Field, SerializerFunctionWrapHandler, field_validator, model_serializer

from ...data.skeleton import Skeleton
from ...errors import plural
from ...formats.readers.result_record import LiftParams
from ...lifting.config import calibration_settings, settings_match
from ...stats import conformal_quantile
from ...versioned_json import FileModel, ShippedFile

FORMAT = "zedo.measures"
FORMAT_VERSION = 1
LEVELS = (0.5, 0.7, 0.8, 0.9, 0.95)  # interval levels a calibration carries; 0.9 is the default
DEFAULT_LEVEL = 0.9
# A call rests on one end of the interval (symmetric: the upper one), and each end of the 80 % interval
# misses at most 10 % of the time: 0.8 is the level of calls meant to be right 9 times in 10. Chosen on the
# held-out lifts of folds 0-1 (docs/clinical.md, the risk-coverage table): images 15-16 % decisive with
# 88-91 % agreement (0.9: 3 % with 79-83 %), clips 22 % with 92.5 % (0.9: 15 % with 95 %).
DEFAULT_CALL_LEVEL = 0.8
WEIGHT_GRID = tuple(np.round(np.arange(1.0, 0.39, -0.05), 2))  # shrinkage weights tried; 1 = the measured value

MeasureFunction = Callable[[np.ndarray], dict[str, np.ndarray]]


def wrap_deg(d: np.ndarray) -> np.ndarray:
    """Differences of angles wrapped into [-180, 180)."""
    return (np.asarray(d) + 180.0) % 360.0 - 180.0


def residuals(truth: np.ndarray, est: np.ndarray, circular: bool) -> np.ndarray:
    d = np.asarray(truth) - np.asarray(est)
    return wrap_deg(d) if circular else d


@dataclass(frozen=True)
class MeasureModel:
    """One measure's estimator and interval constants.

    estimate = center + weight (value - center); the interval's ends are the estimate minus / plus
    the bin's conformal quantiles of (truth - estimate), the bin being the range of the measured
    value the case falls in (`edges`, inner bin edges in degrees)."""

    center: float  # degrees
    weight: float  # 1: the measured value is kept
    edges: tuple[float, ...]  # inner bin edges of the measured value, ascending
    q_low: dict[float, tuple[float, ...]]  # level -> per bin, how far below the estimate the interval reaches
    q_high: dict[float, tuple[float, ...]]  # level -> per bin, how far above
    circular: bool  # residuals and shrinkage on the circle

    def estimate(self, value: np.ndarray) -> np.ndarray:
        value = np.asarray(value, dtype=float)
        d = wrap_deg(value - self.center) if self.circular else value - self.center
        est = self.center + self.weight * d
        return wrap_deg(est) if self.circular else est

    def bins(self, value: np.ndarray) -> np.ndarray:
        return np.searchsorted(np.asarray(self.edges), np.asarray(value, dtype=float), side="right")

    def interval(self, est: np.ndarray, value: np.ndarray, level: float) -> tuple[np.ndarray, np.ndarray]:
        """The interval's ends at `level`; NaN in a bin whose calibration had too few cases (`stats.TOO_FEW_CASES`)."""
        b = self.bins(value)
        return est - np.asarray(self.q_low[level])[b], est + np.asarray(self.q_high[level])[b]


def fit_measure(
    value: np.ndarray, truth: np.ndarray, *, circular: bool, bins: int, weights: Sequence[float] = WEIGHT_GRID
) -> MeasureModel:
    """Fit one measure on held-out cases `(n,)` (NaN cases are left out): the weight of `weights`
    with the least mean absolute error, then per bin of the measured value (`bins` of equal count)
    the conformal quantiles of (truth - estimate) for each level of LEVELS."""
    ok = np.isfinite(value) & np.isfinite(truth)
    value, truth = value[ok], truth[ok]
    center = float(np.median(truth))
    if circular:  # the circular median, near enough: the median of the wrapped offsets from the mean direction
        mean_dir = float(np.degrees(np.arctan2(np.sin(np.radians(truth)).mean(), np.cos(np.radians(truth)).mean())))
        center = float(wrap_deg(mean_dir + np.median(wrap_deg(truth - mean_dir))))
    errors = [np.abs(residuals(truth, MeasureModel(center, w, (), {}, {}, circular).estimate(value), circular)).mean()
              for w in weights]  # fmt: skip
    weight = float(weights[int(np.argmin(errors))])
    edges = tuple(float(e) for e in np.quantile(value, np.linspace(0, 1, bins + 1)[1:-1]))
    model = MeasureModel(center, weight, edges, {}, {}, circular)
    r = residuals(truth, model.estimate(value), circular)
    b = model.bins(value)
    q_high = {lv: tuple(conformal_quantile(r[b == k], (1 + lv) / 2) for k in range(bins)) for lv in LEVELS}
    q_low = {lv: tuple(conformal_quantile(-r[b == k], (1 + lv) / 2) for k in range(bins)) for lv in LEVELS}
    return MeasureModel(center, weight, edges, q_low, q_high, circular)


@dataclass(frozen=True)
class CameraDomain:
    """The camera set-ups a calibration over known cameras was made with, pose by pose: the infant's
    root depth (metres from the camera) and the focal length (pixels) of each pose lifted."""

    root_depth_m: tuple[float, float]
    focal_px: tuple[float, float]

    def describe(self) -> str:
        (d0, d1), (f0, f1) = self.root_depth_m, self.focal_px
        return f"root depth {d0:g}-{d1:g} m, focal length {f0:g}-{f1:g} px"

    def contains(self, depth_m: np.ndarray, focal_px: np.ndarray) -> np.ndarray:
        """`(M,)` bool: the poses of root depths and focal lengths `(M,)` inside the domain (NaN: not inside)."""
        (d0, d1), (f0, f1) = self.root_depth_m, self.focal_px
        with np.errstate(invalid="ignore"):
            return (depth_m >= d0) & (depth_m <= d1) & (focal_px >= f0) & (focal_px <= f1)


def describe_domains(domains: Sequence[CameraDomain]) -> str:
    """The camera ranges of `domains` in words, those of one focal range whose root depths meet as one (a near
    range of 0.4-0.6 m and one of 0.6-2 m: "root depth 0.4-2 m, ...")."""
    merged: list[CameraDomain] = []
    for d in sorted(set(domains), key=lambda d: (d.focal_px, d.root_depth_m)):
        last = merged[-1] if merged else None
        if last is not None and last.focal_px == d.focal_px and d.root_depth_m[0] <= last.root_depth_m[1]:
            depth = (last.root_depth_m[0], max(last.root_depth_m[1], d.root_depth_m[1]))
            merged[-1] = CameraDomain(depth, d.focal_px)
        else:
            merged.append(d)
    return "; ".join(sorted(d.describe() for d in merged))


@dataclass(frozen=True)
class MeasureCalibration:
    """Models of every measure for one prior, lifting settings, temporal mode and camera (with
    `domain`, the range of known cameras it holds for, pose by pose)."""

    prior_sha256: str
    settings: dict[str, Any]  # lifting.config.calibration_settings of the lift
    temporal_mode: str  # "none" for images, else the lift's temporal mode
    cameras: tuple[str, ...]  # the camera sources the calibration lifts used (e.g. "pseudo")
    joints: tuple[str, ...]
    measures: dict[str, MeasureModel]
    provenance: dict[str, Any] = field(default_factory=dict)
    domain: CameraDomain | None = None  # None: every pose of a result it matches
    # measure -> the model of the cases where a joint the measure uses was filled by the prior (wider); empty: such
    # cases get no interval
    filled: dict[str, MeasureModel] = field(default_factory=dict)
    scope: str = "frames"  # "frames": models of frame measures; "clips": of clip features (a case a clip)

    def mismatch(self, params: dict[str, Any], joints: tuple[str, ...]) -> str | None:
        """Why this calibration does not hold for a result lifted with `params` (None: it holds)."""
        lift = LiftParams.from_dict(params)
        if lift.prior_sha256 != self.prior_sha256 or tuple(joints) != self.joints:
            return "no measure calibration for this prior"
        mode = "none" if lift.temporal_mode is None else lift.temporal_mode
        if mode != self.temporal_mode:
            return f"no measure calibration for temporal mode {mode}"
        if lift.config is None or not settings_match(self.settings, calibration_settings(dict(lift.config))):
            return "no measure calibration for these lifting settings (calibrated: the default preset)"
        cams = lift.camera_sources
        if not cams or not set(cams) <= set(self.cameras):
            return f"no measure calibration for this camera (calibrated: {', '.join(self.cameras)})"
        return None


def find_calibration(
    calibrations: Sequence[MeasureCalibration], params: dict[str, Any], joints: tuple[str, ...], scope: str = "frames"
) -> tuple[MeasureCalibration | None, str]:
    """The calibration of `scope` that holds for a result lifted with `params`, or None and why none does."""
    calibrations = [c for c in calibrations if c.scope == scope]
    if not params:
        return None, "the result records no lifting parameters: no measure calibration applies"
    reasons = []
    for c in calibrations:
        why = c.mismatch(params, joints)
        if why is None:
            return c, "calibrated"
        reasons.append(why)
    if not reasons:
        return None, "no measure calibration installed"
    # the most specific reason: one of a calibration that got furthest
    order = ("camera", "settings", "temporal", "prior")
    return None, min(reasons, key=lambda r: order.index(next((w for w in order if w in r), "prior")))


@dataclass(frozen=True)
class Assignment:
    """Which calibration holds for each of M poses: `index (M,)` into `calibrations`, -1 where none does,
    and `why_not (M,)` why (empty where one holds)."""

    calibrations: tuple[MeasureCalibration, ...]
    index: np.ndarray  # (M,) int
    why_not: np.ndarray  # (M,) str (object)
    stand_in: int = 0  # poses whose stated camera lies outside every known camera's range: the pseudo's calibration

    @property
    def any(self) -> bool:
        return bool((self.index >= 0).any())

    def used(self) -> list[MeasureCalibration]:
        """The calibrations that hold for at least one pose, in their order."""
        return [self.calibrations[i] for i in np.unique(self.index[self.index >= 0])]

    def note(self) -> str:
        """ "calibrated" where every pose has a calibration, else the most common reason of those without."""
        missing = self.why_not[self.index < 0]
        if not len(missing):
            return "calibrated"
        reasons, counts = np.unique(missing.astype(str), return_counts=True)
        return str(reasons[np.argmax(counts)])


def camera_stand_in(
    calibrations: Sequence[MeasureCalibration], params: dict[str, Any], joints: tuple[str, ...], scope: str = "frames"
) -> MeasureCalibration | None:  # fmt: skip
    """For a result lifted with a stated camera: the pseudo camera's calibration of `scope` that holds for it but for
    the camera. It stands in where the stated camera lies outside every known camera calibration's range, so that
    stating the camera never loses an interval that leaving it out would give (measured on clips of another source:
    docs/clinical.md, "Stated camera or not"). None for a pseudo-camera result or without such a calibration."""
    sources = LiftParams.from_dict(params).camera_sources
    if not sources or set(sources) <= {"pseudo"}:
        return None
    as_pseudo = {**params, "camera_sources": ["pseudo"]}
    return next((c for c in calibrations if c.scope == scope and c.domain is None and set(c.cameras) == {"pseudo"}
                 and c.mismatch(as_pseudo, joints) is None), None)  # fmt: skip


def assign_calibrations(
    calibrations: Sequence[MeasureCalibration], params: dict[str, Any], joints: tuple[str, ...],
    depth_m: np.ndarray, focal_px: np.ndarray,
) -> Assignment:  # fmt: skip
    """Per pose of a result lifted with `params` (root depths `depth_m (M,)` in metres and focal lengths
    `focal_px (M,)` in pixels, NaN where the result does not state them): the first calibration that
    matches the result (`MeasureCalibration.mismatch`) and whose camera domain holds the pose (frame scope)."""
    m = len(depth_m)
    index = np.full(m, -1)
    calibrations = [c for c in calibrations if c.scope == "frames"]
    matching = [c for c in calibrations if params and c.mismatch(params, joints) is None]
    if not matching:
        _, why = find_calibration(calibrations, params, joints)
        return Assignment((), index, np.full(m, why, dtype=object))
    for i, c in enumerate(matching):
        inside = np.ones(m, bool) if c.domain is None else c.domain.contains(depth_m, focal_px)
        index[(index < 0) & inside] = i
    stand_in = camera_stand_in(calibrations, params, joints)
    stated = np.isfinite(depth_m) & np.isfinite(focal_px)
    replaced = (index < 0) & stated if stand_in is not None else np.zeros(m, bool)
    if replaced.any():
        matching = [*matching, stand_in]
        index[replaced] = len(matching) - 1
    why_not = np.full(m, "", dtype=object)
    out = index < 0
    if out.any():
        ranges = describe_domains([c.domain for c in matching if c.domain is not None])
        why_not[out & ~stated] = ("the result states no root depth or camera for this pose (a root-frame CSV or "
                                  f"NPZ?), so the camera calibration ({ranges}) cannot be checked")  # fmt: skip
        known = np.flatnonzero(out & stated)
        if len(known):  # one reason per distinct (depth, focal) rounded: a clip's poses share a few
            keys = np.round(np.stack([depth_m[known], focal_px[known]], 1), 2)
            uniq, inverse = np.unique(keys, axis=0, return_inverse=True)
            texts = np.array([f"camera outside the calibrated range (root depth {d:.2f} m, focal length {f:.0f} px; "
                              f"calibrated: {ranges})" for d, f in uniq], dtype=object)  # fmt: skip
            why_not[known] = texts[inverse.ravel()]
    return Assignment(tuple(matching), index, why_not, int(replaced.sum()))


def clip_camera_mismatch(calibration: MeasureCalibration, depth_m: np.ndarray, focal_px: np.ndarray) -> str | None:
    """Why a clip-scope calibration does not hold for one clip for its camera, from the root depths and focal
    lengths `(M,)` of the clip's lifted poses: a calibration over known cameras holds where the clip's median
    root depth and median focal length lie in its domain (None: they do, or it has no domain)."""
    domain = calibration.domain
    if domain is None:
        return None
    depth = float(np.nanmedian(depth_m)) if np.isfinite(depth_m).any() else np.nan
    focal = float(np.nanmedian(focal_px)) if np.isfinite(focal_px).any() else np.nan
    if not (np.isfinite(depth) and np.isfinite(focal)):
        return (f"the result states no root depth or camera for this clip (a root-frame CSV or NPZ?), so the camera "
                f"calibration ({domain.describe()}) cannot be checked")  # fmt: skip
    if domain.contains(np.array([depth]), np.array([focal]))[0]:
        return None
    return (f"camera outside the calibrated range (the clip's median root depth {depth:.2f} m, focal length "
            f"{focal:.0f} px; calibrated: {domain.describe()})")  # fmt: skip


# The file's entries (pydantic): what `read_calibrations` validates and `write_calibrations` writes; `of` makes one
# of the dataclass the code computes with (the written precision: 4 decimals, focal lengths 2), `value` the dataclass.

Quantiles = dict[str, list[float | None]]  # level ("0.9") -> per bin; null: too few calibration cases (NaN)


def _rounded(q: dict[float, tuple[float, ...]]) -> Quantiles:
    return {str(k): [round(x, 4) if np.isfinite(x) else None for x in v] for k, v in q.items()}


def _read(q: Quantiles) -> dict[float, tuple[float, ...]]:
    return {float(k): tuple(np.nan if x is None else float(x) for x in v) for k, v in q.items()}


class MeasureModelEntry(FileModel):
    """One measure's `MeasureModel`."""

    center: float
    weight: float
    circular: bool
    edges: list[float]
    q_low: Quantiles
    q_high: Quantiles

    @field_validator("q_low", "q_high")
    @classmethod
    def _levels_are_numbers(cls, q: Quantiles) -> Quantiles:
        for k in q:
            try:
                float(k)
            except ValueError:
                raise ValueError(f"level {k!r} is not a number") from None
        return q

    @classmethod
    def of(cls, m: MeasureModel) -> MeasureModelEntry:
        edges = [round(e, 4) for e in m.edges]
        return cls(center=round(m.center, 4), weight=round(m.weight, 4), circular=m.circular, edges=edges,
                   q_low=_rounded(m.q_low), q_high=_rounded(m.q_high))  # fmt: skip

    def value(self) -> MeasureModel:
        return MeasureModel(self.center, self.weight, tuple(self.edges), _read(self.q_low), _read(self.q_high),
                            self.circular)  # fmt: skip


Pair = Annotated[list[float], Field(min_length=2, max_length=2)]


class CameraDomainEntry(FileModel):
    """A `CameraDomain`: [low, high] of each."""

    root_depth_m: Pair
    focal_px: Pair

    @classmethod
    def of(cls, d: CameraDomain) -> CameraDomainEntry:
        return cls(root_depth_m=[round(x, 4) for x in d.root_depth_m], focal_px=[round(x, 2) for x in d.focal_px])

    def value(self) -> CameraDomain:
        (d0, d1), (f0, f1) = self.root_depth_m, self.focal_px
        return CameraDomain((d0, d1), (f0, f1))


class MeasureCalibrationEntry(FileModel):
    """A `MeasureCalibration`; `domain`, `filled` and `scope` are left out of the file where they are their
    defaults (the pseudo camera's and frame measures' entries read and write as before they existed)."""

    prior_sha256: str
    settings: dict[str, Any]
    temporal_mode: str
    cameras: list[str]
    joints: list[str]
    provenance: dict[str, Any] = {}
    measures: dict[str, MeasureModelEntry]
    domain: CameraDomainEntry | None = None
    filled: dict[str, MeasureModelEntry] = {}
    scope: Literal["frames", "clips"] = "frames"

    @model_serializer(mode="wrap")
    def _defaults_left_out(self, handler: SerializerFunctionWrapHandler) -> dict[str, Any]:
        out = handler(self)
        for key, default in (("domain", None), ("filled", {}), ("scope", "frames")):
            if out.get(key) == default:
                out.pop(key, None)
        return out

    @classmethod
    def of(cls, c: MeasureCalibration) -> MeasureCalibrationEntry:
        return cls(prior_sha256=c.prior_sha256, settings=c.settings, temporal_mode=c.temporal_mode,
                   cameras=list(c.cameras), joints=list(c.joints), provenance=c.provenance,
                   measures={k: MeasureModelEntry.of(v) for k, v in c.measures.items()},
                   domain=None if c.domain is None else CameraDomainEntry.of(c.domain),
                   filled={k: MeasureModelEntry.of(v) for k, v in c.filled.items()},
                   scope=c.scope)  # type: ignore[arg-type]  # fmt: skip

    def value(self) -> MeasureCalibration:
        return MeasureCalibration(self.prior_sha256, dict(self.settings), self.temporal_mode, tuple(self.cameras),
                                  tuple(self.joints), {k: v.value() for k, v in self.measures.items()},
                                  dict(self.provenance), None if self.domain is None else self.domain.value(),
                                  {k: v.value() for k, v in self.filled.items()}, self.scope)  # fmt: skip


_FILE = ShippedFile("measures.json", FORMAT, FORMAT_VERSION, "calibrations", "measure calibration",
                    MeasureCalibrationEntry)  # fmt: skip


def bundled_path() -> Path:
    return _FILE.bundled_path()


@functools.cache
def bundled_calibrations() -> tuple[MeasureCalibration, ...]:
    return _FILE.read_bundled()


def read_calibrations(path: str | Path) -> list[MeasureCalibration]:
    """The calibrations of a measure-calibration file (format `zedo.measures`, version 1)."""
    return _FILE.read(path)


def write_calibrations(path: str | Path, calibrations: Sequence[MeasureCalibration]) -> None:
    _FILE.write(path, calibrations)


def measure_joints(skeleton: Skeleton, measures: MeasureFunction, names: Sequence[str]) -> dict[str, np.ndarray]:
    """Per measure, the joints `(J,)` bool it depends on (found by moving each joint of a generic pose)."""
    rng = np.random.default_rng(0)
    pose = rng.normal(0.0, 0.1, (1, skeleton.num_joints, 3))
    base = measures(pose)
    uses = {n: np.zeros(skeleton.num_joints, bool) for n in names}
    for j in range(skeleton.num_joints):
        moved = pose.copy()
        moved[0, j] += 0.02
        after = measures(moved)
        for n in names:
            uses[n][j] = not np.isclose(after[n][0], base[n][0], atol=1e-9, equal_nan=True)
    return uses


def calibration_id(calibration: MeasureCalibration) -> str:
    """A short name of a calibration's content: the first 16 hex digits of the sha256 of its file entry."""
    entry = MeasureCalibrationEntry.of(calibration).model_dump(mode="json")
    return hashlib.sha256(json.dumps(entry, sort_keys=True).encode()).hexdigest()[:16]


def backing(calibration: MeasureCalibration) -> dict[str, Any]:
    """What backs the intervals a calibration gives: its id, scope, temporal mode, cameras and data."""
    return {"id": calibration_id(calibration), "scope": calibration.scope, "temporal_mode": calibration.temporal_mode,
            "cameras": list(calibration.cameras),
            "camera_range": None if calibration.domain is None else calibration.domain.describe(),
            "data": calibration.provenance.get("data")}  # fmt: skip


def held_out_note(calibration: MeasureCalibration) -> str:
    """How far a calibration's intervals can be trusted off the clips it was fitted on: each source's coverage
    when the calibration is fitted on the other sources only (its provenance's `held_out_by_source_coverage_90`),
    or, for a calibration of one source, that no other source has checked it."""
    held = calibration.provenance.get("held_out_by_source_coverage_90")
    what = "the 3d_ features' intervals" if calibration.scope == "clips" else "the frame measures' intervals"
    if not held:
        return (f"{what} were fitted on one clip source; on clips unlike it (real movement) they may hold the truth "
                "less often than their level says")  # fmt: skip
    per_source = ", ".join(f"{100 * fams['all']:.0f} % ({source})" for source, fams in sorted(held.items()))
    low = min(fams["all"] for fams in held.values())
    unlike = "both sources" if len(held) == 2 else "every source"
    trust = "" if low >= 0.85 else f"; read them as approximate on clips unlike {unlike}"
    fitted = f"{'clips' if calibration.scope == 'clips' else 'lifts'} of {plural(len(held), 'source')}"
    return (f"{what} were fitted on {fitted}; each source scored by a fit on the others alone, "
            f"their 90 % intervals held the truth in {per_source} of cases{trust}")  # fmt: skip


def backing_note(calibration: MeasureCalibration) -> str:
    b = backing(calibration)
    where = f"; {b['camera_range']}" if b["camera_range"] else ""
    return (f"{b['scope']} intervals backed by measure calibration {b['id']} (temporal {b['temporal_mode']}, "
            f"{', '.join(b['cameras'])} camera{where}; {b['data'] or 'data not recorded'})")  # fmt: skip
