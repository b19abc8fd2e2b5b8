"""`zedo fit-augmenter` (train the domain-conditioned network) and `zedo augment` (convert adult
poses into infant-like ones)."""

from __future__ import annotations

from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Optional

import numpy as np
import typer

from ..data.datasets import PoseSet, load_npz_poses, load_syrip_3d
from ..errors import ConfigError
from ..files import atomic_path, check_writable
from ..settings.augment import AugmentOptions, FitAugmenterOptions
from ..settings.device import check_device
from .common import epoch_progress, err_console, error_boundary, output_option, step_progress
from .config import config_option, model_option, print_config_option, resolve_options

if TYPE_CHECKING:
    from ..augment.augmenter import AugmenterTraining
    from ..prior.weights import Prior


def load_adult_source(adult_poses: Optional[Path], adult_dir: Optional[Path], skeleton: str) -> PoseSet:
    if (adult_poses is None) == (adult_dir is None):
        raise ConfigError("give exactly one adult source: ADULT_POSES (an npz file) or --adult-dir")
    if adult_dir is not None:
        from ..data.adult import load_adult_poses  # torch (its augmentation): not for --help

        return load_adult_poses(adult_dir, skeleton)
    assert adult_poses is not None
    return load_npz_poses(adult_poses, skeleton)


def load_infant_source(infant: Optional[Path], syrip_dir: Optional[Path], split: str, skeleton: str) -> PoseSet | None:
    """The infant poses of --syrip-dir or --infant (the settings models allow at most one); None: neither."""
    if syrip_dir is not None:
        return load_syrip_3d(syrip_dir, split)
    return load_npz_poses(infant, skeleton) if infant is not None else None


_fit_opt = partial(model_option, FitAugmenterOptions)  # the option `key` of FitAugmenterOptions, with its help text
_aug_opt = partial(model_option, AugmentOptions)  # the option `key` of AugmentOptions, with its help text


@error_boundary
def fit_augmenter_command(
    infant: Annotated[Optional[Path], _fit_opt("infant")] = None,
    syrip_dir: Annotated[Optional[Path], _fit_opt("syrip_dir")] = None,
    split: Annotated[str, _fit_opt("split")] = FitAugmenterOptions.default("split"),
    adult_dir: Annotated[Optional[Path], _fit_opt("adult_dir")] = None,
    adult_poses: Annotated[Optional[Path], _fit_opt("adult_poses")] = None,
    skeleton: Annotated[str, _fit_opt("skeleton")] = FitAugmenterOptions.default("skeleton"),
    init: Annotated[str, _fit_opt("init")] = FitAugmenterOptions.default("init"),
    out: Annotated[Path, output_option(FitAugmenterOptions.help("output"))] = FitAugmenterOptions.default("output"),
    epochs: Annotated[int, _fit_opt("epochs")] = FitAugmenterOptions.default("epochs"),
    batch_size: Annotated[int, _fit_opt("batch_size")] = FitAugmenterOptions.default("batch_size"),
    lr: Annotated[float, _fit_opt("lr")] = FitAugmenterOptions.default("lr"),
    warmup_steps: Annotated[int, _fit_opt("warmup_steps")] = FitAugmenterOptions.default("warmup_steps"),
    seed: Annotated[int, _fit_opt("seed")] = 0,
    weights: Annotated[str, _fit_opt("weights")] = FitAugmenterOptions.default("weights"),
    dtype: Annotated[str, _fit_opt("dtype")] = FitAugmenterOptions.default("dtype"),
    license_text: Annotated[Optional[str], _fit_opt("license", "--license")] = None,
    device: Annotated[str, _fit_opt("device")] = "cpu",
    overwrite: Annotated[bool, _fit_opt("overwrite")] = False,
    quiet: Annotated[bool, _fit_opt("quiet", "--quiet", "-q")] = False,
    config: Annotated[Optional[Path], config_option("fit-augmenter")] = None,
    print_config: Annotated[bool, print_config_option()] = False,
) -> None:
    """Train the domain-conditioned network of `zedo augment` on adult and infant 3D poses.

    The network is the prior's with two learnable domain tokens (adult, infant) added to its time
    embedding. It sees size-normalised poses, infant poses repeated to balance the adult ones,
    every batch randomly rotated; by default it starts from the bundled adult prior.

    Examples:

      zedo fit-augmenter --adult-dir ../shared/data/adult --syrip-dir ../shared/data/syrip -o augmenter.safetensors

      zedo augment --adult-dir ../shared/data/adult --model augmenter.safetensors --count 600 -o aug.npz
    """
    o: FitAugmenterOptions = resolve_options(FitAugmenterOptions).options  # option errors before any data is read
    device = check_device(o.device)  # auto: CUDA when present
    from ..augment.augmenter import train_augmenter  # torch from here on
    from ..prior.weights import load_prior, resolve_prior_path

    check_writable(o.output, o.overwrite)
    cfg = o.training()
    start = None if o.init == "none" else load_prior(resolve_prior_path(o.init), device="cpu")
    infant_set = load_infant_source(o.infant, o.syrip_dir, o.split, o.skeleton)
    assert infant_set is not None  # FitAugmenterOptions.check: one infant source
    adult_set = load_adult_source(o.adult_poses, o.adult_dir, o.skeleton)
    err_console.print(
        f"training an augmenter on {len(adult_set.names)} adult poses ({adult_set.source}) and "
        f"{len(infant_set.names)} infant poses ({infant_set.source}), from "
        f"{start.label if start else 'fresh weights'}: {cfg.epochs} epochs, batch {cfg.batch_size}, seed {cfg.seed}"
    )
    with epoch_progress(o.quiet, "fit-augmenter", cfg.epochs) as on_epoch:
        trained = train_augmenter(adult_set, infant_set, cfg, init=start, device=device, callback=on_epoch)
    sha = write_augmenter(o, trained, start, adult_set, infant_set, device)
    err_console.print(
        f"wrote {o.output} ({o.weights} weights, {o.dtype}, sha256 {sha[:12]}); {trained.result.steps} steps in "
        f"{trained.result.seconds:.0f} s, final loss {trained.result.final_loss:.3f}"
    )


