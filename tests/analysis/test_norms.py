"""The comparison with typical infants (analysis.norms.norms, analysis.norms.norms_file)."""

from __future__ import annotations

import json
import math
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

from zedo_cli.analysis.clip.published_features import PREREGISTERED as PUBLISHED_PART_FEATURES
from zedo_cli.analysis.norms.norms import (
    ALL_AGES,
    BRACKET_OLD,
    BRACKET_YOUNG,
    FEATURE_SET_VERSION,
    ClipValues,
    asymmetry_indices,
    build_norms,
    compare,
)
from zedo_cli.analysis.norms.norms_file import read_norms, write_norms
from zedo_cli.errors import ConfigError, InputFormatError

VERSION = "9.9.9"
SIDE_FEATURES = ("median_vel_angle_LElbow", "median_vel_angle_RElbow", "medianvelx_LWrist", "medianvelx_RWrist",
                 "3d_median_vel_angle_LKnee", "3d_median_vel_angle_RKnee", "lrCorr_angle_Knee",
                 "symmetry_forearm_median_deg")  # fmt: skip


def _clip(rng: np.random.Generator, i: int, age: float | None = None, shift: float = 0.0) -> ClipValues:
    values = {n: float(rng.normal(1.0 + k, 0.1 + 0.01 * k)) for k, n in enumerate(PUBLISHED_PART_FEATURES)}
    values.update({n: float(abs(rng.normal(2.0, 0.2))) for n in SIDE_FEATURES})
    values["median_vel_angle_LElbow"] += shift
    values["zedo_own_feature"] = float(rng.normal())
    return ClipValues(f"clip{i}.zedo.json", 0, values, age)


def _reference(n: int = 20, ages: list[float] | None = None, seed: int = 0) -> list[ClipValues]:
    rng = np.random.default_rng(seed)
    return [_clip(rng, i, None if ages is None else ages[i]) for i in range(n)]


def test_fits_are_maximum_likelihood_normals() -> None:
    clips = _reference()
    norms = build_norms(clips, VERSION)
    assert norms.brackets == [ALL_AGES]
    x = np.array([c.values["Knee_mean_angle"] for c in clips])
    fit = norms.fits[ALL_AGES]["Knee_mean_angle"]
    assert fit.mean == pytest.approx(x.mean()) and fit.sd == pytest.approx(x.std(ddof=0)) and fit.n == 20


def test_published_surprise_by_hand() -> None:
    clips = _reference()
    norms = build_norms(clips, VERSION)
    new = _clip(np.random.default_rng(99), 99).values
    c = compare(new, norms, None)

    def loglik(values: dict[str, float]) -> float:
        total = 0.0
        for n in PUBLISHED_PART_FEATURES:
            x = np.array([cl.values[n] for cl in clips])
            m, v = x.mean(), x.var()
            total += -(0.5 * math.log(2 * math.pi * v) + (values[n] - m) ** 2 / (2 * v))
        return total

    ref = np.array([loglik(cl.values) for cl in clips])
    z = (loglik(new) - ref.mean()) / ref.std(ddof=1)
    assert c.published.total == pytest.approx(loglik(new))
    assert c.published.z == pytest.approx(z)
    assert c.published.p == pytest.approx(math.erfc(abs(z) / math.sqrt(2)))
    assert c.published.features == 38 and c.published.reference_clips == 20


def _all_reliable(names: list[str]) -> tuple:
    from zedo_cli.analysis.norms.calibrated import ReliabilityEntry

    return (ReliabilityEntry(source="test", clips=40, temporal_mode="smooth", icc=dict.fromkeys(names, 1.0),
                             provenance={}),)  # fmt: skip


EXTENDED = [*SIDE_FEATURES, "asym_logratio_median_vel_angle_Elbow", "asym_logratio_medianvelx_Wrist",
            "asym_logratio_3d_median_vel_angle_Knee"]  # fmt: skip


def test_the_extended_comparison_is_calibrated_over_per_side_asymmetry_and_3d_features() -> None:
    """The extended p is the conformal p (calibrated.py) over the reliable per-side, asymmetry and 3D features:
    neither the published part-level features nor a feature without a retest's agreement take part."""
    from zedo_cli.analysis.norms.calibrated import calibrated_surprise

    clips = _reference()
    norms = build_norms(clips, VERSION)
    new = _clip(np.random.default_rng(7), 7).values
    names = sorted(EXTENDED)
    c = compare(new, norms, None, reliability=_all_reliable(names))
    full = [{**cl.values, **asymmetry_indices(cl.values)} for cl in clips]
    reference = np.array([[f[n] for n in names] for f in full])
    expected = calibrated_surprise(np.array([{**new, **asymmetry_indices(new)}[n] for n in names]), reference)
    assert c.extended == expected and c.extended.features == len(names) and c.extended.reference_clips == 20
    fewer = compare(new, norms, None, reliability=_all_reliable(names[:3]))  # the others not reliable
    assert fewer.extended.features == 3


