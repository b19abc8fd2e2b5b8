"""How a lift's batch is cut into chunks and run on the CPU's threads, so that the answer does not
depend on the thread count, the batch size or the order in which chunks finish (docs/lifting.md,
"Same answer on every machine").

torch's intra-op threads split a matrix product's sums differently for each thread count, and
MKL's products of fewer than 16 rows take other kernels: with 1 and 2 threads the same lift
differed by about a micrometre. So on the CPU every chunk runs on one intra-op thread, and the
threads (`torch.get_num_threads()`, or `lift(threads=)`) each run whole chunks at once (torch
releases the GIL inside its operations). With one intra-op thread and at least 16 rows, a pose's
result does not depend on the other rows of its chunk (measured: chunks of 16 to 4096 rows gave
the same bits), so the cut may follow the thread count; a chunk under 16 rows of a batch of
several chunks is padded with copies of its last instance. The hypotheses' noise (K > 1) comes
from one random stream per block of instances (`noise_block`), seeded by the lift's seed and the
block's index, and chunks are made of whole blocks: an instance's draws are the same however the
batch is cut.

CUDA and other devices run the chunks one after another in the calling thread; CUDA with
torch's deterministic settings (`deterministic_cuda`).
"""

from __future__ import annotations

import os
import threading
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np
import torch

# Rows (instances x hypotheses) below which MKL's matrix products take other kernels (measured on the
# bundled prior's network: a row's result is the same in any chunk of 16 to 4096 rows, and differs
# in chunks of 1 to 15 rows).
MIN_CHUNK_ROWS = 16
# A batch is cut for more threads only into chunks of at least this many rows (each chunk costs
# about 0.2 s of fixed work on one thread).
MIN_SPLIT_ROWS = 32
# Rows of the hypotheses' noise drawn from one random stream.
NOISE_BLOCK_ROWS = 512
# cuBLAS's fixed workspace that makes its results repeat (NVIDIA's cuBLAS docs, "Results reproducibility").
CUBLAS_WORKSPACE = ":4096:8"


@dataclass(frozen=True)
class Chunk:
    start: int  # the chunk's first position in the list of instances to lift
    stop: int
    pad: int  # copies of its last instance added so that it has MIN_CHUNK_ROWS rows

    def positions(self) -> np.ndarray:
        """Positions `(stop - start + pad,)` in the list of instances to lift, padding included."""
        return np.concatenate([np.arange(self.start, self.stop), np.full(self.pad, self.stop - 1)])


