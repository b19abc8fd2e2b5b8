"""`zedo adapt`: adapt a prior (e.g. the bundled adult prior) to a small infant data set."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Annotated, Optional

import typer

from ..data.datasets import load_npz_poses, npz_license
from ..files import check_writable
from ..prior.schedules import ADAPT_TRAINING, STRATEGIES, default_training
from .checks import DEVICE_HELP, check_choice, check_device, check_seed, check_syrip_split
from .common import check_weights_output, epoch_progress, err_console, error_boundary, output_option
from .fit import load_training_poses


@error_boundary
def adapt_command(
    poses: Annotated[
        Optional[Path],
        typer.Argument(
            help="Infant 3D poses (npz with 'poses' (N,J,3) in metres, 'joint_names'), in the base's joint set."
        ),
    ] = None,
    base: Annotated[
        str, typer.Option(help="Prior to adapt: a bundled name (adult12-rotscale, syrip12-scratch) or a weights file.")
    ] = "adult12-rotscale",
    strategy: Annotated[
        str,
        typer.Option(
            help="control (frozen base + trainable branch), finetune (all weights from the base) or scratch (fresh net of the base's size)."
        ),
    ] = "control",
    out: Annotated[Path, output_option("Weights file to write (.safetensors); `zedo lift --prior` loads it.")] = Path(
        "adapted.safetensors"
    ),
    syrip_dir: Annotated[Optional[Path], typer.Option(help="Adapt on the SyRIP data folder instead of POSES.")] = None,
    split: Annotated[str, typer.Option(help="SyRIP side: train (600 poses), test or all.")] = "train",
    skeleton: Annotated[Optional[str], typer.Option(help="Joint set of POSES when its file does not name it.")] = None,
    add_poses: Annotated[
        Optional[Path],
        typer.Option(help="Also train on these poses (npz, e.g. from `zedo augment`), added after the --limit subset."),
    ] = None,
    limit: Annotated[
        Optional[int], typer.Option(help="Train on a seeded, reproducible subset of N poses (default: all).")
    ] = None,
    epochs: Annotated[
        Optional[int],
        typer.Option(
            help="Passes over the data; one step each while N <= batch size. Default: 1000 (control, finetune), 8000 (scratch)."
        ),
    ] = None,
    batch_size: Annotated[int, typer.Option(help="Poses per step.")] = ADAPT_TRAINING.batch_size,
    lr: Annotated[float, typer.Option(help="Adam learning rate after warm-up.")] = ADAPT_TRAINING.lr,
    warmup_steps: Annotated[
        Optional[int], typer.Option(help="Linear warm-up steps. Default: 200 (control, finetune), 5000 (scratch).")
    ] = None,
    seed: Annotated[
        int, typer.Option(help="Seed of the --limit subset, new weights (prompt, scratch net), noise and shuffling.")
    ] = 0,
    weights: Annotated[
        str,
        typer.Option(
            help="Which weights to save: ema (moving average, the default: steadier on held-out poses) or raw (last step)."
        ),
    ] = "ema",
    dtype: Annotated[str, typer.Option(help="Stored precision: float16 or float32.")] = "float16",
    license_text: Annotated[
        Optional[str],
        typer.Option("--license", help="Terms of POSES, stored with the base's terms (SyRIP's are filled in)."),
    ] = None,
    device: Annotated[str, typer.Option(help=DEVICE_HELP)] = "cpu",
    overwrite: Annotated[bool, typer.Option(help="Replace the output if it exists.")] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="No progress bar.")] = False,
) -> None:
    """Adapt a pose prior to a small infant 3D data set; write a prior `zedo lift` loads.

    The default base is the bundled adult prior. `control` trains a ControlNet-like branch
    beside the frozen base (the written file carries both and names its base); `finetune`
    trains every weight starting from the base; `scratch` trains a fresh network of the same
    size, as a baseline.

    Examples:

      zedo adapt --syrip-dir ../shared/data/syrip --strategy control --limit 100 --seed 1 -o ca100.safetensors

      zedo adapt my_infants.npz --strategy finetune --epochs 1000 -o ft.safetensors

      zedo adapt --syrip-dir ../shared/data/syrip --add-poses aug.npz --strategy finetune -o ft_aug.safetensors

      zedo lift keypoints.json --prior ca100.safetensors
    """
    check_choice("--strategy", strategy, STRATEGIES)
    check_weights_output(weights, dtype)
    check_syrip_split(split)
    check_seed(seed)
    device = check_device(device)  # auto: CUDA when present
    from ..prior.adapt import adapt_prior, select_subset, with_added_poses, write_adapted_prior  # torch from here on
    from ..prior.recipes import DTYPES, SYRIP_LICENSE
    from ..prior.weights import load_prior, resolve_prior_path

    check_writable(out, overwrite)
    recipe = default_training(strategy)
    cfg = replace(recipe, epochs=recipe.epochs if epochs is None else epochs, batch_size=batch_size, lr=lr,
                  warmup_steps=recipe.warmup_steps if warmup_steps is None else warmup_steps, seed=seed)  # fmt: skip
    prior = load_prior(resolve_prior_path(base), device="cpu")
    data = select_subset(load_training_poses(poses, syrip_dir, split, skeleton), limit, seed)
    if add_poses is not None:
        data = with_added_poses(data, load_npz_poses(add_poses, data.skeleton.name))
    terms = (
        license_text
        if license_text is not None
        else (SYRIP_LICENSE if syrip_dir is not None else "as the terms of the adaptation data")
    )
    err_console.print(
        f"adapting {prior.label} by {strategy} on {len(data.names)} poses from {data.source}: "
        f"{cfg.epochs} epochs, batch {cfg.batch_size}, lr {cfg.lr}, seed {cfg.seed}, {device}"
    )
    with epoch_progress(quiet, "adapt", cfg.epochs) as on_epoch:
        adapted = adapt_prior(prior, data, strategy, cfg, device=device, callback=on_epoch)
    base_terms = prior.metadata.get("license", "unknown")
    license_all = terms if strategy == "scratch" else f"{terms} Adapted from a prior whose terms are: {base_terms}"
    added_terms = None if add_poses is None else npz_license(add_poses)
    if added_terms is not None:  # e.g. augmented poses derived from non-commercial data
        license_all += f" Also trained on poses from {add_poses.name}, whose terms are: {added_terms}"
    sha = write_adapted_prior(
        out, adapted, prior, data, cfg, license_text=license_all, weights=weights, dtype=DTYPES[dtype],
        extra={"device": device, "limit": limit, "added_poses": None if add_poses is None else str(add_poses)},
    )  # fmt: skip
    err_console.print(
        f"wrote {out} ({strategy}, {adapted.trainable:,} of {adapted.total:,} parameters trained, {dtype}, "
        f"sha256 {sha[:12]}); {adapted.result.steps} steps in {adapted.result.seconds:.0f} s, "
        f"final loss {adapted.result.final_loss:.3f}"
    )
