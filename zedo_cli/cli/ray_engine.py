"""`zedo lift --engine ray`: the same batch over a Ray cluster, one prior load per worker.

Each worker is a Ray Data actor that loads the prior once and runs the local engine's per-file
function (`cli.lift.lift_and_write`) on the inputs it is given with the local engine's torch thread
count, so the outputs are exactly those of `--engine local` on the same kind of machine (same
names, same content apart from timestamps, written atomically by the worker). Outputs were checked before any work by the driver (`lift_plan.plan_outputs`); an
input's error comes back as data and is reported and counted as in the local engine.

Inputs and outputs must be on a file system every node sees (one machine, or a shared mount);
zedo must be installed on every node. Ray is an optional extra: `pip install 'zedo[ray]'`.
"""

from __future__ import annotations

import logging
import os
import warnings
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import errors
from ..errors import ConfigError, ZedoError
from .common import internal_error

if TYPE_CHECKING:
    from ..pipeline.lift import LiftPlan

# lift_and_write(source, output, prior, plan) -> an outcome with .instances, .lifted, .seconds, .warnings, .written
LiftOne = Callable[[str, str, Any, Any], Any]

RAY_MISSING = "--engine ray needs Ray, an optional extra: pip install 'zedo[ray]'"


class LiftWorker:
    """A Ray Data actor: loads the prior once, then lifts one input per call."""

    def __init__(self, prior_path: str, settings: LiftPlan, threads: int, lift_one: LiftOne) -> None:
        import torch

        from ..prior.weights import load_prior

        torch.set_num_threads(threads)  # one worker per CPU by default: no oversubscription
        self.prior = load_prior(prior_path, device=settings.device)
        self.settings = replace(settings, options=settings.options.replace(quiet=True))  # the driver reports each input
        self.lift_one = lift_one

    def __call__(self, batch: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        rows: list[dict[str, Any]] = []
        for index, source, output in zip(batch["index"], batch["source"], batch["output"], strict=True):
            row = {"index": int(index), "instances": 0, "lifted": 0, "seconds": 0.0, "error_type": "", "error": "",
                   "warnings": "", "written": ""}  # fmt: skip
            try:
                outcome = self.lift_one(str(source), str(output), self.prior, self.settings)
                row.update(instances=outcome.instances, lifted=outcome.lifted, seconds=outcome.seconds,
                           warnings="\n".join(outcome.warnings), written="\n".join(outcome.written))  # fmt: skip
            except Exception as exc:  # isolated like the local engine: one line, no traceback
                error = exc if isinstance(exc, ZedoError) else internal_error(str(source), exc)
                row.update(error_type=type(error).__name__, error=str(error))
            rows.append(row)
        return {key: np.array([r[key] for r in rows]) for key in rows[0]}


def _error(kind: str, message: str) -> ZedoError:
    """The worker's error as the same class, so that exit codes match the local engine's."""
    cls = getattr(errors, kind, None)
    if isinstance(cls, type) and issubclass(cls, ZedoError):
        return cls(message)
    return ZedoError(message)


def connect(address: str | None) -> None:
    """Start Ray on this machine, or join the cluster at `address` (else RAY_ADDRESS)."""
    try:
        import ray
    except ImportError:
        raise ConfigError(RAY_MISSING) from None
    if ray.is_initialized():
        return
    address = address or os.environ.get("RAY_ADDRESS") or None
    try:
        ray.init(address=address, include_dashboard=False, log_to_driver=False, logging_level="ERROR")
    except ConnectionError as exc:
        raise ConfigError(f"--ray-address {address}: cannot connect to a Ray cluster ({exc})") from None


@dataclass(frozen=True)
class RayOutcome:
    """What a worker reports for one input: counts, or the error (as the same ZedoError class)."""

    instances: int
    lifted: int
    seconds: float
    error: ZedoError | None
    warnings: tuple[str, ...]  # its `zedo: warning:` lines, one line each
    written: tuple[str, ...] = ()  # the files it wrote (every track's TRC / C3D, a CSV's sidecar)


def lift_files_on_ray(
    sources: list[str],
    outputs: list[str],
    prior_path: str,
    settings: LiftPlan,
    lift_one: LiftOne,
    *,
    address: str | None = None,
    workers: int | None = None,
) -> list[RayOutcome]:
    """Lift every input with `lift_one` (the local engine's per-file function) on a Ray
    cluster; the outcomes come back in input order."""
    connect(address)
    import ray
    import torch

    # Each worker gets the local engine's torch thread count: matrix products sum in an order
    # that depends on it, so only then are the outputs the local engine's to the last digit.
    # `--workers` trades that for more, thinner workers (differences of a micrometre).
    cpus = int(ray.cluster_resources().get("CPU", 1))
    local_threads = torch.get_num_threads()
    if workers is None:
        threads = min(local_threads, cpus)
        size = max(1, cpus // threads)
    else:
        size = workers
        threads = max(1, cpus // workers)
    size = min(size, len(sources))
    context = ray.data.DataContext.get_current()
    context.enable_progress_bars = not settings.quiet
    context.print_on_execution_start = False
    if settings.quiet:
        logging.getLogger("ray.data").setLevel(logging.ERROR)
    items = [{"index": i, "source": s, "output": o} for i, (s, o) in enumerate(zip(sources, outputs, strict=True))]
    dataset = ray.data.from_items(items, override_num_blocks=len(items))
    with warnings.catch_warnings():
        # max_restarts is passed the only way Ray Data takes it (as a remote argument, deprecated
        # from Ray 2.60 without a replacement yet): a worker that dies fails the batch loudly,
        # and Ray does not warn per actor that a restart could lose its arguments.
        warnings.filterwarnings("ignore", message=".*ray_remote_args.*deprecated")
        mapped = dataset.map_batches(
            LiftWorker,
            fn_constructor_kwargs={
                "prior_path": prior_path,
                "settings": settings,
                "threads": threads,
                "lift_one": lift_one,
            },
            batch_size=1,
            compute=ray.data.ActorPoolStrategy(size=size),
            num_cpus=threads,
            max_restarts=0,
        )
    results = mapped.take_all()
    by_index = {int(r["index"]): r for r in results}
    rows = [by_index[i] for i in range(len(sources))]
    return [
        RayOutcome(int(r["instances"]), int(r["lifted"]), float(r["seconds"]),
                   _error(str(r["error_type"]), str(r["error"])) if r["error_type"] else None,
                   tuple(str(r["warnings"]).split("\n")) if str(r["warnings"]) else (),
                   tuple(str(r["written"]).split("\n")) if str(r["written"]) else ())
        for r in rows
    ]  # fmt: skip
