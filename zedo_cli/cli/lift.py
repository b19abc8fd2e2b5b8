"""`zedo lift`: 2D keypoint files -> 3D pose files, one model load for every input."""

from __future__ import annotations

import time
from collections import Counter
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Optional

import numpy as np
import typer
from rich.table import Table
from rich.text import Text

from ..camera.sanity import check_camera_sanity
from ..data.keypoints import Keypoints2D
from ..data.skeleton import SKELETONS, get_skeleton
from ..errors import ConfigError, InputFormatError, IntrinsicsError, ZedoError, plural
from ..files import check_can_create, output_failure
from ..footage.video_check import check_against_video, video_options
from ..formats import INPUT_FORMATS, input_sha256, read_keypoints
from ..formats.readers.inputs import fill_image_sizes
from ..formats.writers.common import group_frames
from ..formats.writers.markers import MARKER_AXES, marker_frame_numbers
from ..formats.writers.outputs import FRAMES, MARKER_FORMATS, OUTPUT_FORMATS, UNITS, output_format, write_result
from ..lifting.config import (
    DEFAULT_PRESET,
    DEFAULT_SIGMA_FRAMES,
    MAX_HYPOTHESES,
    PRESETS,
    TEMPORAL_MODES,
    LiftConfig,
    get_preset,
)
from ..lifting.people import PERSON_MODES, select_people
from ..lifting.sequence import check_sequence
from ..version import __version__
from .checks import (
    DEVICE_HELP,
    MAX_FPS,
    MAX_SIGMA_FRAMES,
    check_choice,
    check_device,
    check_range,
    check_seed,
    check_steps,
)
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
    from collections.abc import Sequence

    from ..camera.model import CameraModel
    from ..camera.video import VideoInfo
    from ..lifting.solver import LiftProgress, LiftResult
    from ..lifting.uncertainty import UncertaintyModel
    from ..prior.weights import Prior

# torch and the network code are imported inside the functions that lift, so that `zedo lift
# --help` and option errors answer at once (tests/cli/test_startup.py).


def run_lift(
    kp: Keypoints2D, prior: Prior, cfg: LiftConfig, intrinsics: np.ndarray, *, min_confidence: float,
    device: str, quiet: bool, label: str = "lift", temporal: str = "none", sigma: float = DEFAULT_SIGMA_FRAMES,
    tracks: np.ndarray | None = None, frames: np.ndarray | None = None, seed: int = 0,
    calibrations: tuple[UncertaintyModel, ...] | None = None, lenses: Sequence[CameraModel | None] | None = None,
) -> LiftResult:  # fmt: skip
    """Lift with a progress bar on stderr; frame by frame, or as a sequence (`temporal`: the
    frames checked to be one first); with the calibrated per-joint uncertainty where the prior and
    settings have one in `calibrations` (None: the bundled ones; frame by frame only). `lenses
    (N,)`: each instance's camera with distortion (its 2D is undistorted to lift; reprojection
    errors and the poor-fit test are in the original image)."""
    from ..lifting.solver import lift
    from ..lifting.temporal import lift_sequence
    from ..lifting.uncertainty import attach_uncertainty, bundled_calibrations

    with progress_bar(quiet) as bar:
        task = bar.add_task(label, total=1, status=plural(len(kp), "pose"))

        def on_step(p: LiftProgress) -> None:
            bar.update(task, completed=p.done, total=p.total)

        if temporal != "none":
            res = lift_sequence(kp.xy, kp.confidence, intrinsics, prior, cfg, mode=temporal, sigma=sigma,
                                tracks=tracks, frames=frames, min_confidence=min_confidence, device=device,
                                callback=on_step, seed=seed, cameras=lenses, image_sizes=kp.image_sizes,
                                file_names=kp.file_names)  # fmt: skip
            return replace(res, uncertainty_note=f"not calibrated for --temporal {temporal}")
        res = lift(kp.xy, kp.confidence, intrinsics, prior, cfg, min_confidence=min_confidence,
                   device=device, callback=on_step, seed=seed, cameras=lenses)  # fmt: skip
    models = bundled_calibrations() if calibrations is None else calibrations
    return attach_uncertainty(res, prior.sha256, prior.skeleton.joints, models)


