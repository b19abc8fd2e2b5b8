"""Tests of the score network (zedo_cli.prior.model), the subVP SDE (zedo_cli.prior.sde) and the reverse step
(zedo_cli.prior.sampling): known values from ALGORITHM.md sections 1.1, 2.1-2.3 and 3.5(c)."""

from __future__ import annotations

import math

import numpy as np
import pytest
import torch

from zedo_cli.prior.model import PriorConfig, ScoreNet, parameter_count, positional_embedding
from zedo_cli.prior.sampling import probability_flow_step
from zedo_cli.prior.sde import SubVPSDE

TINY = PriorConfig(num_joints=5, hidden=32, embed=16, num_blocks=2, groups=4)


def _tiny_model(seed: int = 0, cfg: PriorConfig = TINY) -> ScoreNet:
    with torch.random.fork_rng():
        torch.manual_seed(seed)
        return ScoreNet(cfg)


def _scalar(value: float) -> torch.Tensor:
    return torch.tensor(value, dtype=torch.float64)


# --- network -------------------------------------------------------------------------------


@pytest.mark.parametrize(("joints", "expected"), [(12, 7_172_644), (17, 7_203_379)])
def test_parameter_count_at_paper_size(joints: int, expected: int) -> None:
    with torch.random.fork_rng():
        model = ScoreNet(PriorConfig(num_joints=joints))
    assert parameter_count(model) == expected


def test_parameter_breakdown_j17() -> None:
    with torch.random.fork_rng():
        model = ScoreNet(PriorConfig(num_joints=17))
    assert parameter_count(model.stem) == 580_608
    assert parameter_count(model.time_mlp) == 262_656
    assert [parameter_count(b) for b in model.blocks] == [3_153_920, 3_153_920]
    assert parameter_count(model.head) == 52_275


@pytest.mark.parametrize("batch", [1, 3])
def test_output_shape_equals_input_shape(batch: int) -> None:
    model = _tiny_model().eval()
    x = torch.randn(batch, 5, 3, generator=torch.Generator().manual_seed(batch))
    t = torch.full((batch,), 0.3)
    with torch.no_grad():
        out = model(x, t)
    assert out.shape == x.shape
    assert torch.isfinite(out).all()


def test_shared_scalar_time_matches_per_sample_time_in_eval() -> None:
    model = _tiny_model(1).eval()
    x = torch.randn(4, 5, 3, generator=torch.Generator().manual_seed(2))
    with torch.no_grad():
        for value in (0.01, 0.055, 0.1, 0.9):
            shared = model(x, torch.tensor(value))
            per_sample = model(x, torch.full((4,), value))
            np.testing.assert_allclose(shared.numpy(), per_sample.numpy(), atol=1e-5)


def test_eval_is_deterministic_and_train_uses_dropout() -> None:
    model = _tiny_model(3)
    x = torch.randn(2, 5, 3, generator=torch.Generator().manual_seed(4))
    t = torch.full((2,), 0.5)
    model.eval()
    with torch.no_grad():
        assert torch.equal(model(x, t), model(x, t))
    model.train()
    with torch.no_grad(), torch.random.fork_rng():
        torch.manual_seed(0)
        a = model(x, t)
        b = model(x, t)
    assert not torch.equal(a, b)


def test_network_sees_scaled_time() -> None:
    # The time label is time_scale * t: equal labels give equal outputs.
    a_cfg = PriorConfig(num_joints=5, hidden=32, embed=16, groups=4, time_scale=999.0)
    b_cfg = PriorConfig(num_joints=5, hidden=32, embed=16, groups=4, time_scale=99.9)
    a, b = _tiny_model(5, a_cfg).eval(), _tiny_model(5, b_cfg).eval()
    x = torch.randn(2, 5, 3, generator=torch.Generator().manual_seed(6))
    with torch.no_grad():
        np.testing.assert_allclose(a(x, torch.tensor(0.01)).numpy(), b(x, torch.tensor(0.1)).numpy(), atol=1e-5)


def test_positional_embedding_sin_half_first() -> None:
    labels = torch.tensor([0.0, 1.0, 99.9, 999.0])
    emb = positional_embedding(labels, 512)
    assert emb.shape == (4, 512)
    # Label 0: sin half is 0, cos half is 1.
    np.testing.assert_allclose(emb[0, :256].numpy(), 0.0, atol=0)
    np.testing.assert_allclose(emb[0, 256:].numpy(), 1.0, atol=0)
    # First frequency is 1, last is 1/10000.
    k = np.arange(256)
    freqs = np.exp(-k * math.log(10000.0) / 255)
    assert freqs[0] == 1.0 and freqs[-1] == pytest.approx(1e-4)
    for row, label in enumerate(labels.tolist()):
        np.testing.assert_allclose(emb[row, :256].numpy(), np.sin(label * freqs), atol=2e-4)
        np.testing.assert_allclose(emb[row, 256:].numpy(), np.cos(label * freqs), atol=2e-4)


# --- SDE -----------------------------------------------------------------------------------


