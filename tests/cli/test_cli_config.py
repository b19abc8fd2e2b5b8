"""`--config FILE` and `--print-config`: a TOML config and the same flags give
identical poses, flags given on the command line win, a zedo result reruns its lift, and a bad
file is one line with exit code 2."""

from __future__ import annotations

import json
import tomllib
from pathlib import Path

import numpy as np
import pytest
from test_cli import runner, write_coco

from zedo_cli.cli import app


def _lift(*args: str) -> dict:
    result = runner.invoke(app, ["lift", *args, "-q"])
    assert result.exit_code == 0, result.output
    return result


def _poses(path: Path) -> np.ndarray:
    doc = json.loads(path.read_text())
    return np.array([p["keypoints_3d"] for f in doc["frames"] for p in f["persons"]], dtype=float)


def _printed(*args: str) -> dict:
    result = runner.invoke(app, [*args, "--print-config"])
    assert result.exit_code == 0, result.output
    return tomllib.loads(result.stdout)


def test_a_config_and_the_same_flags_give_identical_poses(tiny_prior_path: Path, tmp_path: Path) -> None:
    src = write_coco(tmp_path / "kp.json")
    config = tmp_path / "study.toml"
    config.write_text(f'[lift]\nprior = "{tiny_prior_path}"\nsteps = 5\nseed = 3\nfocal = 1500\n')
    _lift(str(src), "--config", str(config), "-o", str(tmp_path / "a.json"))
    _lift(str(src), "--prior", str(tiny_prior_path), "--steps", "5", "--seed", "3", "--focal", "1500",
          "-o", str(tmp_path / "b.json"))  # fmt: skip
    np.testing.assert_array_equal(_poses(tmp_path / "a.json"), _poses(tmp_path / "b.json"))
    # the config's values were used: another focal gives other poses
    config.write_text(f'[lift]\nprior = "{tiny_prior_path}"\nsteps = 5\nseed = 3\nfocal = 900\n')
    _lift(str(src), "--config", str(config), "-o", str(tmp_path / "c.json"))
    assert not np.allclose(_poses(tmp_path / "a.json"), _poses(tmp_path / "c.json"))


def test_a_result_as_config_lifts_again_to_identical_poses(tiny_prior_path: Path, tmp_path: Path) -> None:
    src = write_coco(tmp_path / "kp.json")
    first = tmp_path / "first.zedo.json"
    _lift(str(src), "--prior", str(tiny_prior_path), "--steps", "5", "--focal", "1800", "--principal-point", "300",
          "200", "--hypotheses", "2", "--seed", "9", "--twin-rate", "0.5", "-o", str(first))  # fmt: skip
    again = tmp_path / "again.zedo.json"
    _lift(str(src), "--config", str(first), "-o", str(again))
    np.testing.assert_array_equal(_poses(first), _poses(again))
    a, b = (json.loads(p.read_text())["params"] for p in (first, again))
    assert a["options"] == b["options"] and a["config"] == b["config"] and a["options"]["focal"] == 1800.0
    # a flag still wins over what the result records
    assert _printed("lift", str(src), "--config", str(first), "--steps", "7")["lift"]["steps"] == 7


def test_flags_given_beat_the_config_and_defaults_fill_the_rest(tmp_path: Path) -> None:
    config = tmp_path / "study.toml"
    config.write_text('[lift]\nsteps = 30\nfocal = 1500\nperson = "all"\nquiet = true\n')
    printed = _printed("lift", "kp.json", "--config", str(config), "--focal", "1800", "--seed", "2")["lift"]
    assert (printed["steps"], printed["focal"], printed["seed"], printed["person"]) == (30, 1800.0, 2, "all")
    assert printed["preset"] == "fast" and "skeleton" not in printed  # a default, and an option not set
    # a flag equal to the default still wins (an explicit --person auto over the file's all)
    assert _printed("lift", "kp.json", "--config", str(config), "--person", "auto")["lift"]["person"] == "auto"


