"""`zedo analyze` (clinical measures of lifted poses) and `zedo benchmark-symmetry` (their
accuracy on SyRIP Test100)."""

from __future__ import annotations

from dataclasses import asdict
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Optional

import typer
from rich.table import Table

from ..analysis.analyse import (
    SYMMETRY_NAMES,
    Analysis,
    poses_counted,
    summary,
)
from ..analysis.pose.joint_angles import ANGLE_NAMES
from ..analysis.pose.symmetry import DEFAULT_THRESHOLD_DEG, PAIRS, measure_name
from ..errors import ConfigError, InputFormatError, ZedoError
from ..files import check_writable, make_output_folder
from ..formats.readers.openpose import is_openpose_folder
from ..formats.readers.result import read_result
from ..lifting.config import get_preset
from ..pipeline.analyze_result import Reference, analyse_result, read_reference, write_analysis
from ..settings.analyze import AnalyzeOptions
from ..settings.device import check_device
from ..settings.evaluate import BenchmarkSymmetryOptions
from .common import (
    EXIT_PARTIAL,
    EXIT_RUNTIME,
    check_report_output,
    err_console,
    error_boundary,
    one_line,
    output_option,
    print_table,
    progress_bar,
    report_figures,
    stdout_console,
)
from .config import config_option, model_option, print_config_option, resolve_options
from .lift_plan import STDIN, expand_inputs, output_stem

if TYPE_CHECKING:
    from ..evaluation.symmetry_benchmark import SymmetryBenchmark
    from ..lifting.solver import LiftProgress


_RESULT_SUFFIXES = (".json", ".jsonl", ".ndjson", ".csv", ".npz")


def _is_result_name(path: Path) -> bool:
    return ".zedo." in path.name and path.suffix in _RESULT_SUFFIXES and not path.name.endswith(".meta.json")


def _result_files(folder: Path) -> list[str]:
    found = sorted(str(p) for p in folder.iterdir() if _is_result_name(p))
    if not found and is_openpose_folder(folder):
        raise InputFormatError(f"{folder}: a folder of OpenPose 2D keypoint frames, not zedo results: lift it "
                               f"first (zedo lift {folder} -o {folder.name or 'frames'}.zedo.json)")  # fmt: skip
    if not found:
        raise InputFormatError(f"{folder}: folder holds no zedo results (*.zedo.json/.jsonl/.csv/.npz)")
    return found


_opt = partial(model_option, AnalyzeOptions)  # the option `key` of AnalyzeOptions, with the model's help text
_sym_opt = partial(model_option, BenchmarkSymmetryOptions)  # the option `key` of BenchmarkSymmetryOptions


def _D(key: str) -> object:  # noqa: N802  (the option's default, from the model)
    return AnalyzeOptions.default(key)


def expand_results(args: list[str]) -> list[str]:
    """Result paths in the order given: `-`, files, folders (their `*.zedo.*` results) and glob
    patterns the shell did not expand (sidecars left out). Duplicates are dropped."""
    return expand_inputs(args, folder=_result_files, keep=lambda p: not p.name.endswith(".meta.json"))


ANALYSIS_FORMATS = {".csv": "csv", ".json": "json"}


