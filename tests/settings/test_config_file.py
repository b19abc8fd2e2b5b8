"""`--config FILE` read for one command (settings.config_file, settings.config): a table per
command, options by their long names, strict types, one-line errors naming the file and key, a
note for another command's table, and --print-config's TOML read back to the same settings."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest

from zedo_cli.errors import ConfigError
from zedo_cli.settings.analyze import AnalyzeOptions
from zedo_cli.settings.calibrate import CalibrateOptions
from zedo_cli.settings.config import read_config
from zedo_cli.settings.config_file import config_toml, toml_value
from zedo_cli.settings.lift import LiftOptions

COMMANDS = ("lift", "analyze", "render", "calibrate", "export", "norms")


def _config(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "study.toml"
    path.write_text(text)
    return path


def test_a_table_gives_its_command_the_options_by_long_name(tmp_path: Path) -> None:
    path = _config(
        tmp_path, "[lift]\nsteps = 30\nseed = 3\nfocal = 1500\nmin-confidence = 0.2\nimage_size = [640, 480]\n"
    )
    config = read_config(path, LiftOptions, COMMANDS)
    assert config.values == {"steps": 30, "seed": 3, "focal": 1500, "min_confidence": 0.2, "image_size": [640, 480]}
    options = LiftOptions.validated(config.values)
    assert options.focal == 1500.0 and options.image_size == (640.0, 480.0) and options.preset == "fast"
    assert config.notes == ()


@pytest.mark.parametrize(
    ("text", "needle"),
    [
        ("[lift]\nstpes = 30\n", "study.toml: [lift] stpes: no such option of zedo lift; did you mean steps?"),
        ("[lift]\nmin-confidense = 0.2\n", "did you mean min_confidence?"),
        ("[lift]\nbanana = 1\n", "[lift] banana: no such option of zedo lift (zedo lift --help lists them)"),
        ('[lift]\nsteps = "30"\n', "study.toml: [lift] steps: expected an integer in [1, 100000], got '30'"),
        ("[lift]\nsteps = 30.5\n", "[lift] steps: expected an integer in [1, 100000], got 30.5"),
        ("[lift]\nsteps = 0\n", "[lift] steps: expected an integer in [1, 100000], got 0"),
        ("[lift]\nsave-hypotheses = 1\n", "[lift] save_hypotheses: expected true or false, got 1"),
        (
            '[lift]\npreset = "quick"\n',
            "[lift] preset: expected one of faithful, fast, fast-bf16, fast-fp32, got 'quick'",
        ),
        ("[lift]\nimage-size = [640]\n", "[lift] image_size: expected two numbers, WIDTH HEIGHT, each > 0, got 640"),
        ("[lift]\nsteps = 3\nsteps = 4\n", "study.toml: not a TOML file"),
        ("[lift]\nsteps = 3\nsteps_ = 4\n", "no such option"),
        ("[lift]\nmin-confidence = 0.1\nmin_confidence = 0.2\n", "given twice"),
        ("steps = 30\n", "study.toml: steps: options go in a table per command, e.g. [lift]"),
        ("[lfit]\nsteps = 30\n", "study.toml: [lfit]: no zedo command of that name; did you mean [lift]?"),
        ("[lift\nsteps = 30\n", "study.toml: not a TOML file"),
    ],
)
def test_a_bad_key_or_value_is_one_line_naming_the_file_and_key(tmp_path: Path, text: str, needle: str) -> None:
    with pytest.raises(ConfigError) as info:
        read_config(_config(tmp_path, text), LiftOptions, COMMANDS)
    message = str(info.value)
    assert needle in message and "\n" not in message
    assert info.value.exit_code == 2


def test_a_missing_file_is_a_usage_error(tmp_path: Path) -> None:
    with pytest.raises(ConfigError, match=r"nowhere\.toml: cannot read the --config file"):
        read_config(tmp_path / "nowhere.toml", LiftOptions, COMMANDS)


def test_another_commands_table_is_left_to_it_with_a_note(tmp_path: Path) -> None:
    path = _config(tmp_path, "[analyze]\nfps = 30.0\nbogus = 1\n\n[lift]\nsteps = 30\n")
    config = read_config(path, LiftOptions, COMMANDS)
    assert config.values == {"steps": 30}  # analyze's fps is not lift's, and its table is not checked here
    assert config.notes == (f"{path}: [analyze] is for zedo analyze; zedo lift reads [lift]",)
    only_analyze = read_config(_config(tmp_path, "[analyze]\nfps = 30.0\n"), AnalyzeOptions, COMMANDS)
    assert only_analyze.values == {"fps": 30.0} and only_analyze.notes == ()


def test_the_printed_settings_read_back_to_the_same_settings(tmp_path: Path) -> None:
    values = {"steps": 30, "focal": 1500.0, "image_size": (640, 480), "prior": 'my "x".st',
              "images": Path("a b/ann.json"), "person": "all", "save_hypotheses": True}  # fmt: skip
    options = LiftOptions.validated(values)
    text = config_toml(options, "study.toml")
    assert "# skeleton =  (not set)" in text and "steps = 30" in text
    again = LiftOptions.validated(read_config(_config(tmp_path, text), LiftOptions, COMMANDS).values)
    assert again == options
    calibrate = CalibrateOptions.validated({"board": "9x6", "square": 0.025, "output": "cam.yml"})
    path = tmp_path / "cal.toml"
    path.write_text(config_toml(calibrate))
    assert CalibrateOptions.validated(read_config(path, CalibrateOptions, COMMANDS).values) == calibrate


@pytest.mark.parametrize("value", ["plain", 'quote " and \\ backslash', "tab\tnewline\n", "del\x7f", "é ü"])
def test_a_string_is_written_as_toml_reads_it(value: str) -> None:
    assert tomllib.loads(f"x = {toml_value(value)}")["x"] == value


def test_the_options_model_checks_what_the_command_line_checked() -> None:
    for values, needle in (
        ({"steps": 0}, "--steps must be an integer in [1, 100000], got 0"),
        ({"ray_weight": 0.0}, "--ray-weight must be a number in (0, 1], got 0"),
        ({"twin_ratio_cap": 0.5}, "--twin-ratio-cap must be 0 (off) or a number in [1, 100], got 0.5"),
        ({"fps": float("inf")}, "--fps must be a number in (0, 100000], got inf"),
        ({"camera": "left"}, "--camera picks a camera of an --intrinsics file"),
        ({"preset": "nope"}, "--preset must be one of faithful, fast, fast-bf16, fast-fp32, got 'nope'"),
    ):
        with pytest.raises(ConfigError) as info:
            LiftOptions.validated(values)
        assert str(info.value) == needle or needle in str(info.value)
    for values, needle in (
        ({"age_weeks": 500.0, "norms": "n.json"}, "--age-weeks must be between 0 and 200 weeks, got 500"),
        ({"level": 0.6}, "--level must be one of 0.5, 0.7, 0.8, 0.9, 0.95, got 0.6"),
        ({"age_weeks": 12.0}, "--age-weeks picks the age bracket of a reference: give it with --norms"),
    ):
        with pytest.raises(ConfigError, match=None) as info:
            AnalyzeOptions.validated(values)
        assert needle in str(info.value)


def test_every_option_has_help_and_the_model_defaults_are_the_presets() -> None:
    for model in (LiftOptions, AnalyzeOptions, CalibrateOptions):
        assert all(model.help(key) for key in model.keys()), model
    assert LiftOptions().lift_config().to_dict() == __import__("zedo_cli").PRESETS["fast"].to_dict()
    assert LiftOptions.validated({"steps": 7, "twin_rate": 0.5}).lift_config().steps == 7


def test_the_augment_models_read_their_tables_and_train_as_the_recipe(tmp_path: Path) -> None:
    from dataclasses import replace

    from zedo_cli.prior.schedules import AUGMENTER_TRAINING
    from zedo_cli.settings.augment import AugmentOptions, FitAugmenterOptions

    commands = (*COMMANDS, "fit-augmenter", "augment")
    path = _config(tmp_path, '[fit-augmenter]\nsyrip-dir = "s"\nadult-poses = "a.npz"\nepochs = 3\n'
                             "[augment]\ncount = 5\n")  # fmt: skip
    config = read_config(path, FitAugmenterOptions, commands)
    assert config.notes == (f"{path}: [augment] is for zedo augment; zedo fit-augmenter reads [fit-augmenter]",)
    fit = FitAugmenterOptions.validated(config.values)
    assert fit.syrip_dir == Path("s") and fit.training() == replace(AUGMENTER_TRAINING, epochs=3)
    assert FitAugmenterOptions().training() == AUGMENTER_TRAINING
    assert AugmentOptions.validated(read_config(path, AugmentOptions, commands).values).count == 5
    with pytest.raises(ConfigError, match="need infant reference poses"):
        AugmentOptions.validated({"bones": "infant"})


def test_the_evaluation_models_read_their_tables_and_lift_as_the_presets(tmp_path: Path) -> None:
    from dataclasses import replace

    from zedo_cli.lifting.config import PRESETS
    from zedo_cli.settings.evaluate import (
        BUNDLED_RECIPE,
        BenchmarkOptions,
        BenchmarkSymmetryOptions,
        EvaluateOptions,
    )

    commands = (*COMMANDS, "evaluate", "benchmark", "benchmark-symmetry")
    tables = ('[benchmark]\npreset = ["fast", "faithful", "fast"]\nhypotheses = 3\nchunk-size = 512\n'
              '[benchmark-symmetry]\nsyrip-dir = "s"\ninputs = "detected"\n[evaluate]\ngt = "t.npz"\n')  # fmt: skip
    path = _config(tmp_path, tables)
    config = read_config(path, BenchmarkOptions, commands)
    assert config.notes == tuple(f"{path}: [{c}] is for zedo {c}; zedo benchmark reads [benchmark]"
                                 for c in ("benchmark-symmetry", "evaluate"))  # fmt: skip
    bench = BenchmarkOptions.validated({**config.values, "scale": (64,)})
    configs = bench.lift_configs()  # each preset once, in order, with --hypotheses
    assert list(configs) == ["fast", "faithful"] and {c.hypotheses for c in configs.values()} == {3}
    assert bench.scale_config() == replace(PRESETS["fast"], chunk_size=512) and bench.inputs_2d() == ("gt", "detected")
    assert bench.recipe_path() == BUNDLED_RECIPE and BUNDLED_RECIPE.is_file()
    sym = BenchmarkSymmetryOptions.validated(read_config(path, BenchmarkSymmetryOptions, commands).values)
    assert sym.syrip_dir == Path("s") and sym.inputs_2d() == ("detected",) and sym.preset == "fast"
    assert EvaluateOptions.validated(read_config(path, EvaluateOptions, commands).values).gt == Path("t.npz")
    with pytest.raises(ConfigError, match="--syrip-dir is needed"):
        BenchmarkOptions.validated({})
    with pytest.raises(ConfigError, match="either --syrip-dir or --gt"):
        EvaluateOptions.validated({"gt": "t.npz", "syrip_dir": "s"})
