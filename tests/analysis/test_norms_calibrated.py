"""The calibrated p of the comparison with typical infants (analysis.norms.calibrated): its false-alarm rate is what
it says on heavy-tailed features, where the published normal z is not, and a clear one-sided difference still
shows."""

from __future__ import annotations

import math

import numpy as np
import pytest

from zedo_cli.analysis.norms.calibrated import (
    RELIABILITY_FILE,
    RELIABLE_ICC,
    ReliabilityEntry,
    bundled_reliability,
    calibrated_surprise,
    leave_one_out_scores,
    reliable_features,
)
from zedo_cli.analysis.norms.norms import ClipValues, build_norms, compare
from zedo_cli.errors import WeightsError
from zedo_cli.stats import icc_agreement


def _heavy_tailed(rng: np.random.Generator, rows: int, features: int = 40) -> np.ndarray:
    return rng.standard_t(3.0, size=(rows, features)) * np.linspace(0.5, 5.0, features) + 10.0


def test_a_typical_clip_gets_p_below_005_about_one_time_in_21() -> None:
    rng = np.random.default_rng(0)
    trials = 1200
    flagged = sum(calibrated_surprise(*_split(_heavy_tailed(rng, 21))).p < 0.05 for _ in range(trials))
    # exchangeable clips: P(p <= 1/21) = 1/21 exactly (0.048); 3 standard errors either side
    assert abs(flagged / trials - 1 / 21) < 3 * math.sqrt(1 / 21 * 20 / 21 / trials)


def _split(m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return m[-1], m[:-1]


def test_the_smallest_p_is_one_over_n_plus_one_and_a_clear_difference_gets_it() -> None:
    rng = np.random.default_rng(1)
    reference = _heavy_tailed(rng, 20)
    clip = _heavy_tailed(rng, 1)[0]
    clip[:3] += 40 * np.linspace(0.5, 5.0, 40)[:3]  # three features far outside
    s = calibrated_surprise(clip, reference)
    assert s.p == pytest.approx(1 / 21) and s.features == 40 and s.reference_clips == 20


def test_the_score_is_each_rows_mean_squared_robust_z_from_the_others() -> None:
    m = np.array([[0.0, 1.0], [1.0, 2.0], [2.0, 4.0], [10.0, 3.0]])
    others = m[1:]
    centre = np.median(others, 0)
    scale = np.maximum(1.4826 * np.median(np.abs(others - centre), 0), 0.25 * others.std(0))
    assert leave_one_out_scores(m)[0] == pytest.approx(np.mean(((m[0] - centre) / scale) ** 2))


def test_features_the_clip_lacks_are_left_out() -> None:
    rng = np.random.default_rng(2)
    reference = _heavy_tailed(rng, 20)
    clip = _heavy_tailed(rng, 1)[0]
    clip[5] = np.nan
    assert calibrated_surprise(clip, reference).features == 39


def test_the_normal_recipe_false_alarms_on_heavy_tails_the_calibrated_ps_do_not() -> None:
    """The reason the calibrated p exists: with heavy-tailed features the published recipe's normal p (a summed
    log-likelihood's z) is under 0.05 far more often than 1 time in 20 for clips drawn like the reference's; the
    extended and asymmetry comparisons' conformal p are not."""
    from zedo_cli.analysis.norms.norms import ALL_AGES, summed_surprise, with_asymmetry

    rng = np.random.default_rng(3)
    names = [f"asym_logratio_feature_{k}" for k in range(40)]
    entries = (ReliabilityEntry(source="test", clips=3, temporal_mode="smooth", icc=dict.fromkeys(names, 1.0),
                                provenance={}),)  # fmt: skip
    normal = extended = asymmetry = 0
    for _ in range(15):
        m = _heavy_tailed(rng, 40)
        # the 38 published features are needed to build a reference: give them normal, harmless values
        pub = rng.normal(1.0, 0.1, (40, 38))
        clips = [ClipValues(str(i), 0, {**dict(zip(names, m[i], strict=True)), **_published(pub[i])})
                 for i in range(40)]  # fmt: skip
        norms = build_norms(clips[:20], "x")
        for c in clips[20:]:
            comp = compare(c.values, norms, None, reliability=entries)
            normal += summed_surprise(with_asymmetry(c.values), norms, ALL_AGES, names).p < 0.05
            extended += comp.extended.p < 0.05
            asymmetry += comp.asymmetry.p < 0.05
    assert normal / 300 > 0.15
    assert extended / 300 < 0.09 and asymmetry / 300 < 0.09


def _published(values: np.ndarray) -> dict[str, float]:
    from zedo_cli.analysis.clip.published_features import PREREGISTERED

    return dict(zip(PREREGISTERED, values.tolist(), strict=True))


def test_only_features_reliable_on_every_source_take_part() -> None:
    a = ReliabilityEntry(source="a", clips=40, temporal_mode="smooth", icc={"x": 0.95, "y": 0.95, "z": 0.5},
                         provenance={})  # fmt: skip
    b = ReliabilityEntry(source="b", clips=40, temporal_mode="smooth", icc={"x": 0.99, "y": 0.85}, provenance={})
    assert reliable_features(["x", "y", "z", "w"], [a, b]) == ["x"]


def test_the_bundled_reliability_file_reads_and_round_trips(tmp_path) -> None:  # noqa: ANN001
    entries = bundled_reliability()
    assert entries, "zedo_cli/weights/reliability.json is shipped"
    assert all(e.clips >= 40 and len(e.icc) > 100 for e in entries)
    assert any(v < RELIABLE_ICC for e in entries for v in e.icc.values())  # the gate keeps some out
    path = tmp_path / "reliability.json"
    RELIABILITY_FILE.write(path, entries)
    assert tuple(RELIABILITY_FILE.read(path)) == entries
    path.write_text(path.read_text().replace('"clips"', '"klips"', 1))
    with pytest.raises(WeightsError, match="reliability.json: unreadable clip feature reliability"):
        RELIABILITY_FILE.read(path)


def test_icc_of_a_retest_with_an_offset_is_lower_than_one() -> None:
    rng = np.random.default_rng(4)
    truth = rng.normal(0.0, 1.0, 200)
    assert icc_agreement(np.c_[truth, truth]) == pytest.approx(1.0)
    assert icc_agreement(np.c_[truth, truth + 1.0]) == pytest.approx(1 / (1 + 0.5), abs=0.05)  # offset^2 / 2 added
    assert math.isnan(icc_agreement(np.c_[truth[:2], truth[:2]]))