def test_the_printed_config_read_back_gives_the_same_settings(tmp_path: Path) -> None:
    first = _printed("lift", "kp.json", "--steps", "12", "--image-size", "640", "480", "--units", "mm")
    config = tmp_path / "printed.toml"
    config.write_text(runner.invoke(app, ["lift", "kp.json", "--steps", "12", "--image-size", "640", "480",
                                          "--units", "mm", "--print-config"]).stdout)  # fmt: skip
    assert _printed("lift", "kp.json", "--config", str(config)) == first


def test_a_bad_config_is_one_line_and_exit_code_2(tmp_path: Path) -> None:
    config = tmp_path / "study.toml"
    for text, needle in (
        (
            "[lift]\nstpes = 30\n",
            f"zedo: error: {config}: [lift] stpes: no such option of zedo lift; did you mean steps?",
        ),
        (
            '[lift]\nsteps = "many"\n',
            f"zedo: error: {config}: [lift] steps: expected an integer in [1, 100000], got 'many'",
        ),
        (
            "[lift]\nseed = -1\n",
            f"zedo: error: {config}: [lift] seed: expected an integer in [0, 9223372036854775807], got -1",
        ),
    ):
        config.write_text(text)
        result = runner.invoke(app, ["lift", "kp.json", "--config", str(config)])
        assert result.exit_code == 2, result.output
        assert result.output == needle + "\n"
    result = runner.invoke(app, ["lift", "kp.json", "--config", str(tmp_path / "none.toml")])
    assert result.exit_code == 2 and result.output.count("\n") == 1 and "cannot read the --config file" in result.output


def test_another_commands_table_is_ignored_with_a_note(tmp_path: Path) -> None:
    config = tmp_path / "study.toml"
    config.write_text("[analyze]\nfps = 30.0\n[calibrate]\nsquare = 0.025\n[lift]\nsteps = 9\n")
    result = runner.invoke(app, ["lift", "kp.json", "--config", str(config), "--steps", "4", "--print-config"])
    assert result.exit_code == 0 and tomllib.loads(result.stdout)["lift"]["steps"] == 4
    analyze = runner.invoke(app, ["analyze", "r.zedo.json", "--config", str(config), "--print-config"])
    assert analyze.exit_code == 0 and tomllib.loads(analyze.stdout)["analyze"]["fps"] == 30.0


def test_analyze_render_and_calibrate_take_a_config(tmp_path: Path) -> None:
    config = tmp_path / "study.toml"
    config.write_text('[analyze]\nsymmetry-threshold = 30.0\nlevel = 0.8\n[render]\noutput = "out.mp4"\n'
                      'video = "clip.mp4"\nside-view = true\n[calibrate]\nboard = "9x6"\nsquare = 0.025\n'
                      'output = "cam.yml"\nmin-views = 8\n')  # fmt: skip
    analyze = _printed("analyze", "r.zedo.json", "--config", str(config))["analyze"]
    assert analyze["symmetry_threshold"] == 30.0 and analyze["level"] == 0.8
    render = _printed("render", "r.zedo.json", "--config", str(config))["render"]
    assert render == {"output": "out.mp4", "video": "clip.mp4", "side_view": True, "overwrite": False, "quiet": False}
    # the required --board, --square and -o come from the file
    calibrate = _printed("calibrate", "board.png", "--config", str(config), "--square", "0.03")["calibrate"]
    assert (calibrate["board"], calibrate["square"], calibrate["min_views"]) == ("9x6", 0.03, 8)
    config.write_text("[calibrate]\nmin-views = 2\n")
    bad = runner.invoke(app, ["calibrate", "b.png", "--board", "9x6", "--square", "0.03", "-o", "c.yml",
                              "--config", str(config)])  # fmt: skip
    assert (
        bad.exit_code == 2
        and bad.output == f"zedo: error: {config}: [calibrate] min_views: expected an integer >= 3, got 2\n"
    )