def test_sde_defaults_and_sigma_known_values() -> None:
    sde = SubVPSDE()
    assert (sde.beta_min, sde.beta_max, sde.num_scales) == (0.1, 20.0, 1000)
    assert float(sde.sigma(_scalar(0.1))) == pytest.approx(0.104, rel=0.02)
    assert float(sde.sigma(_scalar(0.01))) == pytest.approx(0.002, rel=0.02)
    assert float(sde.sigma(_scalar(0.0))) == 0.0


def test_beta_is_linear() -> None:
    sde = SubVPSDE()
    t = torch.linspace(0, 1, 11, dtype=torch.float64)
    np.testing.assert_allclose(sde.beta(t).numpy(), (0.1 + 19.9 * t).numpy(), atol=1e-12)
    np.testing.assert_allclose(sde.integrated_beta(t).numpy(), (0.1 * t + 9.95 * t**2).numpy(), atol=1e-12)
    np.testing.assert_allclose(sde.mean_coeff(t).numpy(), torch.exp(-0.5 * (0.1 * t + 9.95 * t**2)).numpy(), atol=1e-12)


def test_perturb_with_zero_noise_is_scaled_x0() -> None:
    sde = SubVPSDE()
    g = torch.Generator().manual_seed(7)
    x0 = torch.randn(3, 4, 3, generator=g, dtype=torch.float64)
    t = torch.tensor([0.01, 0.3, 1.0], dtype=torch.float64)
    out = sde.perturb(x0, t, torch.zeros_like(x0))
    np.testing.assert_allclose(out.numpy(), (sde.mean_coeff(t)[:, None, None] * x0).numpy(), atol=1e-12)
    noise = torch.randn(x0.shape, generator=g, dtype=torch.float64)
    full = sde.perturb(x0, t, noise)
    expected = sde.mean_coeff(t)[:, None, None] * x0 + sde.sigma(t)[:, None, None] * noise
    np.testing.assert_allclose(full.numpy(), expected.numpy(), atol=1e-12)


def test_score_from_noise() -> None:
    sde = SubVPSDE()
    eps = torch.ones(2, 3, 3, dtype=torch.float64)
    t = torch.tensor([0.1, 0.01], dtype=torch.float64)
    score = sde.score_from_noise(eps, t)
    np.testing.assert_allclose(score[:, 0, 0].numpy(), (-1.0 / sde.sigma(t)).numpy())
    shared = sde.score_from_noise(eps, _scalar(0.1))
    np.testing.assert_allclose(shared.numpy(), -eps.numpy() / float(sde.sigma(_scalar(0.1))))


# --- reverse step (ALGORITHM.md 3.5(c)) ----------------------------------------------------


@pytest.mark.parametrize(
    ("t", "x_multiplier", "eps_coeff"),
    [(0.1, 1.001045, 0.003963), (0.055, 1.000597, 0.002347), (0.01, 1.000150, 0.000597)],
)
def test_probability_flow_step_table(t: float, x_multiplier: float, eps_coeff: float) -> None:
    sde = SubVPSDE()
    one, zero = torch.ones(1, dtype=torch.float64), torch.zeros(1, dtype=torch.float64)
    step_x = probability_flow_step(one, zero, _scalar(t), sde, delta=1e-3, flow=1.0)
    step_eps = probability_flow_step(zero, one, _scalar(t), sde, delta=1e-3, flow=1.0)
    # The table gives 6 decimals: agree to within one unit of the last one.
    assert float(step_x) == pytest.approx(x_multiplier, abs=1e-6)
    assert -float(step_eps) == pytest.approx(eps_coeff, abs=1e-6)
    assert -float(step_eps) == pytest.approx(eps_coeff, rel=2e-3)


def test_probability_flow_step_is_linear_and_flow_scales_eps() -> None:
    sde = SubVPSDE()
    g = torch.Generator().manual_seed(8)
    x = torch.randn(2, 4, 3, generator=g, dtype=torch.float64)
    eps = torch.randn(2, 4, 3, generator=g, dtype=torch.float64)
    t = _scalar(0.05)
    full = probability_flow_step(x, eps, t, sde, 1e-3, 1.0)
    parts = probability_flow_step(x, 0 * eps, t, sde, 1e-3, 1.0) + probability_flow_step(0 * x, eps, t, sde, 1e-3, 1.0)
    np.testing.assert_allclose(full.numpy(), parts.numpy(), atol=1e-12)
    half = probability_flow_step(0 * x, eps, t, sde, 1e-3, 0.5)
    np.testing.assert_allclose(
        half.numpy(), 0.5 * probability_flow_step(0 * x, eps, t, sde, 1e-3, 1.0).numpy(), atol=1e-12
    )


def test_eps_coefficients_sum_over_the_loop() -> None:
    # ALGORITHM.md 3.5(c): over t = linspace(0.1, 0.01, 1000) the eps coefficients sum to 2.32
    # and the X multipliers multiply to 1.82.
    sde = SubVPSDE()
    t = torch.linspace(0.1, 0.01, 1000, dtype=torch.float64)
    ones, zeros = torch.ones_like(t), torch.zeros_like(t)
    multipliers = probability_flow_step(ones, zeros, t, sde, 1e-3, 1.0)
    coeffs = -probability_flow_step(zeros, ones, t, sde, 1e-3, 1.0)
    assert float(coeffs.sum()) == pytest.approx(2.32, abs=0.01)
    assert float(multipliers.prod()) == pytest.approx(1.82, abs=0.01)
