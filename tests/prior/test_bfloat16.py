"""The bfloat16 form of the score network (`Bfloat16Network`) and `group_norm`."""

from __future__ import annotations

import torch

from zedo_cli.prior.model import BF16_BLOCK_ROWS, Bfloat16Network, PriorConfig, ScoreNet, group_norm


def _net() -> ScoreNet:
    with torch.random.fork_rng():
        torch.manual_seed(0)
        return ScoreNet(PriorConfig(12, hidden=256, embed=64, groups=8, num_blocks=2)).eval()


def test_group_norm_is_torch_group_norm_to_float_rounding() -> None:
    norm = torch.nn.GroupNorm(32, 1024)
    with torch.no_grad():
        norm.weight.normal_()
        norm.bias.normal_()
        h = torch.randn(300, 1024) * 3 + 1
        torch.testing.assert_close(group_norm(h, 32, norm.weight, norm.bias, norm.eps), norm(h), rtol=1e-5, atol=1e-5)


def test_bfloat16_network_is_close_to_the_float32_one() -> None:
    net = _net()
    x, t = torch.randn(40, 12, 3) * 0.2, torch.tensor(0.1)
    with torch.no_grad():
        full, half = net(x, t), Bfloat16Network(net)(x, t)
        per_row = Bfloat16Network(net)(x, torch.full((40,), 0.1))  # a time per row: the same numbers
    assert half.dtype == torch.float32 and half.shape == x.shape
    error = (half - full).abs().mean() / full.abs().mean()
    assert 0 < error < 0.02, error  # bfloat16's 8-bit mantissa: about 0.3 % per product
    torch.testing.assert_close(per_row, half)


def test_a_rows_bfloat16_result_does_not_depend_on_the_batch() -> None:
    """Products run in blocks of BF16_BLOCK_ROWS rows, so oneDNN's choice of kernel by row count
    (three results for one row on an AMX CPU) cannot make a pose's noise prediction depend on the
    other poses of its chunk."""
    net = Bfloat16Network(_net())
    x, t = torch.randn(2 * BF16_BLOCK_ROWS + 40, 12, 3) * 0.2, torch.tensor(0.3)
    whole = net(x, t)
    for rows in (1, 17, 40, 300, BF16_BLOCK_ROWS, 2 * BF16_BLOCK_ROWS + 1):
        assert torch.equal(net(x[-rows:], t), whole[-rows:]), rows
