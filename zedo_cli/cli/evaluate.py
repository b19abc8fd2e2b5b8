"""`zedo evaluate` (score a result file) and `zedo benchmark` (the paper's SyRIP table)."""

from __future__ import annotations

from collections.abc import Callable
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Optional

import typer
from rich.table import Table

from ..data.datasets import load_npz_poses, load_syrip_3d
from ..errors import ConfigError
from ..evaluation.result_scoring import align_to_truth, read_result_file
from ..settings.device import check_device
from ..settings.evaluate import BenchmarkOptions, EvaluateOptions
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
from .config import config_option, model_option, print_config_option, resolve_options

if TYPE_CHECKING:
    from ..evaluation.device_benchmark import DeviceReport
    from ..evaluation.syrip_benchmark import Score, Throughput
    from ..lifting.solver import LiftProgress
    from ..prior.weights import Prior


_eval_opt = partial(model_option, EvaluateOptions)  # the option `key` of EvaluateOptions, with its help text
_bench_opt = partial(model_option, BenchmarkOptions)  # the option `key` of BenchmarkOptions, with its help text


@error_boundary
def evaluate_command(
    result: Annotated[Path, typer.Argument(help="A zedo result file (from zedo lift).")],
    syrip_dir: Annotated[Optional[Path], _eval_opt("syrip_dir")] = None,
    split: Annotated[str, _eval_opt("split")] = EvaluateOptions.default("split"),
    gt: Annotated[Optional[Path], _eval_opt("gt")] = None,
    protocol: Annotated[str, _eval_opt("protocol")] = EvaluateOptions.default("protocol"),
    as_json: Annotated[bool, _eval_opt("json", "--json")] = False,
    output: Annotated[Optional[str], output_option(EvaluateOptions.help("output"))] = None,
    overwrite: Annotated[bool, _eval_opt("overwrite")] = False,
    quiet: Annotated[bool, _eval_opt("quiet", "--quiet", "-q")] = False,
    config: Annotated[Optional[Path], config_option("evaluate")] = None,
    print_config: Annotated[bool, print_config_option()] = False,
) -> None:
    """Score lifted poses against 3D ground truth: MPJPE and PA-MPJPE in mm.

    PA-MPJPE aligns each prediction by similarity Procrustes (no reflections). Both sides are
    converted to the protocol's joints and centred on its root; they are joined on the image
    file name (else the image id). Scores are overall and per joint.

    Example: zedo evaluate test100.zedo.json --syrip-dir ../shared/data/syrip --split test
    """
    o: EvaluateOptions = resolve_options(EvaluateOptions).options  # option errors before any data is read
    check_report_output(o.output, o.overwrite)
    truth = load_syrip_3d(o.syrip_dir, o.split) if o.syrip_dir is not None else load_npz_poses(o.gt)  # type: ignore[arg-type]
    from ..evaluation.syrip_benchmark import score_poses  # heavy imports only once the options are read

    pred = read_result_file(result)
    p, t, skel = align_to_truth(pred, truth, o.protocol)
    mpjpe, pa, per_joint = score_poses(p, t, skel.joints)
    missing = len(truth.names) - len(p)  # e.g. persons the lift refused: not in the result as lifted
    doc = {"protocol": o.protocol, "count": len(p), "unmatched_predictions": len(pred.keys) - len(p),
           "ground_truth_without_prediction": missing,
           "mpjpe_mm": round(mpjpe, 2), "pa_mpjpe_mm": round(pa, 2),
           "per_joint_mpjpe_mm": {k: round(v, 2) for k, v in per_joint.items()}}  # fmt: skip
    if report_figures(doc, o.output, o.as_json, overwrite=o.overwrite, quiet=o.quiet):
        return
    unscored = f" ({missing} ground-truth poses have no lifted prediction)" if missing else ""
    title = f"{result} vs {truth.source}, protocol {o.protocol}, {len(p)} poses{unscored}"
    print_table(_evaluate_table(title, per_joint, mpjpe, pa), stdout_console())


def _evaluate_table(title: str, per_joint: dict[str, float], mpjpe: float, pa_mpjpe: float) -> Table:
    table = Table(title=title)
    table.add_column("joint")
    table.add_column("MPJPE (mm)", justify="right")
    for joint, err in per_joint.items():
        table.add_row(joint, f"{err:.1f}")
    table.add_row("[b]mean[/b]", f"[b]{mpjpe:.1f}[/b]")
    table.add_row("PA-MPJPE", f"{pa_mpjpe:.1f}")
    return table