def lift_params(prior: Prior, cfg: LiftConfig, *, seed: int, device: str, min_confidence: float) -> dict[str, Any]:
    return {
        "preset": cfg.preset,
        "steps": cfg.steps,
        "init_steps": cfg.init_steps,
        "noise_t": [cfg.t_start, cfg.t_end],
        "min_confidence": min_confidence,
        "hypotheses": cfg.hypotheses,
        "seed": seed,
        "device": device,
        "prior": {"file": Path(prior.path).name, "sha256": prior.sha256, "skeleton": prior.skeleton.name},
        "config": cfg.to_dict(),
    }


def uncertainty_params(res: LiftResult) -> dict[str, Any]:
    """What the output says about `uncertainty_m`: present or not, and why."""
    return {"uncertainty_m": res.uncertainty_m is not None, "coverage": res.uncertainty_coverage,
            "note": res.uncertainty_note}  # fmt: skip


@dataclass(frozen=True)
class LiftSettings:
    """Everything `zedo lift` applies to each input alike."""

    cfg: LiftConfig
    input_format: str | None
    skeleton: str | None
    image_size: tuple[float, float] | None
    images: Path | None
    focal: float | None
    principal_point: tuple[float, float] | None
    intrinsics: Path | None
    min_confidence: float
    person: str
    fps: float | None
    temporal: str
    sigma: float
    output_format: str | None
    units: str
    frame: str
    plot_dir: Path | None
    seed: int
    device: str
    overwrite: bool
    quiet: bool
    save_hypotheses: bool = False
    calibrations: tuple[UncertaintyModel, ...] | None = None  # --calibration's models, read once; None: bundled
    video: VideoInfo | None = None  # --video: the keypoints are checked against it (footage.video_check)
    marker_axes: str = "level"  # TRC / C3D axes (formats.writers.markers.MARKER_AXES)
    camera: str | None = None  # --camera: the camera of a calibration file of several


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


def read_input(source: str, st: LiftSettings) -> Keypoints2D:
    """Every instance of one input, as read (before --image-size, --person and the prior's joint set)."""
    kp = read_keypoints(source, format=st.input_format, images=st.images, skeleton=st.skeleton)
    if len(kp) == 0:
        raise InputFormatError(f"{source}: no keypoint instances in the input")
    return kp


def read_selected(
    source: str, prior: Prior, st: LiftSettings, kp: Keypoints2D | None = None
) -> tuple[Keypoints2D, np.ndarray, dict[str, Any]]:
    """The input's instances (`kp`: already read) chosen by --person, in the prior's joint set,
    each one's place in its frame (the track label of the temporal mode), and what the choice
    kept and left out (`person_counts`)."""
    kp = read_input(source, st) if kp is None else kp
    chosen = select_people(kp, st.person)
    counts = person_counts(kp, chosen.index, st.person)
    return kp.subset(chosen.index).to_skeleton(prior.skeleton), chosen.person, counts


def person_counts(kp: Keypoints2D, kept: np.ndarray, mode: str) -> dict[str, Any]:
    """What --person did, for the output's params and stderr: instances read and kept, and
    how many were left out in how many frames."""
    from ..lifting.people import group_by_frame

    groups = group_by_frame(kp)
    return {"mode": mode, "frames": len(groups), "instances_read": len(kp), "instances_kept": len(kept),
            "left_out": len(kp) - len(kept), "frames_with_several": sum(len(g) > 1 for g in groups)}  # fmt: skip


def warn(warnings: list[str], message: str) -> None:
    """Print `message` as a `zedo: warning:` line and keep it for the input's outcome (the Ray
    engine's driver prints a worker's warnings, which would otherwise go to the worker's log)."""
    warnings.append(one_line(message))
    err_console.print(f"zedo: warning: {warnings[-1]}", markup=False, soft_wrap=True)


def _report_left_out(source: str, counts: dict[str, Any], warnings: list[str]) -> None:
    """A warning when --person left people out: the output holds fewer people than the input."""
    if counts["left_out"]:
        warn(warnings,
             f"{source}: --person {counts['mode']} kept one person per frame: "
             f"{plural(counts['instances_kept'], 'instance')} of {counts['instances_read']}; "
             f"{plural(counts['left_out'], 'instance')} left out in {plural(counts['frames_with_several'], 'frame')} "
             "with several people (--person all lifts every one)")  # fmt: skip