def test_norms_takes_a_config_and_the_flags_given_win(tmp_path: Path) -> None:
    config = tmp_path / "study.toml"
    config.write_text('[norms]\nage-weeks = [8.0, 14.0]\nfps = 30.0\noutput = "typical.json"\n')
    norms = _printed("norms", "a.zedo.json", "b.zedo.json", "--config", str(config), "--fps", "25")["norms"]
    assert norms == {"output": "typical.json", "age_weeks": [8.0, 14.0], "fps": 25.0, "overwrite": False,
                     "quiet": False}  # fmt: skip
    config.write_text("[norms]\nage-weeks = 8.0\n")  # a list, even of one age
    bad = runner.invoke(app, ["norms", "a.zedo.json", "--config", str(config)])
    assert bad.exit_code == 2 and bad.output.startswith(f"zedo: error: {config}: [norms] age_weeks: expected ")
    bad = runner.invoke(app, ["norms", "a.zedo.json", "-o", "typical.csv"])
    assert bad.exit_code == 2 and bad.output == "zedo: error: typical.csv: -o/--output writes the reference as .json\n"


def test_export_takes_a_config_with_lifts_option_names(tmp_path: Path) -> None:
    config = tmp_path / "study.toml"
    config.write_text('[export]\nmarker-axes = "overhead"\nunits = "mm"\noutput-format = "trc"\n')
    export = _printed("export", "r.zedo.json", "--config", str(config), "--format", "c3d")["export"]
    assert (export["marker_axes"], export["units"], export["output_format"]) == ("overhead", "mm", "c3d")
    config.write_text('[export]\nunits = "cm"\n')
    bad = runner.invoke(app, ["export", "r.zedo.json", "--config", str(config)])
    assert (
        bad.exit_code == 2 and bad.output == f"zedo: error: {config}: [export] units: expected one of m, mm, got 'cm'\n"
    )
    bad = runner.invoke(app, ["export", "r.zedo.json", "--marker-axes", "sideways"])
    assert bad.exit_code == 2 and bad.output.startswith("zedo: error: --marker-axes must be one of level, overhead")


def test_a_result_is_a_config_of_lift_only(tmp_path: Path) -> None:
    result_file = tmp_path / "r.zedo.json"
    result_file.write_text(json.dumps({"schema": "zedo.pose3d/1", "params": {}}))
    result = runner.invoke(app, ["analyze", "x.zedo.json", "--config", str(result_file)])
    assert result.exit_code == 2 and "a zedo result is a --config of zedo lift" in result.output
    other = tmp_path / "other.json"
    other.write_text('{"steps": 3}')
    result = runner.invoke(app, ["lift", "kp.json", "--config", str(other)])
    assert result.exit_code == 2 and "not a zedo result" in result.output


def test_a_result_lifted_with_another_prior_is_refused(tiny_prior_path: Path, tmp_path: Path) -> None:
    src = write_coco(tmp_path / "kp.json", n=1)
    first = tmp_path / "first.zedo.json"
    _lift(str(src), "--prior", str(tiny_prior_path), "--steps", "3", "-o", str(first))
    doc = json.loads(first.read_text())
    doc["params"]["prior"]["sha256"] = "0" * 64  # as if the weights file had changed since
    first.write_text(json.dumps(doc))
    result = runner.invoke(app, ["lift", str(src), "--config", str(first), "-o", str(tmp_path / "b.json"), "-q"])
    assert result.exit_code == 2 and "lifted with a prior of sha256 000000000000..." in result.output
    assert result.output.count("\n") == 1
    # --prior on the command line: the user's choice
    _lift(str(src), "--config", str(first), "--prior", str(tiny_prior_path), "-o", str(tmp_path / "c.json"))


def test_an_older_result_without_its_options_lifts_again(tiny_prior_path: Path, tmp_path: Path) -> None:
    src = write_coco(tmp_path / "kp.json")
    first = tmp_path / "first.zedo.json"
    _lift(str(src), "--prior", str(tiny_prior_path), "--steps", "4", "--twin-rate", "0.3", "-o", str(first))
    doc = json.loads(first.read_text())
    del doc["params"]["options"]  # as zedo wrote results before params.options
    first.write_text(json.dumps(doc))
    refused = runner.invoke(app, ["lift", str(src), "--config", str(first), "-q"])
    assert refused.exit_code == 2 and "is not bundled" in refused.output and "--prior" in refused.output
    again = tmp_path / "again.json"
    _lift(str(src), "--config", str(first), "--prior", str(tiny_prior_path), "-o", str(again))
    np.testing.assert_array_equal(_poses(first), _poses(again))
    doc["params"]["camera_sources"] = ["cli"]  # --focal, which such a result does not record
    first.write_text(json.dumps(doc))
    refused = runner.invoke(app, ["lift", str(src), "--config", str(first), "--prior", str(tiny_prior_path)])
    assert refused.exit_code == 2 and "lifted with a camera from cli" in refused.output