def plan_outputs(
    sources: list[str], output: str | None, output_dir: Path | None, report: Path | None, as_json: bool,
    overwrite: bool,
) -> list[dict[str, str | None]]:  # fmt: skip
    """Per input: its csv, json and report paths (None = not written, - = stdout), checked
    before any work. -o's format is its extension's (- : the CSV on stdout); --json puts the
    JSON on stdout."""
    if output is not None and len(sources) > 1:
        raise ConfigError("-o/--output names one output; for several inputs use --output-dir (or none: beside each)")
    if output is not None and output_dir is not None:
        raise ConfigError("give -o/--output or --output-dir, not both")
    if as_json and (output is not None or output_dir is not None):
        raise ConfigError("--json prints the JSON on stdout: give it without -o/--output and --output-dir")
    if as_json and len(sources) > 1:
        raise ConfigError(f"--json prints one input's JSON on stdout, not {len(sources)}: use --output-dir")
    fmt = None
    if output is not None and output != STDIN:
        fmt = ANALYSIS_FORMATS.get(Path(output).suffix.lower())
        if fmt is None:
            raise ConfigError(f"{output}: -o/--output writes .csv or .json (or - for the CSV on stdout)")
    plans: list[dict[str, str | None]] = []
    for source in sources:
        stem = output_stem(source)
        if as_json:
            plan = {"csv": None, "json": STDIN}
        elif output is not None:
            plan = {"csv": output if fmt != "json" else None, "json": output if fmt == "json" else None}
        elif source == STDIN and output_dir is None:
            plan = {"csv": STDIN, "json": None}  # a pipeline: the tidy CSV to stdout
        else:
            folder = output_dir if output_dir is not None else Path(source).parent
            plan = {"csv": str(folder / f"{stem}.analysis.csv"), "json": str(folder / f"{stem}.analysis.json")}
        plan["report"] = str(report / f"{stem}.report.html") if report is not None else None
        plans.append(plan)
    seen: set[str] = set()
    for plan in plans:
        for path in plan.values():
            if path is None or path == STDIN:
                continue
            key = str(Path(path).resolve())
            if key in seen:
                raise ConfigError(f"{path}: two inputs would write it; use separate runs or rename the inputs")
            seen.add(key)
            check_writable(Path(path), overwrite)  # and its folder can be made
    return plans


def _summary_table(a: Analysis) -> Table:
    res = a.result
    table = Table(title=f"{res.source}: {poses_counted(res.frame_index[a.index], res.person[a.index])}, "
                  f"symmetric at <= {a.settings.threshold_deg:g} deg")  # fmt: skip
    for col in ("pair", "mean deg", "median deg", "symmetric", "asymmetric", "uncertain"):
        table.add_column(col, justify="left" if col == "pair" else "right")
    stats = summary(a)
    for name in SYMMETRY_NAMES:
        s = stats[name]
        mean = f"{s['mean']:.1f}" if "mean" in s else "-"
        median = f"{s['median']:.1f}" if "median" in s else "-"
        pair = name.removeprefix("symmetry_").removesuffix("_deg")
        table.add_row(pair, mean, median, str(s["symmetric"]), str(s["asymmetric"]), str(s["uncertain"]))
    return table


def analyze_file(source: str, plan: dict[str, str | None], options: AnalyzeOptions,
                 comparison: Reference | None = None) -> Analysis:  # fmt: skip
    """Read, analyse and write one result (errors are raised; the batch loop isolates them)."""
    a = analyse_result(read_result(source), options, comparison)
    write_analysis(a, plan, options)
    if not options.quiet:
        print_table(_summary_table(a))
        for note in a.notes:
            err_console.print(f"note: {note}", markup=False, soft_wrap=True)
        written = [p for p in plan.values() if p and p != STDIN]
        if written:
            err_console.print(f"wrote {', '.join(written)}", markup=False, soft_wrap=True)
    return a


