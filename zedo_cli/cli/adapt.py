"""`zedo adapt`: adapt a prior (e.g. the bundled adult prior) to a small infant data set."""

from __future__ import annotations

from dataclasses import replace
from functools import partial
from pathlib import Path
from typing import Annotated, Optional

import typer

from ..data.datasets import load_npz_poses, npz_license
from ..files import check_writable
from ..prior.schedules import default_training
from ..settings.adapt import AdaptOptions
from ..settings.device import check_device
from .common import epoch_progress, err_console, error_boundary, output_option
from .config import config_option, model_option, print_config_option, resolve_options
from .fit import load_training_poses

_opt = partial(model_option, AdaptOptions)  # the option `key` of AdaptOptions, with the model's help text


@error_boundary
def adapt_command(
    poses: Annotated[
        Optional[Path],
        typer.Argument(
            help="Infant 3D poses (npz with 'poses' (N,J,3) in metres, 'joint_names'), in the base's joint set."
        ),
    ] = None,
    base: Annotated[str, _opt("base")] = AdaptOptions.default("base"),
    strategy: Annotated[str, _opt("strategy")] = AdaptOptions.default("strategy"),
    out: Annotated[Path, output_option(AdaptOptions.help("output"))] = AdaptOptions.default("output"),
    syrip_dir: Annotated[Optional[Path], _opt("syrip_dir")] = None,
    split: Annotated[str, _opt("split")] = AdaptOptions.default("split"),
    skeleton: Annotated[Optional[str], _opt("skeleton")] = None,
    add_poses: Annotated[Optional[Path], _opt("add_poses")] = None,
    limit: Annotated[Optional[int], _opt("limit")] = None,
    epochs: Annotated[Optional[int], _opt("epochs")] = None,
    batch_size: Annotated[int, _opt("batch_size")] = AdaptOptions.default("batch_size"),
    lr: Annotated[float, _opt("lr")] = AdaptOptions.default("lr"),
    warmup_steps: Annotated[Optional[int], _opt("warmup_steps")] = None,
    seed: Annotated[int, _opt("seed")] = 0,
    weights: Annotated[str, _opt("weights")] = AdaptOptions.default("weights"),
    dtype: Annotated[str, _opt("dtype")] = AdaptOptions.default("dtype"),
    license_text: Annotated[Optional[str], _opt("license", "--license")] = None,
    device: Annotated[str, _opt("device")] = "cpu",
    overwrite: Annotated[bool, _opt("overwrite")] = False,
    quiet: Annotated[bool, _opt("quiet", "--quiet", "-q")] = False,
    config: Annotated[Optional[Path], config_option("adapt")] = None,
    print_config: Annotated[bool, print_config_option()] = False,
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
    o: AdaptOptions = resolve_options(AdaptOptions).options
    device = check_device(o.device)  # auto: CUDA when present
    from ..prior.adapt import adapt_prior, select_subset, with_added_poses, write_adapted_prior  # torch from here on
    from ..prior.recipes import DTYPES, SYRIP_LICENSE
    from ..prior.weights import load_prior, resolve_prior_path

    check_writable(o.output, o.overwrite)
    recipe = default_training(o.strategy)
    cfg = replace(recipe, epochs=recipe.epochs if o.epochs is None else o.epochs, batch_size=o.batch_size, lr=o.lr,
                  warmup_steps=recipe.warmup_steps if o.warmup_steps is None else o.warmup_steps, seed=o.seed)  # fmt: skip
    prior = load_prior(resolve_prior_path(o.base), device="cpu")
    data = select_subset(load_training_poses(poses, o.syrip_dir, o.split, o.skeleton), o.limit, o.seed)
    if o.add_poses is not None:
        data = with_added_poses(data, load_npz_poses(o.add_poses, data.skeleton.name))
    terms = (
        o.license
        if o.license is not None
        else (SYRIP_LICENSE if o.syrip_dir is not None else "as the terms of the adaptation data")
    )
    err_console.print(
        f"adapting {prior.label} by {o.strategy} on {len(data.names)} poses from {data.source}: "
        f"{cfg.epochs} epochs, batch {cfg.batch_size}, lr {cfg.lr}, seed {cfg.seed}, {device}"
    )
    with epoch_progress(o.quiet, "adapt", cfg.epochs) as on_epoch:
        adapted = adapt_prior(prior, data, o.strategy, cfg, device=device, callback=on_epoch)
    base_terms = prior.metadata.get("license", "unknown")
    license_all = terms if o.strategy == "scratch" else f"{terms} Adapted from a prior whose terms are: {base_terms}"
    added_terms = None if o.add_poses is None else npz_license(o.add_poses)
    if added_terms is not None:  # e.g. augmented poses derived from non-commercial data
        license_all += f" Also trained on poses from {o.add_poses.name}, whose terms are: {added_terms}"
    sha = write_adapted_prior(
        o.output, adapted, prior, data, cfg, license_text=license_all, weights=o.weights, dtype=DTYPES[o.dtype],
        extra={"device": device, "limit": o.limit, "added_poses": None if o.add_poses is None else str(o.add_poses)},
    )  # fmt: skip
    err_console.print(
        f"wrote {o.output} ({o.strategy}, {adapted.trainable:,} of {adapted.total:,} parameters trained, {o.dtype}, "
        f"sha256 {sha[:12]}); {adapted.result.steps} steps in {adapted.result.seconds:.0f} s, "
        f"final loss {adapted.result.final_loss:.3f}"
    )
