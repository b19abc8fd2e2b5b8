"""End-to-end lifting with a tiny prior: generated poses, exact projections, known K."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
import torch
from helpers import K_TEST, SKELETON, project_poses, synthetic_poses

from zedo_cli.data.skeleton import center_on_root
from zedo_cli.errors import ConfigError
from zedo_cli.evaluation.metrics import mpjpe_mm
from zedo_cli.lifting.config import LiftConfig, get_preset
from zedo_cli.lifting.solver import lift
from zedo_cli.prior.weights import Prior

FAST = LiftConfig(steps=200, init_steps=200)


def _inputs(n: int, seed: int = 1) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    poses = synthetic_poses(n, seed)
    return poses, project_poses(poses), np.ones((n, 12)), np.repeat(K_TEST[None], n, 0)


def test_lifting_recovers_generated_poses(tiny_prior: Prior) -> None:
    poses, xy, conf, k = _inputs(20)
    res = lift(xy, conf, k, tiny_prior, FAST)
    err = mpjpe_mm(res.poses_root_relative, poses)
    # The flat pose (all joints at the root's depth on their rays) is the no-prior baseline.
    flat = center_on_root(np.concatenate([xy, np.ones((20, 12, 1))], -1) @ np.linalg.inv(K_TEST).T, SKELETON)
    assert err < 25.0, err
    assert err < 0.8 * mpjpe_mm(flat, poses)
    assert np.nanmax(res.reprojection_error_px) < 2.0  # the last prior step moves joints slightly off the rays
    assert np.allclose(res.root_translation[:, 2], 1.0, atol=0.1)  # depth recovered: 1 m
    assert res.lifted.all() and res.observed.all()


def test_lifting_is_deterministic(tiny_prior: Prior) -> None:
    _, xy, conf, k = _inputs(4)
    a = lift(xy, conf, k, tiny_prior, FAST)
    b = lift(xy, conf, k, tiny_prior, FAST)
    np.testing.assert_array_equal(a.poses_camera, b.poses_camera)


def test_each_pose_independent_of_batch(tiny_prior: Prior) -> None:
    _, xy, conf, k = _inputs(6)
    together = lift(xy, conf, k, tiny_prior, FAST)
    alone = lift(xy[:1], conf[:1], k[:1], tiny_prior, FAST)
    np.testing.assert_allclose(together.poses_camera[0], alone.poses_camera[0], atol=1e-4)


def test_missing_joints_are_filled_and_flagged(tiny_prior: Prior) -> None:
    poses, xy, conf, k = _inputs(10)
    conf[:, 2] = 0.0  # right ankle missing everywhere
    xy[:, 2] = np.nan
    res = lift(xy, conf, k, tiny_prior, FAST)
    assert not res.observed[:, 2].any() and res.observed[:, [0, 1, 3]].all()
    assert np.isnan(res.reprojection_error_px[:, 2]).all()
    assert np.isfinite(res.poses_camera).all()
    ankle_err = np.linalg.norm(res.poses_root_relative[:, 2] - poses[:, 2], axis=-1).mean() * 1000
    assert ankle_err < 60.0, ankle_err  # filled by the prior near where it belongs


def test_instances_with_too_few_joints_are_not_lifted(tiny_prior: Prior) -> None:
    _, xy, conf, k = _inputs(3)
    conf[1, 2:] = 0.0  # two observed joints only
    res = lift(xy, conf, k, tiny_prior, FAST)
    assert res.lifted.tolist() == [True, False, True]
    assert np.isnan(res.poses_camera[1]).all() and np.isfinite(res.poses_camera[[0, 2]]).all()


def test_min_confidence_marks_joints_missing(tiny_prior: Prior) -> None:
    _, xy, conf, k = _inputs(2)
    conf[:, 5] = 0.2
    res = lift(xy, conf, k, tiny_prior, replace(FAST, steps=20, init_steps=10), min_confidence=0.3)
    assert not res.observed[:, 5].any()


def test_faithful_preset_has_the_reference_numbers() -> None:
    cfg = get_preset("faithful")
    assert (cfg.steps, cfg.init_steps, cfg.init_lr, cfg.t_start, cfg.t_end) == (1000, 500, 0.1, 0.1, 0.01)
    assert (cfg.scale_min, cfg.scale_max, cfg.init_depth_m, cfg.step_delta, cfg.flow) == (0.5, 8.0, 1.0, 1e-3, 1.0)
    assert round(cfg.steps * (1 - cfg.release_fraction)) == 950
    with pytest.raises(ConfigError):
        get_preset("nope")


def test_wrong_joint_count_is_an_error(tiny_prior: Prior) -> None:
    with pytest.raises(ConfigError):
        lift(np.zeros((1, 17, 2)), np.ones((1, 17)), K_TEST[None], tiny_prior, FAST)


def test_fast_preset_takes_few_stable_steps_with_the_length_terms() -> None:
    fast, faithful = get_preset("fast"), get_preset("faithful")
    assert (fast.steps, fast.init_steps, fast.release_fraction, fast.t_start) == (20, 100, 0.15, 0.2)
    assert fast.delta == pytest.approx(0.03) and faithful.delta == pytest.approx(1e-3)  # 1/20 capped
    loop_terms = (
        "ray_weight",
        "ray_confidence_ratio",
        "twin_rate",
        "proportion_rate",
        "length_iterations",
        "twin_ratio_cap",
    )
    assert [getattr(fast, k) for k in loop_terms] == [0.75, 0.6, 0.85, 0.7, 2, 1.4]
    assert [getattr(faithful, k) for k in loop_terms] == [1.0, 0.0, 0.0, 0.0, 1, 0.0]  # the reference
    assert replace(fast, steps=40).delta == pytest.approx(1 / 40)  # --steps: 1/steps ...
    assert replace(fast, steps=25).delta == pytest.approx(0.03)  # ... up to the stable step size
    assert get_preset("fast-bf16") == replace(fast, preset="fast-bf16", bf16=True)
    assert fast.to_dict()["delta"] == pytest.approx(0.03)


@pytest.mark.parametrize(
    "bad", [{"step_delta": 0.0}, {"release_fraction": 1.5}, {"chunk_size": 0}, {"steps": 0}, {"t_end": 0.0}]
)
def test_invalid_settings_are_refused(bad: dict[str, float]) -> None:
    with pytest.raises(ConfigError):
        LiftConfig(**bad)


def test_fast_preset_is_no_worse_than_faithful(tiny_prior: Prior) -> None:
    poses, xy, conf, k = _inputs(20)
    fast = mpjpe_mm(lift(xy, conf, k, tiny_prior, get_preset("fast")).poses_root_relative, poses)
    faithful = mpjpe_mm(lift(xy, conf, k, tiny_prior, get_preset("faithful")).poses_root_relative, poses)
    assert fast < faithful + 2.0, (fast, faithful)  # with t_start 0.2, fast is the better one


def test_bf16_network_changes_little(tiny_prior: Prior) -> None:
    poses, xy, conf, k = _inputs(6)
    cfg = replace(FAST, steps=40, init_steps=50)
    full = lift(xy, conf, k, tiny_prior, replace(cfg, bf16=False))
    half = lift(xy, conf, k, tiny_prior, replace(cfg, bf16=True))
    assert np.isfinite(half.poses_camera).all()
    assert mpjpe_mm(half.poses_root_relative, full.poses_root_relative) < 5.0


def test_progress_reaches_the_total_in_order(tiny_prior: Prior) -> None:
    _, xy, conf, k = _inputs(5)
    seen = []
    lift(xy, conf, k, tiny_prior, replace(FAST, steps=37, init_steps=3, chunk_size=2), callback=seen.append)
    done = [p.done for p in seen]
    assert done == sorted(done) and done[-1] == seen[-1].total == 3 * (37 + 3)


def test_throughput_counts_every_pose(tiny_prior: Prior) -> None:
    from zedo_cli.data.keypoints import Keypoints2D
    from zedo_cli.evaluation.syrip_benchmark import measure_throughput

    _, xy, conf, _ = _inputs(7)
    kp = Keypoints2D(xy, conf, SKELETON, list(range(7)), [None] * 7, np.tile([640.0, 480.0], (7, 1)),
                     [None] * 7, "mem", "test")  # fmt: skip
    rate = measure_throughput({"a": kp, "b": kp.subset([0, 1])}, tiny_prior, replace(FAST, steps=5, init_steps=2))
    assert rate.count == 9 and rate.seconds > 0 and rate.poses_per_second == pytest.approx(9 / rate.seconds)


@pytest.mark.parametrize("dtype", [torch.float32, torch.float64])
def test_rotation_fit_adam_equals_torch_adam_to_the_bit(dtype: torch.dtype) -> None:
    from zedo_cli.lifting.solver import _Adam

    gen = torch.Generator().manual_seed(0)
    start = [torch.randn(16, 4, generator=gen, dtype=dtype), torch.randn(16, 1, generator=gen, dtype=dtype)]
    ours = [t.clone().requires_grad_(True) for t in start]
    theirs = [t.clone().requires_grad_(True) for t in start]
    steppers = [(ours, _Adam(ours, lr=0.1)), (theirs, torch.optim.Adam(theirs, lr=0.1))]
    for _ in range(100):
        for params, opt in steppers:
            loss = (params[0].sin() * params[1]).abs().sum() + (params[0] ** 2).sum()
            for p in params:
                p.grad = None
            loss.backward()
            opt.step()
    assert all(torch.equal(a, b) for a, b in zip(ours, theirs, strict=True))
