"""A clip's features as `zedo norms` collects them, and its comparison with a reference as rows of the
analysis (`zedo analyze --norms`)."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ..formats.readers.result_record import LiftParams
from ..lifting.config import PRESETS, calibration_settings, settings_match
from .analyse import Analysis, Row
from .clip.clip_features import epoch_features
from .clip.movement import movement_values
from .norms.norms import ClipValues, Comparison, Norms, compare, is_lift_artifact
from .table import clip_row

# The `interval` column of the comparison rows: a z or p has no interval of its own.
INTERVAL_COMPARISON = "none: comparison with the reference"
Z_SUFFIX = "_norm_z"


def _preset_of(config: Mapping[str, Any] | None) -> str:
    """The preset whose settings a result's recorded `config` has ("other settings" for none, "unknown" when
    the result records none)."""
    if config is None:
        return "unknown settings"
    wanted = calibration_settings(dict(config))
    return next((f"preset {name}" for name, cfg in PRESETS.items()
                 if settings_match(calibration_settings(cfg), wanted)), "other settings")  # fmt: skip


def lifting_of(params: dict) -> str:
    """How a result was lifted, as far as its clip features depend on it: the prior, the lifting settings, the
    temporal mode and the kind of camera (`params` of the result; "unknown" for what it does not record)."""
    lift = LiftParams.from_dict(params)
    sources = lift.camera_sources or ()
    camera = "unknown camera" if not sources else "pseudo camera" if set(sources) == {"pseudo"} else "known camera"
    sha, mode = lift.prior_sha256, "none" if lift.temporal_mode is None else lift.temporal_mode
    return (f"prior {'unknown' if sha is None else sha[:12]}, {_preset_of(lift.config)}, "
            f"temporal {mode}, {camera}")  # fmt: skip


def features_by_person(a: Analysis, age_weeks: float | None = None) -> list[ClipValues]:
    """Per person track of a clip: its clip-level features (the rows without a frame), NaN where empty. The
    measured value (`raw_value`) where a calibration gave an estimate: a reference and a clip are compared on
    what was measured, whichever calibration (or none) held for each. Counts of the lift's flagged frames are left
    out: they measure the lift, not the infant."""
    out: dict[int, dict[str, float]] = {}
    for r in a.clip_rows:
        if not r.measure.endswith(Z_SUFFIX) and not is_lift_artifact(r.measure):
            measured = r.raw_value if np.isfinite(r.raw_value) else r.value
            out.setdefault(r.person, {})[r.measure] = float(measured)
    lifting = lifting_of(a.result.params)
    return [ClipValues(a.result.source, p, values, age_weeks, lifting, track_seconds(a, p))
            for p, values in sorted(out.items())]  # fmt: skip


def track_seconds(a: Analysis, person: int) -> float | None:
    """How long person `person`'s track lasts in the analysed frames, first to last (None without an fps)."""
    frames = a.result.frame_index[a.index][a.result.person[a.index] == person]
    if not a.fps or not len(frames):
        return None
    return float((frames.max() - frames.min() + 1) / a.fps)


def reference_seconds(norms: Norms) -> float | None:
    """The median length of the reference's clips (None: its clips do not record it)."""
    known = [c.seconds for c in norms.clips if c.seconds is not None]
    return float(np.median(known)) if known else None


def in_epochs(typical: float | None, seconds: float | None) -> bool:
    """Whether a clip of `seconds` is compared by its epochs: over LENGTH_RATIO times as long as the reference's
    clips (`typical`, their median length)."""
    return seconds is not None and typical is not None and seconds > LENGTH_RATIO * typical


def length_mismatch(norms: Norms, seconds: float | None) -> str | None:
    """A note where the clip lasts over LENGTH_RATIO times as long (or as short) as the reference's clips' median
    (None: alike, or either side does not say)."""
    typical = reference_seconds(norms)
    if seconds is None or typical is None:
        return None
    ratio = seconds / typical
    if 1 / LENGTH_RATIO <= ratio <= LENGTH_RATIO:
        return None
    if in_epochs(typical, seconds):
        return (f"this clip's track lasts {seconds:.0f} s, the reference's clips a median {typical:.0f} s ({ratio:.1f} "
                f"times as long): the feature z and the extended and asymmetry p take its epochs of {typical:.0f} s "
                "(the median epoch); the published z and p stay on the whole clip, as published, where ranges and "
                "entropies grow with a clip's length")  # fmt: skip
    return (f"this clip's track lasts {seconds:.0f} s, the reference's clips a median {typical:.0f} s ({ratio:.1f} "
            "times as long): features that grow with a clip's length (ranges, entropies) are compared across lengths; "
            "build a reference of clips as long as the clips compared with it")  # fmt: skip


