"""`zedo lift`: 2D keypoint files -> 3D pose files, one model load for every input.

The command parses its options into `settings.LiftOptions` (defaults < --config < flags) and
runs the batch: inputs and outputs checked first, then each input lifted by `pipeline.lift`
(the library behind `zedo_cli.lift_file`) and written, with progress, warnings and a summary
on stderr and the batch's exit code.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Optional

import numpy as np
import typer
from rich.table import Table
from rich.text import Text

from ..camera.sanity import check_camera_sanity
from ..errors import ConfigError, ZedoError, plural
from ..files import check_can_create, output_failure
from ..formats import INPUT_FORMATS
from ..formats.writers.outputs import output_format
from ..pipeline.lift import (
    LiftPlan,
    clip_fallback_warning,
    lift_prepared,
    load_plan_prior,
    not_lifted_counts,
    plan_lift,
    prepare_input,
    read_input,
)
from ..settings.lift import LiftOptions
from .common import (
    COMMAND_START,
    EXIT_PARTIAL,
    err_console,
    error_boundary,
    internal_error,
    one_line,
    print_table,
    progress_bar,
)
from .config import Resolved, check_prior, config_option, model_option, print_config_option, resolve_options
from .lift_plan import (
    STDIN,
    check_inputs,
    check_output_options,
    check_plot_paths,
    expand_inputs,
    plan_outputs,
    plot_prefix,
    refused_inputs,
)

if TYPE_CHECKING:
    from ..data.keypoints import Keypoints2D
    from ..lifting.solver import LiftProgress, LiftResult
    from ..prior.weights import Prior

# torch and the network code are imported inside the functions that lift, so that `zedo lift
# --help` and option errors answer at once (tests/cli/test_startup.py).


@dataclass
class FileOutcome:
    """What happened to one input: counts and output, or the error."""

    source: str
    output: str
    instances: int = 0
    lifted: int = 0
    seconds: float = 0.0
    error: ZedoError | None = None
    warnings: tuple[str, ...] = ()  # the input's `zedo: warning:` lines (printed as they came)
    written: tuple[str, ...] = ()  # the files written: a CSV's sidecar, every track's TRC / C3D (none for stdout)

    def files(self) -> str:
        """The files written, for a `wrote ...` line and the summary table (`output` for stdout)."""
        return ", ".join(self.written) if self.written else self.output


def warn(warnings: list[str], message: str) -> None:
    """Print `message` as a `zedo: warning:` line and keep it for the input's outcome (the Ray
    engine's driver prints a worker's warnings, which would otherwise go to the worker's log)."""
    warnings.append(one_line(message))
    err_console.print(f"zedo: warning: {warnings[-1]}", markup=False, soft_wrap=True)


def lift_and_write(
    source: str, output: str, prior: Prior, plan: LiftPlan, kp: Keypoints2D | None = None
) -> FileOutcome:
    """Read (unless `kp` is the input, read already), lift and write one input, with progress
    on stderr; errors are raised (the batch loop isolates them)."""
    o, warnings = plan.options, []
    fmt = output_format(output, o.output_format)
    prep = prepare_input(source, prior, plan, kp, lambda message: warn(warnings, message), fmt)
    kp = prep.keypoints
    if not o.quiet:
        err_console.print(one_line(f"lifting {plural(len(kp), 'instance')} from {source} ({kp.format}) with "
                          f"{prior.label}, preset {plan.cfg.preset}, {plan.cfg.steps} steps, {plan.device}"),
                          markup=False, soft_wrap=True)  # fmt: skip
    with progress_bar(o.quiet) as bar:
        task = bar.add_task("lift", total=1, status=plural(len(kp), "pose"))

        def on_step(p: LiftProgress) -> None:
            bar.update(task, completed=p.done, total=p.total)

        lifted = lift_prepared(prep, prior, plan, on_step, warnings)
    res = lifted.result
    # Plots first: a plot that cannot be written is an error, and no result is left without its plots
    # (nor plots without their result: they are removed when the result cannot be written).
    plots = [] if o.plot is None else write_plots(o.plot / plot_prefix(output), kp, res, plan)
    try:
        written = lifted.write(output, output_format=fmt, units=o.units, frame=o.frame, marker_axes=o.marker_axes,
                               overwrite=o.overwrite)  # fmt: skip
    except BaseException:
        for png in plots:
            png.unlink(missing_ok=True)
        raise
    if not o.quiet and plots:
        err_console.print(one_line(f"plots: {', '.join(str(p) for p in plots)}"), markup=False, soft_wrap=True)
    outcome = FileOutcome(source, output, len(kp), lifted.lifted, res.seconds, written=tuple(str(p) for p in written))
    _report_file(outcome, kp, res, o.quiet, warnings)
    return replace(outcome, warnings=tuple(warnings))


