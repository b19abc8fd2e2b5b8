"""The device benchmark (`zedo benchmark --scale`), run on the CPU with a tiny prior:
the synthetic inputs, the agreement's classes, the figures and their JSON, and the refusals."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from helpers import BASE_POSE, SKELETON, tiny_recipe

from zedo_cli.evaluation.device_benchmark import (
    CLASSES,
    IMAGE_SIZE,
    INPUT_BLOCK,
    ScaleSettings,
    classify_pairs,
    run_device_benchmark,
    synthetic_inputs,
)
from zedo_cli.lifting.config import get_preset
from zedo_cli.lifting.solver import LIFTED
from zedo_cli.prior.recipes import Recipe
from zedo_cli.prior.schedules import TrainConfig
from zedo_cli.prior.weights import Prior

FAST = replace(get_preset("fast"), steps=6, init_steps=10)
TINY_RECIPE = tiny_recipe(epochs=8000, batch_size=5000)


def _pose() -> np.ndarray:
    return BASE_POSE - BASE_POSE[list(SKELETON.root_indices)].mean(0)


def test_classes_of_constructed_pairs() -> None:
    joints = SKELETON.joints
    bones = np.asarray(SKELETON.bones)
    elbow, wrist = joints.index("left_elbow"), joints.index("left_wrist")
    base = _pose().copy()
    base[wrist, 2] = base[elbow, 2] + 0.06  # the forearm points 6 cm away from the camera
    a = np.repeat(base[None], 7, 0)
    b = a.copy()
    b[1, 3] += [0.0005, 0.0, 0.0]  # 0.5 mm off
    b[2, 3] += [0.0, 0.005, 0.0]  # 5 mm off
    b[3, wrist, 2] = base[elbow, 2] - 0.06  # the forearm's depth flipped: 12 cm
    b[4, 3] += [0.03, 0.0, 0.0]  # 30 mm off, no flip
    status_a = np.array([LIFTED] * 5 + ["poor_fit", LIFTED], dtype=object)
    status_b = np.array([LIFTED] * 5 + ["poor_fit", "behind_camera"], dtype=object)
    a[5], b[5], b[6] = np.nan, np.nan, np.nan  # not lifted: NaN, as lift() gives them
    cls, dist, flips = classify_pairs(a, b, status_a, status_b, bones)
    assert [CLASSES[c] for c in cls] == ["within_1mm", "within_1mm", "within_10mm", "depth_flip", "other_over_10mm",
                                         "same_refusal", "status_differs"]  # fmt: skip
    np.testing.assert_allclose(dist[:5], [0.0, 0.0005, 0.005, 0.12, 0.03], atol=1e-12)
    assert np.isnan(dist[5:]).all()
    forearm = [i for i, (p, c) in enumerate(bones) if {p, c} == {elbow, wrist}]
    assert np.flatnonzero(flips[3]).tolist() == forearm and not flips[[0, 1, 2, 4, 5, 6]].any()


def test_a_flat_segment_crossing_zero_depth_is_not_a_flip() -> None:
    joints = SKELETON.joints
    elbow, wrist = joints.index("left_elbow"), joints.index("left_wrist")
    a = _pose()[None].copy()
    a[0, wrist, 2] = a[0, elbow, 2] + 0.002  # nearly flat: 2 mm of depth, then -2 mm
    b = a.copy()
    b[0, wrist, 2] = a[0, elbow, 2] - 0.002
    status = np.array([LIFTED], dtype=object)
    cls, _, flips = classify_pairs(a, b, status, status, np.asarray(SKELETON.bones))
    assert CLASSES[cls[0]] == "within_10mm" and not flips.any()


def test_synthetic_inputs_repeat_and_a_larger_batch_starts_with_a_smaller_one() -> None:
    pool = np.repeat(_pose()[None], 5, 0) + np.random.default_rng(0).normal(0, 0.01, (5, 12, 3))
    xy, conf, k = synthetic_inputs(pool, INPUT_BLOCK + 10, seed=1)
    small, _, _ = synthetic_inputs(pool, 100, seed=1)
    np.testing.assert_array_equal(xy[:100], small)
    np.testing.assert_array_equal(xy, synthetic_inputs(pool, INPUT_BLOCK + 10, seed=1)[0])
    assert not np.array_equal(small, synthetic_inputs(pool, 100, seed=2)[0])
    assert np.isfinite(xy).all() and (conf == 1).all() and k.shape == (INPUT_BLOCK + 10, 3, 3)
    assert (xy >= 0).all() and (xy[..., 0] <= IMAGE_SIZE[0]).all() and (xy[..., 1] <= IMAGE_SIZE[1]).all()


def test_settings_are_checked() -> None:
    from zedo_cli.errors import ConfigError

    for bad in ({"sizes": ()}, {"sizes": (0,)}, {"agreement_poses": -1}, {"fit_epochs": 1}):
        with pytest.raises(ConfigError):
            ScaleSettings(**bad)  # type: ignore[arg-type]


def test_the_benchmark_runs_on_the_cpu(tiny_prior: Prior, tmp_path: Path) -> None:
    (tmp_path / "r.toml").write_text(TINY_RECIPE)
    from zedo_cli.prior.recipes import load_recipe

    recipe = load_recipe(tmp_path / "r.toml")
    stages: list[str] = []
    report = run_device_benchmark(
        tiny_prior, FAST, ScaleSettings((120, 200), agreement_poses=150, fit_epochs=3), device="cpu", preset="fast",
        recipe=recipe, on_stage=lambda label, n: stages.append(label) or None,
    )  # fmt: skip
    assert [r.count for r in report.runs] == [120, 200]
    assert all(r.poses_per_second > 0 and r.seconds > 0 and r.chunk_rows == FAST.chunk_size for r in report.runs)
    assert all(r.peak_memory_mib is None or r.peak_memory_mib > 0 for r in report.runs)
    assert stages[:2] == ["cpu, 120 poses", "cpu, 200 poses"] and stages[2] == "cpu, first 150 poses"
    a = report.agreement
    assert a is not None and a.poses == 150
    # the CPU against itself: the same bits, so every pose agrees (a refusal for the same reason too)
    assert a.share_within_1mm == 1.0 and a.counts["within_1mm"] + a.counts["same_refusal"] == 150
    assert sum(a.counts.values()) == 150 and not a.flipped_segments and a.largest == []
    fit = report.fit
    assert fit is not None and fit.epochs_run == 3 and fit.recipe_epochs == 8000 and fit.steps_per_epoch == 1
    assert fit.extrapolated_seconds == pytest.approx(fit.seconds_per_epoch * 8000)
    assert "sampled from" in report.pose_source


def test_fit_timing_counts_the_steps_of_an_epoch(tiny_prior: Prior) -> None:
    from zedo_cli.data.datasets import PoseSet
    from zedo_cli.evaluation.device_benchmark import time_fit_prior

    poses = np.repeat(_pose()[None], 30, 0)
    recipe = Recipe(model={"hidden": 32, "embed": 8, "num_blocks": 1, "groups": 4, "dropout": 0.0},
                    training=TrainConfig(epochs=50, batch_size=8))  # fmt: skip
    fit = time_fit_prior(PoseSet(poses, SKELETON, [str(i) for i in range(30)], "test"), recipe, 2, "cpu")
    assert fit.steps_per_epoch == 4 and fit.recipe_epochs == 50 and fit.poses == 30


def test_agreement_reports_shares_segments_and_the_largest_differences(tiny_prior: Prior) -> None:
    from helpers import K_TEST, project_poses, synthetic_poses

    from zedo_cli.evaluation.device_benchmark import agreement
    from zedo_cli.lifting.solver import lift

    n = 20
    xy = project_poses(synthetic_poses(n, seed=4))
    ref = lift(xy, np.ones((n, 12)), np.repeat(K_TEST[None], n, 0), tiny_prior, FAST)
    assert ref.lifted.all() and ref.status is not None
    poses, status = ref.poses_root_relative.copy(), ref.status.copy()
    poses[1, 5] += [0.0, 0.003, 0.0]  # 3 mm
    poses[2, 7] += [0.02, 0.0, 0.0]  # 20 mm
    poses[3] = np.nan
    status[3] = "poor_fit"
    other = replace(ref, poses_root_relative=poses, status=status)
    a = agreement(ref, other, tiny_prior)
    assert a.poses == n and a.both_lifted == n - 1
    assert a.counts["within_1mm"] == n - 3 and a.counts["within_10mm"] == 1 and a.counts["status_differs"] == 1
    assert a.counts["other_over_10mm"] + a.counts["depth_flip"] == 1
    assert a.share_within_1mm == pytest.approx((n - 3) / n) and a.share_within_10mm == pytest.approx((n - 2) / n)
    assert [w["pose"] for w in a.largest] == [2, 1, 3]
    assert a.largest[0]["max_joint_mm"] == pytest.approx(20.0, abs=1e-6)
    assert a.largest[0]["joint"] == SKELETON.joints[7]
    assert a.largest[2] == {"pose": 3, "class": "status_differs", "cpu": "lifted", "device": "poor_fit"}
