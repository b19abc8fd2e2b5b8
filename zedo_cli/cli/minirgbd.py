"""`zedo benchmark-minirgbd`: lift MINI-RGBD test frames and score them (MPJPE / PA-MPJPE)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Optional

import typer
from rich.table import Table

from ..data.minirgbd import DEFAULT_DROPPED_JOINT, SIDES, check_stride, get_mapping, protocol_joints, split_sequences
from ..lifting.config import PRESETS, get_preset
from ..settings.limits import REPORT_OUTPUT_HELP
from .checks import DEVICE_HELP, check_device, check_steps
from .common import (
    check_report_output,
    err_console,
    error_boundary,
    output_option,
    print_table,
    progress_bar,
    report_figures,
    stdout_console,
)

if TYPE_CHECKING:
    from ..evaluation.minirgbd_benchmark import MiniScore
    from ..lifting.solver import LiftProgress


def _score_table(s: MiniScore, title: str) -> Table:
    table = Table(title=title)
    table.add_column("joint / sequence")
    table.add_column("MPJPE (mm)", justify="right")
    for joint, err in s.per_joint_mm.items():
        table.add_row(joint, f"{err:.1f}")
    for seq, err in s.per_sequence_mm.items():
        table.add_row(f"sequence {seq}", f"{err:.1f}")
    table.add_row("[b]MPJPE[/b]", f"[b]{s.mpjpe_mm:.1f}[/b]")
    table.add_row("[b]PA-MPJPE[/b]", f"[b]{s.pa_mpjpe_mm:.1f}[/b]")
    return table


# Typer options one annotated line each, as in the other commands.
# fmt: off
@error_boundary
def benchmark_minirgbd_command(
    minirgbd_dir: Annotated[Path, typer.Option(help="Your local MINI-RGBD folder, the one holding 01 .. 12 (each with joints_3D/ and joints_2Ddep/).")],
    prior_spec: Annotated[str, typer.Option("--prior", help="An h36m17 prior (weights file), e.g. from: zedo fit-prior --minirgbd-dir DIR.")],
    preset: Annotated[str, typer.Option(help=f"Lifting preset: {', '.join(PRESETS)}. faithful is the reference's 1000 steps.")] = "faithful",
    steps: Annotated[Optional[int], typer.Option(help="Override the preset's prior iterations (for quick runs).")] = None,
    split: Annotated[str, typer.Option(help="Sequence split: paper (train 01-09, test 10-12, as the paper states) or reference (train 01-10, test 11-12, as the authors' code).")] = "paper",
    side: Annotated[str, typer.Option(help=f"Which side of the split to lift: {', '.join(SIDES)}.")] = "test",
    mapping: Annotated[str, typer.Option(help="SMIL -> H36M-17 joints: reference (ankles from the toe joints, shoulders from the collars, as the authors: compares with the paper) or anatomical (ankle and upper-arm joints). Use the mapping the prior was trained with.")] = "reference",
    protocol: Annotated[str, typer.Option(help="Scored joints: 17 (all H36M-17, the authors' code) or 16 (the paper's tables: 17 minus --drop-joint).")] = "17",
    drop_joint: Annotated[str, typer.Option(help="The H36M-17 joint left out of the 16-joint protocol (unknown in the paper). Default: pelvis, the root, whose error is zero after centring.")] = DEFAULT_DROPPED_JOINT,
    stride: Annotated[int, typer.Option(help="Lift every N-th frame of each sequence (1: all 1000 per sequence; 10: a quick run).")] = 1,
    device: Annotated[str, typer.Option(help=DEVICE_HELP)] = "cpu",
    as_json: Annotated[bool, typer.Option("--json", help="Print the scores as JSON on stdout.")] = False,
    output: Annotated[Optional[str], output_option(REPORT_OUTPUT_HELP)] = None,
    overwrite: Annotated[bool, typer.Option(help="Replace the output if it exists.")] = False,
    quiet: Annotated[bool, typer.Option("--quiet", "-q", help="No progress bar.")] = False,
) -> None:
    """Run the MINI-RGBD benchmark: lift the test frames from their 2D and score MPJPE / PA-MPJPE.

    The 2D of joints_2Ddep is lifted with the Kinect depth camera's intrinsics (fx 588.68,
    fy 590.26, cx 322.22, cy 237.47 px) and the reference's MINI depth-scale clamp [0, 4];
    prediction and ground truth (joints_3D, metres) are both centred on the pelvis. PA-MPJPE
    aligns each pose by similarity Procrustes. The data set is not shipped: point
    --minirgbd-dir at your own copy.

    Examples:

      zedo fit-prior --minirgbd-dir ~/data/MINI-RGBD --minirgbd-split paper --split train -o mini.safetensors

      zedo benchmark-minirgbd --minirgbd-dir ~/data/MINI-RGBD --prior mini.safetensors --protocol 16

      zedo benchmark-minirgbd --minirgbd-dir ~/data/MINI-RGBD --prior mini.safetensors --split reference --stride 10 --json
    """
    # Option errors before the prior and the data are read.
    cfg = get_preset(preset)
    check_steps(steps)
    if steps is not None:
        cfg = replace(cfg, steps=steps)
    device = check_device(device)  # auto: CUDA when present
    sequences = split_sequences(split, side)
    protocol_joints(protocol, drop_joint)
    get_mapping(mapping)
    check_stride(stride)
    check_report_output(output, overwrite)
    from ..evaluation.minirgbd_benchmark import DEPTH_INTRINSICS, minirgbd_lift_config, run_minirgbd_benchmark
    from ..prior.weights import load_prior, resolve_prior_path  # torch loads here, not for --help

    prior = load_prior(resolve_prior_path(prior_spec), device=device)
    if not quiet:
        err_console.print(f"lifting MINI-RGBD {split} {side} (sequences {', '.join(sequences)}, stride {stride}) "
                          f"with {prior.label}, preset {cfg.preset}, {cfg.steps} steps, {device}", markup=False)  # fmt: skip
    with progress_bar(quiet) as bar:
        task = bar.add_task("benchmark-minirgbd", total=1, status="")

        def on_step(p: LiftProgress) -> None:
            bar.update(task, completed=p.done, total=p.total)

        run = run_minirgbd_benchmark(minirgbd_dir, prior, cfg, split=split, side=side, mapping=mapping,
                                     protocol=protocol, dropped=drop_joint, stride=stride, device=device,
                                     callback=on_step)  # fmt: skip
    s = run.score
    doc = {"dataset": "MINI-RGBD", "prior": prior.path, "prior_sha256": prior.sha256, "device": device,
           "preset": cfg.preset, "stride": stride, "dropped_joint": drop_joint if protocol == "16" else None,
           "intrinsics": DEPTH_INTRINSICS.matrix().tolist(), "config": minirgbd_lift_config(cfg).to_dict(),
           **vars(s)}  # fmt: skip
    if report_figures(doc, output, as_json, overwrite=overwrite, quiet=quiet):
        return
    dropped = f" (without {drop_joint})" if protocol == "16" else ""
    title = (f"MINI-RGBD {split} split, {side} side, {s.count} frames, {mapping} mapping, "
             f"{protocol} joints{dropped}, pelvis centred (mm)")  # fmt: skip
    print_table(_score_table(s, title), stdout_console())
    err_console.print(f"lifted {s.count} frames in {s.seconds:.1f} s ({s.poses_per_second:.1f} poses/s), mean "
                      f"reprojection error {s.mean_reprojection_error_px:.2f} px; prior {prior.label}; device {device}",
                      markup=False)  # fmt: skip
# fmt: on