def write_plots(prefix: Path, kp: Keypoints2D, res: LiftResult, plan: LiftPlan) -> list[Path]:
    from ..formats.plots import write_pose_plots  # matplotlib loads only when plots are asked for

    return write_pose_plots(prefix, kp, res, units=plan.options.units, overwrite=plan.options.overwrite)


def _report_file(outcome: FileOutcome, kp: Keypoints2D, res: LiftResult, quiet: bool, warnings: list[str]) -> None:
    """The input's line (what was lifted, and every file written: `kick_P1.trc, kick_P2.trc`
    for the tracks of --person all, `x.csv, x.meta.json` for a CSV) and its warnings."""
    source, lifted = outcome.source, outcome.lifted
    if not quiet:
        rate = lifted / res.seconds if res.seconds > 0 else float("nan")
        reproj = float(np.nanmean(res.reprojection_error_px)) if lifted else float("nan")
        err_console.print(one_line(f"lifted {lifted}/{plural(len(kp), 'instance')} in {res.seconds:.2f} s of lifting "
                                   f"({rate:.1f} poses/s), mean reprojection error {reproj:.2f} px"
                                   + (f"; wrote {outcome.files()}" if outcome.written else "")),
                          markup=False, soft_wrap=True)  # fmt: skip
    if lifted < len(kp):
        warn(warnings, f"{source}: {not_lifted_counts(res)}: not lifted (null in the output, flagged "
                       "not_lifted_<reason>)")  # fmt: skip
    sanity = check_camera_sanity(kp.xy, res.observed, kp.image_sizes, res.root_translation, res.lifted)
    for line in sanity.warnings():  # flagged in the output too (camera.sanity)
        warn(warnings, f"{source}: {line}")
    fallback = clip_fallback_warning(res, source)  # recorded in params.temporal.skeletons too
    if fallback is not None:
        warn(warnings, fallback)


def _summary_table(outcomes: list[FileOutcome]) -> Table:
    """One row per input with its full path (folded, never cut short); a failure's message was
    printed once, as its `zedo: error:` line, and its row says only that it failed."""
    failed = sum(o.error is not None for o in outcomes)
    title = f"zedo lift: {plural(len(outcomes), 'input')}" + (f", {failed} failed" if failed else "")
    table = Table(title=title)
    for col in ("input", "instances", "lifted", "s", "output / error"):
        numeric = col in ("instances", "lifted", "s")
        table.add_column(col, justify="right" if numeric else "left", overflow="fold", no_wrap=numeric)
    for o in outcomes:  # Text: names and messages are shown as they are, never read as rich markup
        if o.error is not None:
            result = Text(f"failed, exit code {o.error.exit_code} (its error is above)", style="red")
        else:
            result = Text(one_line(o.files()))
        table.add_row(Text(one_line(o.source)), str(o.instances), str(o.lifted), f"{o.seconds:.1f}", result)
    return table


def batch_exit_code(outcomes: list[FileOutcome]) -> int:
    """0 when every input was lifted; EXIT_PARTIAL when some failed and others were written, or
    when all failed for different reasons (e.g. 2 and 3: the table says which); else the
    failures' common exit code."""
    failed = [o.error for o in outcomes if o.error is not None]
    if not failed:
        return 0
    codes = {e.exit_code for e in failed}
    if len(failed) < len(outcomes) or len(codes) > 1:
        return EXIT_PARTIAL
    return codes.pop()