def test_norms_help_states_the_reference_minimum() -> None:
    from zedo_cli.analysis.norms.norms import MIN_REFERENCE_CLIPS

    text = " ".join(runner.invoke(app, ["norms", "--help"]).output.split())
    assert f"at least {MIN_REFERENCE_CLIPS} per bracket" in text


def test_adapt_takes_a_config_and_names_its_bad_values() -> None:
    from typing import get_args

    from zedo_cli.prior.recipes import DTYPES, WEIGHT_CHOICES
    from zedo_cli.settings.adapt import AdaptOptions

    fields = AdaptOptions.model_fields  # the options take exactly what a recipe's output takes
    assert get_args(fields["weights"].annotation) == WEIGHT_CHOICES and get_args(fields["dtype"].annotation) == tuple(
        DTYPES
    )
    adapt = _printed("adapt", "--strategy", "finetune", "--limit", "100", "--seed", "3")["adapt"]
    assert (adapt["strategy"], adapt["limit"], adapt["seed"], adapt["output"]) == ("finetune", 100, 3,
                                                                                   "adapted.safetensors")  # fmt: skip
    for args, message in ((["--strategy", "tune"], "--strategy must be one of control, finetune, scratch"),
                          (["--limit", "0"], "--limit must be an integer >= 1, got 0"),
                          (["--dtype", "bf16"], "--dtype must be one of float16, float32")):  # fmt: skip
        bad = runner.invoke(app, ["adapt", *args])
        assert bad.exit_code == 2 and bad.output.startswith(f"zedo: error: {message}"), bad.output


def test_fit_prior_takes_a_config_and_leaves_the_rest_to_its_recipe(tmp_path: Path) -> None:
    config = tmp_path / "study.toml"
    config.write_text('[fit-prior]\nrecipe = "weights_spec/syrip12-scratch.toml"\nepochs = 2000\nweights = "ema"\n')
    fit = _printed("fit-prior", "--config", str(config), "--seed", "4")["fit-prior"]
    assert (fit["recipe"], fit["epochs"], fit["weights"], fit["seed"]) == ("weights_spec/syrip12-scratch.toml", 2000,
                                                                          "ema", 4)  # fmt: skip
    assert "batch_size" not in fit  # unset: the recipe's
    bad = runner.invoke(app, ["fit-prior", "--minirgbd-split", "mine"])
    assert bad.exit_code == 2 and bad.output.startswith("zedo: error: --minirgbd-split must be one of paper, reference")


def _refused(args: list[str], message: str) -> None:
    """`args` exit with code 2 and the one line `message` (its start)."""
    bad = runner.invoke(app, args)
    assert bad.exit_code == 2 and bad.output.startswith(f"zedo: error: {message}"), bad.output
    assert bad.output.count("\n") == 1, bad.output


@pytest.fixture
def no_data_read(monkeypatch: pytest.MonkeyPatch) -> None:
    """Reading poses or weights fails the test: the settings are refused before."""
    import zedo_cli.augment.augmenter
    import zedo_cli.cli.augment
    import zedo_cli.prior.weights

    def read(*args: object, **kwargs: object) -> None:
        raise AssertionError("data read before the settings were checked")

    for name in ("load_infant_source", "load_adult_source"):
        monkeypatch.setattr(zedo_cli.cli.augment, name, read)
    monkeypatch.setattr(zedo_cli.prior.weights, "load_prior", read)
    monkeypatch.setattr(zedo_cli.augment.augmenter, "load_augmenter", read)


