"""`zedo lift`: 2D keypoints file -> 3D poses JSON."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any, Optional

import numpy as np
import typer

from .. import __version__
from ..camera import check_focal, resolve_intrinsics
from ..errors import ConfigError, InputFormatError
from ..formats import INPUT_FORMATS, Keypoints2D, read_keypoints
from ..formats.result_json import build_result_document, write_json
from ..lifting import DEFAULT_PRESET, PRESETS, LiftConfig, LiftProgress, LiftResult, get_preset, lift, observed_mask
from ..weights import Prior, file_sha256, load_prior, resolve_prior_path
from .common import check_output_path, err_console, error_boundary, progress_bar


def default_output_path(input_path: Path) -> Path:
    """`<input stem>.zedo.json` beside the input."""
    return input_path.with_name(input_path.stem + ".zedo.json")


def run_lift(
    kp: Keypoints2D, prior: Prior, cfg: LiftConfig, intrinsics: np.ndarray, *, min_confidence: float,
    device: str, quiet: bool, label: str = "lift",
) -> LiftResult:  # fmt: skip
    """Lift with a progress bar on stderr."""
    with progress_bar(quiet) as bar:
        task = bar.add_task(label, total=1, status=f"{len(kp)} poses")

        def on_step(p: LiftProgress) -> None:
            bar.update(task, completed=p.done, total=p.total)

        return lift(kp.xy, kp.confidence, intrinsics, prior, cfg, min_confidence=min_confidence,
                    device=device, callback=on_step)  # fmt: skip


def lift_params(prior: Prior, cfg: LiftConfig, *, seed: int, device: str, min_confidence: float) -> dict[str, Any]:
    return {
        "preset": cfg.preset,
        "steps": cfg.steps,
        "init_steps": cfg.init_steps,
        "noise_t": [cfg.t_start, cfg.t_end],
        "min_confidence": min_confidence,
        "hypotheses": 1,
        "seed": seed,
        "device": device,
        "prior": {"file": Path(prior.path).name, "sha256": prior.sha256, "skeleton": prior.skeleton.name},
        "config": cfg.to_dict(),
    }


@error_boundary
def lift_command(
    keypoints: Annotated[Path, typer.Argument(help="2D keypoints: COCO annotations, COCO results or zedo 2D JSON (H36M-17, COCO-17 or SyRIP-12 joints).")],
    out: Annotated[Optional[str], typer.Option("--out", "-o", help="Output JSON file, or - for stdout. Default: <input stem>.zedo.json beside the input.")] = None,
    prior_spec: Annotated[Optional[str], typer.Option("--prior", help="A bundled prior's name or a weights file. Default: the bundled syrip12-scratch.")] = None,
    preset: Annotated[str, typer.Option(help=f"Lifting preset: {', '.join(PRESETS)}. fast: 50 prior steps, about 20x faithful's poses/s at the same accuracy; faithful: the paper's 1000 steps; fast-bf16: fast with the network in bfloat16 (quicker only on CPUs with AVX512-BF16/AMX, and GPUs).")] = DEFAULT_PRESET,
    steps: Annotated[Optional[int], typer.Option(help="Override the preset's prior iterations (fast: 50, faithful: 1000).")] = None,
    input_format: Annotated[str, typer.Option("--format", help=f"Input layout: {', '.join(INPUT_FORMATS)}.")] = "auto",
    image_size: Annotated[Optional[tuple[float, float]], typer.Option(help="W H in pixels for inputs that lack image sizes (COCO results).")] = None,
    images: Annotated[Optional[Path], typer.Option(help="COCO annotation file giving image sizes and names for a COCO results input.")] = None,
    focal: Annotated[Optional[float], typer.Option(help="Focal length in pixels (fx = fy). Default: the pseudo 2000 px.")] = None,
    principal_point: Annotated[Optional[tuple[float, float]], typer.Option(help="CX CY in pixels. Default: the image centre.")] = None,
    intrinsics: Annotated[Optional[Path], typer.Option(help="K.json: {\"K\": 3x3} or {\"fx\",\"fy\",\"cx\",\"cy\"}, and/or per image {\"images\": {id or file name: ...}}.")] = None,
    min_confidence: Annotated[float, typer.Option(help="Joints with a lower confidence are treated as missing (the prior fills them).")] = 0.0,
    seed: Annotated[int, typer.Option(help="Seed, recorded in the output (every preset is deterministic).")] = 0,
    device: Annotated[str, typer.Option(help="cpu, cuda or cuda:N.")] = "cpu",
    overwrite: Annotated[bool, typer.Option(help="Replace the output file if it exists.")] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="No progress bar or summary on stderr.")] = False,
) -> None:
    """Lift 2D keypoints to 3D poses in metres, in the camera frame (x right, y down, z forward).

    Each instance is fitted by the ZeDO-i optimisation: its joints stay on their camera rays
    while the diffusion prior denoises the pose. Missing joints (COCO v=0, confidence 0 or
    below --min-confidence) are filled by the prior and flagged. Without calibration the
    camera is the paper's pseudo camera: f = 2000 px at the image centre.

    Examples:

      zedo lift examples/syrip_test5_coco.json                  # writes examples/syrip_test5_coco.zedo.json

      zedo lift detections.json --images annotations.json -o - | jq .summary

      zedo lift kp.json --intrinsics K.json --min-confidence 0.3 -o kp3d.json
    """
    check_focal(focal)  # before the prior is loaded: a usage error should fail fast
    if not 0.0 <= min_confidence <= 1.0:
        raise ConfigError(f"--min-confidence must be in [0, 1], got {min_confidence}")
    out_path = out if out == "-" else Path(out) if out else default_output_path(keypoints)
    if out_path != "-":
        check_output_path(Path(out_path), overwrite)
    cfg = get_preset(preset)
    if steps is not None:
        from dataclasses import replace

        cfg = replace(cfg, steps=steps)
    fmt = None if input_format == "auto" else input_format
    kp = read_keypoints(keypoints, format=fmt, image_size=image_size, images=images)
    prior = load_prior(resolve_prior_path(prior_spec), device=device)
    kp = kp.to_skeleton(prior.skeleton)
    mats, sources = resolve_intrinsics(
        kp.image_sizes, kp.image_ids, kp.file_names, focal=focal, principal_point=principal_point,
        intrinsics_file=str(intrinsics) if intrinsics else None,
    )  # fmt: skip
    usable = observed_mask(kp.xy, kp.confidence, min_confidence).sum(1) >= cfg.min_observed
    if not usable.any():
        raise InputFormatError(
            f"{keypoints}: no instance has {cfg.min_observed} or more observed {prior.skeleton.name} joints "
            f"(all missing, or below --min-confidence {min_confidence})"
        )
    if not quiet:
        err_console.print(f"lifting {len(kp)} instances from {keypoints} ({kp.format}) with {prior.label}, "
                          f"preset {cfg.preset}, {cfg.steps} steps, {device}", markup=False)  # fmt: skip
    res = run_lift(kp, prior, cfg, mats, min_confidence=min_confidence, device=device, quiet=quiet)
    params = lift_params(prior, cfg, seed=seed, device=device, min_confidence=min_confidence)
    input_info = {"path": str(keypoints), "format": kp.format, "skeleton": kp.skeleton.name,
                  "sha256": file_sha256(keypoints), "zedo_version": __version__}  # fmt: skip
    doc = build_result_document(kp, res, mats, sources, params=params, input_info=input_info)
    write_json(doc, out_path)
    lifted = int(res.lifted.sum())
    if not quiet:
        rate = lifted / res.seconds if res.seconds > 0 else float("nan")
        err_console.print(f"lifted {lifted}/{len(kp)} instances in {res.seconds:.1f} s ({rate:.1f} poses/s), "
                          f"mean reprojection error {doc['summary']['mean_reprojection_error_px']} px"
                          + ("" if out_path == "-" else f"; wrote {out_path}"), markup=False)  # fmt: skip
    if lifted < len(kp):
        err_console.print(f"zedo: warning: {len(kp) - lifted} instances had fewer than {cfg.min_observed} "
                          "observed joints and were not lifted (null in the output)", markup=False)  # fmt: skip