def test_a_one_sided_difference_shows_in_the_extended_comparison() -> None:
    norms = build_norms(_reference(), VERSION)
    rng = np.random.default_rng(5)
    reliable = _all_reliable(EXTENDED)
    typical = [compare(_clip(rng, i).values, norms, None, reliability=reliable) for i in range(20)]
    still_left = compare(_clip(rng, 99, shift=-1.5).values, norms, None, reliability=reliable)  # a still left elbow
    assert sum(c.extended.p > 0.05 for c in typical) >= 16  # about 20 in 21 expected
    assert still_left.extended.p < 0.05
    assert still_left.z["median_vel_angle_LElbow"] < -5
    assert still_left.z["asym_logratio_median_vel_angle_Elbow"] < -5


def test_asymmetry_index_is_the_log_ratio() -> None:
    idx = asymmetry_indices({"median_vel_angle_LElbow": 2.0, "median_vel_angle_RElbow": 1.0,
                             "medianvelx_LWrist": 0.0, "medianvelx_RWrist": 1.0})  # fmt: skip
    assert idx["asym_logratio_median_vel_angle_Elbow"] == pytest.approx(math.log(2.0))
    assert math.isnan(idx["asym_logratio_medianvelx_Wrist"])  # not > 0: no index
    assert math.isnan(idx["asym_logratio_median_vel_angle_Knee"])  # absent


def test_age_brackets_split_at_ten_weeks() -> None:
    ages = [6.0] * 20 + [14.0] * 20
    norms = build_norms(_reference(40, ages), VERSION)
    assert norms.brackets == [BRACKET_YOUNG, BRACKET_OLD]
    assert compare(_reference(1)[0].values, norms, 10.0).bracket == BRACKET_YOUNG  # 10 weeks: the younger side
    assert compare(_reference(1)[0].values, norms, 10.5).bracket == BRACKET_OLD
    with pytest.raises(ConfigError, match="--age-weeks"):
        compare(_reference(1)[0].values, norms, None)
    young_only = build_norms(_reference(20, [6.0] * 20), VERSION)
    with pytest.raises(InputFormatError, match="outside its age brackets"):
        compare(_reference(1)[0].values, young_only, 20.0)


def test_refusals() -> None:
    with pytest.raises(ConfigError, match="at least 20 clips per age bracket; bracket all has 19"):
        build_norms(_reference(19), VERSION)
    with pytest.raises(ConfigError, match="bracket >10w has 4"):
        build_norms(_reference(24, [6.0] * 20 + [14.0] * 4), VERSION)
    with pytest.raises(ConfigError, match="some clips but not"):
        build_norms(_reference(20, [6.0] * 19 + [None]), VERSION)  # type: ignore[list-item]
    clips = _reference()
    for c in clips[:11]:
        c.values["Wrist_meanent"] = math.nan
    with pytest.raises(ConfigError, match="Wrist_meanent"):
        build_norms(clips, VERSION)


def test_a_clip_missing_a_feature_is_compared_on_the_others() -> None:
    norms = build_norms(_reference(), VERSION)
    values = _clip(np.random.default_rng(3), 3).values
    values["Knee_lrCorr_angle"] = math.nan
    c = compare(values, norms, None)
    assert c.published.features == 37 and "Knee_lrCorr_angle" in c.not_compared
    assert math.isfinite(c.published.z)


def test_file_round_trip_and_version_refusals(tmp_path: Path) -> None:
    norms = build_norms(_reference(), VERSION)
    path = tmp_path / "norms.json"
    write_norms(path, norms)
    back = read_norms(path, VERSION)
    new = _clip(np.random.default_rng(11), 11).values
    assert compare(new, back, None) == compare(new, norms, None)
    with pytest.raises(InputFormatError, match="zedo_version"):
        read_norms(path, "0.0.1")
    doc = json.loads(path.read_text())
    doc["feature_set_version"] = "zedo-clip-features/0"
    path.write_text(json.dumps(doc))
    with pytest.raises(InputFormatError, match="feature_set_version"):
        read_norms(path, VERSION)
    doc["feature_set_version"] = FEATURE_SET_VERSION
    doc["fits"]["all"]["Knee_mean_angle"]["sd"] = -1
    path.write_text(json.dumps(doc))
    with pytest.raises(InputFormatError, match=r"fits\.all\.Knee_mean_angle\.sd"):
        read_norms(path, VERSION)
    (tmp_path / "other.json").write_text('{"schema": "zedo.pose3d/1"}')
    with pytest.raises(InputFormatError, match="zedo norms"):
        read_norms(tmp_path / "other.json", VERSION)


_ORACLE = """
import sys, types, pickle, json
import numpy as np, pandas as pd
sys.modules.setdefault("seaborn", types.ModuleType("seaborn"))
sys.path.insert(0, sys.argv[1] + "/src/data")
import compute_surprise as C
rows = json.load(open(sys.argv[2]))
pd.DataFrame(rows).to_pickle(sys.argv[3] + "/features_merged.pkl")
C.main(sys.argv[3])
s = pd.read_pickle(sys.argv[3] + "/bayes_surprise.pkl")
json.dump({r.infant: r.z for r in s.itertuples()}, open(sys.argv[3] + "/z.json", "w"))
"""


