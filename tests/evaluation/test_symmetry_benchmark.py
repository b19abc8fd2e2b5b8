"""Cohen's kappa, the comparison of measures, and the SyRIP symmetry benchmark (the last one
slow and skipped without ../shared/data/syrip)."""

from __future__ import annotations

import numpy as np
import pytest
from analysis_poses import SKEL, set_limb, standing, to_array
from helpers import SYRIP_DIR

from zedo_cli.data.datasets import load_syrip_3d
from zedo_cli.evaluation.metrics import cohen_kappa
from zedo_cli.evaluation.symmetry_benchmark import compare_measures, load_syrip_hwhup, run_symmetry_benchmark
from zedo_cli.lifting.config import get_preset
from zedo_cli.prior.weights import bundled_prior_path, load_prior

needs_syrip = pytest.mark.skipif(not SYRIP_DIR.is_dir(), reason="SyRIP data not found at ../shared/data/syrip")


def test_kappa_of_a_hand_computed_table() -> None:
    # 50 items: both yes 20, A yes / B no 5, A no / B yes 10, both no 15.
    # p_o = 35/50 = 0.7; A says yes 25/50, B 30/50: p_e = 0.5 * 0.6 + 0.5 * 0.4 = 0.5; kappa = 0.2 / 0.5 = 0.4
    a = ["yes"] * 20 + ["yes"] * 5 + ["no"] * 10 + ["no"] * 15
    b = ["yes"] * 20 + ["no"] * 5 + ["yes"] * 10 + ["no"] * 15
    assert cohen_kappa(np.array(a), np.array(b)) == pytest.approx(0.4)
    assert cohen_kappa(np.array(a), np.array(a)) == pytest.approx(1.0)
    flipped = np.where(np.array(a) == "yes", "no", "yes")
    assert cohen_kappa(np.array(a), flipped) == pytest.approx(-1.0)  # a balanced set: complete disagreement
    assert np.isnan(cohen_kappa(np.array(["s", "s"]), np.array(["s", "s"])))  # p_e = 1
    with pytest.raises(ValueError):
        cohen_kappa(np.array(["s"]), np.array(["s", "a"]))


def test_compare_measures_on_known_poses() -> None:
    poses = []
    for bend in (0.0, 10.0, 50.0, 70.0):
        pts = standing()
        set_limb(pts, "left", "leg", 0.0, 0.0, bend=bend)
        poses.append(to_array(pts))
    truth = np.array(poses)
    same = compare_measures(truth, truth, SKEL)
    assert same.mean_angle_error_deg == pytest.approx(0.0, abs=1e-9) and same.agreement == 1.0
    assert same.kappa["symmetry_shank_deg"] == pytest.approx(1.0)
    assert same.mean_joint_angle_error_deg == pytest.approx(0.0, abs=1e-9)
    # predict every knee bend 20 degrees larger: shank error 20, calls change only at bend 10 (-> 30)
    pred = []
    for bend in (20.0, 30.0, 70.0, 90.0):
        pts = standing()
        set_limb(pts, "left", "leg", 0.0, 0.0, bend=bend)
        pred.append(to_array(pts))
    s = compare_measures(np.array(pred), truth, SKEL)
    assert s.angle_error_deg["symmetry_shank_deg"] == pytest.approx(20.0, abs=1e-6)
    assert s.angle_error_deg["symmetry_thigh_deg"] == pytest.approx(0.0, abs=1e-6)
    assert s.joint_angle_error_deg["left_knee_flexion_deg"] == pytest.approx(20.0, abs=1e-6)
    # shank calls: truth s, s, a, a; predicted s, a, a, a -> p_o 3/4, p_e = 1/2*1/4 + 1/2*3/4 = 1/2, kappa 1/2
    assert s.kappa["symmetry_shank_deg"] == pytest.approx(0.5)


@needs_syrip
def test_hwhup_reference_poses_are_the_test_rows() -> None:
    truth = load_syrip_3d(SYRIP_DIR, "test")
    hwhup = load_syrip_hwhup(SYRIP_DIR, truth.names)
    assert hwhup.shape == (100, 12, 3)
    # the weak truth was made by rotating HW-HuP's bones: the same bone lengths
    bones = np.array(SKEL.bones)
    lengths = lambda p: np.linalg.norm(p[:, bones[:, 0]] - p[:, bones[:, 1]], axis=-1)  # noqa: E731
    limbs = [i for i, (a, b) in enumerate(SKEL.bones) if SKEL.joints[a].split("_")[0] == SKEL.joints[b].split("_")[0]]
    np.testing.assert_allclose(lengths(hwhup)[:, limbs], lengths(truth.poses)[:, limbs], atol=1e-4)


@pytest.mark.slow
@needs_syrip
def test_symmetry_benchmark_on_test100() -> None:
    """The figures of docs/uncertainty.md and docs/clinical.md: the bundled prior, fast preset; the HW-HuP
    reference reaches ~0.65."""
    prior = load_prior(bundled_prior_path(), skeleton="syrip12")
    bench = run_symmetry_benchmark(SYRIP_DIR, prior, get_preset("fast"))
    by = {s.source: s for s in bench.scores}
    assert sorted(by) == ["detected", "gt", "hwhup"]
    assert 0.3 < bench.truth_asymmetric_share < 0.5
    for key in ("gt", "detected"):
        assert 12.0 < by[key].mean_angle_error_deg < 22.0 and 0.2 < by[key].pooled_kappa < 0.5
    assert by["hwhup"].pooled_kappa == pytest.approx(0.65, abs=0.03)
    assert by["hwhup"].mean_angle_error_deg < by["gt"].mean_angle_error_deg
