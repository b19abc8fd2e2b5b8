"""One input lifted: read, choose the people, settle the cameras, lift, attach the calibrated
uncertainty and say what was done (params), then write. `zedo lift` runs this for each input of
a batch (cli/lift.py: progress, summary, exit codes; cli/ray_engine.py: the same on Ray), and
`zedo_cli.lift_file` for one file from Python.

    from zedo_cli import lift_file
    lifted = lift_file("examples/prior_samples_coco.json", steps=30, seed=3)
    lifted.result.poses_camera  # (N, J, 3) metres, camera frame

The settings are `settings.LiftOptions`, by the option names of `zedo lift`; torch is imported
inside the functions that need it.
"""

from __future__ import annotations

import functools
from collections import Counter
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..data.keypoints import Keypoints2D
from ..errors import InputFormatError, IntrinsicsError, plural
from ..footage.video_check import check_against_video
from ..formats import input_sha256, read_keypoints
from ..formats.readers.inputs import fill_image_sizes
from ..formats.writers.common import group_frames
from ..formats.writers.markers import marker_frame_numbers
from ..formats.writers.outputs import MARKER_FORMATS, write_result
from ..formats.writers.outputs import output_format as format_of
from ..lifting.config import LiftConfig
from ..lifting.people import select_people
from ..lifting.sequence import check_sequence
from ..settings.lift import LiftOptions
from ..version import __version__

if TYPE_CHECKING:
    from ..camera.model import CameraModel
    from ..camera.video import VideoInfo
    from ..footage.video_check import VideoCheck
    from ..formats import ResultPoses
    from ..lifting.camera import ResolvedCameras
    from ..lifting.solver import LiftProgress, LiftResult
    from ..lifting.uncertainty import UncertaintyModel
    from ..prior.weights import Prior

Warn = Callable[[str], None]  # a warning about one input: printed by the CLI, kept by the Python API
Progress = Callable[["LiftProgress"], None]


@dataclass(frozen=True)
class LiftPlan:
    """Everything a batch applies to each input alike: the options as given, and what was made
    of them once for every input (the LiftConfig, the device, calibrations, the video)."""

    options: LiftOptions
    cfg: LiftConfig
    device: str  # resolved: `auto` made cpu or cuda
    image_size: tuple[float, float] | None  # --image-size, else --video's
    fps: float | None  # --fps, else --video's
    calibrations: tuple[UncertaintyModel, ...] | None = None  # --calibration's models, read once; None: bundled
    video: VideoInfo | None = None  # --video: the keypoints are checked against it (footage.video_check)

    @property
    def quiet(self) -> bool:
        return self.options.quiet


def plan_lift(options: LiftOptions) -> LiftPlan:
    """The plan of `options`, whose files (--video, --intrinsics, --calibration) are read and
    checked here, before any input is (torch loads here: --device)."""
    from ..settings.device import check_device

    cfg = options.lift_config()
    image_size, fps, video = options.image_size, options.fps, None
    if options.video is not None:  # the video's size and fps, unless given
        from ..footage.video_check import video_options

        video, image_size, fps = video_options(options.video, image_size, fps)
    if options.intrinsics is not None:  # a broken calibration file, or --camera not in it, fails before any work
        from ..camera.files import read_camera_file

        read_camera_file(str(options.intrinsics), options.camera)
    device = check_device(options.device)  # auto: CUDA when present
    calibrations = None
    if options.calibration is not None:  # read once for every input; a broken file fails before any work
        from ..lifting.uncertainty import read_calibrations

        calibrations = tuple(read_calibrations(options.calibration))
    return LiftPlan(options, cfg, device, image_size, fps, calibrations, video)


def load_plan_prior(plan: LiftPlan) -> Prior:
    from ..prior.weights import load_prior, resolve_prior_path

    return load_prior(resolve_prior_path(plan.options.prior), device=plan.device)


def read_input(source: str, plan: LiftPlan) -> Keypoints2D:
    """Every instance of one input, as read (before --image-size, --person and the prior's joint set)."""
    o = plan.options
    kp = read_keypoints(source, format=None if o.format == "auto" else o.format, images=o.images, skeleton=o.skeleton)
    if len(kp) == 0:
        raise InputFormatError(f"{source}: no keypoint instances in the input")
    return kp


def person_counts(kp: Keypoints2D, kept: np.ndarray, mode: str) -> dict[str, Any]:
    """What --person did, for the output's params and stderr: instances read and kept, and
    how many were left out in how many frames."""
    from ..lifting.people import group_by_frame

    groups = group_by_frame(kp)
    return {"mode": mode, "frames": len(groups), "instances_read": len(kp), "instances_kept": len(kept),
            "left_out": len(kp) - len(kept), "frames_with_several": sum(len(g) > 1 for g in groups)}  # fmt: skip