@error_boundary
def analyze_command(
    results: Annotated[
        list[str],
        typer.Argument(
            help="zedo results (from zedo lift): .json, .jsonl, .csv (with its .meta.json), .npz; folders, "
            "glob patterns; - reads stdin (JSON, JSON Lines or CSV).",
            show_default=False,
        ),
    ],
    output: Annotated[Optional[str], output_option(AnalyzeOptions.help("output"))] = None,
    csv_out: Annotated[Optional[str], typer.Option("--csv", hidden=True, help="Older spelling of -o x.csv.")] = None,
    output_dir: Annotated[Optional[Path], _opt("output_dir")] = None,
    as_json: Annotated[bool, _opt("json", "--json")] = False,
    report: Annotated[Optional[Path], _opt("report")] = None,
    symmetry_threshold: Annotated[float, _opt("symmetry_threshold")] = _D("symmetry_threshold"),
    fps: Annotated[Optional[float], _opt("fps")] = None,
    level: Annotated[float, _opt("level")] = _D("level"),
    call_level: Annotated[float, _opt("call_level")] = _D("call_level"),
    max_angular_velocity: Annotated[float, _opt("max_angular_velocity")] = _D("max_angular_velocity"),
    norms: Annotated[Optional[Path], _opt("norms")] = None,
    age_weeks: Annotated[Optional[float], _opt("age_weeks")] = None,
    video: Annotated[Optional[Path], _opt("video")] = None,
    images: Annotated[Optional[Path], _opt("images")] = None,
    overwrite: Annotated[bool, _opt("overwrite")] = False,
    quiet: Annotated[bool, _opt("quiet", "--quiet", "-q")] = False,
    config: Annotated[Optional[Path], config_option("analyze")] = None,
    print_config: Annotated[bool, print_config_option()] = False,
) -> None:
    """Clinical measures of lifted poses: symmetry, joint angles, movement.

    Per frame and person: the symmetry angle of upper arm, forearm, thigh
    and shank (Huang et al. 2022: the left segment against the right one
    mirrored through the body's mid-plane), called symmetric at most
    --symmetry-threshold degrees (28), with the paper's bands (< 30, 30-60,
    >= 60); knee and elbow flexion, hip and shoulder flexion and abduction
    in a trunk frame (conventions: docs/clinical.md). From the input's 2D face
    points (kept by zedo lift): head tilt against the shoulder line and head
    turn (left, right, midline, to the infant's own side).

    For a video (--fps, or the fps given to zedo lift), per person: median
    and IQR of |angular velocity|, range of motion and the left-right
    correlation of every angle; the head-turn shares and median tilt, with
    intervals for correlated frames.

    Each measure's value is an estimate calibrated on held-out lifts, with a
    90 % interval (--level) where a measure calibration holds for the result's
    prior, settings, temporal mode and camera (the bundled prior, default
    preset, pseudo camera, images or --temporal smooth). A call is symmetric or
    asymmetric only when its --call-level interval (call_low, call_high) lies
    on one side of the threshold, else "uncertain"; without a calibration
    every call is uncertain and interval_note says why.

    Outputs: a tidy CSV (frame_index, image_id, file_name, person, measure,
    value, unit, low, high, level, call, interval, interval_note, raw_value,
    flag, call_low, call_high), a JSON with the same rows,
    the settings and a summary, and with --report DIR a self-contained HTML
    report. Files are replaced only with --overwrite. A file that is not a
    zedo result, or has no lifted person, exits with code 3.

    Examples:

      zedo analyze test100.zedo.json                 # test100.analysis.csv + .json
      zedo lift kp.json -o - -q | zedo analyze -     # the CSV on stdout
      zedo analyze clip.zedo.json --json | jq .summary
      zedo analyze clip.zedo.csv --fps 30 --report report/
      zedo analyze results/ --output-dir analysis/ --symmetry-threshold 30
    """
    if csv_out is not None:  # --csv PATH, the older spelling of -o PATH.csv
        if output is not None:
            raise ConfigError("give -o/--output (the older --csv is the same option), not both")
        if csv_out != STDIN and Path(csv_out).suffix.lower() != ".csv":
            raise ConfigError(f"--csv {csv_out}: a .csv file name, or -")
    o: AnalyzeOptions = resolve_options(AnalyzeOptions).options
    if csv_out is not None:
        o = o.replace(output=csv_out)
    analyze_batch(results, o)