def noise_block(hypotheses: int) -> int:
    """Instances per random stream of the hypotheses' noise (1 without noise: K = 1)."""
    return 1 if hypotheses == 1 else max(1, NOISE_BLOCK_ROWS // hypotheses)


def plan_chunks(instances: int, hypotheses: int, chunk_rows: int, workers: int) -> list[Chunk]:
    """The chunks of `instances` instances of `hypotheses` rows each: whole noise blocks, at most
    `chunk_rows` rows (or one block), as many as `workers` where each keeps MIN_SPLIT_ROWS rows,
    of even sizes. Where there are several, each is padded to MIN_CHUNK_ROWS rows; a batch of one
    chunk is one chunk for every thread count, and is not padded (that would cost a one-pose lift
    about 0.1 s, for a difference of under a micrometre from the same pose in a larger batch)."""
    if instances == 0:
        return []
    block = noise_block(hypotheses)
    blocks = -(-instances // block)
    most = max(1, chunk_rows // (hypotheses * block))  # blocks per chunk at most
    rows = instances * hypotheses
    count = min(blocks, max(-(-blocks // most), min(workers, rows // MIN_SPLIT_ROWS)))
    edges = [min(instances, (i * blocks // count) * block) for i in range(count + 1)]
    chunks = []
    for start, stop in zip(edges, edges[1:], strict=False):
        short = MIN_CHUNK_ROWS - (stop - start) * hypotheses if count > 1 else 0
        chunks.append(Chunk(start, stop, max(0, -(-short // hypotheses))))
    return chunks


def lift_workers(device: str, threads: int | None = None) -> int:
    """Chunks run at once: `threads` (default: torch's thread count) on the CPU, 1 elsewhere."""
    if torch.device(device).type != "cpu":
        return 1
    return max(1, torch.get_num_threads() if threads is None else threads)


class BlockNoise:
    """Standard normal draws for the rows of one chunk (instance by instance, K hypotheses each, then
    the padding's rows): one stream per noise block, seeded by `seed` and the block's index, and
    zeros for the padding."""

    def __init__(self, seed: int, chunk: Chunk, hypotheses: int, device: str | torch.device) -> None:
        block = noise_block(hypotheses)
        self.device, self.pad_rows = device, chunk.pad * hypotheses
        self.streams: list[tuple[torch.Generator, int]] = []
        for b in range(chunk.start // block, -(-chunk.stop // block)):
            state = np.random.SeedSequence([seed % 2**64, b]).generate_state(2, np.uint32)
            gen = torch.Generator(device=device).manual_seed(int(state[0]) << 31 | int(state[1]) >> 1)
            count = min(chunk.stop, (b + 1) * block) - max(chunk.start, b * block)
            self.streams.append((gen, count * hypotheses))

    def randn(self, tail: tuple[int, ...], dtype: torch.dtype) -> torch.Tensor:
        """Draws `(rows, *tail)`."""
        parts = [torch.randn((rows, *tail), generator=gen, device=self.device, dtype=dtype)
                 for gen, rows in self.streams]  # fmt: skip
        if self.pad_rows:
            parts.append(torch.zeros((self.pad_rows, *tail), device=self.device, dtype=dtype))
        return parts[0] if len(parts) == 1 else torch.cat(parts)


class Cancelled(Exception):
    """A chunk stopped because another one failed (or the lift was interrupted)."""


def run_chunks(
    chunks: Sequence[Chunk], work: Callable[[Chunk, Callable[[int], None]], None], workers: int, device: str,
    on_steps: Callable[[int], None],
) -> None:  # fmt: skip
    """`work(chunk, tick)` for every chunk: on the CPU on `workers` threads of one intra-op thread
    each, elsewhere in order in this thread. `tick(steps)` reports steps done (`on_steps`, called
    under a lock, so in order); once a chunk fails, the others stop at their next tick."""
    if not chunks:
        return
    lock, stop = threading.Lock(), threading.Event()

    def tick(steps: int) -> None:
        if stop.is_set():
            raise Cancelled
        with lock:
            on_steps(steps)

    if torch.device(device).type != "cpu":
        for chunk in chunks:
            work(chunk, tick)
        return

    def one(chunk: Chunk) -> None:
        torch.set_num_threads(1)  # this thread's intra-op threads
        work(chunk, tick)

    saved = torch.get_num_threads()
    try:
        with ThreadPoolExecutor(max_workers=max(1, min(workers, len(chunks))), thread_name_prefix="zedo-lift") as pool:
            futures = [pool.submit(one, chunk) for chunk in chunks]
            try:
                for future in futures:
                    future.result()
            except BaseException:
                stop.set()
                for future in futures:
                    future.cancel()
                raise
    finally:
        torch.set_num_threads(saved)  # torch keeps the last count set by any thread as its default


def deterministic_cuda() -> None:
    """torch's settings for CUDA runs that repeat to the bit where torch can: deterministic
    algorithms (a warning, not an error, where an operation has none), cuBLAS's fixed workspace
    (read when cuBLAS first starts, so set before the first product), cuDNN without autotuning,
    and full float32 products (no TF32). Process-wide, as torch's settings are."""
    os.environ.setdefault("CUBLAS_WORKSPACE_CONFIG", CUBLAS_WORKSPACE)
    torch.use_deterministic_algorithms(True, warn_only=True)
    torch.backends.cudnn.deterministic = True
    torch.backends.cudnn.benchmark = False
    torch.backends.cuda.matmul.allow_tf32 = False
    torch.backends.cudnn.allow_tf32 = False
