"""Where a lift's time goes: per-phase wall time of `lift` on one thread.

Lifts the first `--poses` of SyRIP's 1400 real poses (700 images, ground-truth then FiDIP 2D; the
throughput set of `zedo benchmark`, never Test100 alone) with a preset, `--rounds` times, and
prints the total and the time in each phase, timed by wrapping the solver's functions:

    python benchmarks/speed/lift_profile.py --syrip-dir ../shared/data/syrip --preset fast --poses 500
    python benchmarks/speed/lift_profile.py --syrip-dir ../shared/data/syrip --preset fast --bf16 false

Phases: `fit` (the rotation/depth fit of the template), `network` (the prior's noise
predictions), `rays` (moving joints onto their rays), `twin` and `proportions` (the bone-length
terms), `cap` (the twin-ratio cap), `translation` (the root translation solves), `flow` (the
probability-flow update); `loop` is the whole prior loop, `other` the rest of `lift` (input
checks, chunking, the copies back, the status checks).
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np
import torch

from zedo_cli.evaluation.syrip_benchmark import load_throughput_inputs
from zedo_cli.lifting import precision, solver
from zedo_cli.lifting.camera import resolve_intrinsics
from zedo_cli.lifting.config import get_preset
from zedo_cli.prior.weights import load_prior, resolve_prior_path

TIMES: dict[str, float] = {}


def timed(name: str, fn: Callable[..., Any]) -> Callable[..., Any]:
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        start = time.perf_counter()
        out = fn(*args, **kwargs)
        TIMES[name] = TIMES.get(name, 0.0) + time.perf_counter() - start
        return out

    return wrapper


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--syrip-dir", required=True)
    parser.add_argument("--preset", default="fast")
    parser.add_argument("--bf16", choices=("true", "false", "auto"), default=None, help="override the preset's")
    parser.add_argument("--poses", type=int, default=500)
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    torch.set_num_threads(1)
    prior = load_prior(resolve_prior_path(None), skeleton="syrip12")
    kps = [kp.to_skeleton(prior.skeleton) for kp in load_throughput_inputs(args.syrip_dir).values()]
    mats = [resolve_intrinsics(kp.image_sizes, kp.image_ids, kp.file_names)[0] for kp in kps]
    xy = np.concatenate([kp.xy for kp in kps])[: args.poses]
    conf = np.concatenate([kp.confidence for kp in kps])[: args.poses]
    k = np.concatenate(mats)[: args.poses]
    cfg = get_preset(args.preset)
    if args.bf16 is not None:
        cfg = replace(cfg, bf16={"true": True, "false": False, "auto": None}[args.bf16])
    for name, attr in (("fit", "fit_rotation_depth"), ("rays", "project_onto_rays"), ("twin", "twin_limb_step"),
                       ("proportions", "bone_proportion_step"), ("cap", "cap_twin_ratios"),
                       ("translation", "solve_root_translation_ex"), ("flow", "probability_flow_step"),
                       ("loop", "_prior_loop")):  # fmt: skip
        setattr(solver, attr, timed(name, getattr(solver, attr)))
    network = precision.lift_network
    solver.lift_network = lambda *a: timed("network", network(*a))  # type: ignore[assignment]
    print(f"{args.preset}, bfloat16 network: {precision.uses_bfloat16(cfg, 'cpu')}, {len(xy)} poses, 1 thread")
    for _ in range(args.rounds):
        TIMES.clear()
        start = time.perf_counter()
        solver.lift(xy, conf, k, prior, cfg)
        total = time.perf_counter() - start
        TIMES["other"] = total - TIMES["fit"] - TIMES["loop"]
        phases = ", ".join(f"{name} {seconds * 1000:.0f}" for name, seconds in TIMES.items())
        print(f"total {total:.3f} s ({len(xy) / total:.0f} poses/s); ms: {phases}")


if __name__ == "__main__":
    main()