def analyze_batch(results: list[str], o: AnalyzeOptions) -> None:
    """Analyse every result with the settings `o`: the reference and every output checked first."""
    comparison = read_reference(o.norms, o.age_weeks)
    sources = expand_results(results)
    if o.video is not None or o.images is not None:
        if o.report is None:
            raise ConfigError("--video / --images give the report its thumbnails: give them with --report DIR")
        if o.video is not None and o.images is not None:
            raise ConfigError("give the footage as --video FILE or as --images DIR, not both")
        if len(sources) != 1:
            raise ConfigError("--video / --images are the footage of one result: give one input")
    plans = plan_outputs(sources, o.output, o.output_dir, o.report, o.as_json, o.overwrite)
    if o.report is not None:
        make_output_folder(o.report)
    if len(sources) == 1:
        analyze_file(sources[0], plans[0], o, comparison)
        return
    codes = []
    for source, plan in zip(sources, plans, strict=True):
        try:
            analyze_file(source, plan, o, comparison)
        except ZedoError as exc:
            err_console.print(f"zedo: error: {one_line(str(exc))}", markup=False, soft_wrap=True)
            codes.append(exc.exit_code)
    if codes:  # 4 when some inputs were analysed, else the failures' common code (1 when they differ)
        raise typer.Exit(
            EXIT_PARTIAL if len(codes) < len(sources) else codes[0] if len(set(codes)) == 1 else EXIT_RUNTIME
        )


def _benchmark_tables(bench: SymmetryBenchmark) -> list[Table]:
    labels = {"gt": "GT 2D", "detected": "FiDIP 2D", "hwhup": "HW-HuP"}
    sym = Table(title=f"SyRIP Test100 symmetry vs weak 3D truth, threshold {bench.threshold_deg:g} deg "
                f"(truth: {100 * bench.truth_asymmetric_share:.0f}% asymmetric)")  # fmt: skip
    sym.add_column("pair", justify="left")
    for s in bench.scores:
        sym.add_column(f"{labels.get(s.source, s.source)} err", justify="right")
        sym.add_column("kappa", justify="right")
    for pair in PAIRS:
        n = measure_name(pair)
        cells = [c for s in bench.scores for c in (f"{s.angle_error_deg[n]:.1f}", f"{s.kappa[n]:.2f}")]
        sym.add_row(pair.replace("_", " "), *cells)
    pooled = [c for s in bench.scores for c in (f"{s.mean_angle_error_deg:.1f}", f"{s.pooled_kappa:.2f}")]
    sym.add_row("[b]all (pooled)[/b]", *(f"[b]{c}[/b]" for c in pooled))
    sym.add_row("equal calls", *(c for s in bench.scores for c in (f"{100 * s.agreement:.0f}%", "")))
    sym.add_row("asymmetric", *(c for s in bench.scores for c in (f"{100 * s.asymmetric_share:.0f}%", "")))
    sym.add_row("raw err", *(c for s in bench.scores for c in (_deg(s.raw_mean_angle_error_deg), "")))
    for pair in PAIRS:
        n = measure_name(pair)
        sym.add_row(f"90% cover {pair.replace('_', ' ')}",
                    *(c for s in bench.scores for c in (_pct(s.interval_coverage, n), "")))  # fmt: skip
    tables = [sym]
    lifted = [s for s in bench.scores if s.risk_coverage]
    if lifted:
        risk = Table(title="Selective calls: share of the pair-cases with a decisive call, and how often those "
                     "agree with the weak truth's call, per interval level")  # fmt: skip
        risk.add_column("level", justify="right")
        for s in lifted:
            risk.add_column(f"{labels.get(s.source, s.source)} decisive", justify="right")
            risk.add_column("agree", justify="right")
        for i, row in enumerate(lifted[0].risk_coverage or []):
            cells = [c for s in lifted for r in [(s.risk_coverage or [])[i]]
                     for c in (f"{100 * r['decisive']:.0f}%", f"{100 * r['agreement']:.0f}%")]  # fmt: skip
            risk.add_row(f"{row['level']:.2f}", *cells)
        tables.append(risk)
    ang = Table(title="Joint-angle error vs the weak 3D ground truth (mean |difference|, deg)")
    ang.add_column("angle", justify="left")
    for s in bench.scores:
        ang.add_column(labels.get(s.source, s.source), justify="right")
    for n in ANGLE_NAMES:
        ang.add_row(n.removesuffix("_deg"), *(f"{s.joint_angle_error_deg[n]:.1f}" for s in bench.scores))
    ang.add_row("[b]mean[/b]", *(f"[b]{s.mean_joint_angle_error_deg:.1f}[/b]" for s in bench.scores))
    return [*tables, ang]


