"""`zedo fit-augmenter` (train the domain-conditioned network) and `zedo augment` (convert adult
poses into infant-like ones)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Annotated, Optional

import numpy as np
import typer

from ..data.datasets import PoseSet, load_npz_poses, load_syrip_3d
from ..errors import ConfigError
from ..files import atomic_path, check_writable
from ..prior.schedules import AUGMENTER_TRAINING
from .checks import (
    DEVICE_HELP,
    MAX_COUNT,
    check_choice,
    check_device,
    check_range,
    check_seed,
    check_steps,
    check_syrip_split,
)
from .common import check_weights_output, epoch_progress, err_console, error_boundary, output_option, step_progress

ORIENT_MODES = ("keep", "infant")
BONE_MODES = ("keep", "infant")
DEFAULT_STRENGTH = 0.2  # the smallest sweep strength closing >= 90 % of the proportion gap (docs/benchmarks.md)


def load_adult_source(adult_poses: Optional[Path], adult_dir: Optional[Path], skeleton: str) -> PoseSet:
    if (adult_poses is None) == (adult_dir is None):
        raise ConfigError("give exactly one adult source: ADULT_POSES (an npz file) or --adult-dir")
    if adult_dir is not None:
        from ..data.adult import load_adult_poses  # torch (its augmentation): not for --help

        return load_adult_poses(adult_dir, skeleton)
    assert adult_poses is not None
    return load_npz_poses(adult_poses, skeleton)


def load_infant_source(infant: Optional[Path], syrip_dir: Optional[Path], split: str, skeleton: str) -> PoseSet | None:
    if infant is not None and syrip_dir is not None:
        raise ConfigError("give at most one infant source: --infant (an npz file) or --syrip-dir")
    if syrip_dir is not None:
        return load_syrip_3d(syrip_dir, split)
    return load_npz_poses(infant, skeleton) if infant is not None else None


@error_boundary
def fit_augmenter_command(
    infant: Annotated[
        Optional[Path], typer.Option(help="Infant 3D poses (npz with 'poses' (N,J,3) in metres, 'joint_names').")
    ] = None,
    syrip_dir: Annotated[
        Optional[Path], typer.Option(help="Take the infant poses from the SyRIP data folder instead.")
    ] = None,
    split: Annotated[str, typer.Option(help="SyRIP side: train (600 poses), test or all.")] = "train",
    adult_dir: Annotated[
        Optional[Path], typer.Option(help="Adult motion-capture folder (three *_h36m17.npz files).")
    ] = None,
    adult_poses: Annotated[
        Optional[Path], typer.Option(help="Adult 3D poses as an npz file, instead of --adult-dir.")
    ] = None,
    skeleton: Annotated[str, typer.Option(help="Joint set of the model (the infant data's).")] = "syrip12",
    init: Annotated[
        str, typer.Option(help="Start from this plain prior (bundled name or file), or 'none' for fresh weights.")
    ] = "adult12-rotscale",
    out: Annotated[Path, output_option("Augmenter weights file to write (.safetensors).")] = Path(
        "augmenter.safetensors"
    ),
    epochs: Annotated[
        int, typer.Option(help="Passes over the balanced adult + infant set.")
    ] = AUGMENTER_TRAINING.epochs,
    batch_size: Annotated[
        int, typer.Option(help="Poses per step (half adult, half infant on average).")
    ] = AUGMENTER_TRAINING.batch_size,
    lr: Annotated[float, typer.Option(help="Adam learning rate after warm-up.")] = AUGMENTER_TRAINING.lr,
    warmup_steps: Annotated[int, typer.Option(help="Linear warm-up steps.")] = AUGMENTER_TRAINING.warmup_steps,
    seed: Annotated[int, typer.Option(help="Seed of the tokens, fresh weights, rotations, noise and shuffling.")] = 0,
    weights: Annotated[
        str, typer.Option(help="Which weights to save: ema (moving average) or raw (last step).")
    ] = "ema",
    dtype: Annotated[str, typer.Option(help="Stored precision: float16 or float32.")] = "float16",
    license_text: Annotated[
        Optional[str],
        typer.Option("--license", help="Terms of the infant data (SyRIP's are filled in); the adult terms are added."),
    ] = None,
    device: Annotated[str, typer.Option(help=DEVICE_HELP)] = "cpu",
    overwrite: Annotated[bool, typer.Option(help="Replace the output if it exists.")] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="No progress bar.")] = False,
) -> None:
    """Train the domain-conditioned network of `zedo augment` on adult and infant 3D poses.

    The network is the prior's with two learnable domain tokens (adult, infant) added to its time
    embedding. It sees size-normalised poses, infant poses repeated to balance the adult ones,
    every batch randomly rotated; by default it starts from the bundled adult prior.

    Examples:

      zedo fit-augmenter --adult-dir ../shared/data/adult --syrip-dir ../shared/data/syrip -o augmenter.safetensors

      zedo augment --adult-dir ../shared/data/adult --model augmenter.safetensors --count 600 -o aug.npz
    """
    from ..augment.augmenter import save_augmenter, train_augmenter  # torch from here on
    from ..data.adult import ADULT_LICENSE
    from ..prior.recipes import DTYPES, SYRIP_LICENSE
    from ..prior.weights import load_prior, resolve_prior_path

    check_weights_output(weights, dtype)
    check_syrip_split(split)
    check_seed(seed)
    device = check_device(device)  # auto: CUDA when present
    check_writable(out, overwrite)
    cfg = replace(AUGMENTER_TRAINING, epochs=epochs, batch_size=batch_size, lr=lr, warmup_steps=warmup_steps, seed=seed)
    start = None if init == "none" else load_prior(resolve_prior_path(init), device="cpu")
    infant_set = load_infant_source(infant, syrip_dir, split, skeleton)
    if infant_set is None:
        raise ConfigError("give the infant poses: --infant (an npz file) or --syrip-dir")
    adult_set = load_adult_source(adult_poses, adult_dir, skeleton)
    err_console.print(
        f"training an augmenter on {len(adult_set.names)} adult poses ({adult_set.source}) and "
        f"{len(infant_set.names)} infant poses ({infant_set.source}), from "
        f"{start.label if start else 'fresh weights'}: {cfg.epochs} epochs, batch {cfg.batch_size}, seed {cfg.seed}"
    )
    with epoch_progress(quiet, "fit-augmenter", cfg.epochs) as on_epoch:
        trained = train_augmenter(adult_set, infant_set, cfg, init=start, device=device, callback=on_epoch)
    terms = license_text if license_text is not None else (SYRIP_LICENSE if syrip_dir else "as the infant data's")
    adult_terms = ADULT_LICENSE if adult_dir is not None else "as the adult data's"
    sha = save_augmenter(
        out, trained.result.state(weights), trained.model.cfg, trained.sde, adult_set.skeleton,
        trained.sizes, training={**cfg.to_dict(), "weights": weights, "device": device, **trained.result.summary()},
        data={"adult": adult_set.summary(), "infant": infant_set.summary()},
        license_text=f"Infant data: {terms} Adult data: {adult_terms}", dtype=DTYPES[dtype],
        initialised_from=None if start is None else {"file": Path(start.path).name, "sha256": start.sha256},
    )  # fmt: skip
    err_console.print(
        f"wrote {out} ({weights} weights, {dtype}, sha256 {sha[:12]}); {trained.result.steps} steps in "
        f"{trained.result.seconds:.0f} s, final loss {trained.result.final_loss:.3f}"
    )


@error_boundary
def augment_command(
    adult_poses: Annotated[
        Optional[Path],
        typer.Argument(help="Adult 3D poses to convert (npz with 'poses' (N,J,3) in metres, 'joint_names')."),
    ] = None,
    model: Annotated[Path, typer.Option(help="Augmenter weights file written by `zedo fit-augmenter`.")] = Path(
        "augmenter.safetensors"
    ),
    adult_dir: Annotated[
        Optional[Path], typer.Option(help="Convert poses of the adult motion-capture folder instead of ADULT_POSES.")
    ] = None,
    count: Annotated[
        int,
        typer.Option(
            help="Number of poses to write, drawn from the adult poses (seeded; without repeats when there are enough)."
        ),
    ] = 600,
    out: Annotated[
        Path,
        output_option(
            "npz file to write: 'poses' (count, J, 3) metres, 'joint_names', 'names', 'source_poses'.",
        ),
    ] = Path("augmented.npz"),
    strength: Annotated[
        float,
        typer.Option(help="Noise level t0 in (0, 1]: higher changes more (proportions, then posture); 0 only resizes."),
    ] = DEFAULT_STRENGTH,
    steps: Annotated[int, typer.Option(help="Reverse diffusion steps from t0.")] = 100,
    scale: Annotated[
        str,
        typer.Option(
            help="Size of the outputs: infant (drawn from the infant training sizes stored in the model) or keep (each input's own size)."
        ),
    ] = "infant",
    orient: Annotated[
        str,
        typer.Option(
            help="keep (the input's orientation) or infant (turn each pose's torso like a random pose of --infant / --syrip-dir)."
        ),
    ] = "keep",
    bones: Annotated[
        str,
        typer.Option(
            help="keep (the converted bone lengths) or infant (each pose takes the bone proportions of a random pose of --infant / --syrip-dir, keeping its joint angles and size)."
        ),
    ] = "keep",
    infant: Annotated[
        Optional[Path],
        typer.Option(help="Infant reference poses (npz) for --orient infant, --bones infant and --plot."),
    ] = None,
    syrip_dir: Annotated[
        Optional[Path], typer.Option(help="Use SyRIP's training poses as the infant reference.")
    ] = None,
    plot: Annotated[
        Optional[Path],
        typer.Option(
            help="Folder for PNGs: bone-length and bone-angle distributions (infant, augmented, adult) and adult/converted pairs."
        ),
    ] = None,
    seed: Annotated[
        int, typer.Option(help="Seed of the pose draw, noise, sizes, bone proportions and orientations.")
    ] = 0,
    overwrite: Annotated[bool, typer.Option(help="Replace the output and the PNGs if they exist.")] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="No progress bar.")] = False,
) -> None:
    """Convert adult 3D poses into infant-like ones with a domain-conditioned diffusion model.

    Each drawn adult pose is size-normalised, noised to level --strength and denoised in --steps
    reverse steps under the infant token, so posture survives while proportions become an
    infant's; then it is sized (--scale), optionally given a real infant's bone proportions
    (--bones) and turned into the infant data's camera orientation (--orient). The npz written feeds `zedo adapt --add-poses`.

    Examples:

      zedo augment --adult-dir ../shared/data/adult --model augmenter.safetensors --count 600 --orient infant --syrip-dir ../shared/data/syrip -o aug.npz --plot aug_plots

      zedo adapt --syrip-dir ../shared/data/syrip --add-poses aug.npz --strategy finetune -o ft_aug.safetensors
    """
    from ..augment.augmenter import load_augmenter  # torch from here on
    from ..augment.conversion import (
        SCALE_MODES,
        check_strength,
        choose_sources,
        convert_poses,
        orient_like,
        skeleton_size,
        take_bone_lengths,
    )
    from ..augment.plots import PLOT_NAMES

    check_strength(strength)
    check_range("--count", count, 1, MAX_COUNT)
    check_steps(steps)
    check_seed(seed)
    check_choice("--scale", scale, SCALE_MODES)
    check_choice("--orient", orient, ORIENT_MODES)
    check_choice("--bones", bones, BONE_MODES)
    if infant is None and syrip_dir is None and (orient == "infant" or bones == "infant" or plot is not None):
        raise ConfigError(
            "--orient infant, --bones infant and --plot need infant reference poses: --infant (npz) or --syrip-dir"
        )
    check_writable(out, overwrite)
    if plot is not None and plot.is_dir():
        for name in PLOT_NAMES:  # refuse before any work, not after the conversion
            check_writable(plot / name, overwrite)
    augmenter = load_augmenter(model)
    skel = augmenter.skeleton
    reference = load_infant_source(infant, syrip_dir, "train", skel.name)
    if reference is not None and reference.skeleton.name != skel.name:
        raise ConfigError(f"infant reference poses are {reference.skeleton.name}, the augmenter {skel.name}")
    adult = load_adult_source(adult_poses, adult_dir, skel.name)
    rows = choose_sources(len(adult.poses), count, seed)
    sources = adult.poses[rows]
    err_console.print(
        f"converting {len(rows)} of {len(adult.poses)} adult poses ({adult.source}) with {augmenter.label}: "
        f"strength {strength}, {steps} steps, scale {scale}, bones {bones}, orient {orient}, seed {seed}"
    )
    with step_progress(quiet, "augment: reverse steps") as on_step:
        poses = convert_poses(augmenter.model, augmenter.sde, augmenter.sizes, skel, sources, strength=strength,
                              steps=steps, scale=scale, seed=seed, on_step=on_step)  # fmt: skip
    if bones == "infant":
        assert reference is not None
        poses = take_bone_lengths(poses, reference.poses, skel, seed)
    converted = poses  # in the sources' orientation, for side-by-side pairs
    if orient == "infant":
        assert reference is not None
        poses = orient_like(poses, reference.poses, skel, seed)
    names = np.array([f"{adult.names[r]}#{r}" for r in rows])
    with atomic_path(out, overwrite=overwrite) as tmp, open(tmp, "wb") as fh:
        np.savez(fh, poses=poses, joint_names=np.array(skel.joints), names=names, source_poses=sources,
                 strength=strength, steps=steps, scale=scale, bones=bones, orient=orient, seed=seed,
                 augmenter_sha256=augmenter.sha256, license=augmenter.metadata.get("license", ""))  # fmt: skip
    size = np.median(skeleton_size(poses, skel))
    err_console.print(f"wrote {out}: {len(poses)} {skel.name} poses, median skeleton size {size:.3f} m")
    if plot is not None:
        assert reference is not None
        from ..augment.plots import write_augmentation_plots

        # Bone lengths and angles do not depend on orientation; pairs are drawn in the source's.
        paths = write_augmentation_plots(plot, skel, reference.poses, converted, sources, overwrite=overwrite)
        err_console.print(f"wrote {', '.join(str(p) for p in paths)}")