def test_fit_augmenter_takes_a_config_and_the_flags_given_win(tmp_path: Path) -> None:
    from zedo_cli.prior.schedules import AUGMENTER_TRAINING

    config = tmp_path / "study.toml"
    config.write_text('[fit-augmenter]\nsyrip-dir = "syrip"\nadult-dir = "adult"\nepochs = 16\nseed = 3\n')
    fit = _printed("fit-augmenter", "--config", str(config), "--epochs", "4")["fit-augmenter"]
    assert (fit["syrip_dir"], fit["adult_dir"], fit["epochs"], fit["seed"]) == ("syrip", "adult", 4, 3)
    assert (fit["batch_size"], fit["lr"], fit["warmup_steps"]) == (AUGMENTER_TRAINING.batch_size,
                                                                   AUGMENTER_TRAINING.lr,
                                                                   AUGMENTER_TRAINING.warmup_steps)  # fmt: skip
    assert (fit["output"], fit["weights"], fit["dtype"], fit["init"]) == ("augmenter.safetensors", "ema", "float16",
                                                                          "adult12-rotscale")  # fmt: skip
    printed = tmp_path / "printed.toml"
    printed.write_text(runner.invoke(app, ["fit-augmenter", "--config", str(config), "--lr", "0.001",
                                           "--print-config"]).stdout)  # fmt: skip
    assert _printed("fit-augmenter", "--config", str(printed))["fit-augmenter"] == {**fit, "epochs": 16, "lr": 0.001}


def test_fit_augmenter_refuses_bad_settings_before_any_data_is_read(tmp_path: Path, no_data_read: None) -> None:
    out = tmp_path / "a.safetensors"
    sources = ["--syrip-dir", str(tmp_path), "--adult-dir", str(tmp_path), "-o", str(out)]
    for args, message in (
        (["--epochs", "0"], "--epochs must be an integer >= 1, got 0"),
        (["--batch-size", "0"], "--batch-size must be an integer >= 1, got 0"),
        (["--lr", "inf"], "--lr must be a number in (0, 1], got inf"),
        (["--warmup-steps", "-1"], "--warmup-steps must be an integer >= 0, got -1"),
        (["--seed", "-1"], "--seed must be an integer in [0, 9223372036854775807], got -1"),
        (["--split", "bogus"], "--split must be one of train, test, all, got 'bogus'"),
        (["--weights", "last"], "--weights must be one of raw, ema, got 'last'"),
        (["--dtype", "bf16"], "--dtype must be one of float16, float32, got 'bf16'"),
    ):
        _refused(["fit-augmenter", *sources, *args], message)
    _refused(["fit-augmenter", "--adult-dir", str(tmp_path)], "give the infant poses: --infant (an npz file) or")
    _refused(["fit-augmenter", *sources, "--infant", "i.npz"], "give at most one infant source")
    _refused(["fit-augmenter", "--syrip-dir", str(tmp_path)], "give exactly one adult source: --adult-poses")
    config = tmp_path / "study.toml"
    config.write_text("[fit-augmenter]\nepochs = 0\n")
    _refused(["fit-augmenter", *sources, "--config", str(config)],
             f"{config}: [fit-augmenter] epochs: expected an integer >= 1, got 0")  # fmt: skip
    assert not out.exists()


def test_augment_takes_a_config_and_the_flags_given_win(tmp_path: Path) -> None:
    config = tmp_path / "study.toml"
    config.write_text('[augment]\nstrength = 0.3\ncount = 50\norient = "infant"\nsyrip-dir = "syrip"\n')
    aug = _printed("augment", "adult.npz", "--config", str(config), "--count", "12")["augment"]
    assert (aug["strength"], aug["count"], aug["orient"], aug["syrip_dir"]) == (0.3, 12, "infant", "syrip")
    assert (aug["model"], aug["output"], aug["steps"], aug["scale"], aug["bones"]) == (
        "augmenter.safetensors", "augmented.npz", 100, "infant", "keep")  # fmt: skip
    printed = tmp_path / "printed.toml"
    printed.write_text(runner.invoke(app, ["augment", "--config", str(config), "--steps", "20",
                                           "--print-config"]).stdout)  # fmt: skip
    assert _printed("augment", "--config", str(printed))["augment"] == {**aug, "count": 50, "steps": 20}