def _with_image_size(source: str, kp: Keypoints2D, st: LiftSettings, warnings: list[str]) -> Keypoints2D:
    """--image-size for the instances whose size neither the input nor --images states; a warning
    when it fills none, since the option the user gave then changes nothing (--video's size is
    checked against the keypoints instead: footage.video_check)."""
    if st.image_size is None:
        return kp
    kp, filled = fill_image_sizes(kp, st.image_size)
    if not filled and st.video is None:
        stated = f"the input or --images {st.images}" if st.images is not None else "the input"
        w, h = st.image_size
        warn(warnings, f"{source}: --image-size {w:g} {h:g} is not used: {stated} states every image's size "
                       "(--image-size fills only the sizes that the input and --images leave unknown)")  # fmt: skip
    return kp


def lift_file(source: str, output: str, prior: Prior, st: LiftSettings, kp: Keypoints2D | None = None) -> FileOutcome:
    """Read (unless `kp` is the input, read already), lift and write one input; errors are
    raised (the batch loop isolates them)."""
    from ..camera.model import undistort_instances
    from ..lifting.camera import resolve_cameras
    from ..lifting.solver import LIFTED, NOT_LIFTED, geometry_status, observed_mask

    warnings: list[str] = []
    kp = _with_image_size(source, read_input(source, st) if kp is None else kp, st, warnings)
    for note in kp.notes:  # what the reader left out (annotation labels that name no joint, ...)
        warn(warnings, note)
    kp, places, counts = read_selected(source, prior, st, kp)
    _report_left_out(source, counts, warnings)
    video = check_against_video(kp, st.video, source) if st.video is not None else None
    if video is not None and video.warning():
        warn(warnings, f"{source}: {video.warning()}")
    fmt = output_format(output, st.output_format)
    if fmt in MARKER_FORMATS:  # a marker file needs frame numbers (or --fps): refused before any lifting
        marker_frame_numbers(kp, st.fps, fmt)
    try:
        cams = resolve_cameras(
            kp.image_sizes, kp.image_ids, kp.file_names, focal=st.focal, principal_point=st.principal_point,
            intrinsics_file=str(st.intrinsics) if st.intrinsics else None, camera=st.camera,
        )  # fmt: skip
    except IntrinsicsError as exc:  # name the input whose camera could not be settled (same type: exit code)
        raise type(exc)(f"{source}: {exc}") from None
    mats, sources = cams.matrices, cams.sources
    kp.image_sizes = cams.image_sizes  # the calibration file's image size where the input states none
    obs = observed_mask(kp.xy, kp.confidence, st.min_confidence)
    status = geometry_status(undistort_instances(kp.xy, cams.lenses), mats, obs, st.cfg.min_observed)  # cheap
    if (status == "too_few_observed_joints").all():
        raise InputFormatError(
            f"{source}: no instance has {st.cfg.min_observed} or more observed {prior.skeleton.name} joints "
            f"(all missing, or below --min-confidence {st.min_confidence})"
        )
    if not (status == LIFTED).any():
        first = str(Counter(str(s) for s in status).most_common(1)[0][0])
        raise InputFormatError(f"{source}: no instance can be lifted ({_reason_counts(status)}; "
                               f"{first}: {NOT_LIFTED[first]})")  # fmt: skip
    tracks, frames = places if st.person == "all" else None, _frame_numbers(kp)
    if st.temporal != "none":  # photos are not a video: refused before any work (lifting.sequence)
        check_sequence(kp.xy, obs, st.temporal, tracks=tracks, frames=frames, image_sizes=kp.image_sizes,
                       file_names=kp.file_names, source=source)  # fmt: skip
    if not st.quiet:
        err_console.print(one_line(f"lifting {plural(len(kp), 'instance')} from {source} ({kp.format}) with "
                          f"{prior.label}, preset {st.cfg.preset}, {st.cfg.steps} steps, {st.device}"),
                          markup=False, soft_wrap=True)  # fmt: skip
    res = run_lift(kp, prior, st.cfg, mats, min_confidence=st.min_confidence, device=st.device, quiet=st.quiet,
                   temporal=st.temporal, sigma=st.sigma, tracks=tracks, frames=frames, seed=st.seed,
                   calibrations=st.calibrations, lenses=cams.lenses)  # fmt: skip
    if not st.save_hypotheses:  # the writers write the hypotheses a result keeps
        res = replace(res, hypotheses=None)
    if not res.lifted.any():  # nothing but flags to write: fail loudly instead
        first = str(Counter(str(s) for s in res.status).most_common(1)[0][0])
        raise InputFormatError(f"{source}: no instance could be lifted ({_not_lifted_counts(res)}; "
                               f"{first}: {NOT_LIFTED[first]})")  # fmt: skip
    params = lift_params(prior, st.cfg, seed=st.seed, device=st.device, min_confidence=st.min_confidence)
    if st.camera is not None:
        params["camera"] = st.camera
    params.update(
        person=st.person,
        person_selection=counts,
        fps=st.fps,
        temporal={"mode": st.temporal, "sigma_frames": st.sigma},
        camera_sources=sorted(set(sources)),  # pseudo, cli or file: what measure calibrations are matched with
        uncertainty=uncertainty_params(res),
        save_hypotheses=st.save_hypotheses,
    )
    if video is not None:
        params["video"] = video.params()
    input_info = {"path": source, "format": kp.format, "skeleton": kp.skeleton.name,
                  "source_skeleton": kp.source_skeleton, "sha256": input_sha256(source),
                  "zedo_version": __version__,  # frame_numbers: frame_index is the input's (else positions)
                  "frame_numbers": group_frames(kp.image_ids, kp.frame_indices).numbered}  # fmt: skip
    # Plots first: a plot that cannot be written is an error, and no result is left without its plots
    # (nor plots without their result: they are removed when the result cannot be written).
    plots = [] if st.plot_dir is None else write_plots(st.plot_dir / plot_prefix(output), kp, res, st)
    try:
        written = write_result(output, kp, res, mats, sources, params, input_info, fmt=fmt, units=st.units,
                               frame=st.frame, marker_axes=st.marker_axes, overwrite=st.overwrite,
                               lenses=cams.lenses)  # fmt: skip
    except BaseException:
        for png in plots:
            png.unlink(missing_ok=True)
        raise
    if not st.quiet and plots:
        err_console.print(one_line(f"plots: {', '.join(str(p) for p in plots)}"), markup=False, soft_wrap=True)
    lifted = int(res.lifted.sum())
    outcome = FileOutcome(source, output, len(kp), lifted, res.seconds, written=tuple(str(p) for p in written))
    _report_file(outcome, kp, res, st.quiet, warnings)
    return replace(outcome, warnings=tuple(warnings))