def _deg(value: float | None) -> str:
    return "" if value is None else f"{value:.1f}"


def _pct(values: dict[str, float] | None, key: str) -> str:
    return "" if not values else f"{100 * values[key]:.0f}%"


@error_boundary
def benchmark_symmetry_command(
    syrip_dir: Annotated[Path, _sym_opt("syrip_dir")],
    prior_spec: Annotated[Optional[str], _sym_opt("prior", "--prior")] = None,
    preset: Annotated[str, _sym_opt("preset")] = BenchmarkSymmetryOptions.default("preset"),
    inputs: Annotated[str, _sym_opt("inputs")] = BenchmarkSymmetryOptions.default("inputs"),
    symmetry_threshold: Annotated[float, _sym_opt("symmetry_threshold")] = DEFAULT_THRESHOLD_DEG,
    reference: Annotated[bool, _sym_opt("reference")] = True,
    device: Annotated[str, _sym_opt("device")] = "cpu",
    as_json: Annotated[bool, _sym_opt("json", "--json")] = False,
    output: Annotated[Optional[str], output_option(BenchmarkSymmetryOptions.help("output"))] = None,
    overwrite: Annotated[bool, _sym_opt("overwrite")] = False,
    quiet: Annotated[bool, _sym_opt("quiet", "--quiet", "-q")] = False,
    config: Annotated[Optional[Path], config_option("benchmark-symmetry")] = None,
    print_config: Annotated[bool, print_config_option()] = False,
) -> None:
    """How accurate zedo analyze's measures are, on SyRIP Test100.

    Lifts the 100 test images from ground-truth and FiDIP-detected 2D
    (pseudo camera, the chosen preset), measures symmetry and joint angles,
    and compares them with the same measures on the weak 3D ground truth:
    per pair the mean absolute symmetry-angle error and Cohen's kappa of the
    symmetric / asymmetric calls at the threshold, the kappa pooled over the
    four pairs, and the mean absolute error of every joint angle. HW-HuP's
    3D predictions, from which the ground truth was hand-corrected, are
    scored too, as a reference (an upper bound more than a competitor).

    Example:

      zedo benchmark-symmetry --syrip-dir ../shared/data/syrip
    """
    o: BenchmarkSymmetryOptions = resolve_options(BenchmarkSymmetryOptions).options  # option errors before any work
    check_report_output(o.output, o.overwrite)
    from ..evaluation.symmetry_benchmark import run_symmetry_benchmark  # torch from here on
    from ..prior.weights import load_prior, resolve_prior_path

    device = check_device(o.device)  # auto: CUDA when present
    prior = load_prior(resolve_prior_path(o.prior), skeleton="syrip12", device=device)
    chosen = o.inputs_2d()
    with progress_bar(o.quiet) as bar:
        tasks = {k: bar.add_task(f"lift {k}", total=1, status="") for k in chosen}

        def on_step(key: str, p: LiftProgress) -> None:
            bar.update(tasks[key], completed=p.done, total=p.total)

        bench = run_symmetry_benchmark(o.syrip_dir, prior, get_preset(o.preset), inputs=chosen,
                                       threshold=o.symmetry_threshold, reference=o.reference, device=device,
                                       callback=on_step)  # fmt: skip
    doc = {"prior": prior.path, "prior_sha256": prior.sha256, "preset": o.preset, **asdict(bench)}
    if report_figures(doc, o.output, o.as_json, overwrite=o.overwrite, quiet=o.quiet):
        return
    console = stdout_console()
    for table in _benchmark_tables(bench):
        print_table(table, console)
    console.print("err: mean |symmetry-angle error| (deg) of zedo analyze's values (calibrated estimates where a "
                  "measure calibration holds; raw err: of the lifted pose's measures); kappa: Cohen's kappa of the "
                  "symmetric / asymmetric calls at the threshold against the truth's; HW-HuP: the image model the "
                  "weak truth was corrected from (reference)", markup=False)  # fmt: skip
    err_console.print(f"prior {prior.label}; preset {o.preset}; device {device}", markup=False)
