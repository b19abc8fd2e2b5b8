"""A clip much longer than the reference's clips is compared by its epochs, each as long as the reference's clips:
the feature z of the epochs' medians and the calibrated p of the median epoch; the published comparison stays on
the whole clip, as published."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from analysis_results import kicking_poses, write_document
from test_calibration import calibration, document
from test_norms import EXTENDED, VERSION, _all_reliable, _clip, _reference

from zedo_cli.analysis.analyse import AnalysisSettings, analyse
from zedo_cli.analysis.compare import compared, epoch_values, features_by_person, length_mismatch
from zedo_cli.analysis.norms.calibrated import NULL_DRAWS, effective_epochs, epochs_surprise, leave_one_out_scores
from zedo_cli.analysis.norms.norms import build_norms, compare
from zedo_cli.analysis.report.clip_report import comparison_block
from zedo_cli.formats.readers.result import read_result


def _analysed(tmp_path: Path, poses: np.ndarray, name: str) -> object:
    doc = document(poses, fps=30.0, temporal="smooth")
    return analyse(read_result(write_document(tmp_path / name, doc)), AnalysisSettings(),
                   calibrations=[calibration("smooth", width=5.0)])  # fmt: skip


def test_an_epochs_features_are_those_of_the_same_frames_analysed_alone(tmp_path: Path) -> None:
    poses = kicking_poses(90)
    long = _analysed(tmp_path, poses, "long.zedo.json")
    epochs = epoch_values(long, 0, 1.0)
    assert len(epochs) == 3
    alone = features_by_person(_analysed(tmp_path, poses[30:60], "alone.zedo.json"))[0].values
    rates = {n for n in alone if "_fraction_" in n or n.endswith("_share_asymmetric") or n.startswith("head_")}
    assert set(epochs[1]) == set(alone) - rates  # shares and fractions are rates already: the whole clip's are used
    for name, value in epochs[1].items():
        assert value == pytest.approx(alone[name], nan_ok=True), name


def test_epochs_alike_count_as_one_clip_and_are_ranked_among_the_reference_clips_scores() -> None:
    rng = np.random.default_rng(0)
    reference = rng.normal(size=(20, 6))
    epochs = np.repeat(rng.normal(size=(1, 6)), 5, axis=0)  # five epochs of one infant who never changes
    epochs[:, 0] = np.nan  # a feature no epoch has is left out
    s = epochs_surprise(epochs, reference)
    others = leave_one_out_scores(reference[:, 1:])
    assert s.features == 5 and s.epochs == 5 and s.reference_clips == 20
    assert s.epoch_agreement == 1.0 and s.independent_epochs == 1
    assert s.p == pytest.approx(np.mean(others >= s.score), abs=0.02)
    far = epochs_surprise(epochs + 10.0, reference)
    assert far.p == pytest.approx(1 / (1 + NULL_DRAWS))


def test_epochs_that_vary_as_typical_clips_do_count_as_as_many_independent_clips() -> None:
    rng = np.random.default_rng(1)
    reference = rng.normal(size=(40, 60))
    s = epochs_surprise(rng.normal(size=(6, 60)), reference)
    assert s.epoch_agreement < 0.2 and s.independent_epochs >= 5
    assert effective_epochs(6, 0.0) == 6 and effective_epochs(6, 1.0) == 1 and effective_epochs(6, 0.5) == 2


@pytest.mark.parametrize("agreement", [0.0, 0.9])
def test_long_typical_clips_are_called_atypical_about_as_often_as_the_level_says(agreement: float) -> None:
    """Typical clips of 6 epochs, their epochs independent or alike (an infant's own way of moving): p < 0.05 for
    1-10 % of them over several references; ranked as single clips, independent epochs were never called."""
    calls = []
    for draw in range(6):
        rng = np.random.default_rng(draw)
        reference = rng.standard_t(5, size=(20, 30))  # heavy-tailed features, as clip features are
        for _ in range(25):
            infant = rng.standard_t(5, size=30) * np.sqrt(agreement)
            epochs = infant + rng.standard_t(5, size=(6, 30)) * np.sqrt(1 - agreement)
            calls.append(epochs_surprise(epochs, reference).p < 0.05)
    assert 0.01 <= np.mean(calls) <= 0.1


def test_a_long_typical_clip_is_typical_and_a_long_still_arm_is_not() -> None:
    norms = build_norms(_reference(), VERSION)
    reliable = _all_reliable(EXTENDED)
    rng = np.random.default_rng(11)
    typical = [_clip(rng, i).values for i in range(6)]
    whole = {**typical[0], "medianvelx_LWrist": 50.0}  # a whole-clip value that grew with the length
    c = compare(whole, norms, None, reliability=reliable, epochs=typical)
    assert c.extended.epochs == 6 and c.extended.p > 0.05
    assert c.z["medianvelx_LWrist"] == pytest.approx(
        (np.median([e["medianvelx_LWrist"] for e in typical]) - norms.fits["all"]["medianvelx_LWrist"].mean)
        / norms.fits["all"]["medianvelx_LWrist"].sd)  # fmt: skip
    assert c.published == compare(whole, norms, None, reliability=reliable).published  # as published: whole clip
    still = [_clip(rng, 50 + i, shift=-1.5).values for i in range(6)]
    assert compare(still[0], norms, None, reliability=reliable, epochs=still).extended.p < 0.05


def test_a_clip_over_twice_the_references_length_says_it_is_compared_by_epochs(tmp_path: Path) -> None:
    norms = build_norms([replace(c, seconds=1.0) for c in _reference()], VERSION)
    note = length_mismatch(norms, 3.0)
    assert note is not None and "take its epochs of 1 s" in note
    assert "build a reference of clips as long" in length_mismatch(norms, 0.4)
    assert length_mismatch(norms, 1.5) is None
    a = _analysed(tmp_path, kicking_poses(90), "k.zedo.json")
    a = compared(a, norms, None)
    (pc,) = a.comparisons
    assert pc.comparison.extended.epochs == 3 and pc.comparison.asymmetry.epochs == 3
    assert note in a.notes
    block = comparison_block(a)
    assert "of its 3 epochs as long as the reference's clips" in block
    assert "compared by its epochs: about 1 time in 20" in block and "smallest p is 0.0001" in block
    assert "smallest p is 0.048" not in block


def test_epochs_against_a_reference_with_no_score_of_its_own_are_not_called() -> None:
    rng = np.random.default_rng(2)
    s = epochs_surprise(rng.normal(size=(3, 4)) + 10.0, rng.normal(size=(2, 4)))  # each clip has one other: no z
    assert np.isfinite(s.score) and s.p == 1.0