# The panels of `zedo lift --help`, shown in this order (cli/help.py).
PANEL_INPUT = "Input"
PANEL_CAMERA = "Camera"
PANEL_LIFTING = "Lifting"
PANEL_EXPERT = "Lifting, expert (other values: no calibrated uncertainty)"
PANEL_OUTPUT = "Output"
PANEL_PERFORMANCE = "Performance"
PANEL_SETTINGS = "Settings files"


def _opt(key: str, panel: str, *names: str, **extra: object) -> typer.models.OptionInfo:
    """The option `key` of LiftOptions, its help text the model's (one source for the CLI, --config
    and the Python API)."""
    return model_option(LiftOptions, key, *names, rich_help_panel=panel, **extra)


def _check_engine(options: LiftOptions, inputs: list[str]) -> None:
    if options.engine == "ray" and (STDIN in inputs or options.output == STDIN):
        raise ConfigError("--engine ray reads and writes files: stdin (-) and -o - need --engine local")


def _lift_on_ray(
    sources: list[str], outputs: list[str], prior: Prior, plan: LiftPlan, *, alone: bool = True
) -> list[FileOutcome]:
    """Every input on Ray; the per-input lines the local engine prints, printed when the batch returns.
    `alone`: the inputs are the command's only ones (one input's error is then the command's)."""
    from .ray_engine import lift_files_on_ray

    o = plan.options
    done = lift_files_on_ray(sources, outputs, str(prior.path), plan, lift_and_write, address=o.ray_address,
                             workers=o.workers)  # fmt: skip
    outcomes = [
        FileOutcome(source, output, d.instances, d.lifted, d.seconds, d.error, d.warnings, d.written)
        for source, output, d in zip(sources, outputs, done, strict=True)
    ]
    if alone and len(outcomes) == 1 and outcomes[0].error is not None:
        raise outcomes[0].error  # one input: its error is the command's error, as locally
    for o_ in outcomes:
        for line in o_.warnings:  # a worker's warnings went to its log: said here, as locally
            err_console.print(f"zedo: warning: {line}", markup=False, soft_wrap=True)
        if o_.error is not None:
            err_console.print(f"zedo: error: {one_line(str(o_.error))}", markup=False, soft_wrap=True)
        elif not o.quiet:
            rate = o_.lifted / o_.seconds if o_.seconds > 0 else float("nan")
            err_console.print(one_line(f"lifted {o_.lifted}/{plural(o_.instances, 'instance')} from {o_.source} in "
                                       f"{o_.seconds:.2f} s of lifting ({rate:.1f} poses/s); wrote {o_.files()}"),
                              markup=False, soft_wrap=True)  # fmt: skip
    return outcomes


_D = LiftOptions()  # the defaults of every option


