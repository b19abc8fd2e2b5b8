"""`zedo fit-prior`: train a diffusion pose prior from 3D poses."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Optional

import typer

from ..data.datasets import PoseSet, load_npz_poses, load_syrip_3d
from ..data.minirgbd import MINIRGBD_LICENSE, load_minirgbd_3d
from ..errors import ConfigError
from ..files import check_writable
from .checks import DEVICE_HELP, check_device, check_seed, check_syrip_split
from .common import epoch_progress, err_console, error_boundary, output_option


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


@error_boundary
def fit_prior_command(
    poses: Annotated[
        Optional[Path], typer.Argument(help="3D poses (npz with 'poses' (N,J,3) in metres, 'joint_names').")
    ] = None,
    out: Annotated[Path, output_option("Weights file to write (.safetensors).")] = Path("prior.safetensors"),
    syrip_dir: Annotated[Optional[Path], typer.Option(help="Train on the SyRIP data folder instead of POSES.")] = None,
    split: Annotated[
        str,
        typer.Option(
            help="Side of the split: train, test or all (SyRIP: 600, 100, 700 poses; MINI-RGBD: see --minirgbd-split)."
        ),
    ] = "train",
    minirgbd_dir: Annotated[
        Optional[Path], typer.Option(help="Train on a local MINI-RGBD folder (holding 01 .. 12), mapped to h36m17.")
    ] = None,
    minirgbd_split: Annotated[
        str,
        typer.Option(
            help="MINI-RGBD sequences: paper (train 01-09, test 10-12) or reference (train 01-10, test 11-12)."
        ),
    ] = "paper",
    mapping: Annotated[
        str,
        typer.Option(
            help="MINI-RGBD SMIL -> h36m17 joints: reference (toes as ankles, collars as shoulders, as the authors) or anatomical."
        ),
    ] = "reference",
    adult_dir: Annotated[
        Optional[Path],
        typer.Option(
            help="Train on the adult motion-capture folder (three *_h36m17.npz files), in --skeleton's joints (default syrip12)."
        ),
    ] = None,
    skeleton: Annotated[
        Optional[str], typer.Option(help="Joint set of POSES when its file does not name it (h36m17, syrip12, ...).")
    ] = None,
    recipe: Annotated[
        Optional[Path], typer.Option(help="TOML recipe (see weights_spec/); options below override it.")
    ] = None,
    epochs: Annotated[Optional[int], typer.Option(help="Passes over the data (recipe: 8000).")] = None,
    batch_size: Annotated[Optional[int], typer.Option(help="Poses per step (recipe: 5000).")] = None,
    lr: Annotated[Optional[float], typer.Option(help="Adam learning rate after warm-up (2e-4).")] = None,
    warmup_steps: Annotated[Optional[int], typer.Option(help="Linear warm-up steps (5000).")] = None,
    seed: Annotated[Optional[int], typer.Option(help="Seed of initial weights, shuffling and noise (0).")] = None,
    weights: Annotated[
        Optional[str], typer.Option(help="Which weights to save: raw (last step, as the reference) or ema.")
    ] = None,
    dtype: Annotated[Optional[str], typer.Option(help="Stored precision: float16 (half the size) or float32.")] = None,
    license_text: Annotated[
        Optional[str],
        typer.Option("--license", help="Terms of the training data, stored in the file (SyRIP's are filled in)."),
    ] = None,
    device: Annotated[str, typer.Option(help=DEVICE_HELP)] = "cpu",
    ema_out: Annotated[
        Optional[Path], typer.Option(help="Also write the EMA weights to this file (to compare with the raw ones).")
    ] = None,
    overwrite: Annotated[bool, typer.Option(help="Replace the output if it exists.")] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="No progress bar.")] = False,
) -> None:
    """Train a score-matching diffusion prior over 3D poses and write it as a weights file.

    Examples:

      zedo fit-prior --syrip-dir ../shared/data/syrip --split train --recipe weights_spec/syrip12-scratch.toml -o my.safetensors

      zedo fit-prior --adult-dir ../shared/data/adult --recipe weights_spec/adult12-rotscale.toml -o adult.safetensors

      zedo fit-prior poses.npz --skeleton h36m17 --epochs 2000 -o adult.safetensors

      zedo fit-prior --minirgbd-dir ~/data/MINI-RGBD --minirgbd-split paper --split train -o mini.safetensors
    """
    check_syrip_split(split)  # option errors before any data is read
    check_seed(seed)
    device = check_device(device)  # auto: CUDA when present
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

    check_writable(out, overwrite)
    if ema_out is not None:
        check_writable(ema_out, overwrite)
    base = load_recipe(recipe) if recipe is not None else Recipe()
    chosen = with_overrides(base, epochs=epochs, batch_size=batch_size, lr=lr, warmup_steps=warmup_steps, seed=seed)
    chosen = with_output(chosen, weights=weights, dtype=dtype)
    data = load_training_poses(poses, syrip_dir, split, skeleton, minirgbd_dir=minirgbd_dir,
                               minirgbd_split=minirgbd_split, mapping=mapping, adult_dir=adult_dir)  # fmt: skip
    if license_text is None:
        license_text = SYRIP_LICENSE if syrip_dir is not None else "as the terms of the training data"
        license_text = MINIRGBD_LICENSE if minirgbd_dir is not None else license_text
        license_text = ADULT_LICENSE if adult_dir is not None else license_text
    err_console.print(
        f"training a {data.skeleton.name} prior on {len(data.names)} poses from {data.source}: "
        f"{chosen.training.epochs} epochs, batch {chosen.training.batch_size}, seed {chosen.training.seed}, {device}"
        + (f"; batches augmented {chosen.augment.to_dict()}" if chosen.augment.active else "")
    )
    seeds = member_seeds(chosen)
    fits = []
    for number, member_seed in enumerate(seeds, 1):  # an ensemble recipe (output.members > 1) trains one per seed
        label = "fit-prior" if len(seeds) == 1 else f"fit-prior, member {number}/{len(seeds)} (seed {member_seed})"
        with epoch_progress(quiet, label, chosen.training.epochs) as on_epoch:
            fits.append(fit_prior(data, with_overrides(chosen, seed=member_seed), device=device, callback=on_epoch))
    extra = {"recipe": str(recipe) if recipe else None, "device": device}
    sha = write_fitted_prior(out, fits, data, chosen, license_text=license_text, extra_training=extra)
    if ema_out is not None:
        ema_recipe = with_output(chosen, weights="ema")
        write_fitted_prior(ema_out, fits, data, ema_recipe, license_text=license_text, extra_training=extra)
        err_console.print(f"wrote {ema_out} (EMA weights)")
    kind = "" if len(fits) == 1 else f", an ensemble of {len(fits)}"
    err_console.print(
        f"wrote {out} ({chosen.output.weights} weights, {chosen.output.dtype}{kind}, sha256 {sha[:12]}); "
        f"{sum(f.result.steps for f in fits)} steps in {sum(f.result.seconds for f in fits):.0f} s, "
        f"final loss {fits[-1].result.final_loss:.3f}"
    )