def read_selected(
    source: str, prior: Prior, plan: LiftPlan, kp: Keypoints2D | None = None
) -> tuple[Keypoints2D, np.ndarray, dict[str, Any]]:
    """The input's instances (`kp`: already read) chosen by --person, in the prior's joint set,
    each one's place in its frame (the track label of the temporal mode), and what the choice
    kept and left out (`person_counts`)."""
    kp = read_input(source, plan) if kp is None else kp
    chosen = select_people(kp, plan.options.person)
    counts = person_counts(kp, chosen.index, plan.options.person)
    return kp.subset(chosen.index).to_skeleton(prior.skeleton), chosen.person, counts


def _with_image_size(source: str, kp: Keypoints2D, plan: LiftPlan, warn: Warn) -> Keypoints2D:
    """--image-size for the instances whose size neither the input nor --images states; a warning
    when it fills none, since the option the user gave then changes nothing (--video's size is
    checked against the keypoints instead: footage.video_check)."""
    if plan.image_size is None:
        return kp
    kp, filled = fill_image_sizes(kp, plan.image_size)
    if not filled and plan.video is None:
        images = plan.options.images
        stated = f"the input or --images {images}" if images is not None else "the input"
        w, h = plan.image_size
        warn(f"{source}: --image-size {w:g} {h:g} is not used: {stated} states every image's size "
             "(--image-size fills only the sizes that the input and --images leave unknown)")  # fmt: skip
    return kp


def _report_left_out(source: str, counts: dict[str, Any], warn: Warn) -> None:
    """A warning when --person left people out: the output holds fewer people than the input."""
    if counts["left_out"]:
        warn(f"{source}: --person {counts['mode']} kept one person per frame: "
             f"{plural(counts['instances_kept'], 'instance')} of {counts['instances_read']}; "
             f"{plural(counts['left_out'], 'instance')} left out in {plural(counts['frames_with_several'], 'frame')} "
             "with several people (--person all lifts every one)")  # fmt: skip


def _frame_numbers(kp: Keypoints2D) -> np.ndarray | None:
    """The input's frame number of each instance, so the temporal filter sees gaps; None if unknown."""
    if kp.frame_indices is None or any(f is None for f in kp.frame_indices):
        return None
    return np.asarray(kp.frame_indices, dtype=np.int64)


def _reason_counts(status: np.ndarray) -> str:
    return ", ".join(f"{c} {reason}" for reason, c in Counter(str(s) for s in status).most_common())


def not_lifted_counts(res: LiftResult) -> str:
    """Why instances were not lifted, most common first ("2 too_few_observed_joints, 1 poor_fit")."""
    return _reason_counts(res.status[~res.lifted])


@dataclass
class PreparedInput:
    """One input read and checked, its cameras settled: what the lift of it needs."""

    source: str
    keypoints: Keypoints2D  # in the prior's joint set, the people --person chose
    cameras: ResolvedCameras
    tracks: np.ndarray | None  # (N,) each instance's person in its frame (--person all), else None
    frames: np.ndarray | None  # (N,) the input's frame numbers, None when unknown
    counts: dict[str, Any]  # what --person kept (person_counts)
    video: VideoCheck | None