@error_boundary
def lift_command(
    keypoints: Annotated[
        list[str],
        typer.Argument(
            help="2D keypoint files, folders or glob patterns; - reads stdin. Formats: "
            + ", ".join(f for f in INPUT_FORMATS if f != "auto")
            + " (detected; docs/inputs.md).",
            show_default=False,
            metavar="KEYPOINTS",
            rich_help_panel=PANEL_INPUT,
        ),
    ],
    input_format: Annotated[str, _opt("format", PANEL_INPUT, "--format")] = _D.format,
    skeleton: Annotated[Optional[str], _opt("skeleton", PANEL_INPUT)] = _D.skeleton,
    person: Annotated[str, _opt("person", PANEL_INPUT)] = _D.person,
    min_confidence: Annotated[float, _opt("min_confidence", PANEL_INPUT)] = _D.min_confidence,
    image_size: Annotated[
        Optional[tuple[float, float]], _opt("image_size", PANEL_INPUT, metavar="WIDTH HEIGHT")
    ] = _D.image_size,
    images: Annotated[Optional[Path], _opt("images", PANEL_INPUT)] = _D.images,
    video: Annotated[Optional[Path], _opt("video", PANEL_INPUT)] = _D.video,
    fps: Annotated[Optional[float], _opt("fps", PANEL_INPUT)] = _D.fps,
    focal: Annotated[Optional[float], _opt("focal", PANEL_CAMERA)] = _D.focal,
    principal_point: Annotated[
        Optional[tuple[float, float]], _opt("principal_point", PANEL_CAMERA, metavar="CX CY")
    ] = _D.principal_point,
    intrinsics: Annotated[Optional[Path], _opt("intrinsics", PANEL_CAMERA)] = _D.intrinsics,
    camera: Annotated[Optional[str], _opt("camera", PANEL_CAMERA)] = _D.camera,
    prior_spec: Annotated[Optional[str], _opt("prior", PANEL_LIFTING, "--prior")] = _D.prior,
    preset: Annotated[str, _opt("preset", PANEL_LIFTING)] = _D.preset,
    steps: Annotated[Optional[int], _opt("steps", PANEL_LIFTING)] = _D.steps,
    temporal: Annotated[str, _opt("temporal", PANEL_LIFTING)] = _D.temporal,
    sigma: Annotated[float, _opt("sigma", PANEL_LIFTING)] = _D.sigma,
    hypotheses: Annotated[Optional[int], _opt("hypotheses", PANEL_LIFTING)] = _D.hypotheses,
    seed: Annotated[int, _opt("seed", PANEL_LIFTING)] = _D.seed,
    calibration: Annotated[Optional[Path], _opt("calibration", PANEL_LIFTING)] = _D.calibration,
    ray_weight: Annotated[Optional[float], _opt("ray_weight", PANEL_EXPERT)] = _D.ray_weight,
    ray_confidence_ratio: Annotated[
        Optional[float], _opt("ray_confidence_ratio", PANEL_EXPERT)
    ] = _D.ray_confidence_ratio,
    hip_ray_factor: Annotated[Optional[float], _opt("hip_ray_factor", PANEL_EXPERT)] = _D.hip_ray_factor,
    twin_rate: Annotated[Optional[float], _opt("twin_rate", PANEL_EXPERT)] = _D.twin_rate,
    proportion_rate: Annotated[Optional[float], _opt("proportion_rate", PANEL_EXPERT)] = _D.proportion_rate,
    twin_ratio_cap: Annotated[Optional[float], _opt("twin_ratio_cap", PANEL_EXPERT)] = _D.twin_ratio_cap,
    out: Annotated[Optional[str], _opt("output", PANEL_OUTPUT, "--output", "-o", "--out", metavar="PATH")] = _D.output,
    output_dir: Annotated[Optional[Path], _opt("output_dir", PANEL_OUTPUT)] = _D.output_dir,
    output_format: Annotated[Optional[str], _opt("output_format", PANEL_OUTPUT, "--output-format")] = _D.output_format,
    units: Annotated[str, _opt("units", PANEL_OUTPUT)] = _D.units,
    frame: Annotated[str, _opt("frame", PANEL_OUTPUT)] = _D.frame,
    marker_axes: Annotated[str, _opt("marker_axes", PANEL_OUTPUT)] = _D.marker_axes,
    plot: Annotated[Optional[Path], _opt("plot", PANEL_OUTPUT)] = _D.plot,
    save_hypotheses: Annotated[bool, _opt("save_hypotheses", PANEL_OUTPUT)] = _D.save_hypotheses,
    overwrite: Annotated[bool, _opt("overwrite", PANEL_OUTPUT)] = _D.overwrite,
    quiet: Annotated[bool, _opt("quiet", PANEL_OUTPUT, "--quiet", "-q")] = _D.quiet,
    device: Annotated[str, _opt("device", PANEL_PERFORMANCE)] = _D.device,
    engine: Annotated[str, _opt("engine", PANEL_PERFORMANCE)] = _D.engine,
    ray_address: Annotated[Optional[str], _opt("ray_address", PANEL_PERFORMANCE)] = _D.ray_address,
    workers: Annotated[Optional[int], _opt("workers", PANEL_PERFORMANCE)] = _D.workers,
    config: Annotated[Optional[Path], config_option("lift", PANEL_SETTINGS)] = None,
    print_config: Annotated[bool, print_config_option(PANEL_SETTINGS)] = False,
) -> None:
    """Lift 2D keypoints to 3D poses, in the camera frame (x right, y down, z forward).

    Each instance is fitted by the ZeDO-i optimisation: its joints stay on their camera rays
    while the diffusion prior denoises the pose. Missing joints are filled by the prior and
    flagged. Without a calibration the camera is the paper's pseudo camera (f = 2000 px at the
    image centre).

    Inputs are lifted with one model load; an input that fails is reported and skipped (exit
    code 4). Outputs are written atomically and never replace a file without --overwrite.

    Examples:

      zedo lift examples/prior_samples_coco.json   # -> its .zedo.json beside it
      zedo lift detections.json --images annotations.json -o - | jq .summary
      zedo lift frames/ --fps 30 --temporal smooth -o clip.zedo.csv
      zedo lift 'clips/*.json' --output-dir out/ --plot out/plots
    """
    lift_batch(keypoints, resolve_options(LiftOptions))


