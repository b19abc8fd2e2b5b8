"""`zedo fit-prior`: train a diffusion pose prior from 3D poses."""

from __future__ import annotations

from functools import partial
from pathlib import Path
from typing import Annotated, Optional

import typer

from ..data.datasets import PoseSet, load_npz_poses, load_syrip_3d
from ..data.minirgbd import MINIRGBD_LICENSE, load_minirgbd_3d
from ..errors import ConfigError
from ..files import check_writable
from ..settings.device import check_device
from ..settings.fit_prior import FitPriorOptions
from .common import epoch_progress, err_console, error_boundary, output_option
from .config import config_option, model_option, print_config_option, resolve_options


def load_training_poses(
    poses: Optional[Path], syrip_dir: Optional[Path], split: str, skeleton: Optional[str],
    *, minirgbd_dir: Optional[Path] = None, minirgbd_split: str = "paper", mapping: str = "reference",
    adult_dir: Optional[Path] = None,
) -> PoseSet:  # fmt: skip
    if sum(src is not None for src in (poses, syrip_dir, minirgbd_dir, adult_dir)) != 1:
        raise ConfigError("give exactly one source: a 3D pose file (POSES), --syrip-dir, --minirgbd-dir or --adult-dir")
    if adult_dir is not None:
        from ..data.adult import load_adult_poses  # torch (its augmentation): not for --help

        return load_adult_poses(adult_dir, skeleton or "syrip12")
    if minirgbd_dir is not None:
        if skeleton not in (None, "h36m17"):
            raise ConfigError(f"MINI-RGBD poses are mapped to the h36m17 joint set, not {skeleton!r}")
        return load_minirgbd_3d(minirgbd_dir, minirgbd_split, split, mapping=mapping)
    if syrip_dir is not None:
        if skeleton not in (None, "syrip12"):
            raise ConfigError(f"SyRIP poses are in the syrip12 joint set, not {skeleton!r}")
        return load_syrip_3d(syrip_dir, split)
    assert poses is not None
    return load_npz_poses(poses, skeleton)


_opt = partial(model_option, FitPriorOptions)  # the option `key` of FitPriorOptions, with the model's help text


