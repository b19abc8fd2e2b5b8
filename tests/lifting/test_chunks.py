"""The same lift to the bit for every thread count and batch cut (lifting/chunks.py)."""

from __future__ import annotations

import os
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import torch
from helpers import K_TEST, project_poses, synthetic_poses

import zedo_cli.lifting.solver as solver
from zedo_cli.lifting import chunks
from zedo_cli.lifting.chunks import (
    MIN_CHUNK_ROWS,
    MIN_SPLIT_ROWS,
    BlockNoise,
    Chunk,
    deterministic_cuda,
    noise_block,
    plan_chunks,
    run_chunks,
)
from zedo_cli.lifting.config import get_preset
from zedo_cli.lifting.solver import lift
from zedo_cli.prior.weights import Prior

REPO = Path(__file__).resolve().parents[2]
FAST = replace(get_preset("fast"), steps=8, init_steps=20)


def _inputs(n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    return project_poses(synthetic_poses(n, seed=5)), np.ones((n, 12)), np.repeat(K_TEST[None], n, 0)


@pytest.mark.parametrize("instances", [1, 5, 15, 16, 40, 63, 64, 65, 200, 1000, 5000])
@pytest.mark.parametrize("hypotheses", [1, 3, 8])
@pytest.mark.parametrize("workers", [1, 2, 7])
def test_chunks_cover_the_batch_in_whole_noise_blocks(instances: int, hypotheses: int, workers: int) -> None:
    plan = plan_chunks(instances, hypotheses, 4096, workers)
    assert [c.start for c in plan] == [0] + [c.stop for c in plan[:-1]] and plan[-1].stop == instances
    block = noise_block(hypotheses)
    assert all(c.start % block == 0 for c in plan)
    assert all((c.stop - c.start) * hypotheses <= max(4096, block * hypotheses) for c in plan)
    if len(plan) > 1:  # several chunks: each has the rows whose products are those of any larger chunk
        assert all((c.stop - c.start + c.pad) * hypotheses >= MIN_CHUNK_ROWS for c in plan)
    else:
        assert plan[0].pad == 0
    if hypotheses == 1:  # cut for the threads as far as chunks keep MIN_SPLIT_ROWS rows
        assert len(plan) == max(-(-instances // 4096), min(workers, instances // MIN_SPLIT_ROWS), 1)


def test_a_chunk_is_padded_with_its_last_instance() -> None:
    chunk = Chunk(64, 65, 2)
    assert chunk.positions().tolist() == [64, 64, 64]
    assert plan_chunks(0, 1, 4096, 2) == []


def test_noise_of_an_instance_does_not_depend_on_the_cut() -> None:
    k = 8
    block = noise_block(k)
    whole = BlockNoise(3, Chunk(0, 3 * block, 0), k, "cpu")
    parts = [BlockNoise(3, Chunk(i * block, (i + 1) * block, 0), k, "cpu") for i in range(3)]
    for _ in range(2):  # the start's jitter, then a step's noise
        joined = torch.cat([p.randn((12, 3), torch.float32) for p in parts])
        torch.testing.assert_close(whole.randn((12, 3), torch.float32), joined, rtol=0, atol=0)
    padded = BlockNoise(3, Chunk(0, 1, 1), k, "cpu").randn((12,), torch.float32)
    assert padded.shape == (2 * k, 12) and (padded[k:] == 0).all() and (padded[:k] != 0).all()
    other = BlockNoise(4, Chunk(0, block, 0), k, "cpu").randn((12,), torch.float32)
    assert not torch.equal(other, BlockNoise(3, Chunk(0, block, 0), k, "cpu").randn((12,), torch.float32))


@pytest.mark.parametrize("hypotheses", [1, 4])
def test_thread_counts_and_chunk_sizes_give_the_same_bits(tiny_prior: Prior, hypotheses: int) -> None:
    xy, conf, k = _inputs(70)
    cfg = replace(FAST, hypotheses=hypotheses)
    one = lift(xy, conf, k, tiny_prior, cfg, threads=1, seed=2)
    smaller = replace(cfg, chunk_size=40 * hypotheses)
    for other in (lift(xy, conf, k, tiny_prior, cfg, threads=3, seed=2),
                  lift(xy, conf, k, tiny_prior, smaller, threads=2, seed=2)):  # fmt: skip
        np.testing.assert_array_equal(one.poses_camera, other.poses_camera)
        if hypotheses > 1:
            np.testing.assert_array_equal(one.hypotheses, other.hypotheses)
    assert one.lifted.all()


def test_a_pose_is_lifted_alike_alone_in_a_chunk_and_in_a_larger_batch(tiny_prior: Prior) -> None:
    xy, conf, k = _inputs(80)
    batch = lift(xy, conf, k, tiny_prior, FAST, threads=2)  # two chunks of 40
    part = lift(xy[:17], conf[:17], k[:17], tiny_prior, FAST, threads=1)  # one chunk of 17
    np.testing.assert_array_equal(batch.poses_camera[:17], part.poses_camera)


def test_torch_keeps_its_thread_count_and_progress_stays_in_order(tiny_prior: Prior) -> None:
    xy, conf, k = _inputs(96)
    before = torch.get_num_threads()
    seen: list[int] = []
    lift(xy, conf, k, tiny_prior, FAST, threads=3, callback=lambda p: seen.append(p.done))
    assert torch.get_num_threads() == before
    assert seen == sorted(seen) and seen[-1] == 3 * (FAST.init_steps + FAST.steps)


def test_a_failing_chunk_stops_the_others_and_its_error_is_raised() -> None:
    started: list[int] = []

    def work(chunk: Chunk, tick: object) -> None:
        started.append(chunk.start)
        if chunk.start == 0:
            raise ValueError("chunk 0 failed")
        for _ in range(1000):
            tick(1)  # type: ignore[operator]

    with pytest.raises(ValueError, match="chunk 0 failed"):
        run_chunks(plan_chunks(256, 1, 4096, 4), work, 4, "cpu", lambda steps: None)


def test_cuda_lifts_switch_on_torch_deterministic_settings(tiny_prior: Prior, monkeypatch: pytest.MonkeyPatch) -> None:
    flags = (torch.are_deterministic_algorithms_enabled(), torch.is_deterministic_algorithms_warn_only_enabled(),
             torch.backends.cudnn.deterministic, torch.backends.cudnn.benchmark,
             torch.backends.cuda.matmul.allow_tf32, torch.backends.cudnn.allow_tf32)  # fmt: skip
    monkeypatch.delenv("CUBLAS_WORKSPACE_CONFIG", raising=False)
    try:
        deterministic_cuda()  # needs no GPU
        assert torch.are_deterministic_algorithms_enabled() and torch.is_deterministic_algorithms_warn_only_enabled()
        assert torch.backends.cudnn.deterministic and not torch.backends.cudnn.benchmark
        assert not torch.backends.cuda.matmul.allow_tf32 and not torch.backends.cudnn.allow_tf32
        assert os.environ["CUBLAS_WORKSPACE_CONFIG"] == chunks.CUBLAS_WORKSPACE
    finally:
        torch.use_deterministic_algorithms(flags[0], warn_only=flags[1])
        torch.backends.cudnn.deterministic, torch.backends.cudnn.benchmark = flags[2], flags[3]
        torch.backends.cuda.matmul.allow_tf32, torch.backends.cudnn.allow_tf32 = flags[4], flags[5]

    class Switched(Exception):
        pass

    def switched() -> None:
        raise Switched

    monkeypatch.setattr(solver, "deterministic_cuda", switched)
    xy, conf, k = _inputs(2)
    with pytest.raises(Switched):  # before any tensor is put on the (absent) GPU
        lift(xy, conf, k, tiny_prior, FAST, device="cuda")
    lift(xy, conf, k, tiny_prior, FAST)  # not on the CPU


LIFT_SCRIPT = """
import sys
import numpy as np
from helpers import K_TEST, project_poses, synthetic_poses
from zedo_cli.lifting.config import get_preset
from zedo_cli.lifting.solver import lift
from zedo_cli.prior.weights import bundled_prior_path, load_prior

import torch
xy = project_poses(synthetic_poses(64, seed=11))
res = lift(xy, np.ones((64, 12)), np.repeat(K_TEST[None], 64, 0), load_prior(bundled_prior_path()), get_preset("fast"))
np.save(sys.argv[1], res.poses_camera)
print(torch.get_num_threads())
"""


def test_two_processes_with_one_and_two_threads_give_the_same_bits(tmp_path: Path) -> None:
    """The bundled prior's network (1024 wide), as `zedo lift` runs it: with OMP_NUM_THREADS 1 and 2
    (one chunk of 64 poses, or two of 32 on two threads) the poses are the same to the bit (with
    the sums split over intra-op threads they would differ by up to a micrometre)."""
    outs = []
    for threads in (1, 2):
        env = {**os.environ, "OMP_NUM_THREADS": str(threads), "PYTHONPATH": os.pathsep.join(
            [str(REPO), str(REPO / "tests"), os.environ.get("PYTHONPATH", "")])}  # fmt: skip
        out = tmp_path / f"{threads}.npy"
        done = subprocess.run([sys.executable, "-c", LIFT_SCRIPT, str(out)], env=env, cwd=REPO, capture_output=True,
                              text=True, timeout=120)  # fmt: skip
        assert done.returncode == 0, done.stderr[-2000:]
        assert done.stdout.split() == [str(threads)]
        outs.append(np.load(out))
    assert np.isfinite(outs[0]).all()
    np.testing.assert_array_equal(outs[0], outs[1])