def _benchmark_table(rows: list[tuple[str, Score]]) -> Table:
    table = Table(title="SyRIP Test100, 12 limb joints, hip-midpoint centred (mm)")
    columns = ("prior / preset", "2D input", "MPJPE", "PA-MPJPE", "twin >1.3", "twin >1.6", "sym. err deg",
               "90% cover", "poses", "lift s", "poses/s")  # fmt: skip
    for col in columns:
        table.add_column(col, justify="left" if col in ("prior / preset", "2D input") else "right")
    for label, s in rows:
        coverage = "-" if s.coverage is None else f"{s.coverage:.1%}"
        poses = str(s.count) if not s.not_lifted else f"{s.count} ({s.not_lifted} not lifted, not scored)"
        table.add_row(label, s.input_2d, f"{s.mpjpe_mm:.1f}", f"{s.pa_mpjpe_mm:.1f}", f"{s.twin_over_1_3:.0%}",
                      f"{s.twin_over_1_6:.0%}", f"{s.symmetry_error_deg:.1f}", coverage, poses,
                      f"{s.seconds:.1f}", f"{s.poses_per_second:.1f}")  # fmt: skip
    from ..evaluation.syrip_benchmark import PAPER_FIGURES

    for key, figures in PAPER_FIGURES.items():
        for label, value in figures.items():
            table.add_row(f"[dim]{label}[/dim]", key, f"[dim]{value:.1f}[/dim]", *[""] * (len(columns) - 3))
    return table


def _throughput_table(rates: dict[str, Throughput], device: str) -> Table:
    base_name, base = next(iter(rates.items()))
    table = Table(title=f"Throughput: all 700 real SyRIP images, ground-truth and detected 2D, one batch, {device}")
    for col in ("preset", "poses", "lift s", "poses/s", f"x {base_name}"):
        table.add_column(col, justify="left" if col == "preset" else "right")
    for name, r in rates.items():
        table.add_row(name, str(r.count), f"{r.seconds:.1f}", f"{r.poses_per_second:.1f}",
                      f"{r.poses_per_second / base.poses_per_second:.1f}")  # fmt: skip
    return table


def _accuracy_deltas(rows: list[tuple[str, Score]], base: str) -> dict[str, dict[str, float]]:
    """MPJPE of every preset minus the first preset's, per 2D input (mm)."""
    by_preset: dict[str, dict[str, float]] = {}
    for label, s in rows:
        by_preset.setdefault(label.split(" / ")[-1], {})[s.input_2d] = s.mpjpe_mm
    return {p: {k: v - by_preset[base][k] for k, v in errs.items()} for p, errs in by_preset.items() if p != base}