def _frame_numbers(kp: Keypoints2D) -> np.ndarray | None:
    """The input's frame number of each instance, so the temporal filter sees gaps; None if unknown."""
    if kp.frame_indices is None or any(f is None for f in kp.frame_indices):
        return None
    return np.asarray(kp.frame_indices, dtype=np.int64)


def write_plots(prefix: Path, kp: Keypoints2D, res: LiftResult, st: LiftSettings) -> list[Path]:
    from ..formats.plots import write_pose_plots  # matplotlib loads only when plots are asked for

    return write_pose_plots(prefix, kp, res, units=st.units, overwrite=st.overwrite)


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
        warn(warnings, f"{source}: {_not_lifted_counts(res)}: not lifted (null in the output, flagged "
                       "not_lifted_<reason>)")  # fmt: skip
    sanity = check_camera_sanity(kp.xy, res.observed, kp.image_sizes, res.root_translation, res.lifted)
    for line in sanity.warnings():  # flagged in the output too (camera.sanity)
        warn(warnings, f"{source}: {line}")


def _not_lifted_counts(res: LiftResult) -> str:
    """Why instances were not lifted, most common first ("2 too_few_observed_joints, 1 poor_fit")."""
    return _reason_counts(res.status[~res.lifted])


def _reason_counts(status: np.ndarray) -> str:
    return ", ".join(f"{c} {reason}" for reason, c in Counter(str(s) for s in status).most_common())


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


def _check_options(st: LiftSettings) -> None:
    if not 0.0 <= st.min_confidence <= 1.0:
        raise ConfigError(f"--min-confidence must be in [0, 1], got {st.min_confidence}")
    check_choice("--units", st.units, UNITS)
    check_choice("--frame", st.frame, FRAMES)
    check_choice("--marker-axes", st.marker_axes, tuple(MARKER_AXES))
    check_choice("--person", st.person, PERSON_MODES)
    check_choice("--temporal", st.temporal, TEMPORAL_MODES)
    check_range("--sigma", st.sigma, 0, MAX_SIGMA_FRAMES, low_open=True, unit=" frames")
    check_range("--fps", st.fps, 0, MAX_FPS, low_open=True)
    if st.camera is not None and st.intrinsics is None:
        raise ConfigError("--camera picks a camera of an --intrinsics file: give the file too")


ENGINES = ("local", "ray")