def epoch_values(a: Analysis, person: int, seconds: float) -> list[dict[str, float]]:
    """The measured clip features of each whole epoch of `seconds` of a person's track (as `features_by_person`
    gives the whole clip's): the published 2D and `3d_` features and the joint angles' `movement_values`."""
    fps = float(a.fps or 0.0)
    per = max(1, int(round(seconds * fps)))
    epochs = epoch_features(a.result, a.index, fps, person, per)
    res = a.result
    mine = res.person[a.index] == person
    first = int(res.frame_index[res.person == person].min())
    frames = res.frame_index[a.index]
    epoch_of = (frames - first) // per
    for k, values in enumerate(epochs):
        values.update(movement_values(frames, mine & (epoch_of == k), fps, estimates=a.values, own=a.raw_values,
                                      too_fast=a.too_fast))  # fmt: skip
    return epochs


@dataclass(frozen=True)
class PersonComparison:
    person: int
    comparison: Comparison
    lifting_mismatch: str | None = None  # `lifting_mismatch`'s note where the reference was lifted otherwise


def compared(a: Analysis, norms: Norms, age_weeks: float | None) -> Analysis:
    """The clip `a` compared with `norms`, each person track: per feature its z (`<feature>_norm_z`), and
    `surprise_published_z` / `_p`, and the calibrated `surprise_extended_score` / `_p` and
    `surprise_asymmetry_score` / `_p`, as clip rows, the comparisons (`PersonComparison`) and the reference; notes
    say what was left out. A result without fps has no clip features: only a note says so."""
    if not a.is_sequence:
        return replace(a, notes=(*a.notes, "no comparison with the reference: the result has no fps, so no clip "
                                           "features"))  # fmt: skip
    rows: list[Row] = []
    notes: list[str] = []
    done = []
    clips = features_by_person(a, age_weeks)
    mismatch = lifting_mismatch(norms, clips[0].lifting) if clips else None  # one result: every track alike
    typical = reference_seconds(norms)
    for clip in clips:
        epochs = epoch_values(a, clip.person, typical) if typical and in_epochs(typical, clip.seconds) else None
        c = compare(clip.values, norms, age_weeks, epochs=epochs)
        p = clip.person

        def add(measure: str, value: float, unit: str, p: int = p) -> None:
            rows.append(clip_row(p, measure, value, unit, INTERVAL_COMPARISON, a.settings.level))

        for name in sorted(c.z):
            add(f"{name}{Z_SUFFIX}", c.z[name], "z")
        add("surprise_published_z", c.published.z, "z")
        add("surprise_published_p", c.published.p, "p")
        add("surprise_published_features", float(c.published.features), "features")
        for kind, cal in (("extended", c.extended), ("asymmetry", c.asymmetry)):
            add(f"surprise_{kind}_score", cal.score, "mean z^2")
            add(f"surprise_{kind}_p", cal.p, "p")
            add(f"surprise_{kind}_features", float(cal.features), "features")
        if c.not_compared:
            shown = ", ".join(c.not_compared[:5]) + (", ..." if len(c.not_compared) > 5 else "")
            notes.append(f"person {p}: {len(c.not_compared)} reference features have no value in this clip and "
                         f"are left out of the comparison ({shown})")  # fmt: skip
        done.append(PersonComparison(p, c, mismatch))
    notes.append(f"compared with a reference of {len(norms.clips)} clips of typical infants "
                 f"(age brackets: {', '.join(norms.brackets)})")  # fmt: skip
    if mismatch is not None:
        notes.append(mismatch)
    notes.extend(dict.fromkeys(n for clip in clips if (n := length_mismatch(norms, clip.seconds)) is not None))
    return replace(a, clip_rows=(*a.clip_rows, *rows), notes=(*a.notes, *notes), comparisons=tuple(done),
                   reference=norms)  # fmt: skip


LENGTH_RATIO = 2.0  # a clip over twice as long or short as the reference's is compared with a note


def lifting_mismatch(norms: Norms, lifting: str | None) -> str | None:
    """A note where the reference's clips were lifted otherwise than this clip: its 3D features (`3d_`, the
    symmetry medians) are then measurements of another kind (None: alike, or either side does not say)."""
    known = sorted({c.lifting for c in norms.clips if c.lifting is not None})
    if lifting is None or not known or known == [lifting]:
        return None
    return (f"the reference's clips were lifted with {'; '.join(known)}, this clip with {lifting}: its 3D "
            "features (3d_, symmetry medians) are compared with ones measured otherwise; lift the reference "
            "and the clip alike")  # fmt: skip


def furthest_from_typical(c: Comparison, count: int = 5) -> list[tuple[str, float]]:
    """The features whose |z| is largest, most extreme first."""
    finite = [(n, z) for n, z in c.z.items() if math.isfinite(z)]
    order = np.argsort([-abs(z) for _, z in finite], kind="stable")
    return [finite[i] for i in order[:count]]