def prepare_input(source: str, prior: Prior, plan: LiftPlan, kp: Keypoints2D | None, warn: Warn,
                  output_fmt: str | None = None) -> PreparedInput:  # fmt: skip
    """Read `source` (unless `kp` is it, read already), choose the people, settle the cameras and
    refuse, before any lifting, an input that cannot be lifted (or written as `output_fmt`)."""
    from ..camera.model import undistort_instances
    from ..lifting.camera import resolve_cameras
    from ..lifting.solver import LIFTED, NOT_LIFTED, geometry_status, observed_mask

    o = plan.options
    kp = _with_image_size(source, read_input(source, plan) if kp is None else kp, plan, warn)
    for note in kp.notes:  # what the reader left out (annotation labels that name no joint, ...)
        warn(note)
    kp, places, counts = read_selected(source, prior, plan, kp)
    _report_left_out(source, counts, warn)
    video = check_against_video(kp, plan.video, source) if plan.video is not None else None
    if video is not None and video.warning():
        warn(f"{source}: {video.warning()}")
    if output_fmt in MARKER_FORMATS:  # a marker file needs frame numbers (or --fps): refused before any lifting
        marker_frame_numbers(kp, plan.fps, output_fmt)
    try:
        cams = resolve_cameras(
            kp.image_sizes, kp.image_ids, kp.file_names, focal=o.focal, principal_point=o.principal_point,
            intrinsics_file=str(o.intrinsics) if o.intrinsics else None, camera=o.camera,
        )  # fmt: skip
    except IntrinsicsError as exc:  # name the input whose camera could not be settled (same type: exit code)
        raise type(exc)(f"{source}: {exc}") from None
    kp.image_sizes = cams.image_sizes  # the calibration file's image size where the input states none
    obs = observed_mask(kp.xy, kp.confidence, o.min_confidence)
    status = geometry_status(undistort_instances(kp.xy, cams.lenses), cams.matrices, obs, plan.cfg.min_observed)
    if (status == "too_few_observed_joints").all():
        raise InputFormatError(
            f"{source}: no instance has {plan.cfg.min_observed} or more observed {prior.skeleton.name} joints "
            f"(all missing, or below --min-confidence {o.min_confidence})"
        )
    if not (status == LIFTED).any():
        first = str(Counter(str(s) for s in status).most_common(1)[0][0])
        raise InputFormatError(f"{source}: no instance can be lifted ({_reason_counts(status)}; "
                               f"{first}: {NOT_LIFTED[first]})")  # fmt: skip
    tracks, frames = places if o.person == "all" else None, _frame_numbers(kp)
    if o.temporal != "none":  # photos are not a video: refused before any work (lifting.sequence)
        check_sequence(kp.xy, obs, o.temporal, tracks=tracks, frames=frames, image_sizes=kp.image_sizes,
                       file_names=kp.file_names, source=source)  # fmt: skip
    return PreparedInput(source, kp, cams, tracks, frames, counts, video)


@dataclass
class LiftedInput:
    """One input lifted: what `zedo lift` writes for it, and what `zedo_cli.lift_file` returns."""

    source: str
    keypoints: Keypoints2D  # the 2D that was lifted (the prior's joint set, the people --person chose)
    result: LiftResult  # poses_camera (N, J, 3) metres, status, flags, uncertainty_m, ...
    cameras: ResolvedCameras  # each instance's K, where it came from, and its lens
    params: dict[str, Any]  # the settings, as the result file records them
    input_info: dict[str, Any]  # the input's path, format, skeleton and sha256
    warnings: list[str] = field(default_factory=list)

    @property
    def lifted(self) -> int:
        return int(self.result.lifted.sum())

    def write(self, path: str | Path, *, output_format: str | None = None, units: str = "m", frame: str = "camera",
              marker_axes: str = "level", overwrite: bool = False) -> list[Path]:  # fmt: skip
        """Write the result as `zedo lift -o PATH` does (format from the extension, else
        `output_format`); the files written."""
        fmt = format_of(str(path), output_format)
        return write_result(str(path), self.keypoints, self.result, self.cameras.matrices, self.cameras.sources,
                            self.params, self.input_info, fmt=fmt, units=units, frame=frame,
                            marker_axes=marker_axes, overwrite=overwrite, lenses=self.cameras.lenses)  # fmt: skip

    def poses(self) -> ResultPoses:
        """The result as `zedo analyze` reads it (`formats.ResultPoses`): written as a result
        file into a temporary folder and read back, so it is what the file would give."""
        import tempfile

        from ..formats import read_result

        with tempfile.TemporaryDirectory(prefix="zedo-") as folder:
            path = Path(folder) / f"{Path(self.source).name.split('.')[0] or 'input'}.zedo.json"
            self.write(path)
            return replace(read_result(str(path)), source=self.source)


def lift_params(prior: Prior, cfg: LiftConfig, *, seed: int, device: str, min_confidence: float) -> dict[str, Any]:
    return {
        "preset": cfg.preset,
        "steps": cfg.steps,
        "init_steps": cfg.init_steps,
        "noise_t": [cfg.t_start, cfg.t_end],
        "min_confidence": min_confidence,
        "hypotheses": cfg.hypotheses,
        "stability": stability_note(cfg.hypotheses),
        "seed": seed,
        "device": device,
        "network_precision": network_precision(cfg, device),
        "prior": {"file": Path(prior.path).name, "sha256": prior.sha256, "skeleton": prior.skeleton.name},
        "config": cfg.to_dict(),
    }


def network_precision(cfg: LiftConfig, device: str) -> str:
    """The precision the prior's network ran in: `fast` picks bfloat16 where the device has it, so the
    same options give float32 on another machine (docs/lifting.md, "Same answer on every machine")."""
    from ..lifting.precision import uses_bfloat16

    return "bfloat16" if uses_bfloat16(cfg, device) else "float32"