@error_boundary
def fit_prior_command(
    poses: Annotated[
        Optional[Path], typer.Argument(help="3D poses (npz with 'poses' (N,J,3) in metres, 'joint_names').")
    ] = None,
    out: Annotated[Path, output_option(FitPriorOptions.help("output"))] = FitPriorOptions.default("output"),
    syrip_dir: Annotated[Optional[Path], _opt("syrip_dir")] = None,
    split: Annotated[str, _opt("split")] = FitPriorOptions.default("split"),
    minirgbd_dir: Annotated[Optional[Path], _opt("minirgbd_dir")] = None,
    minirgbd_split: Annotated[str, _opt("minirgbd_split")] = FitPriorOptions.default("minirgbd_split"),
    mapping: Annotated[str, _opt("mapping")] = FitPriorOptions.default("mapping"),
    adult_dir: Annotated[Optional[Path], _opt("adult_dir")] = None,
    skeleton: Annotated[Optional[str], _opt("skeleton")] = None,
    recipe: Annotated[Optional[Path], _opt("recipe")] = None,
    epochs: Annotated[Optional[int], _opt("epochs")] = None,
    batch_size: Annotated[Optional[int], _opt("batch_size")] = None,
    lr: Annotated[Optional[float], _opt("lr")] = None,
    warmup_steps: Annotated[Optional[int], _opt("warmup_steps")] = None,
    seed: Annotated[Optional[int], _opt("seed")] = None,
    weights: Annotated[Optional[str], _opt("weights")] = None,
    dtype: Annotated[Optional[str], _opt("dtype")] = None,
    license_text: Annotated[Optional[str], _opt("license", "--license")] = None,
    device: Annotated[str, _opt("device")] = "cpu",
    ema_out: Annotated[Optional[Path], _opt("ema_out")] = None,
    overwrite: Annotated[bool, _opt("overwrite")] = False,
    quiet: Annotated[bool, _opt("quiet", "--quiet", "-q")] = False,
    config: Annotated[Optional[Path], config_option("fit-prior")] = None,
    print_config: Annotated[bool, print_config_option()] = False,
) -> None:
    """Train a score-matching diffusion prior over 3D poses and write it as a weights file.

    Examples:

      zedo fit-prior --syrip-dir ../shared/data/syrip --split train --recipe weights_spec/syrip12-scratch.toml -o my.safetensors

      zedo fit-prior --adult-dir ../shared/data/adult --recipe weights_spec/adult12-rotscale.toml -o adult.safetensors

      zedo fit-prior poses.npz --skeleton h36m17 --epochs 2000 -o adult.safetensors

      zedo fit-prior --minirgbd-dir ~/data/MINI-RGBD --minirgbd-split paper --split train -o mini.safetensors
    """
    o: FitPriorOptions = resolve_options(FitPriorOptions).options  # option errors before any data is read
    device = check_device(o.device)  # auto: CUDA when present
    from ..data.adult import ADULT_LICENSE  # the training stack loads here, not for --help
    from ..prior.recipes import (
        SYRIP_LICENSE,
        Recipe,
        fit_prior,
        load_recipe,
        member_seeds,
        with_output,
        with_overrides,
        write_fitted_prior,
    )

    check_writable(o.output, o.overwrite)
    if o.ema_out is not None:
        check_writable(o.ema_out, o.overwrite)
    base = load_recipe(o.recipe) if o.recipe is not None else Recipe()
    chosen = with_overrides(base, epochs=o.epochs, batch_size=o.batch_size, lr=o.lr, warmup_steps=o.warmup_steps,
                            seed=o.seed)  # fmt: skip
    chosen = with_output(chosen, weights=o.weights, dtype=o.dtype)
    data = load_training_poses(poses, o.syrip_dir, o.split, o.skeleton, minirgbd_dir=o.minirgbd_dir,
                               minirgbd_split=o.minirgbd_split, mapping=o.mapping, adult_dir=o.adult_dir)  # fmt: skip
    license_text = o.license
    if license_text is None:
        license_text = SYRIP_LICENSE if o.syrip_dir is not None else "as the terms of the training data"
        license_text = MINIRGBD_LICENSE if o.minirgbd_dir is not None else license_text
        license_text = ADULT_LICENSE if o.adult_dir is not None else license_text
    err_console.print(
        f"training a {data.skeleton.name} prior on {len(data.names)} poses from {data.source}: "
        f"{chosen.training.epochs} epochs, batch {chosen.training.batch_size}, seed {chosen.training.seed}, {device}"
        + (f"; batches augmented {chosen.augment.to_dict()}" if chosen.augment.active else "")
    )
    seeds = member_seeds(chosen)
    fits = []
    for number, member_seed in enumerate(seeds, 1):  # an ensemble recipe (output.members > 1) trains one per seed
        label = "fit-prior" if len(seeds) == 1 else f"fit-prior, member {number}/{len(seeds)} (seed {member_seed})"
        with epoch_progress(o.quiet, label, chosen.training.epochs) as on_epoch:
            fits.append(fit_prior(data, with_overrides(chosen, seed=member_seed), device=device, callback=on_epoch))
    extra = {"recipe": str(o.recipe) if o.recipe else None, "device": device}
    sha = write_fitted_prior(o.output, fits, data, chosen, license_text=license_text, extra_training=extra)
    if o.ema_out is not None:
        ema_recipe = with_output(chosen, weights="ema")
        write_fitted_prior(o.ema_out, fits, data, ema_recipe, license_text=license_text, extra_training=extra)
        err_console.print(f"wrote {o.ema_out} (EMA weights)")
    kind = "" if len(fits) == 1 else f", an ensemble of {len(fits)}"
    err_console.print(
        f"wrote {o.output} ({chosen.output.weights} weights, {chosen.output.dtype}{kind}, sha256 {sha[:12]}); "
        f"{sum(f.result.steps for f in fits)} steps in {sum(f.result.seconds for f in fits):.0f} s, "
        f"final loss {fits[-1].result.final_loss:.3f}"
    )
