"""Multiple hypotheses and the twin-limb term of the lifting loop, with a tiny prior."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
import torch
from helpers import K_TEST, SKELETON, project_poses, synthetic_poses

from zedo_cli.data.skeleton import twin_limb_ratio, twin_limbs
from zedo_cli.errors import ConfigError
from zedo_cli.lifting.config import LiftConfig
from zedo_cli.lifting.solver import lift, ray_pull
from zedo_cli.lifting.twin_limbs import cap_twin_ratios, twin_limb_step
from zedo_cli.prior.weights import Prior

BASE = LiftConfig(steps=40, init_steps=50, step_delta=None, release_fraction=0.15)
SPREAD = replace(BASE, hypotheses=4, start_jitter_m=0.05, hypothesis_noise=0.5)


def _inputs(n: int, seed: int = 3) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    poses = synthetic_poses(n, seed)
    return project_poses(poses), np.ones((n, 12)), np.repeat(K_TEST[None], n, 0)


def test_one_hypothesis_is_the_plain_lift_and_keeps_none(tiny_prior: Prior) -> None:
    xy, conf, k = _inputs(5)
    plain = lift(xy, conf, k, tiny_prior, BASE)
    first = lift(xy, conf, k, tiny_prior, replace(SPREAD, aggregate="first"))
    assert plain.hypotheses is None
    # hypothesis 0 is the deterministic lift, whatever the others do
    np.testing.assert_allclose(first.poses_camera, plain.poses_camera, atol=1e-5)


def test_hypotheses_are_seeded_different_and_aggregated(tiny_prior: Prior) -> None:
    xy, conf, k = _inputs(5)
    a = lift(xy, conf, k, tiny_prior, SPREAD, seed=7)
    b = lift(xy, conf, k, tiny_prior, SPREAD, seed=7)
    c = lift(xy, conf, k, tiny_prior, SPREAD, seed=8)
    np.testing.assert_array_equal(a.poses_camera, b.poses_camera)  # same seed, same output
    np.testing.assert_array_equal(a.hypotheses, b.hypotheses)
    assert not np.allclose(a.hypotheses, c.hypotheses)
    assert a.hypotheses.shape == (5, 4, 12, 3)
    spread = np.linalg.norm(a.hypotheses[:, 1:] - a.hypotheses[:, :1], axis=-1).mean()
    assert spread > 1e-3  # genuinely different solutions (metres)
    mean = a.hypotheses.mean(axis=1)  # root-relative mean of the hypotheses is the reported pose
    np.testing.assert_allclose(a.poses_root_relative, mean - mean[:, SKELETON.root_indices].mean(1, keepdims=True),
                               atol=1e-9)  # fmt: skip
    med = lift(xy, conf, k, tiny_prior, replace(SPREAD, aggregate="median"), seed=7)
    assert not np.allclose(med.poses_camera, a.poses_camera)


def test_hypotheses_of_an_instance_do_not_depend_on_the_chunking(tiny_prior: Prior) -> None:
    xy, conf, k = _inputs(3)
    whole = lift(xy, conf, k, tiny_prior, SPREAD, seed=1)
    again = lift(xy, conf, k, tiny_prior, replace(SPREAD, chunk_size=4096), seed=1)
    np.testing.assert_array_equal(whole.poses_camera, again.poses_camera)


def test_unlifted_instances_have_no_hypotheses(tiny_prior: Prior) -> None:
    xy, conf, k = _inputs(3)
    conf[1, 2:] = 0.0  # two joints left: not lifted
    res = lift(xy, conf, k, tiny_prior, SPREAD)
    assert not res.lifted[1] and np.isnan(res.hypotheses[1]).all()
    assert np.isfinite(res.hypotheses[[0, 2]]).all()


@pytest.mark.parametrize("bad", [{"hypotheses": 0}, {"hypotheses": 65}, {"twin_rate": 1.5}, {"twin_rate": -0.1},
                                 {"start_jitter_m": -1.0}, {"aggregate": "mode"}, {"length_iterations": 0},
                                 {"length_iterations": 11}, {"twin_ratio_cap": 0.5}, {"twin_ratio_cap": -1.0},
                                 {"twin_ratio_cap": float("nan")}, {"ray_weight": 0.0}, {"ray_weight": 1.5},
                                 {"ray_weight": float("nan")}, {"ray_confidence_ratio": -0.1},
                                 {"ray_confidence_ratio": 1.5}, {"ray_confidence_ratio": float("nan")}])  # fmt: skip
def test_invalid_hypothesis_settings_are_refused(bad: dict) -> None:
    with pytest.raises(ConfigError):
        replace(BASE, **bad)


def test_twin_step_evens_limbs_and_keeps_observed_joints_on_their_rays() -> None:
    rng = np.random.default_rng(0)
    poses = synthetic_poses(6, 5)
    trans = np.array([0.0, 0.0, 1.0])
    cam = poses + trans
    wrist = SKELETON.index("left_wrist")
    cam[:, wrist] *= 1.0 + 0.3 * rng.random((6, 1))  # further along the same ray: longer forearm
    unit = cam / np.linalg.norm(cam, axis=-1, keepdims=True)
    x = torch.as_tensor(cam - trans, dtype=torch.float32)
    u = torch.as_tensor(unit, dtype=torch.float32)
    obs = torch.ones(6, 12, dtype=torch.bool)
    before = twin_limb_ratio(x.numpy(), SKELETON)
    for _ in range(30):
        x = twin_limb_step(x, u, obs, twin_limbs(SKELETON), 0.5)
    after = twin_limb_ratio(x.numpy(), SKELETON)
    assert (after < before).all() and after.max() < 1.1  # from up to 10
    moved = x.numpy() + trans
    off_ray = np.linalg.norm(np.cross(moved, unit), axis=-1)
    assert off_ray.max() < 1e-5  # observed joints move only along their rays


def test_cap_brings_long_twins_to_the_cap_and_leaves_the_others() -> None:
    even = torch.as_tensor(synthetic_poses(8, 4), dtype=torch.float32)
    free = torch.zeros(8, 12, dtype=torch.bool)
    for _ in range(30):  # twin limbs of equal length to start from
        even = twin_limb_step(even, even, free, twin_limbs(SKELETON), 1.0)
    trans = np.array([0.0, 0.0, 1.0])
    cam = even.numpy().astype(np.float64) + trans
    knee, ankle = SKELETON.index("left_knee"), SKELETON.index("left_ankle")
    shank = cam[:, ankle] - cam[:, knee]
    longer = np.array([1.5, 1.8, 2.2, 2.5, 1.0, 1.1, 1.2, 1.3])[:, None]  # four shanks far too long, four not
    cam[:, ankle] = cam[:, knee] + shank * longer
    unit = torch.as_tensor(cam / np.linalg.norm(cam, axis=-1, keepdims=True), dtype=torch.float32)
    x = torch.as_tensor(cam - trans, dtype=torch.float32)
    obs = torch.ones(8, 12, dtype=torch.bool)
    obs[:, SKELETON.index("right_ankle")] = False  # a missing joint moves freely
    before = twin_limb_ratio(x.numpy(), SKELETON)
    assert (before[:4] > 1.45).all() and (before[4:] < 1.4).all()
    capped = cap_twin_ratios(x, unit, obs, twin_limbs(SKELETON), 1.4)
    after = twin_limb_ratio(capped.numpy(), SKELETON)
    assert ((after[:4] > 1.39) & (after[:4] < 1.45)).all()  # brought to about the cap, not evened
    assert torch.equal(capped[4:], x[4:])  # poses within the cap are not touched
    moved = capped.numpy() + trans
    off_ray = np.linalg.norm(np.cross(moved, unit.numpy()), axis=-1)[obs.numpy()]
    assert off_ray.max() < 1e-5  # observed joints move only along their rays
    assert cap_twin_ratios(x, unit, obs, twin_limbs(SKELETON), 0.0) is x  # 0: off


def test_twin_step_off_is_the_identity() -> None:
    x = torch.randn(3, 12, 3)
    assert twin_limb_step(x, x, torch.ones(3, 12, dtype=torch.bool), twin_limbs(SKELETON), 0.0) is x


def test_twin_term_in_the_loop_evens_the_lifted_limbs(tiny_prior: Prior) -> None:
    xy, conf, k = _inputs(12, seed=9)
    plain = lift(xy, conf, k, tiny_prior, BASE)
    even = lift(xy, conf, k, tiny_prior, replace(BASE, twin_rate=0.5))
    r0, r1 = twin_limb_ratio(plain.poses_root_relative, SKELETON), twin_limb_ratio(even.poses_root_relative, SKELETON)
    assert np.median(r1) < np.median(r0)
    twice = lift(xy, conf, k, tiny_prior, replace(BASE, twin_rate=0.5, length_iterations=2))
    assert np.median(twin_limb_ratio(twice.poses_root_relative, SKELETON)) < np.median(r1)  # two steps per iteration
    # still on the rays: the last prior step moves joints off them about as much as without the term
    assert np.nanmean(even.reprojection_error_px) < 1.5 * np.nanmean(plain.reprojection_error_px) + 1.0


def test_softer_rays_let_the_prior_hold_joints_off_noisy_rays(tiny_prior: Prior) -> None:
    xy, conf, k = _inputs(12, seed=9)
    xy = xy + np.random.default_rng(2).normal(0.0, 4.0, xy.shape)  # 2D noise the prior cannot follow
    exact = lift(xy, conf, k, tiny_prior, BASE)
    soft = lift(xy, conf, k, tiny_prior, replace(BASE, ray_weight=0.5))
    assert exact.lifted.all() and soft.lifted.all()
    # the joints end further from their noisy pixels, by a bounded amount, and the pose moved
    assert np.nanmean(exact.reprojection_error_px) < np.nanmean(soft.reprojection_error_px) < 40.0
    assert np.abs(soft.poses_root_relative - exact.poses_root_relative).max() > 1e-3
    same = lift(xy, conf, k, tiny_prior, replace(BASE, ray_weight=1.0))
    np.testing.assert_array_equal(same.poses_camera, exact.poses_camera)  # 1: the reference loop, to the bit


SEVEN = ("left_hip", "a", "b", "right_hip", "c", "d", "e")  # joint names: two hips, at 0 and 3


def test_ray_pull_scales_the_weight_down_for_joints_less_sure_than_their_pose() -> None:
    conf = np.array([[1.0, 0.8, 0.8, 0.5, 0.2, 0.0, np.nan]])  # median of the observed joints: 0.8
    obs = np.array([[True] * 5 + [False] * 2])
    assert ray_pull(conf, obs, LiftConfig(), SEVEN) is None  # the reference: every joint all the way
    np.testing.assert_allclose(ray_pull(conf, obs, replace(BASE, ray_weight=0.75), SEVEN), np.full((1, 7), 0.75))
    cfg = replace(BASE, ray_weight=0.75, ray_confidence_ratio=0.5)  # below 0.4: in proportion
    expected = [[0.75, 0.75, 0.75, 0.75, 0.375, 0.0, 0.0]]
    np.testing.assert_allclose(ray_pull(conf, obs, cfg, SEVEN), expected)
    np.testing.assert_allclose(ray_pull(0.3 * conf, obs, cfg, SEVEN), expected)  # another detector's scale: the same
    nothing_observed = ray_pull(np.zeros((1, 7)), np.zeros((1, 7), dtype=bool), cfg, SEVEN)
    assert np.isfinite(nothing_observed).all()


def test_ray_pull_holds_the_hips_less_by_their_factor() -> None:
    conf, obs = np.ones((2, 7)), np.ones((2, 7), dtype=bool)
    hips = replace(BASE, hip_ray_factor=0.6)
    np.testing.assert_allclose(ray_pull(conf, obs, hips, SEVEN), np.tile([0.6, 1, 1, 0.6, 1, 1, 1], (2, 1)))
    both = replace(hips, ray_weight=0.75)  # the factor multiplies the pull
    np.testing.assert_allclose(ray_pull(conf, obs, both, SEVEN)[0], [0.45, 0.75, 0.75, 0.45, 0.75, 0.75, 0.75])
    no_hips = ("a", "b", "c", "d", "e", "f", "pelvis")  # a skeleton without hips: nothing to hold less
    np.testing.assert_allclose(ray_pull(conf, obs, hips, no_hips), np.ones((2, 7)))
    with pytest.raises(ConfigError, match="hip_ray_factor"):
        LiftConfig(hip_ray_factor=1.5)


def test_softer_hip_rays_move_only_the_hips_off_their_rays(tiny_prior: Prior) -> None:
    xy, conf, k = _inputs(6, seed=4)
    xy = xy + np.random.default_rng(5).normal(0.0, 3.0, xy.shape)
    exact = lift(xy, conf, k, tiny_prior, BASE)
    held_less = lift(xy, conf, k, tiny_prior, replace(BASE, hip_ray_factor=0.3))
    assert exact.lifted.all() and held_less.lifted.all()
    hips = [tiny_prior.skeleton.joints.index(name) for name in ("left_hip", "right_hip")]
    assert np.nanmean(held_less.reprojection_error_px[:, hips]) > np.nanmean(exact.reprojection_error_px[:, hips])


def test_unsure_joints_are_held_less_to_their_rays(tiny_prior: Prior) -> None:
    xy, conf, k = _inputs(12, seed=9)
    xy = xy + np.random.default_rng(2).normal(0.0, 4.0, xy.shape)
    conf = conf.copy()
    conf[:, ::2] = 0.1  # every other joint: a detection the detector doubts (median 0.55)
    cfg = replace(BASE, ray_weight=0.8)
    alike = lift(xy, conf, k, tiny_prior, cfg)
    doubted = lift(xy, conf, k, tiny_prior, replace(cfg, ray_confidence_ratio=0.5))
    assert alike.lifted.all() and doubted.lifted.all()
    miss_alike, miss_doubted = alike.reprojection_error_px[:, ::2], doubted.reprojection_error_px[:, ::2]
    assert np.nanmean(miss_doubted) > np.nanmean(miss_alike)  # the prior holds doubted joints off their rays


def test_the_spread_of_hypotheses_is_measured_at_the_most_different_joint() -> None:
    from zedo_cli.lifting.result import hypothesis_spread

    reported = np.zeros((3, 2, 3))
    hyps = np.zeros((3, 3, 2, 3))
    hyps[0, 1, 1, 2] = 0.3  # one hypothesis has joint 1 30 cm deeper: RMS over 3 is 0.3 / sqrt(3)
    hyps[1, 1:] = np.nan  # only the reported hypothesis usable: nothing to compare
    hyps[2] = np.nan  # not lifted
    spread = hypothesis_spread(hyps, reported)
    np.testing.assert_allclose(spread[0], 0.3 / np.sqrt(3))
    assert np.isnan(spread[1:]).all()


def test_a_lift_with_hypotheses_reports_their_spread_and_one_without_none(tiny_prior: Prior) -> None:
    xy, conf, k = _inputs(3)
    assert lift(xy, conf, k, tiny_prior, BASE).hypothesis_spread_m is None
    res = lift(xy, conf, k, tiny_prior, SPREAD)
    assert res.hypothesis_spread_m is not None and (res.hypothesis_spread_m > 0).all()
    assert res.unstable() is not None and res.unstable().shape == (3,)