def stability_note(hypotheses: int) -> str:
    """What the output says about poses that may have landed in another solution."""
    from ..lifting.result import UNSTABLE_SPREAD_M

    limit = f"{UNSTABLE_SPREAD_M * 1000:g} mm"
    if hypotheses > 1:
        return (f"each person's hypothesis_spread_mm: how far its hypotheses lie apart; over {limit} its flags say "
                "unstable_solution (it may be another solution, e.g. a limb at another depth)")  # fmt: skip
    return ("not measured: one hypothesis; --hypotheses 8 gives each person's hypothesis_spread_mm and flags "
            f"unstable_solution where its hypotheses lie over {limit} apart")  # fmt: skip


def uncertainty_params(res: LiftResult) -> dict[str, Any]:
    """What the output says about `uncertainty_m`: present or not, and why."""
    return {"uncertainty_m": res.uncertainty_m is not None, "coverage": res.uncertainty_coverage,
            "note": res.uncertainty_note}  # fmt: skip


def run_lift(
    kp: Keypoints2D, prior: Prior, cfg: LiftConfig, intrinsics: np.ndarray, *, min_confidence: float,
    device: str, temporal: str = "none", sigma: float = 2.0, tracks: np.ndarray | None = None,
    frames: np.ndarray | None = None, seed: int = 0, calibrations: tuple[UncertaintyModel, ...] | None = None,
    lenses: Sequence[CameraModel | None] | None = None, callback: Progress | None = None, fps: float | None = None,
) -> LiftResult:  # fmt: skip
    """Lift frame by frame, or as a sequence (`temporal`: the frames checked to be one first);
    with the calibrated per-joint uncertainty where the prior and settings have one in
    `calibrations` (None: the bundled ones; frame by frame only). `lenses (N,)`: each instance's
    camera with distortion (its 2D is undistorted to lift; reprojection errors and the poor-fit
    test are in the original image)."""
    from ..lifting.solver import lift
    from ..lifting.temporal import lift_sequence
    from ..lifting.uncertainty import attach_uncertainty, bundled_calibrations

    if temporal != "none":
        res = lift_sequence(kp.xy, kp.confidence, intrinsics, prior, cfg, mode=temporal, sigma=sigma,
                            tracks=tracks, frames=frames, min_confidence=min_confidence, device=device,
                            callback=callback, seed=seed, cameras=lenses, image_sizes=kp.image_sizes,
                            file_names=kp.file_names, fps=fps)  # fmt: skip
        return replace(res, uncertainty_note=f"not calibrated for --temporal {temporal}")
    res = lift(kp.xy, kp.confidence, intrinsics, prior, cfg, min_confidence=min_confidence,
               device=device, callback=callback, seed=seed, cameras=lenses)  # fmt: skip
    models = bundled_calibrations() if calibrations is None else calibrations
    return attach_uncertainty(res, prior.sha256, prior.skeleton.joints, models)


def clip_fallback_warning(res: LiftResult, source: str) -> str | None:
    """`--temporal clip`: the warning that tracks too short for a skeleton were lifted as two-pass (None: none)."""
    fallbacks = [s for s in res.track_skeletons or () if "fallback" in s]
    if not fallbacks:
        return None
    first = fallbacks[0]
    return (f"{source}: {len(fallbacks)} of {len(res.track_skeletons or ())} tracks lifted as two-pass, not as one "
            f"infant: {first['fallback']} (track {first['track']})")  # fmt: skip