def test_augment_refuses_bad_settings_before_any_data_is_read(tmp_path: Path, no_data_read: None) -> None:
    out = tmp_path / "o.npz"
    base = ["augment", str(tmp_path / "adult.npz"), "-o", str(out)]
    for args, message in (
        (["--count", "0"], "--count must be an integer in [1, 1000000], got 0"),
        (["--strength", "1.5"], "--strength must be a number in [0, 1], got 1.5"),
        (["--strength", "nan"], "--strength must be a number in [0, 1], got nan"),
        (["--steps", "0"], "--steps must be an integer in [1, 100000], got 0"),
        (["--seed", "-1"], "--seed must be an integer in [0, 9223372036854775807], got -1"),
        (["--scale", "adult"], "--scale must be one of infant, keep, got 'adult'"),
        (["--orient", "up"], "--orient must be one of keep, infant, got 'up'"),
        (["--bones", "adult"], "--bones must be one of keep, infant, got 'adult'"),
        (["--plot", "plots"], "--orient infant, --bones infant and --plot need infant reference poses"),
        (["--infant", "i.npz", "--syrip-dir", "s"], "give at most one infant source"),
    ):
        _refused([*base, *args], message)
    config = tmp_path / "study.toml"
    config.write_text("[augment]\nstrength = 2\n")
    _refused([*base, "--config", str(config)], f"{config}: [augment] strength: expected a number in [0, 1], got 2")
    assert not out.exists()


def test_augment_commands_defaults_are_their_models() -> None:
    import inspect

    from zedo_cli.cli.augment import augment_command, fit_augmenter_command
    from zedo_cli.settings.augment import AugmentOptions, FitAugmenterOptions

    for command, model in ((fit_augmenter_command, FitAugmenterOptions), (augment_command, AugmentOptions)):
        defaults = model().values()
        assert all(model.help(key) for key in defaults), model
        for name, param in inspect.signature(command).parameters.items():
            key = {"out": "output", "license_text": "license"}.get(name, name)
            if key in defaults:
                assert defaults[key] == param.default, (command.__name__, key)


@pytest.fixture
def no_evaluation_data_read(monkeypatch: pytest.MonkeyPatch) -> None:
    """Reading a result, ground truth, a prior, a recipe or SyRIP fails the test: the settings are refused before."""
    import zedo_cli.cli.evaluate
    import zedo_cli.evaluation.device_benchmark
    import zedo_cli.evaluation.symmetry_benchmark
    import zedo_cli.evaluation.syrip_benchmark
    import zedo_cli.prior.recipes
    import zedo_cli.prior.weights

    def read(*args: object, **kwargs: object) -> None:
        raise AssertionError("data read before the settings were checked")

    for module, names in (
        (zedo_cli.cli.evaluate, ("load_syrip_3d", "load_npz_poses", "read_result_file")),
        (zedo_cli.prior.weights, ("load_prior",)),
        (zedo_cli.prior.recipes, ("load_recipe",)),
        (zedo_cli.evaluation.syrip_benchmark, ("run_syrip_benchmark", "load_throughput_inputs")),
        (zedo_cli.evaluation.device_benchmark, ("run_device_benchmark",)),
        (zedo_cli.evaluation.symmetry_benchmark, ("run_symmetry_benchmark",)),
    ):
        for name in names:
            monkeypatch.setattr(module, name, read)


def test_evaluate_takes_a_config_and_the_flags_given_win(tmp_path: Path) -> None:
    config = tmp_path / "study.toml"
    config.write_text('[evaluate]\ngt = "truth.npz"\nprotocol = "h36m17"\nsplit = "train"\n')
    ev = _printed("evaluate", "r.json", "--config", str(config), "--protocol", "syrip12")["evaluate"]
    assert (ev["gt"], ev["protocol"], ev["split"], ev["json"], ev["quiet"]) == ("truth.npz", "syrip12", "train",
                                                                                 False, False)  # fmt: skip
    assert "syrip_dir" not in ev and "output" not in ev  # not set
    printed = tmp_path / "printed.toml"
    printed.write_text(runner.invoke(app, ["evaluate", "r.json", "--config", str(config), "--json",
                                           "--print-config"]).stdout)  # fmt: skip
    assert _printed("evaluate", "r.json", "--config", str(printed))["evaluate"] == {**ev, "protocol": "h36m17",
                                                                                     "json": True}  # fmt: skip


