"""One result analysed: read, measured (`analysis.analyse`), compared with a reference of
typical infants (--norms) and written (the tidy CSV, the JSON, the HTML report). `zedo analyze`
runs this for each input (cli/analyze.py: the summary table, exit codes), `zedo_cli.analyze`
for one result from Python.

    from zedo_cli import analyze, lift_file
    table = analyze(lift_file("examples/prior_samples_coco.json")).to_pandas()
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..analysis.analyse import Analysis, analyse
from ..analysis.outputs import write_csv, write_csv_and_json, write_json
from ..errors import ConfigError
from ..formats import ResultPoses, read_result
from ..settings.analyze import AnalyzeOptions
from .lift import LiftedInput, check_setting_names

if TYPE_CHECKING:
    from ..analysis.norms.norms import Norms
    from ..analysis.report.report import Footage

STDIN = "-"


@dataclass(frozen=True)
class Reference:
    """--norms and --age-weeks: the reference of typical infants and the infant's age."""

    norms: Norms
    age_weeks: float | None


def read_reference(norms: Path | None, age_weeks: float | None) -> Reference | None:
    """--norms read and checked before any work; --age-weeks is for a reference split by age."""
    if norms is None:
        if age_weeks is not None:
            raise ConfigError("--age-weeks picks the age bracket of a reference: give it with --norms")
        return None
    from ..analysis.norms.norms import age_bracket, check_age_weeks
    from ..analysis.norms.norms_file import read_norms
    from ..version import __version__

    check_age_weeks(age_weeks)
    reference = read_norms(norms, __version__)
    age_bracket(age_weeks, reference.with_ages)  # a reference split by age needs the infant's age
    return Reference(reference, age_weeks)


def analyse_result(res: ResultPoses, options: AnalyzeOptions, comparison: Reference | None = None) -> Analysis:
    """The measures of a result read, compared with the reference where one is given; the
    footage (--video) is checked to fit the result first."""
    if options.video is not None:
        from ..camera.video import probe_video, require_frame_rate
        from ..footage.thumbnails import check_video_fits

        info = probe_video(options.video)
        require_frame_rate(info, options.fps)  # a bare stream's rate must be stated
        check_video_fits(res, options.video, info)  # refused before anything is written
    a = analyse(res, options.analysis_settings())
    if comparison is not None:
        from ..analysis.compare import compared

        a = compared(a, comparison.norms, comparison.age_weeks)
    return a


def write_analysis(a: Analysis, plan: dict[str, str | None], options: AnalyzeOptions) -> None:
    """The outputs of `plan` (csv, json, report paths; None: not written, - : stdout)."""
    csv, json = plan.get("csv"), plan.get("json")
    if csv and json and STDIN not in (csv, json):
        write_csv_and_json(a, Path(csv), Path(json), overwrite=options.overwrite)
    else:
        if csv:
            write_csv(a, csv, overwrite=options.overwrite)
        if json:
            write_json(a, json, overwrite=options.overwrite)
    if plan.get("report"):
        from ..analysis.report.report import write_report  # matplotlib loads only when a report is asked for

        write_report(a, plan["report"], overwrite=options.overwrite,
                     footage=footage(a, options.video, options.images))  # fmt: skip


def footage(a: Analysis, video: Path | None, images: Path | None) -> Footage | None:
    """For a clip's report: the frames to review, with thumbnails when the footage is given."""
    if not a.is_sequence:
        return None
    from ..analysis.report.clip_report import review_picks
    from ..analysis.report.report import Footage

    picks = review_picks(a)
    if video is None and images is None:
        return Footage(picks)
    from ..footage.thumbnails import cut_thumbnails

    thumbs = cut_thumbnails(a.result, [r.frame_index for r in picks], video=video, images=images)
    return Footage(picks, thumbs)


_BATCH_ONLY = ("output_dir", "json")  # a batch's outputs, or stdout: the command's


def analyze(result: LiftedInput | ResultPoses | str | Path, **settings: Any) -> Analysis:
    """Analyse one result as `zedo analyze RESULT` does, with its settings by their option
    names (`fps=30`, `symmetry_threshold=30`, `norms="ref.json"`, `age_weeks=12`, ...) and its
    defaults. `result`: what `lift_file` returned, a `ResultPoses` or a result file. With
    `output=FILE.csv` / `.json` the table is also written, with `report=DIR` the HTML report.
    `.rows` are the tidy rows; `.to_pandas()` is them as a DataFrame (pandas installed)."""
    check_setting_names("analyze", settings, AnalyzeOptions)
    options = AnalyzeOptions.validated(settings)
    batch = [k for k in _BATCH_ONLY if settings.get(k) not in (None, False)]
    if batch:
        raise ConfigError(f"--{batch[0].replace('_', '-')} is for zedo analyze's batches and stdout: analyze() "
                          "returns the analysis (output=FILE writes it)")  # fmt: skip
    if (options.video is not None or options.images is not None) and options.report is None:
        raise ConfigError("--video / --images give the report its thumbnails: give them with report=DIR")
    comparison = read_reference(options.norms, options.age_weeks)
    if isinstance(result, LiftedInput):
        res, stem = result.poses(), Path(result.source).name.split(".")[0]
    elif isinstance(result, ResultPoses):
        res, stem = result, Path(result.source).name.split(".")[0]
    else:
        res, stem = read_result(str(result)), Path(str(result)).name.split(".zedo.")[0]
    plan: dict[str, str | None] = {"csv": None, "json": None, "report": None}
    if options.output is not None:
        suffix = Path(options.output).suffix.lower()
        if suffix not in (".csv", ".json"):
            raise ConfigError(f"{options.output}: output= writes .csv or .json")
        plan[suffix[1:]] = options.output
    if options.report is not None:
        from ..files import make_output_folder

        make_output_folder(options.report)
        plan["report"] = str(options.report / f"{stem}.report.html")
    a = analyse_result(res, options, comparison)
    write_analysis(a, plan, options)
    return a