def lift_batch(keypoints: list[str], resolved: Resolved) -> None:
    """Lift every input with the settings `resolved`: the options are checked, then the inputs,
    then every output path, then the prior loads (seconds) and each input is lifted and written."""
    o: LiftOptions = resolved.options
    _check_engine(o, keypoints)
    check_output_options(o.output, o.output_dir, o.output_format)
    # torch loads here: help and the errors above answer at once
    from ..lifting.camera import check_focal, check_image_size, check_principal_point

    check_focal(o.focal)  # usage errors fail before the inputs are looked at
    check_principal_point(o.principal_point)
    check_image_size(o.image_size)
    plan = plan_lift(o)  # --video, --intrinsics, --device and --calibration, read once
    # Then the inputs (readable, of a known kind), then the outputs, then the prior (seconds).
    sources = expand_inputs(keypoints)
    if o.video is not None and len(sources) > 1:
        raise ConfigError(f"--video goes with one keypoint input, not {len(sources)}")
    check_inputs([str(p) for p in (o.images,) if p is not None])
    if len(sources) == 1:
        check_inputs(sources)
    refused = refused_inputs(sources) if len(sources) > 1 else {}  # reported and skipped: exit code 4
    for exc in refused.values():
        err_console.print(f"zedo: error: {one_line(str(exc))}", markup=False, soft_wrap=True)
    first = read_input(sources[0], plan) if len(sources) == 1 and o.engine == "local" else None
    outputs = plan_outputs(sources, o.output, o.output_dir, o.output_format, o.overwrite)
    if o.plot is not None:
        check_plot_paths(sources, outputs, o.plot, o.overwrite)
        try:
            o.plot.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise output_failure(o.plot, exc) from None
        check_can_create(o.plot / "plot.png")  # a read-only folder fails here, before any work
    prior = load_plan_prior(plan)
    check_prior(resolved, prior)  # a result as --config: the prior it was lifted with
    if not o.quiet:
        err_console.print(f"start-up {time.perf_counter() - COMMAND_START:.2f} s (imports and loading the prior)",
                          markup=False)  # fmt: skip
    if first is not None:  # one input, read above: its error is the command's error
        lift_and_write(sources[0], outputs[0], prior, plan, first)
        return
    outcomes = [FileOutcome(s, p, error=refused[s]) for s, p in zip(sources, outputs, strict=True) if s in refused]
    todo = [(s, p) for s, p in zip(sources, outputs, strict=True) if s not in refused]
    if o.engine == "ray" and todo:
        outcomes += _lift_on_ray([s for s, _ in todo], [p for _, p in todo], prior, plan, alone=len(sources) == 1)
    elif o.engine != "ray":
        for source, output in todo:
            try:
                outcomes.append(lift_and_write(source, output, prior, plan))
            except BrokenPipeError:  # stdout went away: the run ends (quietly, in the error boundary)
                raise
            except Exception as exc:  # any failure of one input is that input's alone
                error = exc if isinstance(exc, ZedoError) else internal_error(source, exc)
                err_console.print(f"zedo: error: {one_line(str(error))}", markup=False, soft_wrap=True)
                outcomes.append(FileOutcome(source, output, error=error))
    order = {s: i for i, s in enumerate(sources)}
    outcomes.sort(key=lambda outcome: order[outcome.source])  # the refused inputs in their place
    if not o.quiet:
        print_table(_summary_table(outcomes))
    code = batch_exit_code(outcomes)
    if code:
        raise typer.Exit(code)
