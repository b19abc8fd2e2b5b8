"""The bone-proportion term of the lifting loop (lifting/proportions.py), with a tiny prior."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
import torch
from helpers import BASE_POSE, K_TEST, SKELETON, project_poses, synthetic_poses

from zedo_cli.data.skeleton import bone_lengths
from zedo_cli.errors import ConfigError
from zedo_cli.lifting.config import LiftConfig
from zedo_cli.lifting.proportions import bone_proportion_step, template_fractions
from zedo_cli.lifting.solver import lift
from zedo_cli.prior.weights import Prior

BASE = LiftConfig(steps=40, init_steps=50, step_delta=None, release_fraction=0.15)
BONES = torch.as_tensor(SKELETON.bones)


def _fractions(poses: np.ndarray) -> np.ndarray:
    lengths = bone_lengths(poses, SKELETON)
    return lengths / lengths.sum(-1, keepdims=True)


def test_template_fractions_sum_to_one_with_twin_bones_equal() -> None:
    template = torch.as_tensor(BASE_POSE, dtype=torch.float32)
    template[SKELETON.index("left_wrist")] += torch.tensor([0.05, 0.0, 0.0])  # a longer left forearm
    frac = template_fractions(template, SKELETON).numpy()
    assert frac.sum() == pytest.approx(1.0, abs=1e-6) and (frac > 0).all()
    index = {frozenset(b): k for k, b in enumerate(SKELETON.bones)}
    flip = SKELETON.flip_permutation
    for k, (a, b) in enumerate(SKELETON.bones):
        assert frac[k] == pytest.approx(frac[index[frozenset((flip[a], flip[b]))]], abs=1e-7)


def test_proportion_step_moves_bones_to_their_shares_along_the_rays() -> None:
    trans = np.array([0.0, 0.0, 1.0])
    target = torch.as_tensor(_fractions(synthetic_poses(1, 0))[0], dtype=torch.float32)
    cam = synthetic_poses(6, 5) + trans
    rng = np.random.default_rng(1)
    cam *= 1.0 + 0.15 * rng.random((6, 12, 1))  # every joint slid along its own ray: proportions off
    unit = cam / np.linalg.norm(cam, axis=-1, keepdims=True)
    x = torch.as_tensor(cam - trans, dtype=torch.float32)
    u = torch.as_tensor(unit, dtype=torch.float32)
    obs = torch.ones(6, 12, dtype=torch.bool)
    obs[:, SKELETON.index("right_ankle")] = False  # a missing joint moves freely
    before = np.abs(_fractions(x.numpy()) - target.numpy()).mean()
    for _ in range(40):
        x = bone_proportion_step(x, u, obs, BONES, target, 0.5)
    after = np.abs(_fractions(x.numpy()) - target.numpy()).mean()
    assert after < 0.5 * before
    moved = x.numpy() + trans
    off_ray = np.linalg.norm(np.cross(moved, unit), axis=-1)[obs.numpy()]
    assert off_ray.max() < 1e-5  # observed joints move only along their rays


def test_proportion_step_off_is_the_identity() -> None:
    x = torch.randn(3, 12, 3)
    frac = torch.full((len(SKELETON.bones),), 1.0 / len(SKELETON.bones))
    assert bone_proportion_step(x, x, torch.ones(3, 12, dtype=torch.bool), BONES, frac, 0.0) is x


def test_proportion_term_in_the_loop_brings_lifted_proportions_to_the_template(tiny_prior: Prior) -> None:
    poses = synthetic_poses(12, 9)
    xy, conf, k = project_poses(poses), np.ones((12, 12)), np.repeat(K_TEST[None], 12, 0)
    target = template_fractions(tiny_prior.template, SKELETON).numpy()
    plain = lift(xy, conf, k, tiny_prior, BASE)
    even = lift(xy, conf, k, tiny_prior, replace(BASE, proportion_rate=0.5, length_iterations=2))
    gap = [np.abs(_fractions(r.poses_root_relative) - target).mean() for r in (plain, even)]
    assert gap[1] < gap[0]
    assert even.lifted.all()
    assert np.nanmean(even.reprojection_error_px) < 1.5 * np.nanmean(plain.reprojection_error_px) + 1.0


@pytest.mark.parametrize("bad", [{"proportion_rate": -0.1}, {"proportion_rate": 1.5}])
def test_invalid_proportion_rates_are_refused(bad: dict) -> None:
    with pytest.raises(ConfigError):
        replace(BASE, **bad)