# The panels of `zedo lift --help`, shown in this order (cli/help.py).
PANEL_INPUT = "Input"
PANEL_CAMERA = "Camera"
PANEL_LIFTING = "Lifting"
PANEL_EXPERT = "Lifting, expert (other values: no calibrated uncertainty)"
PANEL_OUTPUT = "Output"
PANEL_PERFORMANCE = "Performance"


def _check_engine(engine: str, inputs: list[str], out: Optional[str], workers: Optional[int]) -> None:
    check_choice("--engine", engine, ENGINES)
    if workers is not None and workers < 1:
        raise ConfigError(f"--workers must be >= 1, got {workers}")
    if engine == "ray" and (STDIN in inputs or out == STDIN):
        raise ConfigError("--engine ray reads and writes files: stdin (-) and -o - need --engine local")


def _lift_on_ray(
    sources: list[str],
    outputs: list[str],
    prior: Prior,
    st: LiftSettings,
    address: Optional[str],
    workers: Optional[int],
    *,
    alone: bool = True,
) -> list[FileOutcome]:
    """Every input on Ray; the per-input lines the local engine prints, printed when the batch returns.
    `alone`: the inputs are the command's only ones (one input's error is then the command's)."""
    from .ray_engine import lift_files_on_ray

    done = lift_files_on_ray(sources, outputs, str(prior.path), st, lift_file, address=address, workers=workers)
    outcomes = [
        FileOutcome(source, output, d.instances, d.lifted, d.seconds, d.error, d.warnings, d.written)
        for source, output, d in zip(sources, outputs, done, strict=True)
    ]
    if alone and len(outcomes) == 1 and outcomes[0].error is not None:
        raise outcomes[0].error  # one input: its error is the command's error, as locally
    for o in outcomes:
        for line in o.warnings:  # a worker's warnings went to its log: said here, as locally
            err_console.print(f"zedo: warning: {line}", markup=False, soft_wrap=True)
        if o.error is not None:
            err_console.print(f"zedo: error: {one_line(str(o.error))}", markup=False, soft_wrap=True)
        elif not st.quiet:
            rate = o.lifted / o.seconds if o.seconds > 0 else float("nan")
            err_console.print(one_line(f"lifted {o.lifted}/{plural(o.instances, 'instance')} from {o.source} in "
                                       f"{o.seconds:.2f} s of lifting ({rate:.1f} poses/s); wrote {o.files()}"),
                              markup=False, soft_wrap=True)  # fmt: skip
    return outcomes


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
    input_format: Annotated[
        str, typer.Option("--format", help="Input layout, when detection is not wanted.", rich_help_panel=PANEL_INPUT)
    ] = "auto",
    skeleton: Annotated[
        Optional[str],
        typer.Option(
            help=f"Joint set of an input without joint names: {', '.join(SKELETONS)}.", rich_help_panel=PANEL_INPUT
        ),
    ] = None,
    person: Annotated[
        str,
        typer.Option(
            help=f"Whom to lift in a frame of several people: {', '.join(PERSON_MODES)} (auto: the most complete, "
            "then the same person frame after frame).",
            rich_help_panel=PANEL_INPUT,
        ),
    ] = "auto",
    min_confidence: Annotated[
        float,
        typer.Option(
            help="Joints below this confidence are missing (the prior fills them).", rich_help_panel=PANEL_INPUT
        ),
    ] = 0.0,
    image_size: Annotated[
        Optional[tuple[float, float]],
        typer.Option(
            help="Image size in pixels, for inputs without one (COCO results, OpenPose).",
            metavar="WIDTH HEIGHT",
            rich_help_panel=PANEL_INPUT,
        ),
    ] = None,
    images: Annotated[
        Optional[Path],
        typer.Option(help="COCO annotations giving a COCO results input its image sizes.", rich_help_panel=PANEL_INPUT),
    ] = None,
    video: Annotated[
        Optional[Path],
        typer.Option(
            help="The video the keypoints came from: its image size and fps; keypoint frames beyond it are an error "
            "(docs/footage.md).",
            rich_help_panel=PANEL_INPUT,
        ),
    ] = None,
    fps: Annotated[
        Optional[float],
        typer.Option(
            help="Frame rate of a video input, recorded in the output. Default: --video's.", rich_help_panel=PANEL_INPUT
        ),  # fmt: skip
    ] = None,
    focal: Annotated[
        Optional[float],
        typer.Option(help="Focal length in pixels. Default: the paper's pseudo 2000 px.", rich_help_panel=PANEL_CAMERA),
    ] = None,
    principal_point: Annotated[
        Optional[tuple[float, float]],
        typer.Option(
            help="Principal point in pixels. Default: the image centre.", metavar="CX CY", rich_help_panel=PANEL_CAMERA
        ),  # fmt: skip
    ] = None,
    intrinsics: Annotated[
        Optional[Path],
        typer.Option(
            help="Calibration file, lens distortion included: zedo JSON, OpenCV FileStorage (YAML, XML, JSON), "
            "Pose2Sim / anipose TOML (docs/cameras.md).",
            rich_help_panel=PANEL_CAMERA,
        ),
    ] = None,
    camera: Annotated[
        Optional[str],
        typer.Option(
            help="The camera, by name, of an --intrinsics file holding several.", rich_help_panel=PANEL_CAMERA
        ),
    ] = None,
    prior_spec: Annotated[
        Optional[str],
        typer.Option(
            "--prior",
            help="A bundled prior's name or a weights file. Default: syrip12-scratch.",
            rich_help_panel=PANEL_LIFTING,
        ),  # fmt: skip
    ] = None,
    preset: Annotated[
        str,
        typer.Option(
            help=f"{', '.join(PRESETS)}. fast: 20 prior steps, plausible bone lengths; faithful: the paper's 1000 "
            "steps, about 40x slower; fast-bf16: fast in bfloat16 (docs/lifting.md).",
            rich_help_panel=PANEL_LIFTING,
        ),
    ] = DEFAULT_PRESET,
    steps: Annotated[
        Optional[int], typer.Option(help="Prior iterations instead of the preset's.", rich_help_panel=PANEL_LIFTING)
    ] = None,
    temporal: Annotated[
        str,
        typer.Option(
            help=f"For sequences: {', '.join(TEMPORAL_MODES)}. smooth: a Gaussian filter over time after lifting; "
            "two-pass: smooth, then 3 prior steps back onto the rays.",
            rich_help_panel=PANEL_LIFTING,
        ),
    ] = "none",
    sigma: Annotated[
        float, typer.Option(help="Width of --temporal's Gaussian, in frames.", rich_help_panel=PANEL_LIFTING)
    ] = DEFAULT_SIGMA_FRAMES,
    hypotheses: Annotated[
        Optional[int],
        typer.Option(
            help=f"Solutions per instance (1 to {MAX_HYPOTHESES}); their spread sets uncertainty_m. Default: the "
            "preset's (1).",
            rich_help_panel=PANEL_LIFTING,
        ),
    ] = None,
    seed: Annotated[
        int, typer.Option(help="Seed of the hypotheses: the same seed, the same poses.", rich_help_panel=PANEL_LIFTING)
    ] = 0,
    calibration: Annotated[
        Optional[Path],
        typer.Option(
            help="Uncertainty calibration for a prior of your own (docs/uncertainty.md). Default: the bundled one.",
            rich_help_panel=PANEL_LIFTING,
        ),
    ] = None,
    ray_weight: Annotated[
        Optional[float],
        typer.Option(
            help=f"Share of the way observed joints move onto their rays per step, (0, 1] "
            f"(fast: {PRESETS['fast'].ray_weight:g}).",
            rich_help_panel=PANEL_EXPERT,
        ),
    ] = None,
    ray_confidence_ratio: Annotated[
        Optional[float],
        typer.Option(
            help="Joints below this share of their pose's median confidence move in proportion, [0, 1] "
            f"(fast: {PRESETS['fast'].ray_confidence_ratio:g}).",
            rich_help_panel=PANEL_EXPERT,
        ),
    ] = None,
    hip_ray_factor: Annotated[
        Optional[float],
        typer.Option(
            help=f"The hips' share of that pull, [0, 1] (fast: {PRESETS['fast'].hip_ray_factor:g}).",
            rich_help_panel=PANEL_EXPERT,
        ),
    ] = None,
    twin_rate: Annotated[
        Optional[float],
        typer.Option(
            help=f"Share of each left/right limb-length mismatch removed per step, [0, 1] "
            f"(fast: {PRESETS['fast'].twin_rate:g}).",
            rich_help_panel=PANEL_EXPERT,
        ),
    ] = None,
    proportion_rate: Annotated[
        Optional[float],
        typer.Option(
            help=f"Share of each bone's mismatch with the template's proportions removed per step, [0, 1] "
            f"(fast: {PRESETS['fast'].proportion_rate:g}).",
            rich_help_panel=PANEL_EXPERT,
        ),
    ] = None,
    twin_ratio_cap: Annotated[
        Optional[float],
        typer.Option(
            help=f"Limbs longer than this times their twin are brought to it; 0: off "
            f"(fast: {PRESETS['fast'].twin_ratio_cap:g}).",
            rich_help_panel=PANEL_EXPERT,
        ),
    ] = None,
    out: Annotated[
        Optional[str],
        typer.Option(
            "--output",
            "-o",
            "--out",
            metavar="PATH",
            help="Output file (one input), format from its extension; - for stdout. Default: "
            "<input stem>.zedo.json beside the input.",
            rich_help_panel=PANEL_OUTPUT,
        ),
    ] = None,
    output_dir: Annotated[
        Optional[Path],
        typer.Option(help="Write every output into this folder (made if missing).", rich_help_panel=PANEL_OUTPUT),
    ] = None,
    output_format: Annotated[
        Optional[str],
        typer.Option(
            "--output-format",
            help=f"{', '.join(OUTPUT_FORMATS)} (trc, c3d: marker files, docs/exports.md). Default: from -o, else json.",
            rich_help_panel=PANEL_OUTPUT,
        ),
    ] = None,
    units: Annotated[
        str, typer.Option(help=f"{', '.join(UNITS)} (TRC is always m, C3D mm).", rich_help_panel=PANEL_OUTPUT)
    ] = "m",
    frame: Annotated[
        str,
        typer.Option(
            help=f"{', '.join(FRAMES)}: camera axes (x right, y down, z forward), with the root at the origin for "
            "root.",
            rich_help_panel=PANEL_OUTPUT,
        ),
    ] = "camera",
    marker_axes: Annotated[
        str,
        typer.Option(
            help=f"Axes of TRC / C3D files: {', '.join(MARKER_AXES)} (overhead: a camera above a lying infant).",
            rich_help_panel=PANEL_OUTPUT,
        ),
    ] = "level",
    plot: Annotated[
        Optional[Path],
        typer.Option(help="Also write PNGs of three 3D poses into this folder.", rich_help_panel=PANEL_OUTPUT),
    ] = None,
    save_hypotheses: Annotated[
        bool, typer.Option(help="Also write every hypothesis (JSON, NPZ).", rich_help_panel=PANEL_OUTPUT)
    ] = False,
    overwrite: Annotated[bool, typer.Option(help="Replace outputs that exist.", rich_help_panel=PANEL_OUTPUT)] = False,
    quiet: Annotated[
        bool, typer.Option("--quiet", "-q", help="No progress or summary on stderr.", rich_help_panel=PANEL_OUTPUT)
    ] = False,
    device: Annotated[str, typer.Option(help=DEVICE_HELP, rich_help_panel=PANEL_PERFORMANCE)] = "cpu",
    engine: Annotated[
        str,
        typer.Option(
            help="local, or ray: the batch over a Ray cluster, the same outputs (pip install 'zedo[ray]').",
            rich_help_panel=PANEL_PERFORMANCE,
        ),
    ] = "local",
    ray_address: Annotated[
        Optional[str],
        typer.Option(
            help="The Ray cluster to join (else RAY_ADDRESS, else a local one).", rich_help_panel=PANEL_PERFORMANCE
        ),  # fmt: skip
    ] = None,
    workers: Annotated[
        Optional[int],
        typer.Option(
            help="Ray workers (prior loads). Default: the CPUs / the local engine's threads.",
            rich_help_panel=PANEL_PERFORMANCE,
        ),  # fmt: skip
    ] = None,
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
    check_steps(steps)  # usage errors fail before torch and the prior load
    check_seed(seed)
    check_range("--hypotheses", hypotheses, 1, MAX_HYPOTHESES)
    cfg = get_preset(preset)
    check_range("--ray-weight", ray_weight, 0, 1, low_open=True)
    check_range("--ray-confidence-ratio", ray_confidence_ratio, 0, 1)
    check_range("--hip-ray-factor", hip_ray_factor, 0, 1)
    check_range("--twin-rate", twin_rate, 0, 1)
    check_range("--proportion-rate", proportion_rate, 0, 1)
    if twin_ratio_cap != 0:
        check_range("--twin-ratio-cap", twin_ratio_cap, 1, 100)
    overrides = {"steps": steps, "hypotheses": hypotheses, "ray_weight": ray_weight,
                 "ray_confidence_ratio": ray_confidence_ratio, "hip_ray_factor": hip_ray_factor,
                 "twin_rate": twin_rate, "proportion_rate": proportion_rate, "twin_ratio_cap": twin_ratio_cap}  # fmt: skip
    cfg = replace(cfg, **{name: value for name, value in overrides.items() if value is not None})
    if skeleton is not None:
        get_skeleton(skeleton)  # an unknown name is a usage error, before any work
    video_info = None
    if video is not None:  # the video's size and fps, unless given
        video_info, image_size, fps = video_options(video, image_size, fps)
    st = LiftSettings(cfg, None if input_format == "auto" else input_format, skeleton, image_size, images, focal,
                      principal_point, intrinsics, min_confidence, person, fps, temporal, sigma, output_format, units, frame,
                      plot, seed, device, overwrite, quiet, save_hypotheses, marker_axes=marker_axes,
                      camera=camera)  # fmt: skip
    st = replace(st, video=video_info)
    _check_options(st)
    _check_engine(engine, keypoints, out, workers)
    check_output_options(out, output_dir, output_format)
    # torch loads here: help and the errors above answer at once
    from ..lifting.camera import check_focal, check_image_size, check_principal_point
    from ..prior.weights import load_prior, resolve_prior_path

    check_focal(focal)  # usage errors fail before the inputs are looked at
    check_principal_point(principal_point)
    check_image_size(image_size)
    if intrinsics is not None:  # a broken calibration file, or --camera not in it, fails before any work
        from ..camera.files import read_camera_file

        read_camera_file(str(intrinsics), camera)
    device = check_device(device)  # auto: CUDA when present
    st = replace(st, device=device)
    # Then the inputs (readable, of a known kind), then the outputs, then the prior (seconds).
    sources = expand_inputs(keypoints)
    if video is not None and len(sources) > 1:
        raise ConfigError(f"--video goes with one keypoint input, not {len(sources)}")
    check_inputs([str(p) for p in (images,) if p is not None])
    if len(sources) == 1:
        check_inputs(sources)
    refused = refused_inputs(sources) if len(sources) > 1 else {}  # reported and skipped: exit code 4
    for exc in refused.values():
        err_console.print(f"zedo: error: {one_line(str(exc))}", markup=False, soft_wrap=True)
    first = read_input(sources[0], st) if len(sources) == 1 and engine == "local" else None
    outputs = plan_outputs(sources, out, output_dir, output_format, overwrite)
    if plot is not None:
        check_plot_paths(sources, outputs, plot, overwrite)
        try:
            plot.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise output_failure(plot, exc) from None
        check_can_create(plot / "plot.png")  # a read-only folder fails here, before any work
    if calibration is not None:  # read once for every input; a broken file fails before any work
        from ..lifting.uncertainty import read_calibrations

        st = replace(st, calibrations=tuple(read_calibrations(calibration)))
    prior = load_prior(resolve_prior_path(prior_spec), device=device)
    if not quiet:
        err_console.print(f"start-up {time.perf_counter() - COMMAND_START:.2f} s (imports and loading the prior)",
                          markup=False)  # fmt: skip
    if first is not None:  # one input, read above: its error is the command's error
        lift_file(sources[0], outputs[0], prior, st, first)
        return
    outcomes = [FileOutcome(s, o, error=refused[s]) for s, o in zip(sources, outputs, strict=True) if s in refused]
    todo = [(s, o) for s, o in zip(sources, outputs, strict=True) if s not in refused]
    if engine == "ray" and todo:
        outcomes += _lift_on_ray([s for s, _ in todo], [o for _, o in todo], prior, st, ray_address, workers,
                                 alone=len(sources) == 1)  # fmt: skip
    elif engine != "ray":
        for source, output in todo:
            try:
                outcomes.append(lift_file(source, output, prior, st))
            except BrokenPipeError:  # stdout went away: the run ends (quietly, in the error boundary)
                raise
            except Exception as exc:  # any failure of one input is that input's alone
                error = exc if isinstance(exc, ZedoError) else internal_error(source, exc)
                err_console.print(f"zedo: error: {one_line(str(error))}", markup=False, soft_wrap=True)
                outcomes.append(FileOutcome(source, output, error=error))
    order = {s: i for i, s in enumerate(sources)}
    outcomes.sort(key=lambda o: order[o.source])  # the refused inputs in their place
    if not quiet:
        print_table(_summary_table(outcomes))
    code = batch_exit_code(outcomes)
    if code:
        raise typer.Exit(code)