def test_evaluate_refuses_bad_settings_before_any_data_is_read(tmp_path: Path, no_evaluation_data_read: None) -> None:
    base = ["evaluate", str(tmp_path / "r.json")]
    truth = ["--gt", str(tmp_path / "t.npz")]
    for args, message in (
        ([*truth, "--split", "bogus"], "--split must be one of train, test, all, got 'bogus'"),
        ([*truth, "--protocol", "coco"], "--protocol must be one of syrip12, h36m17, got 'coco'"),
        ([], "give the ground truth as either --syrip-dir or --gt"),
        ([*truth, "--syrip-dir", str(tmp_path)], "give the ground truth as either --syrip-dir or --gt"),
        ([*truth, "-o", str(tmp_path / "scores.txt")], f"{tmp_path / 'scores.txt'}: -o/--output writes the figures"),
    ):
        _refused([*base, *args], message)
    config = tmp_path / "study.toml"
    config.write_text('[evaluate]\nprotocol = "coco"\n')
    _refused([*base, *truth, "--config", str(config)],
             f"{config}: [evaluate] protocol: expected one of syrip12, h36m17, got 'coco'")  # fmt: skip


def test_benchmark_takes_a_config_and_the_flags_given_win(tmp_path: Path) -> None:
    config = tmp_path / "study.toml"
    config.write_text('[benchmark]\nsyrip-dir = "syrip"\npreset = ["fast"]\nhypotheses = 4\nthroughput = false\n')
    bench = _printed("benchmark", "--config", str(config), "--preset", "faithful", "--preset", "fast-fp32",
                     "--throughput")["benchmark"]  # fmt: skip
    assert (bench["syrip_dir"], bench["preset"], bench["hypotheses"], bench["throughput"]) == (
        "syrip", ["faithful", "fast-fp32"], 4, True)  # fmt: skip
    assert (bench["inputs"], bench["scale"], bench["scale_preset"], bench["agreement_poses"], bench["fit_epochs"],
            bench["device"]) == ("gt,detected", [], "fast", 100_000, 200, "cpu")  # fmt: skip
    printed = tmp_path / "printed.toml"
    printed.write_text(runner.invoke(app, ["benchmark", "--config", str(config), "--scale", "64", "--scale", "128",
                                           "--print-config"]).stdout)  # fmt: skip
    again = _printed("benchmark", "--config", str(printed))["benchmark"]
    assert again == {**bench, "preset": ["fast"], "throughput": False, "scale": [64, 128]}


def test_benchmark_refuses_bad_settings_before_any_data_is_read(tmp_path: Path, no_evaluation_data_read: None) -> None:
    out = tmp_path / "bench.json"
    base = ["benchmark", "--syrip-dir", str(tmp_path), "-o", str(out)]
    for args, message in (
        (["--preset", "fast", "--preset", "quick"], "--preset must be one of faithful, fast, fast-bf16, fast-fp32, "
                                                    "got 'quick'"),
        (["--inputs", "gt,x"], "--inputs must list gt and/or detected, got 'gt,x'"),
        (["--hypotheses", "0"], "--hypotheses must be an integer in [1, 64], got 0"),
        (["--scale", "10", "--scale", "0"], "--scale must be an integer in [1, 10000000], got 0"),
        (["--scale", "10", "--agreement-poses", "-1"], "--agreement-poses must be an integer in [0, 10000000], got -1"),
        (["--scale", "10", "--fit-epochs", "100001"], "--fit-epochs must be 0 (skip) or an integer in [2, 100000], "
                                                      "got 100001"),
        (["--scale", "10", "--fit-epochs", "1"], "--fit-epochs must be 0 (skip) or at least 2: the first epoch is not "
                                                 "timed"),
        (["--scale", "10", "--chunk-size", "0"], "--chunk-size must be an integer in [1, 1048576], got 0"),
        (["--scale", "10", "--scale-preset", "nope"], "--scale-preset must be one of faithful, fast, fast-bf16, "
                                                      "fast-fp32, got 'nope'"),
        (["--scale", "10", "--fit-recipe", str(tmp_path / "r.toml")], f"--fit-recipe {tmp_path / 'r.toml'}: recipe "
                                                                      "file not found"),
    ):  # fmt: skip
        _refused([*base, *args], message)
    _refused(["benchmark", "--preset", "fast"], "--syrip-dir is needed (the SyRIP data folder), unless --scale")
    config = tmp_path / "study.toml"
    config.write_text("[benchmark]\nhypotheses = 65\n")
    _refused([*base, "--config", str(config)], f"{config}: [benchmark] hypotheses: expected an integer in [1, 64], "
                                               "got 65")  # fmt: skip
    config.write_text("[benchmark]\npreset = []\n")
    _refused([*base, "--config", str(config)], f"{config}: [benchmark] preset: expected one or more of faithful, "
                                               "fast, fast-bf16, fast-fp32, got none")  # fmt: skip
    assert not out.exists()