def lift_prepared(prep: PreparedInput, prior: Prior, plan: LiftPlan, callback: Progress | None = None,
                  warnings: Sequence[str] = ()) -> LiftedInput:  # fmt: skip
    """Lift a prepared input and record how (the params a result file keeps)."""
    from ..lifting.solver import NOT_LIFTED

    o, kp, source = plan.options, prep.keypoints, prep.source
    res = run_lift(kp, prior, plan.cfg, prep.cameras.matrices, min_confidence=o.min_confidence, device=plan.device,
                   temporal=o.temporal, sigma=o.sigma, tracks=prep.tracks, frames=prep.frames, seed=o.seed,
                   calibrations=plan.calibrations, lenses=prep.cameras.lenses, callback=callback,
                   fps=plan.fps)  # fmt: skip
    if not o.save_hypotheses:  # the writers write the hypotheses a result keeps
        res = replace(res, hypotheses=None)
    if not res.lifted.any():  # nothing but flags to write: fail loudly instead
        first = str(Counter(str(s) for s in res.status).most_common(1)[0][0])
        raise InputFormatError(f"{source}: no instance could be lifted ({not_lifted_counts(res)}; "
                               f"{first}: {NOT_LIFTED[first]})")  # fmt: skip
    params = lift_params(prior, plan.cfg, seed=o.seed, device=plan.device, min_confidence=o.min_confidence)
    if o.camera is not None:
        params["camera"] = o.camera
    params.update(
        person=o.person,
        person_selection=prep.counts,
        fps=plan.fps,
        temporal={
            "mode": o.temporal,
            "sigma_frames": o.sigma,
            **({} if res.track_skeletons is None else {"skeletons": res.track_skeletons}),
        },
        camera_sources=sorted(set(prep.cameras.sources)),  # pseudo, cli or file: what measure calibrations match
        uncertainty=uncertainty_params(res),
        save_hypotheses=o.save_hypotheses,
        options=o.rerun_values(),  # the options as given: the result is a --config that lifts again
    )
    if prep.video is not None:
        params["video"] = prep.video.params()
    input_info = {"path": source, "format": kp.format, "skeleton": kp.skeleton.name,
                  "source_skeleton": kp.source_skeleton, "sha256": input_sha256(source),
                  "zedo_version": __version__,  # frame_numbers: frame_index is the input's (else positions)
                  "frame_numbers": group_frames(kp.image_ids, kp.frame_indices).numbered}  # fmt: skip
    fallback = clip_fallback_warning(res, source)
    if fallback is not None and fallback not in warnings:
        warnings = [*warnings, fallback]
    return LiftedInput(source, kp, res, prep.cameras, params, input_info, list(warnings))


# Runs that `lift_file` cannot be: a batch's options, for the command.
_BATCH_ONLY = ("output_dir", "engine", "ray_address", "workers")


@functools.lru_cache(maxsize=2)
def _cached_prior(spec: str | None, device: str) -> Prior:
    from ..prior.weights import load_prior, resolve_prior_path

    return load_prior(resolve_prior_path(spec), device=device)


def check_setting_names(function: str, settings: dict[str, Any], model: type[Any]) -> None:
    """A TypeError, as Python gives for an unknown keyword, with the nearest setting's name."""
    from ..settings.config_file import did_you_mean

    for name in settings:
        if name not in model.keys():
            close = did_you_mean(name, model.keys())
            hint = f"; did you mean {close!r}?" if close else f" (the options of zedo {model.command}, by name)"
            raise TypeError(f"{function}() got an unexpected setting {name!r}{hint}")


def lift_file(path: str | Path, **settings: Any) -> LiftedInput:
    """Lift one 2D keypoint file as `zedo lift PATH` does, with its settings by their option
    names (`steps=30`, `focal=1500`, `person="all"`, `prior="my.safetensors"`, ...) and its
    defaults. With `output=FILE` the result is also written there (`units`, `frame`,
    `output_format`, `marker_axes`, `overwrite` as for the command), with `plot=DIR` its plots.
    Warnings are in `.warnings` (and issued as Python warnings). The prior is loaded once per
    (prior, device) and kept for the next call."""
    import warnings as python_warnings

    check_setting_names("lift_file", settings, LiftOptions)
    options = LiftOptions.validated(settings)
    batch = [k for k in _BATCH_ONLY if settings.get(k) not in (None, LiftOptions.default(k))]
    if batch:
        from ..errors import ConfigError
        from ..settings.model import option_name

        raise ConfigError(f"{option_name(batch[0])} is for batches of zedo lift: lift_file lifts one file")
    plan = plan_lift(options)
    prior = _cached_prior(options.prior, plan.device)
    source, found = str(path), []

    def keep(message: str) -> None:
        found.append(message)
        python_warnings.warn(message, stacklevel=3)

    fmt = format_of(options.output, options.output_format) if options.output is not None else None
    prep = prepare_input(source, prior, plan, None, keep, fmt)
    lifted = lift_prepared(prep, prior, plan, None, found)
    if options.output is not None:
        lifted.write(options.output, output_format=options.output_format, units=options.units, frame=options.frame,
                     marker_axes=options.marker_axes, overwrite=options.overwrite)  # fmt: skip
    if options.plot is not None:
        from ..formats.plots import write_pose_plots

        options.plot.mkdir(parents=True, exist_ok=True)
        stem = Path(options.output or source).name.split(".")[0]
        write_pose_plots(options.plot / stem, lifted.keypoints, lifted.result, units=options.units,
                         overwrite=options.overwrite)  # fmt: skip
    return lifted
