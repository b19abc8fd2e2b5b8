"""The reference file of `zedo norms` (schema `zedo.norms/1`): a pydantic model, its reader (one-line errors
naming the file and field, another zedo or feature-set version refused) and its writer."""

from __future__ import annotations

import json
import math
from datetime import UTC, datetime
from pathlib import Path
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError

from ...errors import InputFormatError
from ...files import write_text_atomic
from ...formats.readers.source import load_json
from .norms import AGE_THRESHOLD_WEEKS, FEATURE_SET_VERSION, NORMS_SCHEMA, ClipValues, FeatureFit, Norms


class _Closed(BaseModel):
    model_config = ConfigDict(extra="forbid")


class FitModel(_Closed):
    mean: float
    sd: float = Field(gt=0)
    n: int = Field(ge=1)


class ClipModel(_Closed):
    source: str
    person: int
    age_weeks: float | None
    bracket: str
    values: dict[str, float | None] = Field(description="every clip feature of this reference clip (null: none)")
    lifting: str | None = Field(None, description="how its result was lifted: prior, temporal mode, kind of camera")
    seconds: float | None = Field(None, description="how long the clip's track lasts (null: not recorded)")


class NormsDocument(_Closed):
    schema_: Literal["zedo.norms/1"] = Field(alias="schema")
    zedo_version: str
    feature_set_version: str
    created: str
    age_threshold_weeks: float
    brackets: list[str]
    fits: dict[str, dict[str, FitModel]] = Field(description="bracket -> feature -> normal fit (maximum likelihood)")
    left_out: dict[str, list[str]] = Field(description="bracket -> features without a usable fit")
    clips: list[ClipModel]


def _finite_or_none(x: float) -> float | None:
    return x if math.isfinite(x) else None


def write_norms(path: str | Path, norms: Norms, *, overwrite: bool = False) -> None:
    doc = {
        "schema": NORMS_SCHEMA,
        "zedo_version": norms.zedo_version,
        "feature_set_version": norms.feature_set_version,
        "created": datetime.now(UTC).isoformat(timespec="seconds"),
        "age_threshold_weeks": AGE_THRESHOLD_WEEKS,
        "brackets": norms.brackets,
        "fits": {b: {n: vars(f) for n, f in fits.items()} for b, fits in norms.fits.items()},
        "left_out": norms.left_out,
        "clips": [
            {"source": c.source, "person": c.person, "age_weeks": c.age_weeks, "bracket": b,
             "values": {k: _finite_or_none(v) for k, v in sorted(c.values.items())}, "lifting": c.lifting,
             "seconds": c.seconds}
            for c, b in zip(norms.clips, norms.brackets_of_clips, strict=True)
        ],
    }  # fmt: skip
    write_text_atomic(path, json.dumps(doc, indent=1, allow_nan=False) + "\n", overwrite=overwrite)


def read_norms(path: str | Path, zedo_version: str) -> Norms:
    """A reference written by `zedo norms` of this zedo version and feature set; InputFormatError otherwise."""
    name = str(path)
    raw = load_json(name)  # one-line errors for a missing, unreadable or malformed file
    if not isinstance(raw, dict) or raw.get("schema") != NORMS_SCHEMA:
        got = raw.get("schema") if isinstance(raw, dict) else type(raw).__name__
        raise InputFormatError(f"{name}: schema: expected a zedo reference of typical infants ({NORMS_SCHEMA}, "
                               f"made by zedo norms), got {got!r}")  # fmt: skip
    if raw.get("feature_set_version") != FEATURE_SET_VERSION:
        raise InputFormatError(f"{name}: feature_set_version: built with {raw.get('feature_set_version')!r}, this "
                               f"zedo computes {FEATURE_SET_VERSION}: rebuild it with zedo norms")  # fmt: skip
    if raw.get("zedo_version") != zedo_version:
        raise InputFormatError(f"{name}: zedo_version: built by zedo {raw.get('zedo_version')!r}, this is zedo "
                               f"{zedo_version}: rebuild it with this version's zedo norms")  # fmt: skip
    try:
        doc = NormsDocument.model_validate(raw)
    except ValidationError as exc:
        e = exc.errors()[0]
        where = ".".join(str(p) for p in e["loc"])
        raise InputFormatError(f"{name}: {where}: {e['msg']}") from None
    for b in doc.brackets:
        if b not in doc.fits:
            raise InputFormatError(f"{name}: fits: no fits for the bracket {b!r}")
    clips = [
        ClipValues(
            c.source,
            c.person,
            {k: math.nan if v is None else v for k, v in c.values.items()},
            c.age_weeks,
            c.lifting,
            c.seconds,
        )  # fmt: skip
        for c in doc.clips
    ]
    fits = {b: {n: FeatureFit(f.mean, f.sd, f.n) for n, f in fs.items()} for b, fs in doc.fits.items()}
    return Norms(doc.brackets, fits, clips, [c.bracket for c in doc.clips], doc.left_out, doc.zedo_version,
                 doc.feature_set_version)  # fmt: skip