def test_published_z_matches_the_published_code(tmp_path: Path) -> None:
    """compute_surprise.py on the same merged features: the z of reference and new clips agree to 0.05."""
    python = os.environ.get("ZEDO_CHAMBERS_PYTHON")
    code = Path(__file__).resolve().parents[3] / "shared" / "reference" / "chambers2020"
    if not python or not Path(python).exists() or not code.exists():
        pytest.skip("set ZEDO_CHAMBERS_PYTHON to the reference venv's python (shared/reference/chambers2020)")
    ages = [6.0] * 20 + [14.0] * 20
    clips = _reference(40, ages)
    rng = np.random.default_rng(42)
    new = [_clip(rng, 100 + i, age, shift=0.5 * i) for i, age in enumerate((5.0, 9.0, 12.0, 30.0))]
    rows = []
    for cl, risk in [*((c, 0) for c in clips), *((c, 1) for c in new)]:
        for name in PUBLISHED_PART_FEATURES:
            part, feature = name.split("_", 1)
            rows.append({"infant": cl.source, "part": part, "feature_name": feature, "Value": cl.values[name],
                         "category": risk, "age_in_weeks": cl.age_weeks, "risk": risk,
                         "age_bracket": int(cl.age_weeks > 10)})  # fmt: skip
    (tmp_path / "rows.json").write_text(json.dumps(rows))
    (tmp_path / "oracle.py").write_text(_ORACLE)
    subprocess.run([python, str(tmp_path / "oracle.py"), str(code), str(tmp_path / "rows.json"), str(tmp_path)],
                   check=True, capture_output=True, timeout=120)  # fmt: skip
    theirs = json.loads((tmp_path / "z.json").read_text())
    norms = build_norms(clips, VERSION)
    for c in [*clips, *new]:
        ours = compare(c.values, norms, c.age_weeks).published.z
        assert ours == pytest.approx(theirs[c.source], abs=0.05), c.source


def test_an_age_outside_0_to_200_weeks_is_refused_by_both_commands(tmp_path: Path) -> None:
    from typer.testing import CliRunner

    from zedo_cli.analysis.norms.norms import check_age_weeks
    from zedo_cli.cli import app

    check_age_weeks(None)
    check_age_weeks(12.0)
    with pytest.raises(ConfigError, match="between 0 and 200 weeks, got 500"):
        check_age_weeks(500.0)
    runner = CliRunner()
    (tmp_path / "r.zedo.json").write_text("{}")
    for args in (
        ["norms", str(tmp_path / "r.zedo.json"), "-o", str(tmp_path / "n.json"), "--age-weeks", "-1"],
        ["analyze", str(tmp_path / "r.zedo.json"), "--norms", str(tmp_path / "n.json"), "--age-weeks", "500"],
    ):
        result = runner.invoke(app, args)
        assert result.exit_code == 2 and "--age-weeks must be between 0 and 200 weeks" in result.output, result.output


def test_counts_of_the_lifts_flagged_frames_are_never_compared() -> None:
    clips = _reference()
    for i, c in enumerate(clips):
        c.values["Knee_flexion_frames_too_fast"] = float(i % 3)
    norms = build_norms(clips, VERSION)
    assert all("too_fast" not in n for fits in norms.fits.values() for n in fits)
    odd = {**_reference(1, seed=5)[0].values, "Knee_flexion_frames_too_fast": 400.0}
    c = compare(odd, norms, None)
    assert "Knee_flexion_frames_too_fast" not in c.z
    assert c.extended == compare(_reference(1, seed=5)[0].values, norms, None).extended
    older = build_norms(clips, VERSION)  # a reference written before: its fits hold such a count
    older.fits[ALL_AGES]["Knee_flexion_frames_too_fast"] = norms.fits[ALL_AGES]["Knee_mean_angle"]
    assert "Knee_flexion_frames_too_fast" not in compare(odd, older, None).z


def test_a_clip_much_longer_than_the_references_is_compared_with_a_note(tmp_path: Path) -> None:
    from dataclasses import replace

    from zedo_cli.analysis.compare import length_mismatch

    clips = [replace(c, seconds=10.0 + 0.1 * i) for i, c in enumerate(_reference())]
    norms = build_norms(clips, VERSION)
    assert length_mismatch(norms, 15.0) is None and length_mismatch(norms, 6.0) is None
    note = length_mismatch(norms, 60.0)
    assert note is not None and note.startswith("this clip's track lasts 60 s, the reference's clips a median 11 s")
    assert length_mismatch(norms, 3.0) is not None and length_mismatch(norms, None) is None
    write_norms(tmp_path / "n.json", norms)
    again = read_norms(tmp_path / "n.json", VERSION)
    assert [c.seconds for c in again.clips] == [c.seconds for c in clips]
    unknown = build_norms(_reference(), VERSION)  # a reference that does not record lengths: nothing to say
    assert length_mismatch(unknown, 60.0) is None
