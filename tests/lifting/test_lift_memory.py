"""A lift's working set is one chunk, whatever the batch size (docs/lifting.md,
"Memory"): the per-step tensors are never made for more than a chunk's rows, and a batch cut in
many small chunks gives the same bits as one chunk."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from helpers import K_TEST, project_poses, synthetic_poses

import zedo_cli.lifting.solver as solver
from zedo_cli.lifting.chunks import NOISE_BLOCK_ROWS
from zedo_cli.lifting.config import get_preset
from zedo_cli.lifting.solver import lift
from zedo_cli.prior.weights import Prior

FAST = replace(get_preset("fast"), steps=6, init_steps=10)


def _rows_seen(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    """The rows (instances x hypotheses) of every chunk `lift` hands to the loop, as they are lifted."""
    seen: list[int] = []
    inner = solver._lift_chunk

    def counting(prior, xy, *args, **kwargs):  # type: ignore[no-untyped-def]
        out = inner(prior, xy, *args, **kwargs)
        seen.append(out.pose.shape[0] * out.pose.shape[1])
        return out

    monkeypatch.setattr(solver, "_lift_chunk", counting)
    return seen


def test_a_long_batch_is_lifted_a_small_chunk_at_a_time_with_the_same_bits(
    tiny_prior: Prior, monkeypatch: pytest.MonkeyPatch
) -> None:
    n = 300
    xy, conf, k = project_poses(synthetic_poses(n, seed=8)), np.ones((n, 12)), np.repeat(K_TEST[None], n, 0)
    whole = lift(xy, conf, k, tiny_prior, FAST, threads=1)  # one chunk of 300 rows
    seen = _rows_seen(monkeypatch)
    done: list[int] = []
    small = lift(
        xy, conf, k, tiny_prior, replace(FAST, chunk_size=32), threads=1, callback=lambda p: done.append(p.done)
    )
    assert len(seen) == 10 and max(seen) <= 32 and sum(seen) == n  # ten chunks, none over 32 rows
    assert done == sorted(done) and done[-1] == 10 * (FAST.init_steps + FAST.steps)  # progress over all chunks
    np.testing.assert_array_equal(whole.poses_camera, small.poses_camera)
    np.testing.assert_array_equal(whole.status, small.status)
    assert whole.lifted.all()


def test_with_hypotheses_a_chunk_is_at_most_one_noise_block_over_its_size(
    tiny_prior: Prior, monkeypatch: pytest.MonkeyPatch
) -> None:
    n, count = 600, 4
    xy, conf, k = project_poses(synthetic_poses(n, seed=9)), np.ones((n, 12)), np.repeat(K_TEST[None], n, 0)
    seen = _rows_seen(monkeypatch)
    lift(xy, conf, k, tiny_prior, replace(FAST, chunk_size=64, hypotheses=count, steps=2, init_steps=2), threads=1)
    # chunks are whole noise blocks (512 rows): the bound is the larger of chunk_size and one block
    assert sum(seen) == n * count and max(seen) <= max(64, NOISE_BLOCK_ROWS) and len(seen) == -(-n * count // 512)