@error_boundary
def benchmark_command(
    syrip_dir: Annotated[Optional[Path], _bench_opt("syrip_dir")] = None,
    prior_spec: Annotated[Optional[str], _bench_opt("prior", "--prior")] = None,
    preset: Annotated[list[str], _bench_opt("preset")] = BenchmarkOptions.default("preset"),
    inputs: Annotated[str, _bench_opt("inputs")] = BenchmarkOptions.default("inputs"),
    throughput: Annotated[bool, _bench_opt("throughput")] = True,
    hypotheses: Annotated[Optional[int], _bench_opt("hypotheses")] = None,
    device: Annotated[str, _bench_opt("device")] = "cpu",
    scale: Annotated[list[int], _bench_opt("scale", show_default=False)] = BenchmarkOptions.default("scale"),
    scale_preset: Annotated[str, _bench_opt("scale_preset")] = BenchmarkOptions.default("scale_preset"),
    agreement_poses: Annotated[int, _bench_opt("agreement_poses")] = BenchmarkOptions.default("agreement_poses"),
    fit_epochs: Annotated[int, _bench_opt("fit_epochs")] = BenchmarkOptions.default("fit_epochs"),
    fit_recipe: Annotated[Optional[Path], _bench_opt("fit_recipe")] = None,
    chunk_size: Annotated[Optional[int], _bench_opt("chunk_size")] = None,
    as_json: Annotated[bool, _bench_opt("json", "--json")] = False,
    output: Annotated[Optional[str], output_option(BenchmarkOptions.help("output"))] = None,
    overwrite: Annotated[bool, _bench_opt("overwrite")] = False,
    quiet: Annotated[bool, _bench_opt("quiet", "--quiet", "-q")] = False,
    config: Annotated[Optional[Path], config_option("benchmark")] = None,
    print_config: Annotated[bool, print_config_option()] = False,
) -> None:
    """Run the paper's SyRIP Test100 benchmark for one or more presets, side by side.

    For each preset: lifts Test100 from ground-truth 2D and from FiDIP detections (pseudo
    camera f = 2000 px) and scores MPJPE / PA-MPJPE on the 12 limb joints; then (unless
    --no-throughput) lifts all 700 real images from both 2D inputs, 1400 poses in one batch,
    and reports poses per second and the ratio to the first preset.

    Examples:

      zedo benchmark --syrip-dir ../shared/data/syrip       # faithful vs fast

      zedo benchmark --syrip-dir ../shared/data/syrip --preset fast --no-throughput

    With --scale N (repeatable), the device benchmark instead: N synthetic poses lifted
    on --device (poses/s, peak memory), the first --agreement-poses again on the CPU and
    compared, and the bundled recipe's fit-prior time (docs/benchmarks.md, "On a GPU"):

      zedo benchmark --scale 100000 --scale 1000000 --device cuda
    """
    o: BenchmarkOptions = resolve_options(BenchmarkOptions).options  # option errors before any data is read
    if o.scale:
        _scale_benchmark(o)
        return
    check_report_output(o.output, o.overwrite)
    device = check_device(o.device)  # auto: CUDA when present
    from ..prior.weights import load_prior, resolve_prior_path  # torch from here on

    prior = load_prior(resolve_prior_path(o.prior), skeleton="syrip12", device=device)
    rows, rates = _test100(o, prior, device)
    base = o.preset[0]
    deltas = _accuracy_deltas(rows, base)
    doc = {
        "prior": prior.path, "prior_sha256": prior.sha256, "device": device,
        "accuracy": [{"preset": label.split(" / ")[-1], **vars(s)} for label, s in rows],
        "throughput": {n: {**vars(r), f"ratio_to_{base}": r.poses_per_second / rates[base].poses_per_second}
                       for n, r in rates.items()},
        f"mpjpe_minus_{base}_mm": deltas,
    }  # fmt: skip
    if report_figures(doc, o.output, o.as_json, overwrite=o.overwrite, quiet=o.quiet):
        return
    console = stdout_console()
    print_table(_benchmark_table(rows), console)
    if rates:
        print_table(_throughput_table(rates, device), console)
    for name, d in deltas.items():
        ratio = f"{rates[name].poses_per_second / rates[base].poses_per_second:.1f}x the poses/s, " if rates else ""
        console.print(f"{name} vs {base}: {ratio}MPJPE " + ", ".join(f"{v:+.1f} mm ({k})" for k, v in d.items()),
                      markup=False)  # fmt: skip
    err_console.print(f"prior {prior.label}; device {device}", markup=False)


def _test100(o: BenchmarkOptions, prior: Prior, device: str) -> tuple[list[tuple[str, Score]], dict[str, Throughput]]:
    """Each preset's Test100 scores per 2D input and, with --throughput, its poses per second."""
    from ..evaluation.syrip_benchmark import load_throughput_inputs, measure_throughput, run_syrip_benchmark

    assert o.syrip_dir is not None  # BenchmarkOptions.check: needed without --scale
    chosen = o.inputs_2d()
    rows: list[tuple[str, Score]] = []
    rates: dict[str, Throughput] = {}
    speed_inputs = load_throughput_inputs(o.syrip_dir) if o.throughput else {}
    for name, cfg in o.lift_configs().items():
        with progress_bar(o.quiet) as bar:
            tasks = {k: bar.add_task(f"{name} {k}", total=1, status="") for k in (*chosen, "throughput")}

            def on_step(key: str, p: LiftProgress, tasks: dict = tasks) -> None:
                bar.update(tasks[key], completed=p.done, total=p.total)

            scores, _ = run_syrip_benchmark(o.syrip_dir, prior, cfg, inputs=chosen, device=device, callback=on_step)
            if o.throughput:
                rates[name] = measure_throughput(speed_inputs, prior, cfg, device=device,
                                                 callback=lambda p: on_step("throughput", p))  # fmt: skip
        rows += [(f"{Path(prior.path).name} / {name}", s) for s in scores]
    return rows, rates