def test_benchmark_symmetry_takes_a_config_and_the_flags_given_win(tmp_path: Path) -> None:
    config = tmp_path / "study.toml"
    config.write_text('[benchmark-symmetry]\nsyrip-dir = "syrip"\nsymmetry-threshold = 30.0\nreference = false\n'
                      'inputs = "gt"\n')  # fmt: skip
    sym = _printed("benchmark-symmetry", "--config", str(config), "--symmetry-threshold", "20", "--reference")
    sym = sym["benchmark-symmetry"]  # --syrip-dir, required, from the file
    assert (sym["syrip_dir"], sym["symmetry_threshold"], sym["reference"], sym["inputs"]) == ("syrip", 20.0, True,
                                                                                              "gt")  # fmt: skip
    assert (sym["preset"], sym["device"]) == ("fast", "cpu")
    printed = tmp_path / "printed.toml"
    printed.write_text(runner.invoke(app, ["benchmark-symmetry", "--config", str(config), "--preset", "faithful",
                                           "--print-config"]).stdout)  # fmt: skip
    again = _printed("benchmark-symmetry", "--config", str(printed))["benchmark-symmetry"]
    assert again == {**sym, "symmetry_threshold": 30.0, "reference": False, "preset": "faithful"}


def test_benchmark_symmetry_refuses_bad_settings_before_any_data_is_read(
    tmp_path: Path, no_evaluation_data_read: None
) -> None:
    out = tmp_path / "sym.json"
    base = ["benchmark-symmetry", "--syrip-dir", str(tmp_path), "-o", str(out)]
    for args, message in (
        (["--preset", "quick"], "--preset must be one of faithful, fast, fast-bf16, fast-fp32, got 'quick'"),
        (["--inputs", "x"], "--inputs must list gt and/or detected, got 'x'"),
        (["--symmetry-threshold", "181"], "--symmetry-threshold must be a number in [0, 180], got 181"),
        (["--symmetry-threshold", "nan"], "--symmetry-threshold must be a number in [0, 180], got nan"),
    ):
        _refused([*base, *args], message)
    config = tmp_path / "study.toml"
    config.write_text("[benchmark-symmetry]\nsymmetry-threshold = -1.0\n")
    _refused([*base, "--config", str(config)],
             f"{config}: [benchmark-symmetry] symmetry_threshold: expected a number in [0, 180], got -1")  # fmt: skip
    assert not out.exists()


def test_evaluation_commands_defaults_are_their_models() -> None:
    import inspect

    from zedo_cli.cli.analyze import benchmark_symmetry_command
    from zedo_cli.cli.evaluate import benchmark_command, evaluate_command
    from zedo_cli.settings.evaluate import BenchmarkOptions, BenchmarkSymmetryOptions, EvaluateOptions

    for command, model in ((evaluate_command, EvaluateOptions), (benchmark_command, BenchmarkOptions),
                           (benchmark_symmetry_command, BenchmarkSymmetryOptions)):  # fmt: skip
        params = inspect.signature(command).parameters
        keys = {{"prior_spec": "prior", "as_json": "json"}.get(name, name): p for name, p in params.items()}
        assert set(model.keys()) <= set(keys), command.__name__  # every option of the model is the command's
        for key in model.keys():
            assert model.help(key), (model.__name__, key)
            if not model.model_fields[model.keys()[key]].is_required():
                assert model.default(key) == keys[key].default, (command.__name__, key)