def write_augmenter(
    o: FitAugmenterOptions,
    trained: AugmenterTraining,
    start: Prior | None,
    adult: PoseSet,
    infant: PoseSet,
    device: str,
) -> str:
    """Write the trained augmenter with its training, data and terms; its sha256."""
    from ..augment.augmenter import save_augmenter
    from ..data.adult import ADULT_LICENSE
    from ..prior.recipes import DTYPES, SYRIP_LICENSE

    infant_terms = SYRIP_LICENSE if o.syrip_dir is not None else "as the infant data's"
    terms = o.license if o.license is not None else infant_terms
    adult_terms = ADULT_LICENSE if o.adult_dir is not None else "as the adult data's"
    training = {**o.training().to_dict(), "weights": o.weights, "device": device, **trained.result.summary()}
    return save_augmenter(
        o.output, trained.result.state(o.weights), trained.model.cfg, trained.sde, adult.skeleton, trained.sizes,
        training=training, data={"adult": adult.summary(), "infant": infant.summary()},
        license_text=f"Infant data: {terms} Adult data: {adult_terms}", dtype=DTYPES[o.dtype],
        initialised_from=None if start is None else {"file": Path(start.path).name, "sha256": start.sha256},
    )  # fmt: skip


@error_boundary
def augment_command(
    adult_poses: Annotated[
        Optional[Path],
        typer.Argument(help="Adult 3D poses to convert (npz with 'poses' (N,J,3) in metres, 'joint_names')."),
    ] = None,
    model: Annotated[Path, _aug_opt("model")] = AugmentOptions.default("model"),
    adult_dir: Annotated[Optional[Path], _aug_opt("adult_dir")] = None,
    count: Annotated[int, _aug_opt("count")] = AugmentOptions.default("count"),
    out: Annotated[Path, output_option(AugmentOptions.help("output"))] = AugmentOptions.default("output"),
    strength: Annotated[float, _aug_opt("strength")] = AugmentOptions.default("strength"),
    steps: Annotated[int, _aug_opt("steps")] = AugmentOptions.default("steps"),
    scale: Annotated[str, _aug_opt("scale")] = AugmentOptions.default("scale"),
    orient: Annotated[str, _aug_opt("orient")] = AugmentOptions.default("orient"),
    bones: Annotated[str, _aug_opt("bones")] = AugmentOptions.default("bones"),
    infant: Annotated[Optional[Path], _aug_opt("infant")] = None,
    syrip_dir: Annotated[Optional[Path], _aug_opt("syrip_dir")] = None,
    plot: Annotated[Optional[Path], _aug_opt("plot")] = None,
    seed: Annotated[int, _aug_opt("seed")] = 0,
    overwrite: Annotated[bool, _aug_opt("overwrite")] = False,
    quiet: Annotated[bool, _aug_opt("quiet", "--quiet", "-q")] = False,
    config: Annotated[Optional[Path], config_option("augment")] = None,
    print_config: Annotated[bool, print_config_option()] = False,
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
    o: AugmentOptions = resolve_options(AugmentOptions).options  # option errors before any data is read
    from ..augment.augmenter import load_augmenter  # torch from here on
    from ..augment.conversion import choose_sources, convert_poses, orient_like, skeleton_size, take_bone_lengths
    from ..augment.plots import PLOT_NAMES

    check_writable(o.output, o.overwrite)
    if o.plot is not None and o.plot.is_dir():
        for name in PLOT_NAMES:  # refuse before any work, not after the conversion
            check_writable(o.plot / name, o.overwrite)
    augmenter = load_augmenter(o.model)
    skel = augmenter.skeleton
    reference = load_infant_source(o.infant, o.syrip_dir, "train", skel.name)
    if reference is not None and reference.skeleton.name != skel.name:
        raise ConfigError(f"infant reference poses are {reference.skeleton.name}, the augmenter {skel.name}")
    adult = load_adult_source(adult_poses, o.adult_dir, skel.name)
    rows = choose_sources(len(adult.poses), o.count, o.seed)
    sources = adult.poses[rows]
    err_console.print(
        f"converting {len(rows)} of {len(adult.poses)} adult poses ({adult.source}) with {augmenter.label}: "
        f"strength {o.strength}, {o.steps} steps, scale {o.scale}, bones {o.bones}, orient {o.orient}, seed {o.seed}"
    )
    with step_progress(o.quiet, "augment: reverse steps") as on_step:
        poses = convert_poses(augmenter.model, augmenter.sde, augmenter.sizes, skel, sources, strength=o.strength,
                              steps=o.steps, scale=o.scale, seed=o.seed, on_step=on_step)  # fmt: skip
    if o.bones == "infant":
        assert reference is not None
        poses = take_bone_lengths(poses, reference.poses, skel, o.seed)
    converted = poses  # in the sources' orientation, for side-by-side pairs
    if o.orient == "infant":
        assert reference is not None
        poses = orient_like(poses, reference.poses, skel, o.seed)
    names = np.array([f"{adult.names[r]}#{r}" for r in rows])
    with atomic_path(o.output, overwrite=o.overwrite) as tmp, open(tmp, "wb") as fh:
        np.savez(fh, poses=poses, joint_names=np.array(skel.joints), names=names, source_poses=sources,
                 strength=o.strength, steps=o.steps, scale=o.scale, bones=o.bones, orient=o.orient, seed=o.seed,
                 augmenter_sha256=augmenter.sha256, license=augmenter.metadata.get("license", ""))  # fmt: skip
    size = np.median(skeleton_size(poses, skel))
    err_console.print(f"wrote {o.output}: {len(poses)} {skel.name} poses, median skeleton size {size:.3f} m")
    if o.plot is not None:
        assert reference is not None
        from ..augment.plots import write_augmentation_plots

        # Bone lengths and angles do not depend on orientation; pairs are drawn in the source's.
        paths = write_augmentation_plots(o.plot, skel, reference.poses, converted, sources, overwrite=o.overwrite)
        err_console.print(f"wrote {', '.join(str(p) for p in paths)}")