def _scale_benchmark(o: BenchmarkOptions) -> None:
    """`zedo benchmark --scale N ...`: evaluation/device_benchmark.py on one device."""
    recipe_path = o.recipe_path()
    if o.fit_epochs and not recipe_path.is_file():
        raise ConfigError(f"--fit-recipe {recipe_path}: recipe file not found (or --fit-epochs 0)")
    check_report_output(o.output, o.overwrite)
    device = check_device(o.device)  # the one-line refusal of cuda without a GPU, before anything heavy
    from ..evaluation.device_benchmark import ScaleSettings, run_device_benchmark
    from ..prior.recipes import load_recipe
    from ..prior.weights import load_prior, resolve_prior_path

    settings = ScaleSettings(o.scale, o.agreement_poses, o.fit_epochs)
    recipe = load_recipe(recipe_path) if o.fit_epochs else None
    prior = load_prior(resolve_prior_path(o.prior), device=device)
    with progress_bar(o.quiet) as bar:

        def on_stage(label: str, poses: int) -> Callable[[LiftProgress], None]:
            task = bar.add_task(label, total=1, status="")

            def on_step(p: LiftProgress) -> None:
                bar.update(task, completed=p.done, total=p.total)

            return on_step

        report = run_device_benchmark(prior, o.scale_config(), settings, device=device, preset=o.scale_preset,
                                      syrip_dir=o.syrip_dir, recipe=recipe, on_stage=on_stage)  # fmt: skip
    doc = {
        "prior": prior.path, "prior_sha256": prior.sha256, "device": report.device,
        "device_name": _device_name(device), "preset": o.scale_preset, "pose_source": report.pose_source,
        "lift": [vars(r) for r in report.runs],
        "agreement": None if report.agreement is None else {"reference": "cpu", **vars(report.agreement)},
        "fit_prior": None if report.fit is None else {"recipe": str(recipe_path), **vars(report.fit),
                                                       "extrapolated": True},
    }  # fmt: skip
    if report_figures(doc, o.output, o.as_json, overwrite=o.overwrite, quiet=o.quiet):
        return
    _print_scale_report(report, doc["device_name"], o.scale_preset, recipe_path, device)
    err_console.print(f"prior {prior.label}; device {device}", markup=False)


def _print_scale_report(report: DeviceReport, device_name: str, preset: str, recipe_path: Path, device: str) -> None:
    """The device benchmark's tables and lines on stdout."""
    console = stdout_console()
    table = Table(title=f"Lifting {preset} on {device_name}, synthetic poses ({report.pose_source})")
    for col in ("poses", "lifted", "lift s", "poses/s", "chunk rows", "peak memory MiB", "memory measured"):
        table.add_column(col, justify="left" if col == "memory measured" else "right")
    for r in report.runs:
        peak = "-" if r.peak_memory_mib is None else f"{r.peak_memory_mib:.0f}"
        table.add_row(f"{r.count:,}", f"{r.lifted:,}", f"{r.seconds:.1f}", f"{r.poses_per_second:,.0f}",
                      str(r.chunk_rows), peak, r.memory_kind)  # fmt: skip
    print_table(table, console)
    a = report.agreement
    if a is not None:
        console.print(
            f"CPU vs {device}, first {a.poses:,} poses ({a.both_lifted:,} lifted on both): "
            f"{a.share_within_1mm:.2%} within 1 mm, {a.share_within_10mm:.2%} within 10 mm "
            "(largest joint distance, root-relative; a refusal for the same reason agrees)",
            markup=False,
        )
        console.print("  " + ", ".join(f"{k} {v:,}" for k, v in a.counts.items()), markup=False)
        if a.flipped_segments:
            console.print(
                "  depth flips by segment: " + ", ".join(f"{k} {v}" for k, v in a.flipped_segments.items()),
                markup=False,
            )
        for w in a.largest[:5]:
            console.print("  " + ", ".join(f"{k} {v}" for k, v in w.items()), markup=False)
    f = report.fit
    if f is not None:
        console.print(f"fit-prior ({recipe_path.name}, {f.poses} poses): {f.seconds_per_epoch * 1000:.1f} ms per epoch "
                      f"over {f.epochs_run} epochs; the recipe's {f.recipe_epochs} epochs extrapolated: "
                      f"{f.extrapolated_seconds / 60:.1f} min (an estimate, not a full run)", markup=False)  # fmt: skip


def _device_name(device: str) -> str:
    import torch

    if torch.device(device).type == "cuda":
        return f"{device} ({torch.cuda.get_device_name(device)})"
    return f"cpu ({torch.get_num_threads()} threads)"
